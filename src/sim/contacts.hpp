// Contact force modules: grain-grain ("contacts") and grain-wall ("wall-contacts").
//
// The loops are templates over what the scene uses, chosen once when the loop is built:
// whether pair histories are kept (some material has friction), whether grains rotate, and
// the contact law (inline when every material pair of the scene uses one law; otherwise the
// law's function pointer from a per-material-pair table, so the law is resolved once per
// material pair, never by a switch per contact). The walls' narrow phase is looked up once per
// wall in the physics TypeInteractionManager table and run as one batch per wall.
#pragma once

#include <algorithm>
#include <memory>

#include "core/type_interaction.hpp"
#include "physics/law_hertz_mindlin.hpp"
#include "physics/law_linear.hpp"
#include "physics/narrow_phase.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// The law a contact loop calls. Law = -1: per-pair function pointer table.
template <int D, int Law>
struct LawCall {
  static physics::ContactForce<D> call(const Scene<D>& s, size_t pair,
                                       const physics::ContactGeometry<D>& g,
                                       const physics::ContactKinematics<D>& k,
                                       physics::TangentialHistory<D>* h, Real dt) {
    const physics::PairParams& p = s.pairParams[pair];
    if constexpr (Law == static_cast<int>(physics::LawKind::Linear)) {
      return physics::linearContact<D>(p, g, k, h, dt);
    } else if constexpr (Law == static_cast<int>(physics::LawKind::HertzMindlin)) {
      return physics::hertzMindlinContact<D>(p, g, k, h, dt);
    } else {
      return s.pairLawFn[pair](p, g, k, h, dt);
    }
  }
};

// Returns how far behind the positions the velocities the laws see are, in steps: 0.5 for
// plain Verlet's half-step velocities, 0 when synchronized (physics/contact.hpp).
template <int D>
Real velocityLag(const Scene<D>& s) {
  return s.integrator == IntegratorKind::Verlet ? 0.5 : 0.0;
}

// Energy sums of one contact pass.
struct PassEnergy {
  double elastic = 0, damping = 0, friction = 0, springWork = 0, wallWork = 0;
  template <int D>
  void add(const physics::ContactForce<D>& f) {
    elastic += f.elasticEnergy;
    damping += f.dampingLoss;
    friction += f.frictionLoss;
    springWork += f.springWork;
  }
};

template <int D, int Law, bool History, bool Rotation>
class GrainContactModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return History ? "contacts-friction" : "contacts"; }
  SimLevel level() const override { return SimLevel::Contacts; }

  void run(Scene<D>& s) override {
    GrainArrays<D>& a = s.grains.a;
    const Real dt = s.stepDt;
    const size_t nMat = s.nMat();
    const Real lag = velocityLag(s);
    PassEnergy e;
    const size_t nc = s.candidates.size();
    for (size_t kc = 0; kc < nc; ++kc) {
      const uint32_t i = s.candidates[kc].i, j = s.candidates[kc].j;
      const VecD<D> d = a.x[j] - a.x[i];
      const Real rs = a.r[i] + a.r[j];
      if (d.squaredNorm() >= rs * rs) {
        if constexpr (History) s.pairSprings[kc].spring.setZero();  // the contact opened
        continue;
      }
      // A (i) is the grain with the lower slot (the search orders each pair so), so a pair's
      // spring keeps one orientation.
      const auto geom = physics::intersect<D>(physics::SphereShape<D>{a.x[i], a.r[i]},
                                              physics::SphereShape<D>{a.x[j], a.r[j]});
      if (!geom) {
        if constexpr (History) s.pairSprings[kc].spring.setZero();
        continue;
      }
      const physics::ContactGeometry<D>& g = *geom;
      VecD<D> vrel = a.v[j] - a.v[i];
      VecD<D> armA, armB;
      if constexpr (Rotation) {
        armA = g.point - a.x[i];
        armB = g.point - a.x[j];
        vrel += cross(a.w[j], armB) - cross(a.w[i], armA);
      }
      const physics::ContactKinematics<D> k{vrel, 1.0 / (a.invMass[i] + a.invMass[j]),
                                            a.r[i] * a.r[j] / (a.r[i] + a.r[j]), lag};
      physics::TangentialHistory<D>* h = nullptr;
      if constexpr (History) h = &s.pairSprings[kc];
      const physics::ContactForce<D> f =
          LawCall<D, Law>::call(s, a.material[i] * nMat + a.material[j], g, k, h, dt);
      a.f[j] += f.force;
      a.f[i] -= f.force;
      if constexpr (Rotation) {
        a.t[j] += cross(armB, f.force);
        a.t[i] -= cross(armA, f.force);
      }
      e.add(f);
      s.contacts.push_back({i, j, false, f.force});
    }
    s.ledger.elastic += e.elastic;
    s.ledger.dampingLoss += e.damping;
    s.ledger.frictionLoss += e.friction;
    s.ledger.springWork += e.springWork;
  }
};

