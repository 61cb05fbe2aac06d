// Bodies made of balls (clumps, and balls meeting them) through the ball contact kernel, member
// by member: the multi-sphere method as LIGGGHTS's fix multisphere and YADE's clumps run it.
//
// Each step, for the shape pass's candidate pairs whose two elements are unions of balls
// (Geometry::balls, or a ball), every member is made a ball of its own in arrays beside the
// scene's: its centre placed in the world, the velocity of its body's motion there (v + w x r),
// the body's spin, its radius, the body's inverse mass and material. The member pairs of each
// candidate that touch are the kernel's candidates (kernel::hertzPass: the SIMD Hertz-Mindlin
// pass of the ball beds, several contacts a register), and each member's force and torque are
// then summed onto its body: f, and t + (x_m - x) x f, which is the force at the contact point
// about the body's centre.
//
// The effective mass of such a contact is the bodies' reduced mass, m_a m_b / (m_a + m_b), as
// for two balls (and in LIGGGHTS and YADE): the lever terms the shape pass adds for other
// shapes (sim/shape_contacts.hpp) are left out, so the kernel can serve these pairs; the shape
// pass takes the same mass for them when no kernel runs, so the physics does not depend on
// the path. The tangential springs are the shape pass's (Scene::shapeSprings), keyed by the
// candidate's slots and the members' indices, as the clump's rows key them.
//
// Used when the kernel can: 3D, every material pair Hertz-Mindlin, a kernel active
// (contact_kernel.hpp). Otherwise the clump's rows serve these pairs point by point.
#pragma once

#include <vector>

#include "sim/contact_kernel.hpp"
#include "sim/contacts.hpp"
#include "sim/element_chunks.hpp"
#include "sim/element_marks.hpp"
#include "sim/scene.hpp"
#include "sim/shape.hpp"

namespace demlab::sim {

// Returns the balls geometry g is a union of: 1 for the ball, its Geometry::balls' count for
// a union of balls, 0 for any other shape.
template <int D>
uint32_t ballCount(const Geometry<D>& g) {
  return g.shape == ShapeTable<D>::ball() ? 1 : static_cast<uint32_t>(g.balls.size() / (D + 1));
}

// Returns whether element i of s is a union of balls (a ball, or a shape with Geometry::balls).
template <int D>
bool madeOfBalls(const Scene<D>& s, uint32_t i) {
  return ballCount(*s.geometries[s.elements.a.geometry[i]]) > 0;
}

template <int D>
class MemberBallPass {
 public:
  // Returns whether the pass serves s's pairs of ball unions this step (and prepares the
  // kernel): 3D, one Hertz-Mindlin law for every material pair, a kernel active. Changes the
  // kernel choice.
  bool serves(const Scene<D>& s) {
    if constexpr (D != 3) {
      return false;
    } else {
      kernel::Isa isa;
      if (!kernel::activeIsa(&isa)) return false;
      const auto hertz = physics::contactLawFor<D>(physics::LawKind::HertzMindlin);
      for (const auto& fn : s.pairLawFn) {
        if (fn != hertz) return false;
      }
      if (fn_ == nullptr || isa != isa_ || history_ != s.keepHistory || rotation_ != s.rotating) {
        fn_ = kernel::hertzPass(isa, s.keepHistory, s.rotating);
        isa_ = isa, history_ = s.keepHistory, rotation_ = s.rotating;
      }
      return fn_ != nullptr;
    }
  }

