// The watchdog module ("watchdog", level Cleanup: after the step's second kick, before the
// outputs): cheap checks that a run is still physical, after every step. On by default; the
// options are Scene::watchdog (WatchdogOptions, sim/simulation.hpp).
//
// Per step it makes one streaming pass over x, v and w (sums and a maximum, no division), which
// yields the finiteness of the state and the largest speed, and one pass over the contact
// records of the step (the pairs' positions and radii; a wall contact asks the wall's narrow
// phase). Every 16 steps one more pass over the grains computes the energies. Nothing is
// written: a scene runs bit-identically with the watchdog on or off until it fires.
//
// The checks, in the order they are tried:
//   NAN     x, v or w of some grain is not finite (a sum over the pass is not finite);
//   SPEED   max |v| dt > the larger of half the skin and half the smallest radius: faster, the
//           neighbour search runs every step (it never misses a contact: detection.hpp checks
//           the displacement each step, tests/unit/sim/sim_detection_test.cpp), but a contact
//           can begin already half a radius deep, and a grain can cross a thin wall (two radii)
//           within a few steps, which no search can repair;
//   OVERLAP a contact's overlap > overlap x the smaller radius of the two (a grain's radius on a
//           wall). The default, 2, catches a grain gone wholly into another or through a wall
//           (tunnelling): the test scenes and the drum demo use materials so soft that static
//           beds overlap by up to a radius, so a lower default would stop them; for stiff,
//           physical materials 0.2 is a good limit (module watchdog -overlap 0.2). Before the
//           scene's first step the limit is `placed` (default 0.5): grains placed overlapping;
//           before a later run, it is for the contacts of elements and walls that edits placed
//           since the last step (added, moved, grown, turned), the others keeping `overlap`;
//   ENERGY  the ledger's balance (energy present + dissipated - work done - the reference) >
//           energy x the energy scale at two checks in a row, every 16 steps (the pass divides
//           by the masses): the integration creates energy. Only growth counts; the bound
//           allows the O(dt) transient of damped contacts (doc/verification.md, finding 6),
//           a few per cent at 0.2 of the critical step.
// A hit is thrown as WatchdogHit, which SimulationManager::run turns into RunStopped with the
// likely cause and the fix (sim/simulation_run.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>
#include <cstdint>
#include <limits>
#include <vector>

#include "sim/contacts.hpp"
#include "sim/distribution.hpp"
#include "sim/element_chunks.hpp"
#include "sim/rigid_body.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// What the watchdog found. a, b: grain dense indices (b a wall index when wall); value and limit
// in the check's units (NAN: none; SPEED: metres per step; OVERLAP: fraction of the radius;
// ENERGY: joules), extra: SPEED the speed, ENERGY the scale.
struct WatchdogHit {
  enum Kind { Nan, Speed, Overlap, Energy } kind = Nan;
  uint32_t a = 0, b = 0;
  bool hasB = false, wall = false, placed = false;
  double value = 0, limit = 0, extra = 0;
  int rank = -1;  // a distributed scene: the rank whose element it is when not this one
};

// Runs check() (which may throw WatchdogHit) on every rank of a distributed scene and throws on
// every rank when one found a hit: the hit of the lowest rank that has one, its elements known
// to that rank only (the others' hit carries its kind and rank, and
// SimulationManager::describeTrip gives them that rank's description). A serial scene: check().
// Collective in a distributed scene.
template <int D, class Check>
void watchTogether(const Scene<D>& s, Check&& check) {
  if (!s.dist) {
    check();
    return;
  }
  WatchdogHit hit;
  bool found = false;
  try {
    check();
  } catch (const WatchdogHit& h) {
    hit = h;
    found = true;
  }
  // One reduction a step; the ranks' kinds only when some rank found a hit.
  if (!(s.dist->comm->max(found ? 1.0 : 0.0) > 0)) return;
  const std::vector<double> kinds = s.dist->comm->gather({found ? double(hit.kind) : -1.0});
  for (size_t r = 0; r < kinds.size(); ++r) {
    if (kinds[r] < 0) continue;
    if (static_cast<int>(r) == s.dist->comm->rank()) throw hit;
    WatchdogHit other{static_cast<WatchdogHit::Kind>(static_cast<int>(kinds[r]))};
    other.rank = static_cast<int>(r);
    throw other;
  }
}

