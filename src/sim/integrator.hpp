// The integrator modules: explicit, second order velocity Verlet, split around the force
// computation (Predict before it, Correct after it), with its rotational counterpart.
//
// Two variants (Scene::integrator):
// - Verlet: plain velocity Verlet as in LAMMPS and LIGGGHTS. The contact forces at t+dt are
//   evaluated with the half-step velocities v(t+dt/2), while positions are at t+dt.
// - Synchronized (default): after the drift the velocities are advanced to the Euler estimate
//   of v(t+dt) (v(t+dt/2) + a(t) dt/2), so the contact laws see velocities at the same time as
//   the positions (damping, the tangential spring increment and the Coulomb test), and the
//   second kick adds (a(t+dt) - a(t)) dt/2, so v(t+dt) is the same Verlet combination. This is
//   the remedy of Vyas, Ottino, Lueptow and Umbanhowar (Comput. Phys. Commun. 310 (2025)
//   109524): with half-step velocities a small grain pressed by a large one sees a tangential
//   velocity lagging by F dt / (2 m_small), which at size ratios above ~3 is large enough to
//   break static friction; synchronized velocities keep the contact stuck. Positions are
//   identical in both variants for velocity-independent forces, so energy conservation and
//   the dt^2 convergence of elastic scenes are unchanged.
//
// Rotation: grains are discs and spheres (isotropic inertia), so Euler's equations reduce to
// I dw/dt = T with no gyroscopic term; orientations advance by the exact exponential map of the
// half-step angular velocity (core/math.hpp integrate()).
//
// The Predict module also measures the largest squared displacement since the last neighbor
// search (Verlet skin bookkeeping), fused with the drift so the positions are read once.
#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <type_traits>

#include "sim/contact_kernel.hpp"
#include "sim/element_chunks.hpp"
#include "sim/rigid_body.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

template <int D>
class PredictModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "integrate"; }
  SimLevel level() const override { return SimLevel::Predict; }

  void run(Scene<D>& s) override {
    const size_t n = s.ownedCount();
    // Each chunk's largest displacement; their largest is the same for any chunking.
    chunkMax_.assign(elementChunks(n), 0);
    forEachElementChunk(n, [&](size_t b, size_t e, size_t c) { chunkMax_[c] = range(s, b, e); });
    Real maxD2 = s.maxDisp2;
    for (Real m : chunkMax_) maxD2 = std::max(maxD2, m);
    s.maxDisp2 = maxD2;
    // The contact passes of this step rebuild the per-step outputs.
    if (!s.contacts.empty()) s.lastRecorded = s.contacts.size();
    s.contacts.clear();
    s.deepest = {};
    s.ledger.elastic = 0;
  }

 private:
  std::vector<Real> chunkMax_;

  // Runs the drift of elements b .. e - 1; returns their largest squared displacement since
  // the last search (0 when not tracked). Changes their x, v, f, fPrev.
  Real range(Scene<D>& s, size_t b, size_t e) {
    ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt, h = 0.5 * dt;
    const bool sync = s.integrator == IntegratorKind::Synchronized;
    const size_t n = e - b;
    Real maxD2 = 0;
    const bool track = a.x.size() == s.xAtBuild.size();
    // Grains with wide margins (detection.hpp): their displacements weighted.
    const bool weighted = track && s.marginWeight.size() == a.x.size();
    const Real* __restrict weight = weighted ? s.marginWeight.data() + b : nullptr;
    // The arrays through restrict pointers: the loop then keeps them in registers instead of
    // reloading each from the scene after every store.
    VecD<D>* __restrict x = a.x.data() + b;
    VecD<D>* __restrict v = a.v.data() + b;
    VecD<D>* __restrict f = a.f.data() + b;
    VecD<D>* __restrict fPrev = a.fPrev.data() + b;
    const Real* __restrict invMass = a.invMass.data() + b;
    const VecD<D>* __restrict x0 = track ? s.xAtBuild.data() + b : nullptr;
    // 3D: the grains go W at a time through the SIMD kernel when the platform has one
    // (contact_kernel.hpp: the same arithmetic, bit for bit), the last n % W here.
    size_t first = 0;
    if constexpr (D == 3) {
      kernel::Isa isa;
      const kernel::PredictPassFn fn = kernel::activeIsa(&isa) ? kernel::predictPass(isa) : nullptr;
      if (fn != nullptr) {
        kernel::PredictArgs k;
        k.x = reinterpret_cast<double*>(x);
        k.v = reinterpret_cast<double*>(v);
        k.f = reinterpret_cast<double*>(f);
        k.fPrev = reinterpret_cast<double*>(fPrev);
        k.invMass = invMass;
        k.x0 = track ? reinterpret_cast<const double*>(x0) : nullptr;
        k.weight = weight;
        k.n = n;
        k.dt = dt;
        k.sync = sync;
        k.maxDisp2 = maxD2;
        fn(k);
        maxD2 = k.maxDisp2;
        first = k.done;
      }
    }
    auto pass = [&](auto syncTag, auto trackTag) {
      for (size_t i = first; i < n; ++i) {
        const VecD<D> acc = f[i] * invMass[i];
        const VecD<D> vHalf = v[i] + h * acc;
        x[i] += dt * vHalf;
        if constexpr (decltype(syncTag)::value) {
          v[i] = vHalf + h * acc;
        } else {
          v[i] = vHalf;
        }
        fPrev[i] = f[i];
        f[i].setZero();
        if constexpr (decltype(trackTag)::value) {
          const Real d2 = (x[i] - x0[i]).squaredNorm();
          maxD2 = std::max(maxD2, weight ? d2 * weight[i] : d2);
        }
      }
    };
    using Yes = std::true_type;
    using No = std::false_type;
    if (sync) {
      track ? pass(Yes{}, Yes{}) : pass(Yes{}, No{});
    } else {
      track ? pass(No{}, Yes{}) : pass(No{}, No{});
    }
    return maxD2;
  }
};

