// The modules that run behaviors and prescribed wall motion.
//  - "gravity": adds m g to every grain (g: the sum of the gravity behaviors; only its nonzero
//    component when it has one). Its work is the change of the gravitational potential, which
//    the ledger reads from the state.
//  - "loads": each load behavior adds its force and torque, evaluated at the end-of-step time,
//    to its grain or to each grain of its tag group; the work it does over the step, F . dx
//    with dx the step's displacement, goes to the ledger.
//  - "walls": places every moving wall at the end-of-step time (before detection, which must
//    see where the walls are).
#pragma once

#include "sim/integrator.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

template <int D>
class GravityModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "gravity"; }
  SimLevel level() const override { return SimLevel::Behaviors; }
  void run(Scene<D>& s) override {
    const VecD<D> g = s.behaviors.gravity();
    GrainArrays<D>& a = s.grains.a;
    const size_t n = a.size();
    // Gravity along one axis (as usual): one division per grain, not D. Adding the other
    // components' 0 would change nothing (a force sum is never -0), so this is bit-identical.
    int axis = -1, nonzero = 0;
    for (int k = 0; k < D; ++k) {
      if (g[k] != 0) axis = k, ++nonzero;
    }
    if (nonzero == 1) {
      const Real gk = g[axis];
      VecD<D>* __restrict f = a.f.data();
      const Real* __restrict invMass = a.invMass.data();
      for (size_t i = 0; i < n; ++i) f[i][axis] += gk / invMass[i];
      return;
    }
    for (size_t i = 0; i < n; ++i) a.f[i] += g / a.invMass[i];
  }
};

template <int D>
class LoadModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "loads"; }
  SimLevel level() const override { return SimLevel::Behaviors; }
  void run(Scene<D>& s) override {
    const double t = s.time + s.stepDt;
    GrainArrays<D>& a = s.grains.a;
    double work = 0;
    for (const Behavior<D>& b : s.behaviors.items()) {
      if (b.type != BehaviorType::Load) continue;
      VecD<D> F;
      for (int k = 0; k < D; ++k) F[k] = b.forceFn[k] ? b.forceFn[k](t) : b.force[k];
      AngularD<D> T;
      if constexpr (D == 2) {
        T = b.torqueFn[2] ? b.torqueFn[2](t) : b.torque[2];
      } else {
        for (int k = 0; k < 3; ++k) T[k] = b.torqueFn[k] ? b.torqueFn[k](t) : b.torque[k];
      }
      const bool torque = s.rotating && squaredNorm(T) != 0;
      auto apply = [&](uint32_t i) {
        a.f[i] += F;
        work += F.dot(halfStepVelocity(s, i)) * s.stepDt;
        if (torque) {
          a.t[i] += T;
          work += dotAngular(T, halfStepAngularVelocity(s, i)) * s.stepDt;
        }
      };
      if (!b.grain.isNull()) {
        const uint32_t i = s.grains.pool().findDense(b.grain);
        if (i != HandlePool<GrainKind>::kNpos) apply(i);
      } else {
        s.grains.tags().forEach(b.tag, [&](GrainId id) { apply(s.grains.pool().denseIndex(id)); });
      }
    }
    s.ledger.behaviorWork += work;
  }
};

template <int D>
class WallMotionModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "walls"; }
  SimLevel level() const override { return SimLevel::Walls; }
  void run(Scene<D>& s) override {
    const double t = s.time + s.stepDt;
    for (Wall<D>& w : s.walls.items) {
      if (w.moving) w.moveTo(t);
    }
  }
};

}  // namespace demlab::sim
