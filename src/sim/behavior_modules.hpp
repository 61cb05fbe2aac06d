// The modules that run behaviors and prescribed wall motion.
//  - "gravity": adds m g to every grain (g: the sum of the gravity behaviors; only its nonzero
//    component when it has one). Its work is the change of the gravitational potential, which
//    the ledger reads from the state.
//  - one module per other behavior type present, named by its registry row ("loads",
//    "torque-ramp"): each behavior of the type adds its forces and torques, evaluated at the
//    end-of-step time, and the work they do over the step goes to the ledger.
//  - "walls": places every moving wall at the end-of-step time (before detection, which must
//    see where the walls are).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/behavior_registry.hpp"
#include "sim/distribution.hpp"
#include "sim/element_chunks.hpp"
#include "sim/integrator.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

template <int D>
class GravityModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "gravity"; }
  SimLevel level() const override { return SimLevel::Behaviors; }
  bool ownedOnly() const override { return true; }
  void run(Scene<D>& s) override {
    const VecD<D> g = s.behaviors.gravity();
    ElementArrays<D>& a = s.elements.a;
    const size_t n = s.ownedCount();
    // Gravity along one axis (as usual): one division per grain, not D. Adding the other
    // components' 0 would change nothing (a force sum is never -0), so this is bit-identical.
    int axis = -1, nonzero = 0;
    for (int k = 0; k < D; ++k) {
      if (g[k] != 0) axis = k, ++nonzero;
    }
    forEachElementChunk(n, [&](size_t b, size_t e, size_t) {
      if (nonzero == 1) {
        const Real gk = g[axis];
        VecD<D>* __restrict f = a.f.data();
        const Real* __restrict invMass = a.invMass.data();
        for (size_t i = b; i < e; ++i) f[i][axis] += gk / invMass[i];
        return;
      }
      for (size_t i = b; i < e; ++i) a.f[i] += g / a.invMass[i];
    });
  }
};

// Runs every behavior whose module() is its name, in behavior order, each adding its work to
// one sum that goes to the ledger once per step (the bits the loads module always gave).
template <int D>
class BehaviorStageModule final : public SimModule<D> {
 public:
  explicit BehaviorStageModule(std::string name) : name_(std::move(name)) {}
  std::string_view name() const override { return name_; }
  SimLevel level() const override { return SimLevel::Behaviors; }
  void run(Scene<D>& s) override {
    double work = 0;
    for (const auto& b : s.behaviors.items()) {
      if (b->module() == name_) b->apply(s, work);
    }
    s.ledger.behaviorWork += work;
  }

 private:
  std::string name_;
};

// Appends the behavior stage to m: "gravity" when some behavior is a uniform field, then one
// module per registry type present (registry order; "loads", "torque-ramp", ...). Changes
// nothing else.
template <int D>
void appendBehaviorModules(const Scene<D>& s, std::vector<std::unique_ptr<SimModule<D>>>& m) {
  if (s.behaviors.hasGravity()) m.push_back(std::make_unique<GravityModule<D>>());
  for (const BehaviorRow& row : behaviorRegistry()) {
    if (row.info.module == "gravity" || !s.behaviors.hasModule(row.info.module)) continue;
    m.push_back(std::make_unique<BehaviorStageModule<D>>(row.info.module));
  }
}

template <int D>
class WallMotionModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "walls"; }
  SimLevel level() const override { return SimLevel::Walls; }
  void run(Scene<D>& s) override {
    const double t = s.time + s.stepDt;
    // A distributed scene: a servo reads the whole force on its wall, every rank's part (its
    // own elements' contacts) summed, the same bits on every rank.
    std::vector<double>& parts = servoForces_;
    parts.clear();
    if (s.dist) {
      for (const Wall<D>& w : s.walls.items) {
        for (int k = 0; k < D && w.servo; ++k) parts.push_back(w.force[k]);
      }
      if (!parts.empty()) s.dist->comm->sum(parts);
    }
    size_t at = 0;
    for (Wall<D>& w : s.walls.items) {
      if (w.servo) {
        VecD<D> whole = w.force;
        for (int k = 0; k < D && s.dist; ++k) whole[k] = parts[at++];
        w.servoStep(s.time, whole);
      }
      if (w.scripted()) w.scriptStep(s.time, s.stepDt);
      if (w.moving) w.moveTo(t);
    }
  }

 private:
  std::vector<double> servoForces_;  // the servo walls' forces of a distributed scene, reused
};

}  // namespace demlab::sim
