// A load: a force and torque on one grain or on each grain of a tag group, every component a
// constant or a TimeFunction (a script callback, which a checkpoint cannot hold), evaluated at
// the end-of-step time. The work it does over the step, F . dx with dx the step's
// displacement (and T . dtheta), goes to the ledger.
#pragma once

#include <array>

#include "sim/behavior_registry.hpp"
#include "sim/integrator.hpp"
#include "sim/scene.hpp"

namespace demlab::sim {

template <int D>
class LoadBehavior final : public Behavior<D> {
 public:
  ElementId grain;  // null: tag
  std::string tag;
  Vec3d force{}, torque{};  // constants (2D: force x y, torque z)
  std::array<TimeFunction, 3> forceFn{}, torqueFn{};

  static BehaviorTypeInfo info() {
    return {"load",
            "a force and torque on one element or on every element of a tag",
            "loads",
            {{"element", BehaviorParamKind::Element, "", "the element"},
             {"tag", BehaviorParamKind::Tag, "", "every element carrying this tag"},
             {"force", BehaviorParamKind::Vector, "N", "force on each element"},
             {"torque", BehaviorParamKind::Angular, "N m", "torque on each element"}},
            true};
  }
  // Returns a constant load from {element | tag, force, torque}.
  static std::unique_ptr<Behavior<D>> make(const std::vector<BehaviorParam>& p) {
    auto b = std::make_unique<LoadBehavior>();
    if (const BehaviorParam* e = findParam(p, "element")) b->grain = e->grain;
    if (const BehaviorParam* t = findParam(p, "tag")) b->tag = t->text;
    b->force = paramVec(p, "force");
    b->torque = paramVec(p, "torque");
    return b;
  }

  std::string_view type() const override { return "load"; }
  std::string_view module() const override { return "loads"; }
  void apply(Scene<D>& s, double& work) const override {
    const double t = s.time + s.stepDt;
    ElementArrays<D>& a = s.elements.a;
    VecD<D> F;
    for (int k = 0; k < D; ++k) F[k] = forceFn[k] ? forceFn[k](t) : force[k];
    AngularD<D> T;
    if constexpr (D == 2) {
      T = torqueFn[2] ? torqueFn[2](t) : torque[2];
    } else {
      for (int k = 0; k < 3; ++k) T[k] = torqueFn[k] ? torqueFn[k](t) : torque[k];
    }
    const bool withTorque = s.rotating && squaredNorm(T) != 0;
    auto one = [&](uint32_t i) {
      a.f[i] += F;
      work += F.dot(halfStepVelocity(s, i)) * s.stepDt;
      if (withTorque) {
        a.t[i] += T;
        work += dotAngular(T, halfStepAngularVelocity(s, i)) * s.stepDt;
      }
    };
    forEachTarget(s, grain, tag, one);
  }
  bool addsTorque() const override {
    for (int k = 0; k < 3; ++k) {
      if (torque[k] != 0 || torqueFn[k]) return true;
    }
    return false;
  }
  bool hasCallbacks() const override {
    for (int k = 0; k < 3; ++k) {
      if (forceFn[k] || torqueFn[k]) return true;
    }
    return false;
  }
  std::string describe() const override {
    std::string s = "load on " + targetText(grain, tag);
    s += ": force (" + formatVec(force, D) + ") N";
    if (addsTorque()) s += ", torque (" + formatVec(torque, 3) + ") N m";
    if (hasCallbacks()) s += ", time-varying (script callback)";
    return s;
  }
  std::vector<BehaviorParam> params() const override {
    return {targetParam(grain, tag), vecParam("force", force), vecParam("torque", torque)};
  }
  std::unique_ptr<Behavior<D>> clone() const override {
    return std::make_unique<LoadBehavior>(*this);
  }
};

}  // namespace demlab::sim