// Returns the largest distance a grain may move in one step: the larger of half the skin
// (s.skin, or the given one: the skin a configuration about to be prepared will use) and half
// the smallest radius.
template <int D>
Real watchdogStepLimit(const Scene<D>& s, Real skin) {
  Real rmin = std::numeric_limits<Real>::infinity();
  for (Real r : s.elements.a.r) rmin = std::min(rmin, r);
  return std::max(0.5 * skin, 0.5 * rmin);
}
template <int D>
Real watchdogStepLimit(const Scene<D>& s) {
  return watchdogStepLimit(s, s.skin);
}

// Returns the contact record of s whose overlap is the largest fraction of the smaller radius
// above f, with that fraction, among those keep(record) accepts; {null, f} when none is.
// Shapes: the scene has elements that are not balls, whose records are left out (a shape's
// radius is its bound, not a measure of its overlap); false instantiates the loop without the
// test. Changes nothing.
template <bool Shapes, int D, class Keep = bool (*)(const ContactRecord<D>&)>
std::pair<const ContactRecord<D>*, Real> deepestRecord(
    const Scene<D>& s, Real f, Keep keep = [](const ContactRecord<D>&) { return true; }) {
  const ElementArrays<D>& a = s.elements.a;
  const ContactRecord<D>* worst = nullptr;
  Real worstRatio = f;
  for (const ContactRecord<D>& c : s.contacts) {
    if constexpr (Shapes) {
      if (a.geometry[c.a] != 0 || (!c.wall && a.geometry[c.b] != 0)) continue;
    }
    if (!keep(c)) continue;
    const Real ratio = recordOverlapRatio(s, c, f);
    if (ratio > worstRatio) {
      worstRatio = ratio;
      worst = &c;
    }
  }
  return {worst, worstRatio};
}

// Returns deepestRecord among the contacts of an element or wall that edits placed since the
// last step (Scene::placedElements, placedWalls). Changes nothing.
template <int D>
std::pair<const ContactRecord<D>*, Real> deepestPlacedRecord(const Scene<D>& s, Real f) {
  std::vector<uint8_t> element(s.elements.a.size(), 0), wall(s.walls.items.size(), 0);
  for (ElementId id : s.placedElements) {
    if (s.elements.pool().valid(id)) element[s.elements.index(id)] = 1;
  }
  for (WallId id : s.placedWalls) {
    if (s.walls.pool().valid(id)) wall[s.walls.pool().denseIndex(id)] = 1;
  }
  if (s.dist && !s.dist->placed.empty()) {
    // Distributed: by global id, so that a ghost of a placed element is one too.
    std::vector<uint64_t> placed = s.dist->placed;
    std::sort(placed.begin(), placed.end());
    const ElementArrays<D>& a = s.elements.a;
    for (size_t i = 0; i < a.size(); ++i) {
      if (std::binary_search(placed.begin(), placed.end(), a.globalId[i])) element[i] = 1;
    }
  }
  return deepestRecord<true>(s, f, [&](const ContactRecord<D>& c) {
    return element[c.a] || (c.wall ? wall[c.b] : element[c.b]);
  });
}

// Returns the largest squared speed of s's elements (0 with none), as watchdogCheck's pass
// finds it. Changes nothing.
template <int D>
Real fastestSpeed2(const Scene<D>& s) {
  Real v2max = 0;
  for (const VecD<D>& v : s.elements.a.v) v2max = std::max(v2max, v.squaredNorm());
  return v2max;
}

// When a check runs: at the end of a step; before a run that follows edits, when the contacts
// of what they placed are held to the `placed` limit; before the scene's first step, when every
// contact is (the scene as set up).
enum class CheckPoint { Step, BeforeRun, BeforeFirstStep };