// The narrow-phase table for walls: one lookup per wall per step.
template <int D>
struct WallNarrowPhase {
  TypeRegistry types{"shape type"};
  TypeInteractionManager<physics::NarrowPhaseEntry<D>> table{types, "narrow phase"};
  TypeId sphere, byShape[4];
  WallNarrowPhase() {
    physics::registerNarrowPhase<D>(types, table);
    sphere = types.get("sphere");
    byShape[static_cast<int>(WallShape::Plane)] = types.get("plane");
    byShape[static_cast<int>(WallShape::Finite)] = types.get("flatwall");
    byShape[static_cast<int>(WallShape::Box)] = types.get("box");
    byShape[static_cast<int>(WallShape::Drum)] = types.get("drum");
  }
  static const WallNarrowPhase& get() {
    static const WallNarrowPhase instance;
    return instance;
  }
};

template <int D, int Law, bool History, bool Rotation>
class WallContactModule final : public SimModule<D> {
 public:
  std::string_view name() const override {
    return History ? "wall-contacts-friction" : "wall-contacts";
  }
  SimLevel level() const override { return SimLevel::Contacts; }

  void run(Scene<D>& s) override {
    GrainArrays<D>& a = s.grains.a;
    const Real dt = s.stepDt;
    const size_t nMat = s.nMat();
    const Real lag = velocityLag(s);
    const WallNarrowPhase<D>& np = WallNarrowPhase<D>::get();
    PassEnergy e;
    for (size_t w = 0; w < s.walls.size(); ++w) {
      Wall<D>& wall = s.walls.items[w];
      wall.force.setZero();
      if (w >= s.wallCandidates.size()) continue;
      const std::vector<uint32_t>& which = s.wallCandidates[w];
      if (which.empty()) continue;
      geoms_.resize(which.size());
      touched_.resize(which.size());
      const auto& entry = np.table.get(np.sphere, np.byShape[static_cast<int>(wall.kind)]).fn;
      const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, wall.shape);
      const size_t m = entry.grains(shape, a.x.data(), a.r.data(), which.data(), which.size(),
                                    geoms_.data(), touched_.data());
      // touched_ lists the grains in contact in the order of `which`: walk both to find each
      // contact's candidate index (its spring slot), zeroing the springs of those not touched.
      size_t kc = 0;
      for (size_t c = 0; c < m; ++c) {
        const uint32_t i = touched_[c];
        if constexpr (History) {
          while (which[kc] != i) s.wallSprings[w][kc++].spring.setZero();
        }
        const physics::ContactGeometry<D>& g = geoms_[c];
        const VecD<D> vWall = wall.surfaceVelocity(g.point);
        VecD<D> vrel = vWall - a.v[i];
        VecD<D> arm;
        if constexpr (Rotation) {
          arm = g.point - a.x[i];
          vrel -= cross(a.w[i], arm);
        }
        const physics::ContactKinematics<D> k{vrel, 1.0 / a.invMass[i], a.r[i], lag};
        physics::TangentialHistory<D>* h = nullptr;
        if constexpr (History) h = &s.wallSprings[w][kc++];
        const physics::ContactForce<D> f =
            LawCall<D, Law>::call(s, a.material[i] * nMat + wall.material, g, k, h, dt);
        a.f[i] -= f.force;
        if constexpr (Rotation) a.t[i] -= cross(arm, f.force);
        wall.force += f.force;
        e.add(f);
        // Work done by the moving wall on the grain over the step.
        if (wall.moving) e.wallWork -= f.force.dot(vWall) * dt;
        s.contacts.push_back({i, static_cast<uint32_t>(w), true, f.force});
      }
      if constexpr (History) {
        while (kc < which.size()) s.wallSprings[w][kc++].spring.setZero();
      }
    }
    s.ledger.elastic += e.elastic;
    s.ledger.dampingLoss += e.damping;
    s.ledger.frictionLoss += e.friction;
    s.ledger.springWork += e.springWork;
    s.ledger.wallWork += e.wallWork;
  }

 private:
  std::vector<physics::ContactGeometry<D>> geoms_;
  std::vector<uint32_t> touched_;
};

// Returns the grain-grain and grain-wall contact modules for the scene's law set, history and
// rotation flags. law: the one law of every pair, or -1 for mixed laws.
template <int D>
std::vector<std::unique_ptr<SimModule<D>>> makeContactModules(int law, bool history, bool rotation,
                                                              bool walls);

}  // namespace demlab::sim
