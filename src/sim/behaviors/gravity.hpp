// Gravity: a uniform acceleration g on every grain (the GroupBehavior over all grains). The
// "gravity" module applies the sum of the gravity behaviors at once, along one axis when it
// can (sim/behavior_modules.hpp); its work is the change of the gravitational potential, which
// the ledger reads from the state rather than summing it.
#pragma once

#include "sim/behavior_registry.hpp"
#include "sim/scene.hpp"

namespace demlab::sim {

template <int D>
class GravityBehavior final : public Behavior<D> {
 public:
  explicit GravityBehavior(const VecD<D>& g) : g_(g) {}

  static BehaviorTypeInfo info() {
    return {"gravity",
            "uniform gravity on every element",
            "gravity",
            {{"g", BehaviorParamKind::Vector, "m/s^2", "the acceleration", true}},
            false};
  }
  // Returns gravity from {g}; throws VALUE GRAVITY as addGravity.
  static std::unique_ptr<Behavior<D>> make(const std::vector<BehaviorParam>& p) {
    return std::make_unique<GravityBehavior>(toVec<D>(paramVec(p, "g"), "gravity"));
  }

  const VecD<D>& g() const { return g_; }
  std::string_view type() const override { return "gravity"; }
  std::string_view module() const override { return "gravity"; }
  // Adds m g to every grain; no work (the potential accounts for it). The loop does not call
  // this: its gravity module sums the fields first.
  void apply(Scene<D>& s, double&) const override {
    ElementArrays<D>& a = s.elements.a;
    for (size_t i = 0; i < a.size(); ++i) a.f[i] += g_ / a.invMass[i];
  }
  const VecD<D>* uniformAcceleration() const override { return &g_; }
  std::string describe() const override {
    return "gravity (" + formatVec(fromVec<D>(g_), D) + ") m/s^2";
  }
  std::vector<BehaviorParam> params() const override { return {vecParam("g", fromVec<D>(g_))}; }
  std::unique_ptr<Behavior<D>> clone() const override {
    return std::make_unique<GravityBehavior>(*this);
  }

 private:
  VecD<D> g_;
};

}  // namespace demlab::sim
