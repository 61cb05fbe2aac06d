// The "constraints" module: blocked degrees of freedom (fixed elements, elements that may only
// slide along an axis or only turn). It runs after every force of the step (contacts,
// behaviors) and cancels the force and torque components along the blocked degrees of
// freedom (the touch correction, which kicks velocities, holds its own kicks to the free ones:
// TouchModule::holdBlocked), so both halves of the velocity-Verlet kick leave those velocity
// components as they are: a fixed element at rest stays where it is, one given a velocity moves
// at it, as a kinematic body. What it cancels is the constraint's reaction; its work, reaction
// times velocity, goes to the ledger's behaviour work, so the energy balance still closes for
// a blocked element that moves.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Calls fn(dense index, dof:: mask) for each blocked element of s this rank holds, in the
// order they were blocked. Changes nothing but a distributed scene's copy of the answer.
template <int D, class F>
void forEachBlocked(const Scene<D>& s, F&& fn) {
  if (s.ownedBlocked != nullptr) {
    for (const OwnedBlockedElement& b : s.ownedBlocked(s)) fn(b.i, b.dofs);
    return;
  }
  for (const BlockedElement& b : s.blocked) {
    const uint32_t i = s.elements.pool().findDense(b.id);
    if (i != HandlePool<ElementKind>::kNpos) fn(i, b.dofs);
  }
}

// The blocked elements a rank holds, by dense index, for holding velocity kicks along their
// blocked directions: the touch correction's own (TouchModule::holdBlocked) and, in a
// distributed scene, those other ranks send back for their ghosts (GhostForceModule).
class BlockedKickHold {
 public:
  // Takes the blocked elements of s (forEachBlocked). Changes this.
  template <int D>
  void collect(const Scene<D>& s) {
    dofs_.clear();
    forEachBlocked(s, [&](uint32_t i, uint8_t dofs) { dofs_.emplace_back(i, dofs); });
    std::sort(dofs_.begin(), dofs_.end());
  }
  // Removes from dv, a kick to element i, its components along i's blocked degrees of freedom
  // (ConstraintModule cancels the forces there, which kicks bypass), booking the constraint's
  // reaction impulse times the velocity in work, as that module books its forces'.
  template <int D>
  void hold(const ElementArrays<D>& a, uint32_t i, VecD<D>& dv, double& work) const {
    const auto it = std::lower_bound(dofs_.begin(), dofs_.end(), std::pair<uint32_t, uint8_t>{i, 0});
    if (it == dofs_.end() || it->first != i) return;
    for (int k = 0; k < D; ++k) {
      if (!(it->second & (dof::X << k))) continue;
      if (a.invMass[i] > 0) work -= dv[k] / a.invMass[i] * a.v[i][k];
      dv[k] = 0;
    }
  }

 private:
  std::vector<std::pair<uint32_t, uint8_t>> dofs_;  // dense index, dof mask (sorted)
};

template <int D>
class ConstraintModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "constraints"; }
  SimLevel level() const override { return SimLevel::Behaviors; }

  void run(Scene<D>& s) override {
    ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt;
    double work = 0;
    forEachBlocked(s, [&](uint32_t i, uint8_t dofs) {
      for (int k = 0; k < D; ++k) {
        if (dofs & (dof::X << k)) {
          work -= a.f[i][k] * a.v[i][k] * dt;
          a.f[i][k] = 0;
        }
      }
      if (!s.rotating) return;
      if constexpr (D == 2) {
        if (dofs & dof::Rz) {
          work -= a.t[i] * a.w[i] * dt;
          a.t[i] = 0;
        }
      } else {
        for (int k = 0; k < 3; ++k) {
          if (dofs & (dof::Rx << k)) {
            work -= a.t[i][k] * a.w[i][k] * dt;
            a.t[i][k] = 0;
          }
        }
      }
    });
    s.ledger.behaviorWork += work;
  }
};

}  // namespace demlab::sim
