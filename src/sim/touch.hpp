// The "touch" module: the sub-step treatment of contact onset and release
// (physics/touch.hpp has the formulas and why; doc/design.md, "Touch and release").
//
// Level Behaviors, after every force module (makeModules adds it last in its level): it reads
// the velocities the force modules saw and the loads' work was booked with, and changes them
// only after. Per step it goes over the grain-grain candidates and each wall's candidates,
// finds the contacts whose normal force began or ended during the step, and adds the impulse
// correction of each to the velocities of its grains (before the second kick, which is then
// the trapezoid of the other contacts and of the body forces only), and the damping-loss and
// wall-work corrections to the ledger. The forces f at t+dt are left as they are: they are the
// true forces at the step's end, which the next step's first kick needs.
//
// Each end of the step is known exactly for grain pairs: the positions at t are x - dt v(t+dt/2)
// (the drift undone), the velocities the laws saw at t are v(t+dt/2) - dt a(t) for plain
// Verlet, and v(t+dt/2) - a(t) dt/2 for synchronized (Verlet's full-step velocity, which differs
// from the law's by (a(t) - a(t-dt)) dt/2 = O(dt^2) where the force is near zero: enough for
// the O(dt^3) the correction leaves). For a wall the grain is moved back by its displacement
// relative to the wall's surface velocity, which is exact for walls that translate during the
// step and approximate for turning ones (drums, rotating plates: O(dt^2) in the gap).
//
// Which grain pairs have an event comes from the contact passes: with the module on they write
// one state per candidate (Scene::touchNow: touching, and touching with the normal force cut
// off), and the pairs whose state changed since the last step are the step's events, found by
// comparing eight states at a time. Only those are reconstructed. A neighbour search carries
// the states to the new candidates by pair (SpringTransfer, history_store.hpp). The first step
// after an edit of the candidates (or a load without states) has none to compare with: it
// takes the full pass, every candidate tested from its reconstructed start (two squared
// distances and two velocity dots each, then a square root for the few that change state or
// a damped one separating), which is also the tests' oracle. A checkpoint keeps the states, so a loaded run
// takes the events its parent would have. The walls' candidates likewise (the wall pass
// writes their states), with the narrow phase at both ends for the events only. Cost on a
// dense bed: 3 to 4 % of a step (doc/performance.md, Run 19); on by default, nothing when the
// scene turns the module off.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>
#include <vector>

#include "physics/touch.hpp"
#include "sim/constraints.hpp"
#include "sim/contact_kernel.hpp"
#include "sim/contacts.hpp"
#include "sim/integrator.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Returns true if the pair's law damps the normal force (so its force can be cut off while
// the grains overlap). Changes nothing.
inline bool dampsNormal(const physics::PairParams& p) {
  return p.law == physics::LawKind::Linear ? p.dampingRatio != 0 : p.hertzGammaN != 0;
}

