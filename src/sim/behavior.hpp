// Behaviors (thesis chapter 10): forces applied each step. A StandardBehavior acts on one
// grain, a GroupBehavior on every grain carrying a tag (resolved at each step, so grains
// tagged later join). Gravity is the GroupBehavior over all grains. The BehaviorManager holds
// them under generational handles and is run by the "behaviors" module; prescribed wall
// motion is kinematic and lives with the walls (sim/wall.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/handle.hpp"
#include "core/math.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim {

enum class BehaviorType : uint8_t { Gravity, Load };

template <int D>
struct Behavior {
  BehaviorType type = BehaviorType::Gravity;
  VecD<D> g = VecD<D>::Zero();  // gravity
  GrainId grain;                // StandardBehavior target (null: group)
  std::string tag;              // GroupBehavior target
  Vec3d force{}, torque{};      // constants (2D: force x y, torque z)
  std::array<TimeFunction, 3> forceFn{}, torqueFn{};

  // Returns true if some component is a TimeFunction (not serializable).
  bool hasCallbacks() const {
    for (const auto& f : forceFn) {
      if (f) return true;
    }
    for (const auto& f : torqueFn) {
      if (f) return true;
    }
    return false;
  }
  bool hasTorque() const {
    for (int k = 0; k < 3; ++k) {
      if (torque[k] != 0 || torqueFn[k]) return true;
    }
    return false;
  }
};

template <int D>
class BehaviorManager {
 public:
  BehaviorManager() : pool_("behavior") {}

  BehaviorId add(Behavior<D> b) {
    const BehaviorId id = pool_.allocate();
    items_.push_back(std::move(b));
    return id;
  }
  void remove(BehaviorId id) { applySwapRemove(items_, pool_.free(id)); }

  const HandlePool<BehaviorKind>& pool() const { return pool_; }
  HandlePool<BehaviorKind>& pool() { return pool_; }
  std::vector<Behavior<D>>& items() { return items_; }
  const std::vector<Behavior<D>>& items() const { return items_; }

  // Returns the sum of the gravity behaviors' accelerations.
  VecD<D> gravity() const {
    VecD<D> g = VecD<D>::Zero();
    for (const auto& b : items_) {
      if (b.type == BehaviorType::Gravity) g += b.g;
    }
    return g;
  }
  bool hasGravity() const {
    for (const auto& b : items_) {
      if (b.type == BehaviorType::Gravity) return true;
    }
    return false;
  }
  bool hasLoads() const {
    for (const auto& b : items_) {
      if (b.type == BehaviorType::Load) return true;
    }
    return false;
  }
  bool hasTorqueLoads() const {
    for (const auto& b : items_) {
      if (b.type == BehaviorType::Load && b.hasTorque()) return true;
    }
    return false;
  }
  size_t size() const { return items_.size(); }

 private:
  HandlePool<BehaviorKind> pool_;
  std::vector<Behavior<D>> items_;
};

}  // namespace demlab::sim
