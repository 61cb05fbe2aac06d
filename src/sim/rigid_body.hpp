// Rotation of elements whose inertia is not isotropic (3D shapes other than the ball, a cube
// excepted): the full body-frame inertia tensor, with the gyroscopic term.
//
// Such an element is marked by invInertia = 0 in the hot arrays, so the isotropic modules
// (integrator.hpp, the SIMD kernels) leave its angular velocity alone, and its Geometry holds
// the principal moments per unit density and the principal frame. The step is the symplectic
// splitting of the free rotor of Dullweber, Leimkuhler and McLachlan (J. Chem. Phys. 107, 5840,
// 1997) inside the integrator's torque kicks: kick the angular momentum by half a step of torque,
// turn the body as the free rotor over the step by exact rotations about its principal axes
// in the symmetric sequence 1 2 3 2 1 (half, half, whole, half, half), then kick again. Each
// sub-rotation is exact and keeps |L| and the energy of its own part, so the step is second
// order and time-reversible, conserves the angular momentum of a free body exactly (to
// rounding) and its energy to O(dt^2) with no drift; the intermediate-axis instability appears
// as it should (tests/unit/sim/sim_rigid_body_test.cpp).
//
// The angular velocity w in the arrays stays the world-frame one (what contacts read); the
// angular momentum is recomputed from it each step (L = I_world w), so no state is added.
#pragma once

#include <cmath>
#include <vector>

#include "sim/element_chunks.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// The principal frame of element i of anisotropic inertia: its orientation Q (principal frame
// to world) and its principal moments I (from its Geometry and its material's density).
struct PrincipalFrame {
  Quat Q;
  Vec3 I;
};
template <int D>
PrincipalFrame principalFrame(const Scene<D>& s, size_t i) {
  const ElementArrays<D>& a = s.elements.a;
  const Geometry<D>& g = *s.geometries[a.geometry[i]];
  if constexpr (D == 3) {
    return {a.q[i] * g.principal, s.materials[a.material[i]].density * g.principalMoments};
  } else {
    return {Quat::Identity(), s.materials[a.material[i]].density * g.principalMoments};
  }
}

// Returns twice the rotational kinetic energy of element i of anisotropic inertia: w . I w.
template <int D>
[[gnu::noinline]] Real twiceRigidRotationalEnergy(const Scene<D>& s, size_t i) {
  if constexpr (D == 3) {
    const PrincipalFrame f = principalFrame(s, i);
    const Vec3 wb = f.Q.conjugate() * s.elements.a.w[i];
    return wb.dot(f.I.cwiseProduct(wb));
  } else {
    return 0;
  }
}

// Returns twice the rotational kinetic energy of element i: w . I w (the energy passes call it
// per element: the ball's case inline).
template <int D>
[[gnu::always_inline]] inline Real twiceRotationalEnergy(const Scene<D>& s, size_t i) {
  const ElementArrays<D>& a = s.elements.a;
  if (a.invInertia[i] != 0) [[likely]] return squaredNorm(a.w[i]) / a.invInertia[i];
  return twiceRigidRotationalEnergy(s, i);
}

// Returns I_world^-1 x for element i of anisotropic inertia (invInertia 0), x in the world frame.
inline Vec3 rigidInverseInertiaTimes(const Scene<3>& s, size_t i, const Vec3& x) {
  const PrincipalFrame f = principalFrame(s, i);
  return f.Q * (f.Q.conjugate() * x).cwiseQuotient(f.I);
}

// Turns the principal frame Q and the body-frame angular momentum pi as the free rotor with
// principal moments I over time dt (the splitting above). Changes Q and pi.
inline void freeRotor(Quat& Q, Vec3& pi, const Vec3& I, Real dt) {
  const auto turn = [&](int k, Real tau) {
    const Real theta = tau * pi[k] / I[k];
    // The half angle's sine and cosine: by their series where a step turns little (|theta / 2|
    // under 0.01, the terms kept leave an error below 1e-19), else by sincos; the whole angle's
    // by the double-angle identities. Five turns a step, so no trigonometric call in the common
    // case.
    const Real x = 0.5 * theta, x2 = x * x;
    Real sh, ch;
    if (x2 < 1e-4) {
      sh = x * (1 - x2 * (Real{1} / 6) * (1 - x2 * (Real{1} / 20) * (1 - x2 * (Real{1} / 42))));
      ch = 1 - x2 * 0.5 * (1 - x2 * (Real{1} / 12) * (1 - x2 * (Real{1} / 30) * (1 - x2 * (Real{1} / 56))));
    } else {
      sh = std::sin(x), ch = std::cos(x);
    }
    const Real c = ch * ch - sh * sh, sn = 2 * sh * ch;
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    // pi turns by -theta about axis k in the body frame: L stays fixed in the world.
    const Real pu = pi[u], pv = pi[v];
    pi[u] = c * pu + sn * pv;
    pi[v] = -sn * pu + c * pv;
    Quat r(ch, 0, 0, 0);
    r.vec()[k] = sh;
    Q = Q * r;
  };
  const Real h = 0.5 * dt;
  turn(0, h);
  turn(1, h);
  turn(2, dt);
  turn(1, h);
  turn(0, h);
  Q.normalize();
}

