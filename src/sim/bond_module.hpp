// The "bonds" module: every intact bond's force and moment, after the contact passes (a bond
// acts in parallel with the pair's contact law). It runs on the thread pool and gives the bits
// of one serial pass over the bonds in creation order for any thread count (BondModule::run
// says how). A bond whose strength is exceeded still acts for this step
// and is queued to break at the step's end (Scene::deferred); the manager then marks it broken,
// books the energy it held as released and computes the forces of the changed scene.
//
// The increments a model receives are taken with the half-step velocities the drift used, so
// a step's relative displacement is the drift's exactly; the accumulated shear force and
// bending moment are carried into the current bond plane (projected and rescaled to their
// magnitude) before the increment is added. With a zero step (the forces of a scene after an
// edit) no increment is added and the state stays as it was, bit for bit.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/thread_pool.hpp"
#include "sim/bond_model.hpp"
#include "sim/element_chunks.hpp"
#include "sim/integrator.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Returns v with its component along the unit n removed and its length kept (v itself when it
// is zero or along n). Changes nothing.
template <int D>
inline VecD<D> carryIntoPlane(const VecD<D>& v, const VecD<D>& n) {
  const Real len2 = v.squaredNorm();
  if (len2 == 0) return v;
  const VecD<D> p = v - v.dot(n) * n;
  const Real p2 = p.squaredNorm();
  if (p2 == 0) return p;
  return p * std::sqrt(len2 / p2);
}
inline Real carryIntoPlane(Real m, const Vec2&) {
  return m;  // 2D: a bending moment is along the plane's normal, always normal to the axis
}

// The geometry of one bond now: axis, length and the centre the force acts at (the middle of
// the gap between the two surfaces). Changes nothing.
template <int D>
struct BondFrame {
  VecD<D> n, centre;
  Real length;
};
template <int D>
inline BondFrame<D> bondFrame(const VecD<D>& xi, const VecD<D>& xj, Real ri, Real rj) {
  const VecD<D> d = xj - xi;
  BondFrame<D> f;
  f.length = d.norm();
  f.n = d / f.length;
  f.centre = xi + (ri + 0.5 * (f.length - ri - rj)) * f.n;
  return f;
}
template <int D>
inline BondFrame<D> bondFrame(const ElementArrays<D>& a, uint32_t i, uint32_t j) {
  return bondFrame<D>(a.x[i], a.x[j], a.r[i], a.r[j]);
}