template <int D>
class TouchModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "touch"; }
  SimLevel level() const override { return SimLevel::Behaviors; }

  void run(Scene<D>& s) override {
    const Real dt = s.stepDt;
    if (!(dt > 0)) return;  // the force pass before a run: no step, no event
    kicks_.clear();
    double loss = 0, wallWork = 0;
    if (s.touchPrevValid && s.touchNowCurrent()) {
      grainEvents(s, loss);
    } else {
      velocities(s);
      grainPairs(s, loss);
    }
    walls(s, loss, wallWork);
    if (!s.blocked.empty() && !kicks_.empty()) holdBlocked(s);
    VecD<D>* v = s.elements.a.v.data();
    for (const auto& [i, dv] : kicks_) v[i] += dv;
    s.ledger.dampingLoss += loss;
    s.ledger.wallWork += wallWork;
  }

 private:
  // A grain at the step's start, reconstructed from its state at the end (see the file's
  // comment): its half-step velocity (the drift's), its position, and the velocity the laws
  // saw then.
  struct Start {
    VecD<D> vHalf, x, v;
  };

  // Returns the vector from a grain at xi to one at xj: to its nearest image in a periodic
  // scene (the contact passes' measure), with *n the Lees-Edwards cells it crosses. start:
  // the positions are the step's start, when the images' offset was U dt less (the detection
  // module advanced it before the contact passes). Changes nothing.
  static VecD<D> between(const Scene<D>& s, const VecD<D>& xi, const VecD<D>& xj, int* n,
                         bool start) {
    *n = 0;
    if (!s.periodic.any()) return xj - xi;
    VecD<D> d = s.periodic.nearest(xj - xi, n);
    if (start && *n != 0) d[s.periodic.flow] += *n * s.periodic.shearSpeed() * s.stepDt;
    return d;
  }
  // Returns vj - vi for a pair whose vector crossed n Lees-Edwards cells: the image moves with
  // -n U along the flow (as the contact passes take it). Changes nothing.
  static VecD<D> relative(const Scene<D>& s, const VecD<D>& vi, const VecD<D>& vj, int n) {
    VecD<D> v = vj - vi;
    if (n != 0) v[s.periodic.flow] -= n * s.periodic.shearSpeed();
    return v;
  }

  // Returns grain i's Start. Changes nothing.
  static Start startOf(const Scene<D>& s, size_t i) {
    const ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt, h = 0.5 * dt;
    Start g;
    if (s.integrator == IntegratorKind::Synchronized) {
      g.vHalf = a.v[i] - (h * a.invMass[i]) * a.fPrev[i];
      g.v = g.vHalf - (h * a.invMass[i]) * a.fPrev[i];
    } else {
      g.vHalf = a.v[i];
      g.v = g.vHalf - (dt * a.invMass[i]) * a.fPrev[i];
    }
    g.x = a.x[i] - dt * g.vHalf;
    return g;
  }

  // Fills xBefore_ and vBefore_ with every grain's Start, for the full pass.
  void velocities(const Scene<D>& s) {
    const size_t n = s.elements.a.size();
    xBefore_.resize(n);
    vBefore_.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const Start g = startOf(s, i);
      xBefore_[i] = g.x;
      vBefore_[i] = g.v;
    }
  }

  // The drift moves both grains on straight lines: the step's touch (or release) is where
  // |d0 + f (d1 - d0)| = rs, a quadratic in the fraction f of the step. Sets the overlap of the
  // end that does not touch to the value whose linear interpolation gives that f (what
  // physics::touchCorrection interpolates), which removes the error of interpolating the
  // overlap linearly where the grains pass each other obliquely (the overlap is concave in
  // time there). Changes e0 or e1.
  static void straightLineEnds(const VecD<D>& d0, const VecD<D>& d1, Real rs,
                               physics::ContactEnd& e0, physics::ContactEnd& e1) {
    const VecD<D> u = d1 - d0;
    const Real qa = u.squaredNorm(), qb = d0.dot(u), qc = d0.squaredNorm() - rs * rs;
    const Real disc = qb * qb - qa * qc;
    if (!(qa > 0 && disc >= 0)) return;
    // Touch: the first root (qc > 0 apart at the start); release: the second (qc < 0).
    const Real f = e1.touch ? (-qb - std::sqrt(disc)) / qa : (-qb + std::sqrt(disc)) / qa;
    if (!(f > 0 && f < 1)) return;
    if (e1.touch) {
      e0.overlap = -e1.overlap * f / (1 - f);  // e1.overlap / (e1.overlap - e0.overlap) = 1 - f
    } else {
      e1.overlap = -e0.overlap * (1 - f) / f;  // e0.overlap / (e0.overlap - e1.overlap) = f
    }
  }

  void grainPairs(const Scene<D>& s, double& loss) {
    const ElementArrays<D>& a = s.elements.a;
    const size_t nMat = s.nMat();
    const VecD<D>* __restrict x = a.x.data();
    const VecD<D>* __restrict x0 = xBefore_.data();
    const Real* __restrict r = a.r.data();
    const uint32_t* __restrict material = a.material.data();
    const VecD<D>* __restrict v = a.v.data();
    const VecD<D>* __restrict vb = vBefore_.data();
    damped_.resize(nMat * nMat);
    for (size_t k = 0; k < damped_.size(); ++k) damped_[k] = dampsNormal(s.pairParams[k]);
    const uint8_t* __restrict damped = damped_.data();
    const CandidatePair* __restrict cand = s.candidates.data();
    const size_t nc = s.candidates.size();
    // Stage 1, without a branch per candidate: the candidates that may need a correction. In
    // a bed the ones touching at neither end, at both ends undamped, or at both ends and
    // approaching at both are each a large share in no order a predictor learns, and a branch
    // per test cost more than the tests (measured: half the module's time).
    // Where few candidates touch (a loose lattice) the test of the velocities is skipped for the
    // others with a branch, which is then predictable; the share of the last step decides.
    picked_.resize(nc);
    size_t m = 0, touching = 0;
    auto pick = [&](auto denseTag) {
      for (size_t k = 0; k < nc; ++k) {
        const uint32_t i = cand[k].i, j = cand[k].j;
        const Real rs = r[i] + r[j];
        int cross1, cross0;
        const VecD<D> d1 = between(s, x[i], x[j], &cross1, false);
        const VecD<D> d0 = between(s, x0[i], x0[j], &cross0, true);
        // The contact module's test (contacts.hpp), at both ends. (Keeping the test of the
        // last step instead would save the start's distance, but a scene loaded from a
        // checkpoint has no last step: its run would not stay bit-identical to one that never
        // stopped.)
        const bool touch1 = d1.squaredNorm() < rs * rs, touch0 = d0.squaredNorm() < rs * rs;
        touching += touch0 | touch1;
        if constexpr (!decltype(denseTag)::value) {
          if (!(touch0 | touch1)) continue;
        }
        // Touching at both ends: only a damped force separating at one end can be cut off.
        const bool separating = !(relative(s, v[i], v[j], cross1).dot(d1) <= 0) |
                                !(relative(s, vb[i], vb[j], cross0).dot(d0) <= 0);
        picked_[m] = static_cast<uint32_t>(k);
        m += (touch0 != touch1) |
             (touch0 & touch1 & separating & (damped[material[i] * nMat + material[j]] != 0));
      }
    };
    if (dense_) {
      pick(std::true_type{});
    } else {
      pick(std::false_type{});
    }
    dense_ = 4 * touching > nc;
    // Stage 2, the candidates picked, in candidate order (the kicks' order is the loss's).
    for (size_t c = 0; c < m; ++c) {
      const uint32_t i = cand[picked_[c]].i, j = cand[picked_[c]].j;
      PairEnds g;
      if (!pairEnds(s, i, j, x0[i], x0[j], vb[i], vb[j], g)) continue;
      const bool touch1 = g.d1.squaredNorm() < g.rs * g.rs;
      const bool touch0 = g.d0.squaredNorm() < g.rs * g.rs;
      const physics::PairParams& p = s.pairParams[material[i] * nMat + material[j]];
      physics::ContactEnd e0{touch0, g.rs - g.dist0, g.vn0};
      physics::ContactEnd e1{touch1, g.rs - g.dist1, g.vn1};
      // A contact separating in a bed is far from its cut-off at both ends (most are).
      if (touch0 && touch1 && !physics::cutOff(p, e0, g.effMass, g.effRadius) &&
          !physics::cutOff(p, e1, g.effMass, g.effRadius)) {
        continue;
      }
      correctPair(s, i, j, p, g, e0, e1, loss);
    }
  }

  // A grain pair at the step's two ends: the centre lines, their lengths and normals, the
  // normal velocities the laws saw, the reach, the effective mass and radius.
  struct PairEnds {
    VecD<D> d0, d1, n0, n1;
    Real dist0, dist1, vn0, vn1, rs, effMass, effRadius;
  };

  // Sets g for grains i and j, given their positions x0i, x0j and law velocities v0i, v0j at
  // the step's start (the end's are the scene's); returns false, g partly set, if the centres
  // coincide at an end (no normal) or neither grain moves.
  static bool pairEnds(const Scene<D>& s, uint32_t i, uint32_t j, const VecD<D>& x0i,
                       const VecD<D>& x0j, const VecD<D>& v0i, const VecD<D>& v0j, PairEnds& g) {
    const ElementArrays<D>& a = s.elements.a;
    g.rs = a.r[i] + a.r[j];
    int cross1, cross0;
    g.d1 = between(s, a.x[i], a.x[j], &cross1, false);
    g.d0 = between(s, x0i, x0j, &cross0, true);
    g.dist1 = std::sqrt(g.d1.squaredNorm());
    g.dist0 = std::sqrt(g.d0.squaredNorm());
    if (!(g.dist1 > 0 && g.dist0 > 0)) return false;  // coincident centres: no normal
    const Real sumInv = a.invMass[i] + a.invMass[j];
    if (!(sumInv > 0)) return false;  // two fixed grains: nothing moves
    g.n1 = g.d1 * (1 / g.dist1);
    g.n0 = g.d0 * (1 / g.dist0);
    g.vn1 = relative(s, a.v[i], a.v[j], cross1).dot(g.n1);
    g.vn0 = relative(s, v0i, v0j, cross0).dot(g.n0);
    g.effMass = 1 / sumInv;
    g.effRadius = a.r[i] * a.r[j] / g.rs;
    return true;
  }

  // Adds the correction of grains i and j (pair parameters p) for the step whose ends are e0
  // and e1: the touch or release point on the straight lines first (straightLineEnds). Changes
  // kicks_ and loss.
  void correctPair(const Scene<D>& s, uint32_t i, uint32_t j, const physics::PairParams& p,
                   const PairEnds& g, physics::ContactEnd e0, physics::ContactEnd e1,
                   double& loss) {
    if (e0.touch != e1.touch) straightLineEnds(g.d0, g.d1, g.rs, e0, e1);
    const physics::TouchCorrection k = physics::touchCorrection(
        p, g.effMass, g.effRadius, s.stepDt, velocityLag(s), e0, e1);
    if (!k.any()) return;
    const VecD<D> J = k.impulse * (k.atEnd ? g.n1 : g.n0);
    kicks_.emplace_back(i, -s.elements.a.invMass[i] * J);
    kicks_.emplace_back(j, s.elements.a.invMass[j] * J);
    loss += k.loss;
  }

  // The grain pairs from the contact passes' states (Scene::touchNow, touchPrev): only the
  // candidates whose state changed, in candidate order, each with the full pass's arithmetic
  // for its two grains. The touch and cut-off at each end are the laws' own decisions; the
  // overlaps and velocities at the start are reconstructed, each overlap clamped to the side
  // its state gives (they differ only by rounding at the boundary, where the correction is
  // continuous).
  void grainEvents(const Scene<D>& s, double& loss) {
    const size_t nMat = s.nMat();
    const uint8_t* __restrict now = s.touchNow.data();
    const uint8_t* __restrict prev = s.touchPrev.data();
    const size_t nc = s.candidates.size();
    size_t k = 0;
    // Eight states at a time: in a bed nearly all are unchanged.
    for (; k + 8 <= nc; k += 8) {
      uint64_t u, w;
      std::memcpy(&u, now + k, 8);
      std::memcpy(&w, prev + k, 8);
      if (u == w) continue;
      for (size_t l = k; l < k + 8; ++l) {
        if (now[l] != prev[l]) grainEvent(s, l, prev[l], now[l], nMat, loss);
      }
    }
    for (; k < nc; ++k) {
      if (now[k] != prev[k]) grainEvent(s, k, prev[k], now[k], nMat, loss);
    }
  }

  // Candidate k's event from its states at the step's start (was) and end (is). Changes
  // kicks_ and loss.
  void grainEvent(const Scene<D>& s, size_t k, uint8_t was, uint8_t is, size_t nMat,
                  double& loss) {
    const bool touch0 = was & kernel::kTouching, touch1 = is & kernel::kTouching;
    const bool cut0 = was & kernel::kCutOff, cut1 = is & kernel::kCutOff;
    // No force at either end: a cut-off contact parting, a touch with its force cut off.
    if ((touch0 && !touch1 && cut0) || (!touch0 && touch1 && cut1)) return;
    const ElementArrays<D>& a = s.elements.a;
    const uint32_t i = s.candidates[k].i, j = s.candidates[k].j;
    const Start gi = startOf(s, i), gj = startOf(s, j);
    PairEnds g;
    if (!pairEnds(s, i, j, gi.x, gj.x, gi.v, gj.v, g)) return;
    const physics::PairParams& p = s.pairParams[a.material[i] * nMat + a.material[j]];
    // Each overlap on its state's side: a touching end's may not be negative (the Hertz
    // terms take its root).
    const auto side = [](bool touch, Real overlap) {
      return touch ? std::max<Real>(overlap, 0) : std::min<Real>(overlap, 0);
    };
    physics::ContactEnd e0{touch0, side(touch0, g.rs - g.dist0), g.vn0};
    physics::ContactEnd e1{touch1, side(touch1, g.rs - g.dist1), g.vn1};
    correctPair(s, i, j, p, g, e0, e1, loss);
  }

  void walls(const Scene<D>& s, double& loss, double& wallWork) {
    const ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt, lag = velocityLag(s);
    const size_t nMat = s.nMat();
    const WallNarrowPhase<D>& np = WallNarrowPhase<D>::get();
    const size_t nw = std::min(s.walls.size(), s.wallCandidates.size());
    for (size_t w = 0; w < nw; ++w) {
      const Wall<D>& wall = s.walls.items[w];
      const auto& entry = np.table.get(np.sphere, np.byShape[static_cast<int>(wall.kind)]).fn;
      const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, wall.shape);
      const std::vector<uint32_t>& list = s.wallCandidates[w];
      // With both steps' states (the wall pass's, one per candidate of each wall), only the
      // candidates whose state changed.
      const bool events = s.wallTouchPrevValid && s.wallTouchNowValid;
      const uint8_t* stateNow = events ? s.wallTouchNow[w].data() : nullptr;
      const uint8_t* statePrev = events ? s.wallTouchPrev[w].data() : nullptr;
      for (size_t c = 0; c < list.size(); ++c) {
        if (events && stateNow[c] == statePrev[c]) continue;
        const uint32_t i = list[c];
        const physics::SphereShape<D> now{a.x[i], a.r[i]};
        const auto g1 = entry.one(&now, shape);
        const VecD<D> vWall = wall.surfaceVelocity(g1 ? g1->point : a.x[i]);
        const Start start = startOf(s, i);
        const VecD<D>& vh = start.vHalf;
        // The grain at the step's start, relative to the wall where it is now.
        const physics::SphereShape<D> before{a.x[i] + dt * (vWall - vh), a.r[i]};
        const auto g0 = entry.one(&before, shape);
        if (!g0 && !g1) continue;
        if (!(a.invMass[i] > 0)) continue;  // a fixed grain: nothing moves
        const physics::PairParams& p = s.pairParams[a.material[i] * nMat + wall.material];
        const VecD<D> v1 = vWall - a.v[i];
        const VecD<D> v0 = vWall - start.v;
        // Touching at both ends: only a damped force separating at one end can be cut off.
        if (g0 && g1 && (!dampsNormal(p) || (v1.dot(g1->normal) <= 0 && v0.dot(g1->normal) <= 0))) {
          continue;
        }
        const Real m = 1 / a.invMass[i];
        const VecD<D> n1 = g1 ? g1->normal : g0->normal, n0 = g0 ? g0->normal : g1->normal;
        if (g0 && g1 && !physics::cutOff(p, {true, g0->overlap, v0.dot(n0)}, m, a.r[i]) &&
            !physics::cutOff(p, {true, g1->overlap, v1.dot(n1)}, m, a.r[i])) {
          continue;
        }
        // The missing end's signed overlap from the relative half-step velocity.
        const Real rate = (vWall - vh).dot(g1 ? n1 : n0);  // > 0 separating
        const Real o1 = g1 ? g1->overlap : g0->overlap - dt * rate;
        const Real o0 = g0 ? g0->overlap : o1 + dt * rate;
        const physics::ContactEnd e0{bool(g0), o0, v0.dot(n0)};
        const physics::ContactEnd e1{bool(g1), o1, v1.dot(n1)};
        const physics::TouchCorrection k = physics::touchCorrection(p, m, a.r[i], dt, lag, e0, e1);
        if (!k.any()) continue;
        // The impulse acts on the wall (B); the grain receives its opposite.
        const VecD<D> J = k.impulse * (k.atEnd ? n1 : n0);
        kicks_.emplace_back(i, -a.invMass[i] * J);
        loss += k.loss;
        if (wall.moving) wallWork -= J.dot(vWall);
      }
    }
  }

  // Removes the kicks' components along blocked degrees of freedom (ConstraintModule cancels
  // the forces there, which the kicks bypass), booking the constraint's reaction impulse times
  // the velocity as its work, as that module books its forces'. Changes kicks_ and the ledger.
  void holdBlocked(Scene<D>& s) {
    held_.collect(s);
    const ElementArrays<D>& a = s.elements.a;
    double work = 0;
    for (auto& [i, dv] : kicks_) held_.hold(a, i, dv, work);
    s.ledger.behaviorWork += work;
  }

  std::vector<std::pair<uint32_t, VecD<D>>> kicks_;  // grain, velocity change: applied last
  BlockedKickHold held_;                                   // the blocked grains (holdBlocked)
  std::vector<VecD<D>> xBefore_, vBefore_;           // per grain, this step (velocities())
  std::vector<uint8_t> damped_;                      // per material pair: dampsNormal
  std::vector<uint32_t> picked_;                     // grainPairs' candidates with an event
  bool dense_ = true;  // more than a quarter of the candidates touched in the last step
};

}  // namespace demlab::sim
