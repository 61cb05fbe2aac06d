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

// Free rotors turned side by side. One body's five turns are a chain of dependent operations
// (a division, two short series, the products), so a batch of bodies is turned lane by lane,
// each operation for every body in a row: their chains overlap, and the compiler puts two
// lanes in a register. Lanes past a batch's bodies hold a still body.
template <int N>
struct RotorBatch {
  Real q[4][N];   // principal frames (Q: principal frame to world), w x y z
  Real pi[3][N];  // body-frame angular momenta
  Real I[3][N];   // principal moments
};

// One exact turn of the splitting for every lane: pi turns by -theta about body axis K (L stays
// fixed in the world), theta = tau pi_K / I_K, and Q by theta about it. Changes b.q and b.pi.
template <int K, int N>
[[gnu::always_inline]] inline void rotorTurn(RotorBatch<N>& b, Real tau) {
  constexpr int U = (K + 1) % 3, V = (K + 2) % 3;
  Real sh[N], ch[N];
  for (int l = 0; l < N; ++l) {
    // The half angle's sine and cosine by their series (|theta / 2| under 0.01: the terms kept
    // leave an error below 1e-19), else (below) by sin and cos; the whole angle's by the
    // double-angle identities. Five turns a step, so no trigonometric call in the common case.
    const Real x = 0.5 * (tau * b.pi[K][l] / b.I[K][l]), x2 = x * x;
    sh[l] = x * (1 - x2 * (Real{1} / 6) * (1 - x2 * (Real{1} / 20) * (1 - x2 * (Real{1} / 42))));
    ch[l] = 1 - x2 * 0.5 * (1 - x2 * (Real{1} / 12) * (1 - x2 * (Real{1} / 30) * (1 - x2 * (Real{1} / 56))));
  }
  for (int l = 0; l < N; ++l) {
    const Real x = 0.5 * (tau * b.pi[K][l] / b.I[K][l]);
    if (!(x * x < 1e-4)) [[unlikely]] sh[l] = std::sin(x), ch[l] = std::cos(x);
  }
  for (int l = 0; l < N; ++l) {
    const Real c = ch[l] * ch[l] - sh[l] * sh[l], sn = 2 * sh[l] * ch[l];
    const Real pu = b.pi[U][l], pv = b.pi[V][l];
    b.pi[U][l] = c * pu + sn * pv;
    b.pi[V][l] = -sn * pu + c * pv;
    // Q = Q (ch, sh e_K), written out: the product's terms with the zero components dropped.
    const Real qw = b.q[0][l], qk = b.q[1 + K][l], qu = b.q[1 + U][l], qv = b.q[1 + V][l];
    b.q[0][l] = ch[l] * qw - sh[l] * qk;
    b.q[1 + K][l] = ch[l] * qk + sh[l] * qw;
    b.q[1 + U][l] = ch[l] * qu + sh[l] * qv;
    b.q[1 + V][l] = ch[l] * qv - sh[l] * qu;
  }
}

// Turns every lane of b as the free rotor over time dt (the splitting above) and normalises
// its frame. Changes b.q and b.pi.
template <int N>
inline void freeRotors(RotorBatch<N>& b, Real dt) {
  const Real h = 0.5 * dt;
  rotorTurn<0>(b, h);
  rotorTurn<1>(b, h);
  rotorTurn<2>(b, dt);
  rotorTurn<1>(b, h);
  rotorTurn<0>(b, h);
  for (int l = 0; l < N; ++l) {
    const Real n = std::sqrt(b.q[0][l] * b.q[0][l] + b.q[1][l] * b.q[1][l] +
                             b.q[2][l] * b.q[2][l] + b.q[3][l] * b.q[3][l]);
    for (int c = 0; c < 4; ++c) b.q[c][l] /= n;
  }
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
        constexpr int N = 8;
        RotorBatch<N> b;
        uint32_t which[N];
        int n = 0;
        // The rigid elements of the chunk, N at a time: in, turned, out.
        const auto turn = [&] {
          for (int l = n; l < N; ++l) {  // still bodies in the lanes left
            b.q[0][l] = 1, b.q[1][l] = b.q[2][l] = b.q[3][l] = 0;
            for (int c = 0; c < 3; ++c) b.pi[c][l] = 0, b.I[c][l] = 1;
          }
          freeRotors(b, dt);
          for (int l = 0; l < n; ++l) {
            const uint32_t i = which[l];
            const Quat Q(b.q[0][l], b.q[1][l], b.q[2][l], b.q[3][l]);
            const Vec3 I(b.I[0][l], b.I[1][l], b.I[2][l]);
            Vec3 pi(b.pi[0][l], b.pi[1][l], b.pi[2][l]);
            a.q[i] = (Q * s.geometries[a.geometry[i]]->principal.conjugate()).normalized();
            const Mat3 after = Q.toRotationMatrix();
            if (sync) pi += after.transpose() * (h * a.t[i]);
            a.w[i] = after * pi.cwiseQuotient(I);
            a.tPrev[i] = a.t[i];
            a.t[i].setZero();
          }
          n = 0;
        };
        for (size_t i = begin; i < end; ++i) {
          if (a.invInertia[i] != 0) continue;
          const auto [Q, I] = principalFrame(s, i);
          // Body-frame angular momentum after the first kick (Q's matrix: fewer operations
          // than two quaternion rotations).
          const Mat3 before = Q.toRotationMatrix().transpose();
          const Vec3 pi = I.cwiseProduct(before * a.w[i]) + before * (h * a.t[i]);
          b.q[0][n] = Q.w();
          for (int c = 0; c < 3; ++c) b.q[1 + c][n] = Q.vec()[c], b.pi[c][n] = pi[c], b.I[c][n] = I[c];
          which[n++] = static_cast<uint32_t>(i);
          if (n == N) turn();
        }
        if (n > 0) turn();
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