  // Runs the contacts of the candidates of s (s.shapeCandidates) whose elements are both ball
  // unions: forces and torques onto the bodies, springs kept in s.shapeSprings (between its
  // beginStep and endStep), records when s records, energies into e. serves(s) must have said
  // yes this step. Changes s's forces, torques, springs and records, and e.
  void run(Scene<D>& s, PassEnergy& e) {
    if constexpr (D == 3) {
      makeMembers(s);
      if (nc_ == 0) return;
      // Last step's springs of the candidates: a candidate without one has a zero spring.
      if (s.keepHistory) {
        pool_.resize(nc_);
        slotOf_.assign(nc_, kernel::SpringSlots::kNoSlot);
        keys_.resize(nc_);
        const ElementArrays<D>& a = s.elements.a;
        for (size_t k = 0; k < nc_; ++k) {
          const CandidatePair p = s.shapeCandidates[which_[k]];
          keys_[k] = {a.slot[p.i], a.slot[p.j], feature_[k]};
          if (const auto* h = s.shapeSprings.last(keys_[k])) {
            pool_[k] = *h;
            slotOf_[k] = static_cast<uint32_t>(k);
          }
        }
      }
      const size_t nMat = s.nMat();
      pairs_.resize(s.pairParams.size());
      for (size_t k = 0; k < pairs_.size(); ++k) pairs_[k] = hertzPairOf(s.pairParams[k]);
      kernel::HertzPassArgs k;
      k.x = x_.data();
      k.v = v_.data();
      k.w = w_.data();
      k.f = f_.data();
      k.t = t_.data();
      k.r = r_.data();
      k.invMass = invMass_.data();
      k.material = material_.data();
      k.cand = cand_.data();
      k.nCand = nc_;
      kernel::SpringSlots slots;
      if (s.keepHistory) {
        slots.slotOf = slotOf_.data();
        slots.data = reinterpret_cast<double*>(pool_.data());
        slots.owner = this;
        slots.acquire = &acquire;
        slots.release = &release;
        k.springs = &slots;
      }
      k.pairs = pairs_.data();
      k.nMat = nMat;
      k.onePair = pairs_.size() == 1;
      k.dt = s.stepDt;
      k.lag = velocityLag(s);
      k.springCriterion = s.coulomb == physics::CoulombCriterion::Spring;
      Sink sink{this, &s};
      if (s.recordContacts) {
        k.record = &appendRecords;
        k.recordContext = &sink;
      }
      fn_(k);
      e.elastic += k.elastic;
      e.damping += k.damping;
      e.friction += k.friction;
      e.springWork += k.springWork;
      if (s.keepHistory) {
        for (size_t c = 0; c < nc_; ++c) {
          if (slotOf_[c] != kernel::SpringSlots::kNoSlot) s.shapeSprings.keep(keys_[c], pool_[c]);
        }
      }
      gather(s);
    }
  }

  size_t workingBytes() const {
    size_t parts = parts_.capacity() * sizeof(Part);
    for (const Part& p : parts_) {
      parts += (p.cand.capacity() + p.which.capacity() + p.feature.capacity()) * sizeof(uint32_t);
    }
    return parts + (x_.capacity() + v_.capacity() + w_.capacity() + f_.capacity() + t_.capacity() +
            r_.capacity() + invMass_.capacity()) * sizeof(double) +
           (material_.capacity() + cand_.capacity() + slotOf_.capacity() +
            first_.capacity() + bodies_.capacity() + count_.capacity()) * sizeof(uint32_t) +
           marks_.heapBytes() +
           keys_.capacity() * sizeof(ShapeSpringKey) +
           pool_.capacity() * sizeof(physics::TangentialHistory<D>) +
           (which_.capacity() + feature_.capacity()) * sizeof(uint32_t);
  }

 private:
  // Where the kernel's records go: the candidate's bodies, the scene.
  struct Sink {
    MemberBallPass* self;
    Scene<D>* s;
  };
  static void appendRecords(void* context, const uint32_t* cand, const double* force, size_t n) {
    const Sink& k = *static_cast<const Sink*>(context);
    for (size_t c = 0; c < n; ++c) {
      const CandidatePair p = k.s->shapeCandidates[k.self->which_[cand[c]]];
      appendRecord<D>(k.s->contacts, {p.i, p.j, false, VecD<D>(force + D * c)});
    }
  }
  static double* acquire(void* owner, size_t k) {
    auto* self = static_cast<MemberBallPass*>(owner);
    self->slotOf_[k] = static_cast<uint32_t>(k);
    self->pool_[k] = {};
    return reinterpret_cast<double*>(self->pool_.data());
  }
  static void release(void* owner, size_t k) {
    static_cast<MemberBallPass*>(owner)->slotOf_[k] = kernel::SpringSlots::kNoSlot;
  }