// A rigid element with blocked rotations and its spin before an update. The constraint module
// cancels the torque along a blocked axis, but a rigid body's spin also turns by the
// gyroscopic term and through the coupled world tensor: the blocked components are put back
// after each half of the update, so they keep their velocity as for a ball.
struct HeldSpin {
  uint32_t i;
  unsigned dofs;
  Vec3 w;
};

// Returns in out the rigid elements of s with a blocked rotation, with their spins now.
inline void holdSpins(const Scene<3>& s, std::vector<HeldSpin>& out) {
  out.clear();
  for (const BlockedElement& b : s.blocked) {
    if ((b.dofs & (dof::Rx | dof::Ry | dof::Rz)) == 0) continue;
    const uint32_t i = s.elements.pool().findDense(b.id);
    if (i == HandlePool<ElementKind>::kNpos || s.elements.a.invInertia[i] != 0) continue;
    out.push_back({i, b.dofs, s.elements.a.w[i]});
  }
}

// Puts back the blocked components of the held spins. Changes s's angular velocities.
inline void restoreSpins(Scene<3>& s, const std::vector<HeldSpin>& held) {
  for (const HeldSpin& h : held) {
    for (int k = 0; k < 3; ++k) {
      if (h.dofs & (dof::Rx << k)) s.elements.a.w[h.i][k] = h.w[k];
    }
  }
}

// The predict half of the rigid elements' rotation (after PredictRotationModule, which skips
// them): kick, free rotor, and the integrator's velocity estimate.
template <int D>
class PredictRigidRotationModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "rigid-rotation"; }
  SimLevel level() const override { return SimLevel::Predict; }

  void run(Scene<D>& s) override {
    if constexpr (D == 3) {
      ElementArrays<3>& a = s.elements.a;
      const Real dt = s.stepDt, h = 0.5 * dt;
      const bool sync = s.integrator == IntegratorKind::Synchronized;
      if (!s.blocked.empty()) holdSpins(s, held_);
      // Each element on its own: the chunks run on the pool (the same bits for any threads).
      forEachElementChunk(a.size(), [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i) {
          if (a.invInertia[i] != 0) continue;
          const Quat& principal = s.geometries[a.geometry[i]]->principal;
          auto [Q, I] = principalFrame(s, i);
          // Body-frame angular momentum after the first kick.
          Vec3 pi = I.cwiseProduct(Q.conjugate() * a.w[i]) + Q.conjugate() * (h * a.t[i]);
          freeRotor(Q, pi, I, dt);
          a.q[i] = (Q * principal.conjugate()).normalized();
          if (sync) pi += Q.conjugate() * (h * a.t[i]);
          a.w[i] = Q * pi.cwiseQuotient(I);
          a.tPrev[i] = a.t[i];
          a.t[i].setZero();
        }
      });
      if (!s.blocked.empty()) restoreSpins(s, held_);
    }
  }

 private:
  std::vector<HeldSpin> held_;
};

// The correct half: the second kick with the new torque (before CorrectModule, whose kick is
// zero for these elements).
template <int D>
class CorrectRigidRotationModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "rigid-correct"; }
  SimLevel level() const override { return SimLevel::Correct; }

  void run(Scene<D>& s) override {
    if constexpr (D == 3) {
      ElementArrays<3>& a = s.elements.a;
      const Real h = 0.5 * s.stepDt;
      const bool sync = s.integrator == IntegratorKind::Synchronized;
      if (!s.blocked.empty()) holdSpins(s, held_);
      forEachElementChunk(a.size(), [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i) {
          if (a.invInertia[i] != 0) continue;
          const Vec3 kick = h * (sync ? Vec3(a.t[i] - a.tPrev[i]) : a.t[i]);
          a.w[i] += rigidInverseInertiaTimes(s, i, kick);
        }
      });
      if (!s.blocked.empty()) restoreSpins(s, held_);
    }
  }

 private:
  std::vector<HeldSpin> held_;
};

}  // namespace demlab::sim