// Returns q advanced by the exact exponential map of w dt (core/math.hpp integrate()), with
// the series taken further than core's: for |w dt|^2 < 1e-4 the terms up to t^6 leave an error
// below 1e-17, so the common case of a DEM step needs no sin, cos or sqrt.
inline Quat advance(const Quat& q, const Vec3& w, Real dt) {
  const Vec3 phi = w * dt;
  const Real t2 = phi.squaredNorm();
  if (t2 >= 1e-4) return integrate(q, w, dt);
  // The series' coefficients as reciprocals, multiplied: a division by 48 would cost more than
  // the rest of the update (they change the terms by an ulp, far below the result's ulp).
  constexpr Real k24 = 1.0 / 24, k48 = 1.0 / 48, k80 = 1.0 / 80, k120 = 1.0 / 120;
  constexpr Real k168 = 1.0 / 168;
  const Real c = 1 - t2 * 0.125 * (1 - t2 * k48 * (1 - t2 * k120));
  const Real s = 0.5 * (1 - t2 * k24 * (1 - t2 * k80 * (1 - t2 * k168)));
  Quat r = Quat(c, s * phi.x(), s * phi.y(), s * phi.z()) * q;
  // Renormalise by one Newton step for 1/sqrt: |r| differs from 1 by rounding only.
  const Real n2 = r.squaredNorm();
  r.coeffs() *= 1.5 - 0.5 * n2;
  return r;
}
inline Rotation2 advance(const Rotation2& q, Real w, Real dt) {
  return integrate(q, w, dt);
}

// Returns true if the angular velocity w is exactly zero.
inline bool isZeroAngular(Real w) {
  return w == 0;
}
inline bool isZeroAngular(const Vec3& w) {
  return w.x() == 0 && w.y() == 0 && w.z() == 0;
}

// Returns true if every component of the angular quantity w is +0 (bit for bit: -0 is not).
inline bool isZeroBits(Real w) {
  return std::bit_cast<uint64_t>(w) == 0;
}
inline bool isZeroBits(const Vec3& w) {
  return (std::bit_cast<uint64_t>(w.x()) | std::bit_cast<uint64_t>(w.y()) |
          std::bit_cast<uint64_t>(w.z())) == 0;
}

template <int D>
class PredictRotationModule final : public SimModule<D> {
 public:
  // skipRigid: the scene has elements of anisotropic inertia (invInertia 0), which
  // sim/rigid_body.hpp turns; this module then leaves them, and the SIMD kernel, which would
  // not, is not used.
  explicit PredictRotationModule(bool skipRigid = false) : skipRigid_(skipRigid) {}
  std::string_view name() const override { return "rotation"; }
  SimLevel level() const override { return SimLevel::Predict; }