  // Makes the members of the elements of the ball-union candidates and the member pairs that
  // touch, in candidate order and member order within. Changes every array but the springs'.
  void makeMembers(const Scene<D>& s) {
    const ElementArrays<D>& a = s.elements.a;
    const ShapeTable<D>& table = ShapeTable<D>::get();
    // Per geometry, its members (0: not a ball union).
    count_.resize(s.geometries.size());
    type_.resize(s.geometries.size());
    for (size_t g = 0; g < s.geometries.size(); ++g) {
      const Geometry<D>& geom = *s.geometries[g];
      type_[g] = geom.shape;
      count_[g] = ballCount(geom);
    }
    marks_.begin(a.size());
    first_.resize(a.size());
    // The bodies, each once, in the order the candidates name them.
    bodies_.clear();
    uint32_t members = 0;
    const auto mark = [&](uint32_t i) {
      if (!marks_.mark(i)) return;
      first_[i] = members;
      bodies_.push_back(i);
      members += count_[a.geometry[i]];
    };
    for (const CandidatePair& p : s.shapeCandidates) {
      if (count_[a.geometry[p.i]] == 0 || count_[a.geometry[p.j]] == 0) continue;
      mark(p.i), mark(p.j);
    }
    x_.resize(D * size_t{members}), v_.resize(D * size_t{members}), w_.resize(3 * size_t{members});
    r_.resize(members), invMass_.resize(members), material_.resize(members);
    // Each body's members on their own (the chunks on the pool).
    forEachElementChunk(bodies_.size(), [&](size_t begin, size_t end, size_t) {
      for (size_t b = begin; b < end; ++b) placeMembers(s, bodies_[b]);
    });
    // The member pairs, a chunk of candidates a task, each into its own part, the parts then
    // joined in chunk order (candidate order, for any thread count).
    const size_t nCand = s.shapeCandidates.size(), nChunks = elementChunks(nCand);
    if (parts_.size() < nChunks) parts_.resize(nChunks);
    forEachElementChunk(nCand, [&](size_t begin, size_t end, size_t c) {
      pairMembers(s, table, begin, end, parts_[c]);
    });
    size_t nc = 0;
    for (size_t c = 0; c < nChunks; ++c) nc += parts_[c].n;
    if (nc > which_.size()) cand_.resize(2 * nc), which_.resize(nc), feature_.resize(nc);
    for (size_t c = 0, at = 0; c < nChunks; at += parts_[c].n, ++c) {
      const Part& part = parts_[c];
      std::copy_n(part.cand.begin(), 2 * part.n, cand_.begin() + static_cast<std::ptrdiff_t>(2 * at));
      std::copy_n(part.which.begin(), part.n, which_.begin() + static_cast<std::ptrdiff_t>(at));
      std::copy_n(part.feature.begin(), part.n, feature_.begin() + static_cast<std::ptrdiff_t>(at));
    }
    nc_ = nc;  // the arrays keep their room from step to step
    f_.assign(x_.size(), 0.0);
    t_.assign(w_.size(), 0.0);
  }

  // One chunk's member pairs: the touching pairs of its candidates' members, their candidates
  // and features.
  struct Part {
    std::vector<uint32_t> cand, which, feature;
    size_t n = 0;
  };

  // Writes body i's members (first_[i] on) from its pose. Changes those members' entries.
  void placeMembers(const Scene<D>& s, uint32_t i) {
    const ElementArrays<D>& a = s.elements.a;
    const Geometry<D>& g = *s.geometries[a.geometry[i]];
    const uint32_t n = count_[a.geometry[i]];
    for (uint32_t k = 0; k < n; ++k) {
      const size_t m = first_[i] + k;
      VecD<D> c = a.x[i];
      Real radius = a.r[i];
      if (!g.balls.empty()) {
        VecD<D> local;
        for (int d = 0; d < D; ++d) local[d] = g.balls[k * (D + 1) + d];
        c += rotate(a.q[i], local);
        radius = g.balls[k * (D + 1) + D];
      }
      const VecD<D> vel = a.v[i] + cross(a.w[i], VecD<D>(c - a.x[i]));
      for (int d = 0; d < D; ++d) x_[D * m + d] = c[d], v_[D * m + d] = vel[d];
      for (int d = 0; d < 3; ++d) w_[3 * m + d] = a.w[i][d];
      r_[m] = radius;
      invMass_[m] = a.invMass[i];
      material_[m] = a.material[i];
    }
  }

