// A torque ramp: a torque growing at a constant rate on one grain or on each grain of a tag
// group, T(t) = T0 + rate (t - start) from the start time on (none before), its magnitude
// optionally capped at max (the direction kept). 2D: about z; 3D: a vector. Like a load it is
// evaluated at the end-of-step time and its work, T . dtheta over the step, goes to the ledger.
// A linear torque is integrated exactly by the trapezoidal kick, so a free grain's spin follows
// omega(t) = (T0 t + rate t^2 / 2) / I to rounding.
#pragma once

#include <cmath>
#include <limits>

#include "sim/behavior_registry.hpp"
#include "sim/integrator.hpp"
#include "sim/scene.hpp"

namespace demlab::sim {

template <int D>
class TorqueRampBehavior final : public Behavior<D> {
 public:
  static BehaviorTypeInfo info() {
    return {"torque-ramp",
            "a torque growing at a constant rate on one element or on every element of a tag",
            "torque-ramp",
            {{"element", BehaviorParamKind::Element, "", "the element"},
             {"tag", BehaviorParamKind::Tag, "", "every element carrying this tag"},
             {"torque", BehaviorParamKind::Angular, "N m", "the torque at the start (default 0)"},
             {"rate", BehaviorParamKind::Angular, "N m/s", "its rate of change", true},
             {"start", BehaviorParamKind::Number, "s", "when it starts (default 0)"},
             {"max", BehaviorParamKind::Number, "N m", "the largest magnitude (default: none)"}},
            true};
  }
  // Returns a ramp from {element | tag, torque, rate, start, max}. Throws VALUE START (not
  // finite), VALUE MAX (not positive).
  static std::unique_ptr<Behavior<D>> make(const std::vector<BehaviorParam>& p) {
    auto b = std::make_unique<TorqueRampBehavior>();
    if (const BehaviorParam* e = findParam(p, "element")) b->grain_ = e->grain;
    if (const BehaviorParam* t = findParam(p, "tag")) b->tag_ = t->text;
    const Vec3d torque = paramVec(p, "torque"), rate = paramVec(p, "rate");
    checkLoadRange(torque, "torque", D, true);
    checkLoadRange(rate, "rate", D, true);
    b->t0_ = toAngular<D>(torque, "torque");
    b->rate_ = toAngular<D>(rate, "rate");
    b->start_ = paramNumber(p, "start", 0);
    if (!validity::inRange(b->start_, -validity::kMaxTime, validity::kMaxTime))
      throwBad("start", physics::formatReal(b->start_),
               "must be a time within 1e15 s of zero");
    if (findParam(p, "max")) {
      b->max_ = paramNumber(p, "max", 0);
      checkPositive(b->max_, "max");
    }

    return b;
  }

  // Returns the torque at time t.
  AngularD<D> torqueAt(double t) const {
    if (t < start_) {
      if constexpr (D == 2) {
        return 0.0;
      } else {
        return Vec3::Zero();
      }
    }
    // Within the bounds on torque, rate (1e30) and start (1e15 s) T stays finite (|T| < 1e46
    // for any t the scene reaches), and no ramp passes the loads' bound, max or not.
    AngularD<D> T = t0_ + rate_ * (t - start_);
    const Real cap = std::min(max_, validity::kMaxCoefficient);
    const Real n2 = squaredNorm(T);
    if (n2 > cap * cap) T = T * (cap / std::sqrt(n2));
    return T;
  }

  std::string_view type() const override { return "torque-ramp"; }
  std::string_view module() const override { return "torque-ramp"; }
  void apply(Scene<D>& s, double& work) const override {
    const AngularD<D> T = torqueAt(s.time + s.stepDt);
    if (!s.rotating || squaredNorm(T) == 0) return;
    ElementArrays<D>& a = s.elements.a;
    auto one = [&](uint32_t i) {
      a.t[i] += T;
      work += dotAngular(T, halfStepAngularVelocity(s, i)) * s.stepDt;
    };
    forEachTarget(s, grain_, tag_, one);
  }
  bool addsTorque() const override { return squaredNorm(t0_) != 0 || squaredNorm(rate_) != 0; }
  std::string describe() const override {
    std::string s = "torque ramp on " + targetText(grain_, tag_) + ": (" +
                    formatVec(fromAngular(t0_), 3) + ") N m + (" +
                    formatVec(fromAngular(rate_), 3) +
                    ") N m/s from t = " + physics::formatReal(start_) + " s";
    if (std::isfinite(max_)) s += ", at most " + physics::formatReal(max_) + " N m";
    return s;
  }
  std::vector<BehaviorParam> params() const override {
    std::vector<BehaviorParam> p{targetParam(grain_, tag_), vecParam("torque", fromAngular(t0_)),
                                 vecParam("rate", fromAngular(rate_)),
                                 numberParam("start", start_)};
    if (std::isfinite(max_)) p.push_back(numberParam("max", max_));
    return p;
  }
  std::unique_ptr<Behavior<D>> clone() const override {
    return std::make_unique<TorqueRampBehavior>(*this);
  }

 private:
  ElementId grain_;
  std::string tag_;
  AngularD<D> t0_{}, rate_{};
  double start_ = 0;
  double max_ = std::numeric_limits<double>::infinity();
};

}  // namespace demlab::sim
