// Behaviors (thesis chapter 10): forces applied each step. A StandardBehavior acts on one
// grain, a GroupBehavior on every grain carrying a tag (resolved at each step, so grains
// tagged later join). Gravity is the GroupBehavior over all grains.
//
// Behavior<D> is the interface every type implements; the types themselves live one per file
// under sim/behaviors/ and are listed, one row each, in sim/behavior_registry.hpp (name,
// declared options, factory). The BehaviorManager holds them under generational handles; the
// loop runs them in the modules sim/behavior_modules.hpp builds from the types present.
// Prescribed wall motion is kinematic and lives with the walls (sim/wall.hpp).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/handle.hpp"
#include "core/math.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim {

template <int D>
struct Scene;

template <int D>
class Behavior {
 public:
  virtual ~Behavior() = default;
  // Returns the registry name ("gravity", "load", ...) and the loop module running it.
  virtual std::string_view type() const = 0;
  virtual std::string_view module() const = 0;
  // Adds this behavior's forces and torques for the step ending at s.time + s.stepDt to the
  // grains, and the work they do over the step to `work` (summed in behavior order, so the
  // ledger's bits do not depend on how the behaviors are grouped into modules).
  virtual void apply(Scene<D>& s, double& work) const = 0;
  // Returns true if it may put a torque on a grain (the loop then integrates rotation).
  virtual bool addsTorque() const { return false; }
  // Returns true if it holds TimeFunctions (script callbacks): a checkpoint cannot hold it.
  virtual bool hasCallbacks() const { return false; }
  // Returns the acceleration of a uniform field (gravity), whose work the ledger reads as a
  // potential instead of summing it; null for every other type.
  virtual const VecD<D>* uniformAcceleration() const { return nullptr; }
  // Returns one line for `behavior list`, e.g. `load on tag "bed": force (0 0 -1) N`.
  virtual std::string describe() const = 0;
  // Returns its named parameters, the ones its factory takes back (registry row options).
  virtual std::vector<BehaviorParam> params() const = 0;
  virtual std::unique_ptr<Behavior<D>> clone() const = 0;
};

template <int D>
class BehaviorManager {
 public:
  BehaviorManager() : pool_("behavior") {}
  // Copies are deep: every behavior is cloned (TimeFunctions are shared).
  BehaviorManager(const BehaviorManager& o) : pool_(o.pool_) {
    items_.reserve(o.items_.size());
    for (const auto& b : o.items_) items_.push_back(b->clone());
  }
  BehaviorManager& operator=(const BehaviorManager& o) {
    if (this != &o) *this = BehaviorManager(o);
    return *this;
  }
  BehaviorManager(BehaviorManager&&) noexcept = default;
  BehaviorManager& operator=(BehaviorManager&&) noexcept = default;

  // Returns the new behavior's handle; b must not be null.
  BehaviorId add(std::unique_ptr<Behavior<D>> b) {
    const BehaviorId id = pool_.allocate();
    items_.push_back(std::move(b));
    return id;
  }
  void remove(BehaviorId id) { applySwapRemove(items_, pool_.free(id)); }

  const HandlePool<BehaviorKind>& pool() const { return pool_; }
  HandlePool<BehaviorKind>& pool() { return pool_; }
  std::vector<std::unique_ptr<Behavior<D>>>& items() { return items_; }
  const std::vector<std::unique_ptr<Behavior<D>>>& items() const { return items_; }

  // Returns the sum of the uniform fields' accelerations (gravity).
  VecD<D> gravity() const {
    VecD<D> g = VecD<D>::Zero();
    for (const auto& b : items_) {
      if (const VecD<D>* a = b->uniformAcceleration()) g += *a;
    }
    return g;
  }
  bool hasGravity() const {
    for (const auto& b : items_) {
      if (b->uniformAcceleration()) return true;
    }
    return false;
  }
  // Returns true if some behavior runs in the loop module named m.
  bool hasModule(std::string_view m) const {
    for (const auto& b : items_) {
      if (b->module() == m) return true;
    }
    return false;
  }
  bool hasTorqueLoads() const {
    for (const auto& b : items_) {
      if (b->addsTorque()) return true;
    }
    return false;
  }
  size_t size() const { return items_.size(); }

 private:
  HandlePool<BehaviorKind> pool_;
  std::vector<std::unique_ptr<Behavior<D>>> items_;
};

}  // namespace demlab::sim