// Runs every enabled check on the scene as it is; throws WatchdogHit on the first that fails.
// stepLimit: watchdogStepLimit(s); when: see CheckPoint. Returns the largest squared speed
// (fastestSpeed2). Changes nothing.
template <int D>
Real watchdogCheck(const Scene<D>& s, Real stepLimit, CheckPoint when = CheckPoint::Step) {
  const bool placed = when == CheckPoint::BeforeFirstStep;
  const WatchdogOptions& o = s.watchdog;
  const ElementArrays<D>& a = s.elements.a;
  const size_t n = s.ownedCount();
  // One streaming pass, no division: a sum that is not finite when some x, v or w is not (NaN
  // and infinities propagate through sums), and the largest squared speed. As fast as a plain
  // sum over the positions alone (measured: the pass is bound by the add's latency).
  // Per element chunk on the thread pool; the chunks' sums added in chunk order.
  struct Part {
    double xs;
    Real v2max;
  };
  std::vector<Part> parts(elementChunks(n));
  forEachElementChunk(n, [&](size_t b, size_t e, size_t c) {
    double xs = 0;
    Real v2max = 0;
    for (size_t i = b; i < e; ++i) {
      const Real v2 = a.v[i].squaredNorm();
      xs += a.x[i].sum() + a.v[i].sum() + squaredNorm(a.w[i]);
      v2max = std::max(v2max, v2);
    }
    parts[c] = {xs, v2max};
  });
  double xs = 0;
  Real v2max = 0;
  for (const Part& p : parts) {
    xs += p.xs;
    v2max = std::max(v2max, p.v2max);
  }
  const Real dt = s.stepDt;
  const auto fastest = [&] {
    size_t k = 0;
    for (size_t i = 0; i < n; ++i) {
      if (a.v[i].squaredNorm() == v2max) k = i;
    }
    return k;
  };
  if (!std::isfinite(xs)) {
    WatchdogHit h{WatchdogHit::Nan};
    for (size_t i = 0; i < n; ++i) {
      if (!a.x[i].allFinite() || !a.v[i].allFinite() || !std::isfinite(squaredNorm(a.w[i]))) {
        h.a = static_cast<uint32_t>(i);
        break;
      }
    }
    throw h;
  }
  // A grain with nothing to meet (alone, no walls) may move any distance per step: free
  // flight is exact for the integrators, and nothing can be tunnelled through.
  const bool canMeet = n > 1 || !s.walls.items.empty();
  if (o.speed && canMeet && v2max * dt * dt > stepLimit * stepLimit) {
    WatchdogHit h{WatchdogHit::Speed};
    h.a = static_cast<uint32_t>(fastest());
    h.extra = std::sqrt(v2max);
    h.value = h.extra * dt;
    h.limit = stepLimit;
    throw h;
  }
  const auto overlapHit = [&](const ContactRecord<D>* worst, Real ratio, Real limit, bool user) {
    WatchdogHit h{WatchdogHit::Overlap};
    h.a = worst->a;
    h.b = worst->b;
    h.hasB = true;
    h.wall = worst->wall;
    h.value = ratio;
    h.limit = limit;
    h.placed = user;
    return h;
  };
  if (when == CheckPoint::BeforeRun && o.placed > 0 && s.recordContacts &&
      (!s.placedElements.empty() || !s.placedWalls.empty() ||
       (s.dist && !s.dist->placed.empty()))) {
    const auto [worst, ratio] = deepestPlacedRecord(s, o.placed);
    if (worst) throw overlapHit(worst, ratio, o.placed, true);
  }
  const Real f = placed ? o.placed : o.overlap;
  // Between a run's records (its last step, outputs) the passes keep the step's deepest contact
  // themselves (trackDeepest): the same measure, in the same record order, shape contacts left
  // out either way.
  if (f > 0 && (s.recordContacts || s.trackDeepest)) {
    using Found = std::pair<const ContactRecord<D>*, Real>;
    const Found deepest =
        s.deepest.ratio > f ? Found{&s.deepest.record, s.deepest.ratio} : Found{nullptr, f};
    const auto [worst, worstRatio] =
        !s.recordContacts ? deepest
        : s.anyShapes     ? deepestRecord<true>(s, f)
                          : deepestRecord<false>(s, f);
    if (worst) throw overlapHit(worst, worstRatio, f, placed);
  }
  return v2max;
}