  void run(Scene<D>& s) override {
    forEachElementChunk(s.ownedCount(), [&](size_t b, size_t e, size_t) { range(s, b, e); });
  }

 private:
  // Turns elements b .. e - 1. Changes their q, w, t, tPrev.
  void range(Scene<D>& s, size_t b, size_t e) {
    ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt, h = 0.5 * dt;
    const bool sync = s.integrator == IntegratorKind::Synchronized;
    const size_t n = e - b;
    RotationD<D>* __restrict q = a.q.data() + b;
    AngularD<D>* __restrict w = a.w.data() + b;
    AngularD<D>* __restrict t = a.t.data() + b;
    AngularD<D>* __restrict tPrev = a.tPrev.data() + b;
    const Real* __restrict invInertia = a.invInertia.data() + b;
    // 3D: the grains go W at a time through the SIMD kernel when the platform has one
    // (contact_kernel.hpp: the same arithmetic, bit for bit), the last n % W here.
    size_t first = 0;
    if constexpr (D == 3) first = skipRigid_ ? 0 : kernelPass(s, b, e);
    auto pass = [&](auto syncTag) {
      for (size_t i = first; i < n; ++i) {
        if (skipRigid_ && invInertia[i] == 0) continue;
        // An idle grain (no torque, no spin, both +0 bit for bit, as every grain of a falling
        // lattice) stays as it is: only its last torque becomes +0. The same bits as the update.
        if (isZeroBits(t[i]) && isZeroBits(w[i])) {
          if (!isZeroBits(tPrev[i])) tPrev[i] = ElementArrays<D>::zeroAngular();
          continue;
        }
        const AngularD<D> alpha = t[i] * invInertia[i];
        const AngularD<D> wHalf = w[i] + h * alpha;
        // A grain that does not turn keeps its orientation bit for bit (advance() would
        // renormalise it by rounding): grains falling freely or resting without friction skip
        // the quaternion work, as LIGGGHTS's nve/sphere, which keeps no orientation at all.
        if (!isZeroAngular(wHalf)) q[i] = advance(q[i], wHalf, dt);
        if constexpr (decltype(syncTag)::value) {
          w[i] = wHalf + h * alpha;
        } else {
          w[i] = wHalf;
        }
        tPrev[i] = t[i];
        t[i] = ElementArrays<D>::zeroAngular();
      }
    };
    sync ? pass(std::true_type{}) : pass(std::false_type{});
  }

  bool skipRigid_;
  struct Turn {
    RotationD<D>* q;
    Real dt;
  };
  // kernel::RotationArgs::turn: the exact map for a grain that turns far in the step.
  static void turn(void* context, size_t i, const double* wHalf) {
    const Turn& c = *static_cast<const Turn*>(context);
    c.q[i] = advance(c.q[i], Vec3(wHalf[0], wHalf[1], wHalf[2]), c.dt);
  }

  // Returns how many grains (from 0) the kernel updated: 0 when no kernel is active.
  size_t kernelPass(Scene<D>& s, size_t b, size_t e) {
    kernel::Isa isa;
    if (!kernel::activeIsa(&isa)) return 0;
    const kernel::RotationPassFn fn = kernel::rotationPass(isa);
    if (fn == nullptr) return 0;
    static_assert(sizeof(Quat) == 4 * sizeof(double) && sizeof(AngularD<D>) == 3 * sizeof(double));
    ElementArrays<D>& a = s.elements.a;
    Turn t{a.q.data() + b, s.stepDt};
    kernel::RotationArgs k;
    k.q = reinterpret_cast<double*>(a.q.data() + b);
    k.w = reinterpret_cast<double*>(a.w.data() + b);
    k.t = reinterpret_cast<double*>(a.t.data() + b);
    k.tPrev = reinterpret_cast<double*>(a.tPrev.data() + b);
    k.invInertia = a.invInertia.data() + b;
    k.n = e - b;
    k.dt = s.stepDt;
    k.sync = s.integrator == IntegratorKind::Synchronized;
    k.turn = &turn;
    k.turnContext = &t;
    fn(k);
    return k.done;
  }
};