  // Writes to out the touching member pairs of candidates begin .. end - 1 of s (both elements
  // ball unions). Every pair of a candidate's members is written, and kept (the count moved on)
  // when they touch: most tests of a bed go either way, so no branch on them. Changes out.
  void pairMembers(const Scene<D>& s, const ShapeTable<D>& table, size_t begin, size_t end,
                   Part& out) const {
    const ElementArrays<D>& a = s.elements.a;
    size_t nc = 0;
    for (size_t k = begin; k < end; ++k) {
      const CandidatePair p = s.shapeCandidates[k];
      const uint32_t gi = a.geometry[p.i], gj = a.geometry[p.j];
      const uint32_t ni = count_[gi], nj = count_[gj];
      if (ni == 0 || nj == 0) continue;
      if (nc + size_t{ni} * nj > out.which.size()) {
        const size_t room = 2 * (nc + size_t{ni} * nj) + 64;
        out.cand.resize(2 * room), out.which.resize(room), out.feature.resize(room);
      }
      // The rows' feature order: the first member the row's first element's (the table may
      // serve the pair with its elements swapped).
      const bool swapped = table.pair(type_[gi], type_[gj])->swapped();
      const uint32_t fi = first_[p.i], fj = first_[p.j];
      for (uint32_t u = 0; u < ni; ++u) {
        for (uint32_t q = 0; q < nj; ++q) {
          const uint32_t mi = fi + u, mj = fj + q;
          Real d2 = 0;
          for (int d = 0; d < D; ++d) {
            const Real dx = x_[D * mj + d] - x_[D * mi + d];
            d2 += dx * dx;
          }
          const Real rs = r_[mi] + r_[mj];
          out.cand[2 * nc] = mi, out.cand[2 * nc + 1] = mj;
          out.which[nc] = static_cast<uint32_t>(k);
          out.feature[nc] = swapped ? q * kMemberKeyStride + u : u * kMemberKeyStride + q;
          nc += d2 < rs * rs;
        }
      }
    }
    out.n = nc;
  }

  // Adds each member's force and torque to its body's, member by member in order. Changes s's
  // forces and torques.
  void gather(Scene<D>& s) const {
    ElementArrays<D>& a = s.elements.a;
    // A body's members are consecutive: each body sums its own (the chunks on the pool).
    forEachElementChunk(bodies_.size(), [&](size_t begin, size_t end, size_t) {
      for (size_t b = begin; b < end; ++b) {
        const uint32_t i = bodies_[b];
        const size_t first = first_[i], last = first + count_[a.geometry[i]];
        for (size_t m = first; m < last; ++m) {
          const VecD<D> f(f_.data() + D * m);
          a.f[i] += f;
          if (s.rotating) {
            const VecD<D> arm = VecD<D>(x_.data() + D * m) - a.x[i];
            a.t[i] += AngularD<D>(t_.data() + 3 * m) + cross(arm, f);
          }
        }
      }
    });
  }

 public:
  // A member pair's spring key: the candidate's slots and u * kMemberKeyStride + q, u and q
  // the members' indices in the candidate's first and second element (the clump's rows key
  // their points so).
  static constexpr uint32_t kMemberKeyStride = 64;

 private:
  kernel::HertzPassFn fn_ = nullptr;
  kernel::Isa isa_{};
  bool history_ = false, rotation_ = false;
  std::vector<kernel::HertzPair> pairs_;
  // The members: x, v (D each), w, t (3 each), f (D), radius, inverse mass, material.
  std::vector<double> x_, v_, w_, f_, t_, r_, invMass_;
  std::vector<uint32_t> material_;
  // Per element (dense): its first member this step, valid when marks_ has it; the bodies
  // with members this step; per geometry its members (0: not a ball union).
  ElementMarks marks_;
  std::vector<uint32_t> first_, bodies_, count_;
  std::vector<TypeId> type_;  // per geometry, its shape type
  // The member pairs that touch: their members (2 each), spring keys and bodies.
  std::vector<uint32_t> cand_;
  // The member pairs' candidates (indices into s.shapeCandidates) and features; their spring
  // keys, made only with history.
  std::vector<uint32_t> which_, feature_;
  std::vector<ShapeSpringKey> keys_;
  std::vector<Part> parts_;  // per chunk of candidates
  size_t nc_ = 0;  // the member pairs this step (the arrays above have room for more)
  std::vector<uint32_t> slotOf_;
  std::vector<physics::TangentialHistory<D>> pool_;
};

}  // namespace demlab::sim