// Returns true if the ledger's balance exceeds the watchdog's energy bound now: energy x the
// energy scale (as EnergyLedger computes them; one pass over the grains, with divisions).
// hit gets the fastest grain, the balance, the bound and the scale.
template <int D>
bool watchdogEnergyOver(const Scene<D>& s, WatchdogHit& h) {
  const WatchdogOptions& o = s.watchdog;
  const LedgerSums& l = s.ledger;
  if (!(o.energy > 0) || !l.started) return false;
  const ElementArrays<D>& a = s.elements.a;
  const size_t n = s.ownedCount();
  const VecD<D> g = s.behaviors.gravity();
  // Per element chunk on the thread pool; the chunks' sums added in chunk order, the fastest
  // element the first of the largest speed, as one pass would find it.
  struct Part {
    double k2, u;
    Real v2max;
    size_t fastest;
  };
  std::vector<Part> parts(elementChunks(n));
  forEachElementChunk(n, [&](size_t b, size_t e, size_t c) {
    Part p{0, 0, -1, b};
    for (size_t i = b; i < e; ++i) {
      const Real v2 = a.v[i].squaredNorm();
      p.k2 += v2 / a.invMass[i] + twiceRotationalEnergy(s, i);
      p.u -= g.dot(a.x[i]) / a.invMass[i];
      if (v2 > p.v2max) {
        p.v2max = v2;
        p.fastest = i;
      }
    }
    parts[c] = p;
  });
  double k2 = 0, u = 0;
  Real v2max = -1;
  size_t fastest = 0;
  for (const Part& p : parts) {
    k2 += p.k2;
    u += p.u;
    if (p.v2max > v2max) {
      v2max = p.v2max;
      fastest = p.fastest;
    }
  }
  double kin = 0.5 * k2;
  // A distributed scene: the ranks' parts added (every rank checks at the same steps).
  LedgerSums whole = l;
  if (s.dist) reduceLedger(*s.dist->comm, kin, u, whole);
  const double balance = whole.balanceSum(kin, u) - whole.reference;
  const double scale = whole.scaleWith(kin, u, true);
  if (!(scale > 0 && balance > o.energy * scale)) return false;
  h = WatchdogHit{WatchdogHit::Energy};
  h.a = static_cast<uint32_t>(fastest);
  h.value = balance;
  h.limit = o.energy * scale;
  h.extra = scale;
  return true;
}

template <int D>
class WatchdogModule final : public SimModule<D> {
 public:
  // limit: watchdogStepLimit of the scene the loop is built for (radii and skin change only
  // with the configuration, which rebuilds the loop).
  explicit WatchdogModule(Real limit) : limit_(limit) {}
  std::string_view name() const override { return "watchdog"; }
  SimLevel level() const override { return SimLevel::Cleanup; }
  void run(Scene<D>& s) override {
    // The energy every kEnergyEvery steps, firing when two checks in a row exceed the bound:
    // a balance off by O(1) of a still tiny scale in the first steps (a load rising from zero
    // on a grain at rest) fades, while created energy stays. Measured before the step's checks
    // throw: in a distributed scene it is a sum over the ranks, which every rank must take.
    const bool energyStep = s.steps % kEnergyEvery == 0;
    WatchdogHit energyHit;
    const bool over = energyStep && watchdogEnergyOver(s, energyHit);
    watchTogether(s, [&] {
      s.fastestSpeed2 = watchdogCheck(s, limit_);
      if (!energyStep) return;
      if (over && energyOver_) throw energyHit;
      energyOver_ = over;
    });
  }

  static constexpr uint64_t kEnergyEvery = 16;

 private:
  Real limit_;
  bool energyOver_ = false;
};

}  // namespace demlab::sim