template <int D>
class CorrectModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "integrate-correct"; }
  SimLevel level() const override { return SimLevel::Correct; }

  void run(Scene<D>& s) override {
    forEachElementChunk(s.ownedCount(), [&](size_t b, size_t e, size_t) { range(s, b, e); });
    s.time = s.time + s.stepDt;
    s.steps += 1;
  }

 private:
  // Kicks elements b .. e - 1. Changes their v and w.
  void range(Scene<D>& s, size_t b, size_t e) {
    ElementArrays<D>& a = s.elements.a;
    const Real h = 0.5 * s.stepDt;
    const size_t n = e - b;
    VecD<D>* __restrict v = a.v.data() + b;
    const VecD<D>* __restrict f = a.f.data() + b;
    const VecD<D>* __restrict fPrev = a.fPrev.data() + b;
    const Real* __restrict invMass = a.invMass.data() + b;
    AngularD<D>* __restrict w = a.w.data() + b;
    const AngularD<D>* __restrict t = a.t.data() + b;
    const AngularD<D>* __restrict tPrev = a.tPrev.data() + b;
    const Real* __restrict invInertia = a.invInertia.data() + b;
    const bool sync = s.integrator == IntegratorKind::Synchronized;
    // 3D: through the SIMD kernel as the drift (PredictModule), the last n % W here.
    size_t first = 0;
    if constexpr (D == 3) {
      kernel::Isa isa;
      const kernel::CorrectPassFn fn = kernel::activeIsa(&isa) ? kernel::correctPass(isa) : nullptr;
      if (fn != nullptr) {
        kernel::CorrectArgs k;
        k.v = reinterpret_cast<double*>(v);
        k.f = reinterpret_cast<const double*>(f);
        k.fPrev = reinterpret_cast<const double*>(fPrev);
        k.invMass = invMass;
        if (s.rotating) {
          k.w = reinterpret_cast<double*>(w);
          k.t = reinterpret_cast<const double*>(t);
          k.tPrev = reinterpret_cast<const double*>(tPrev);
          k.invInertia = invInertia;
        }
        k.n = n;
        k.h = h;
        k.sync = sync;
        fn(k);
        first = k.done;
      }
    }
    if (sync) {
      for (size_t i = first; i < n; ++i) v[i] += (h * invMass[i]) * (f[i] - fPrev[i]);
      if (s.rotating) {
        for (size_t i = first; i < n; ++i) w[i] += (h * invInertia[i]) * (t[i] - tPrev[i]);
      }
    } else {
      for (size_t i = first; i < n; ++i) v[i] += (h * invMass[i]) * f[i];
      if (s.rotating) {
        for (size_t i = first; i < n; ++i) w[i] += (h * invInertia[i]) * t[i];
      }
    }
  }
};

// Returns the half-step (t+dt/2) velocity of grain i during the force phase of a step: the
// velocity the drift used, whatever the integrator keeps in v.
template <int D>
inline VecD<D> halfStepVelocity(const Scene<D>& s, size_t i) {
  const ElementArrays<D>& a = s.elements.a;
  if (s.integrator == IntegratorKind::Synchronized) {
    return a.v[i] - (0.5 * s.stepDt * a.invMass[i]) * a.fPrev[i];
  }
  return a.v[i];
}

// Returns the half-step angular velocity of grain i during the force phase (as above).
template <int D>
inline AngularD<D> halfStepAngularVelocity(const Scene<D>& s, size_t i) {
  const ElementArrays<D>& a = s.elements.a;
  if (s.integrator == IntegratorKind::Synchronized) {
    if constexpr (D == 3) {
      // An element of anisotropic inertia (sim/rigid_body.hpp) took its estimate through its
      // world inertia tensor.
      if (a.invInertia[i] == 0) {
        return a.w[i] - rigidInverseInertiaTimes(s, i, 0.5 * s.stepDt * a.tPrev[i]);
      }
    }
    return a.w[i] - (0.5 * s.stepDt * a.invInertia[i]) * a.tPrev[i];
  }
  return a.w[i];
}

// Returns the dot product of two angular quantities (torque . angular velocity: a power).
inline Real dotAngular(Real a, Real b) {
  return a * b;
}
inline Real dotAngular(const Vec3& a, const Vec3& b) {
  return a.dot(b);
}

}  // namespace demlab::sim