template <int D>
class BondModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "bonds"; }
  SimLevel level() const override { return SimLevel::Contacts; }
  size_t workingBytes() const override {
    return hot_.capacity() * sizeof(Hot) + result_.capacity() * sizeof(Result) +
           (pair_.capacity() + layout_.capacity()) * sizeof(uint64_t) +
           energy_.capacity() * sizeof(Real) + breaks_.capacity() +
           start_.capacity() * sizeof(size_t) + entries_.capacity() * sizeof(uint64_t);
  }

  // Four passes, all but the last on the thread pool: each element's position, radius and
  // half-step velocities packed together (what a bond reads of an element, in one place);
  // each bond measured and its model run; the bonds' forces gathered per element; the energy
  // summed and the breaks queued. Each element gathers its bonds' forces in creation order, as
  // one serial pass over the bonds would add them, so the bits are those of that pass for any
  // thread count. The gather lists are rebuilt when a bond's elements move in the dense order
  // (a search's spatial sort, an edit), a bond breaks or the element count changes.
  void run(Scene<D>& s) override {
    const std::vector<Bond<D>>& bonds = s.bonds.bonds;
    const size_t n = bonds.size();
    packElements(s);
    pair_.resize(n);
    result_.resize(n);
    energy_.resize(n);
    breaks_.resize(n);
    const bool laidOut = layout_.size() == n;
    const size_t chunks = (n + kChunkBonds - 1) / kChunkBonds;
    moved_.assign(chunks, 0);
    // In regions of kRegionChunks chunks (65 536 bonds: about 5 ms in Release, 0.1 s under the
    // sanitizers), with Ctrl-C polled between them: the pass over millions of bonds is the
    // longest part of a bonded step.
    for (size_t first = 0; first < chunks; first += kRegionChunks) {
      if (first > 0) pollStep(s);
      const size_t count = std::min(kRegionChunks, chunks - first);
      ThreadPool::global().forEach(count, [&](size_t region, unsigned) {
        const size_t c = first + region;
        const size_t end = std::min(n, (c + 1) * kChunkBonds);
        bool moved = !laidOut;
        for (size_t k = c * kChunkBonds; k < end; ++k) {
          measure(s, k);
          moved = moved || pair_[k] != layout_[k];
        }
        moved_[c] = moved;
      });
    }
    if (start_.size() != s.elements.size() + 1 ||
        std::find(moved_.begin(), moved_.end(), 1) != moved_.end()) {
      relayout(s.elements.size());
    }
    ElementArrays<D>& a = s.elements.a;
    const bool rotating = s.rotating;
    forEachElementChunk(s.elements.size(), [&](size_t begin, size_t end, size_t) {
      for (size_t e = begin; e < end; ++e) {
        for (size_t q = start_[e]; q < start_[e + 1]; ++q) {
          const Result& r = result_[entries_[q] >> 1];
          if (entries_[q] & 1) {
            a.f[e] += r.force;
            if (rotating) a.t[e] += r.torqueJ;
          } else {
            a.f[e] -= r.force;
            if (rotating) a.t[e] -= r.torqueI;
          }
        }
      }
    });
    double energy = 0;
    for (size_t k = 0; k < n; ++k) {
      if (pair_[k] == kBroken) continue;
      energy += energy_[k];
      if (breaks_[k]) {
        s.deferred.breakBonds.push_back(
            {static_cast<uint32_t>(k), static_cast<BondBreakMode>(breaks_[k])});
      }
    }
    s.ledger.elastic += energy;
  }

 private:
  static constexpr size_t kChunkBonds = 4096;
  static constexpr size_t kRegionChunks = 16;
  static constexpr uint64_t kBroken = ~uint64_t{0};  // pair_ of a broken bond

  // What a bond reads of an element, packed: position, radius, half-step velocities.
  struct Hot {
    VecD<D> x;
    Real r;
    VecD<D> v;
    AngularD<D> w;
  };

  // One bond's force on its second element and torques about each element's centre, from
  // the measuring pass to the gathering one.
  struct Result {
    VecD<D> force;
    AngularD<D> torqueI, torqueJ;
  };

  // Fills hot_ from the elements' arrays: every element's when the bonds (as last laid out)
  // are at least half as many as the elements, else only the bonded elements', so a large
  // scene with a few bonds pays for those. Changes hot_.
  void packElements(const Scene<D>& s) {
    const ElementArrays<D>& a = s.elements.a;
    hot_.resize(s.elements.size());
    const bool moving = s.stepDt > 0, rotating = s.rotating;
    auto pack = [&](size_t e) {
      Hot& h = hot_[e];
      h.x = a.x[e];
      h.r = a.r[e];
      h.v = moving ? halfStepVelocity(s, e) : VecD<D>::Zero();
      h.w = moving && rotating ? halfStepAngularVelocity(s, e) : ElementArrays<D>::zeroAngular();
    };
    if (entries_.empty() || entries_.size() >= hot_.size()) {
      forEachElementChunk(hot_.size(), [&](size_t begin, size_t end, size_t) {
        for (size_t e = begin; e < end; ++e) pack(e);
      });
      return;
    }
    for (const Bond<D>& b : s.bonds.bonds) {
      if (!b.intact) continue;
      pack(s.elements.pool().findDense(b.a));
      pack(s.elements.pool().findDense(b.b));
    }
  }

  // Measures bond k's kinematics over the step, runs its model, stores the model's state in
  // the bond and the results in slot k of pair_, result_, energy_ and breaks_ (a broken bond
  // only sets pair_). Changes only those.
  void measure(Scene<D>& s, size_t k) {
    Bond<D>& bond = s.bonds.bonds[k];
    if (!bond.intact) {
      pair_[k] = kBroken;
      return;
    }
    const Real dt = s.stepDt;
    const uint32_t i = s.elements.pool().findDense(bond.a);
    const uint32_t j = s.elements.pool().findDense(bond.b);
    const Hot& hi = hot_[i];
    const Hot& hj = hot_[j];
    const BondModel& model = s.bonds.models[bond.model];
    const BondFrame<D> f = bondFrame<D>(hi.x, hj.x, hi.r, hj.r);
    BondKinematics<D> kin{f.n,  f.length,        hi.r,
                          hj.r, VecD<D>::Zero(), ElementArrays<D>::zeroAngular()};
    BondState<D> st = bond.state;
    if (dt > 0) {
      VecD<D> vi = hi.v, vj = hj.v;
      if (s.rotating) {
        vi += cross(hi.w, VecD<D>(f.centre - hi.x));
        vj += cross(hj.w, VecD<D>(f.centre - hj.x));
        kin.dRot = (hj.w - hi.w) * dt;
      }
      const VecD<D> du = (vj - vi) * dt;
      kin.dShear = du - du.dot(f.n) * f.n;
      st.shearForce = carryIntoPlane<D>(st.shearForce, f.n);
      st.bendMoment = carryIntoPlane(st.bendMoment, f.n);
    }
    const BondResponse<D> r =
        bondStep<D>(bondModelTypes()[model.type])(model.values, bond, kin, st);
    bond.state = st;
    pair_[k] = uint64_t{i} << 32 | j;
    Result& out = result_[k];
    out.force = r.force;
    if (s.rotating) {
      out.torqueJ = cross(VecD<D>(f.centre - hj.x), r.force) + r.moment;
      out.torqueI = cross(VecD<D>(f.centre - hi.x), r.force) + r.moment;
    }
    energy_[k] = st.energy;
    breaks_[k] = dt > 0 && r.breaks ? static_cast<uint8_t>(*r.breaks) : 0;
  }

  // Builds each of the ne elements' gather list from pair_: the indices of its intact bonds
  // in creation order, each shifted left by one with the low bit set where the element is the
  // bond's second. Changes start_, entries_ and layout_.
  void relayout(size_t ne) {
    const size_t n = pair_.size();
    start_.assign(ne + 1, 0);
    for (const uint64_t p : pair_) {
      if (p == kBroken) continue;
      ++start_[(p >> 32) + 1];
      ++start_[(p & 0xffffffffu) + 1];
    }
    for (size_t e = 0; e < ne; ++e) start_[e + 1] += start_[e];
    entries_.resize(start_[ne]);
    std::vector<size_t> fill(start_.begin(), start_.end() - 1);
    for (size_t k = 0; k < n; ++k) {
      const uint64_t p = pair_[k];
      if (p == kBroken) continue;
      entries_[fill[p & 0xffffffffu]++] = uint64_t{k} << 1 | 1u;
      entries_[fill[p >> 32]++] = uint64_t{k} << 1;
    }
    layout_ = pair_;
  }

  std::vector<Hot> hot_;           // per element, dense order
  // Per bond, creation order: its elements' dense indices (first << 32 | second, kBroken
  // for a broken bond) now and when the gather lists were built, its results, the energy it
  // holds and how it breaks (0: it holds).
  std::vector<uint64_t> pair_, layout_;
  std::vector<Result> result_;
  std::vector<Real> energy_;
  std::vector<uint8_t> breaks_;
  std::vector<uint8_t> moved_;     // per chunk of bonds: some bond's pair_ is not its layout_
  std::vector<size_t> start_;      // per element: where its gather list begins in entries_
  std::vector<uint64_t> entries_;  // the gather lists: bond index << 1 | second element
};

}  // namespace demlab::sim
