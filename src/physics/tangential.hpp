// The Coulomb-capped tangential spring shared by the contact laws (law_linear.hpp,
// law_hertz_mindlin.hpp): one step of the incremental shear spring of a contact.
//
// Per step: carry the stored spring into the current tangent plane, add the tangential
// displacement of the step (u, the drift's), form the spring force -kt s, and if it exceeds the
// Coulomb limit mu Fn, scale the force down to the limit and the spring with it (the excess
// elongation is slip; the energy it held goes to frictionLoss). The tangential dashpot -ct vt acts only
// while sticking, so a sliding contact's force is exactly mu Fn.
//
// What "exceeds the limit" means, two ways (PairParams::coulomb, a run-time choice):
//  - Total (the default): the sticking force -kt s - ct vt, spring and dashpot, is compared
//    with mu Fn, as LAMMPS's granular history models and MercuryDPM do, so |Ft| <= mu Fn at
//    every step: a grain launched sliding slides from its first contact step. Sliding, the
//    dashpot is off and the spring is capped at mu Fn/kt as always; a spring still shorter
//    than that keeps its length (the force is then its own, below mu Fn, for the few steps
//    it takes to stretch). Unlike LAMMPS's rule (the spring set to -(Ft + ct vt)/kt), no
//    spring energy appears that the motion did not supply, and every step's loss is >= 0.
//  - Spring: only the spring force kt |s| is compared (LIGGGHTS's tangential history, PFC).
//    Right after a touch the spring is short while vt may be large, so the dashpot can push
//    |Ft| far above mu Fn while the contact "sticks" (doc/verification.md, findings 1 and 2).
//    Kept so a run can reproduce LIGGGHTS bit for bit (the settle benchmark, the replay test).
//
// Carrying the spring into the new tangent plane, two ways (a template argument):
//  - Rotate (the linear law): remove the normal component and restore the length, so a rolling
//    or tumbling contact keeps its spring energy. The restoring factor sqrt(|s|^2/|s_t|^2) is
//    taken as 1 + x/2 (x = (s.n)^2/|s_t|^2, the squared tangent of the step's tilt; error x^2/8
//    below 1.3e-15 for x < 1e-7) and with a sqrt only for larger tilts.
//  - Project (Hertz-Mindlin, as LIGGGHTS: shear += vtr dt, then shear -= (shear.en) en): the
//    normal component is dropped; the spring energy it held is booked as frictionLoss (the
//    slip form of the identity below books it).
#pragma once

#include <cmath>

#include "core/math.hpp"
#include "physics/contact.hpp"

namespace demlab::physics {

enum class SpringFrame { Rotate, Project };

// Returns nothing. Changes h.spring to the spring after this step and adds to out: the
// tangential force on B (out.force), the spring's energy ½ kt |s|^2 (out.elasticEnergy), the
// stiffening work (out.springWork) and the step's tangential damping and friction losses.
// n: unit normal; vt: tangential relative velocity at the force time (B minus A, orthogonal to
// n), for the dashpot and the Coulomb test; u: the step's tangential displacement, which the
// spring gains; kt > 0, ct >= 0: spring and dashpot; kt0: the spring's stiffness at its last
// step (Hertz-Mindlin's follows the overlap; read only when h.spring is not zero); cap = mu Fn
// >= 0; criterion: what is compared with the cap (above).
//
// u is what the drift moved, v(t+dt/2) dt (driftDisplacement): with synchronized
// velocities vt dt would run ahead of the positions by a dt^2/2 a step, a first-order scheme
// that damps a stuck contact's vibration numerically (scripts/tangential-schemes.py).
// The losses are booked by the trapezoid identity, the integrator's own work over u:
// friction = ½ (kt0 s0 + kt s).u - (½ kt |s|^2 - ½ kt0 |s0|^2) + stiffening, with s0, kt0 the
// last step's spring and stiffness and the stiffening work ½ (kt - kt0) s0.s (Hertz-Mindlin's
// kt follows the overlap); rearranged, ½ (kt0 s0 + kt s).((s0 + u) - s), the mean spring force
// times the slip. (kt0 estimated from the overlap before the drift's normal displacement, the
// law's, is as good as kept: scripts/ledger-friction.tcl gives the same orders.) The dashpot's
// loss is ct |vt|^2 dt. So a sticking spring loses nothing, a sliding one cap |u|, and the
// ledger's tangential part closes at second order in dt.
template <SpringFrame Frame, int D>
[[gnu::always_inline]] inline void coulombSpringStep(const VecD<D>& n, const VecD<D>& vt,
                                                     const VecD<D>& u, Real kt, Real kt0, Real ct,
                                                     Real cap, Real dt, CoulombCriterion criterion,
                                                     TangentialHistory<D>& h,
                                                     ContactForce<D>& out) {
  const VecD<D> s0 = h.spring;
  VecD<D> s = s0;
  Real sn = 0;  // Project: the normal part dropped
  if constexpr (Frame == SpringFrame::Rotate) {
    const Real sn = s.dot(n);
    if (sn != 0) {
      s -= sn * n;
      const Real t2 = s.squaredNorm();
      if (t2 > 0) {
        const Real x = sn * sn / t2;
        s *= x < 1e-7 ? 1 + 0.5 * x : std::sqrt(1 + x);
      }
    }
    s += u;
  } else {
    s += u;
    sn = s.dot(n);
    s -= sn * n;
  }
  const Real s2 = s.squaredNorm();
  // Project: what the booking needs of the last spring (the SIMD kernels' order).
  Real s0n = 0, s0s = 0;
  if constexpr (Frame == SpringFrame::Project) s0n = s0.dot(n), s0s = s0.dot(s);
  Real r = 1;  // the spring after the step is r s
  const Real f2 = kt * kt * s2;  // |spring force|^2
  Real elastic;
  if (criterion == CoulombCriterion::Total && f2 <= cap * cap &&
      (kt * s + ct * vt).squaredNorm() > cap * cap) {
    // Spring within the limit, spring and dashpot together beyond it: the contact slides on
    // a spring shorter than the limit's (just after a touch, or a reversal). The dashpot is
    // off while sliding, so the force is the spring's alone, and the spring keeps the step's
    // elongation.
    out.force -= kt * s;
    elastic = 0.5 * kt * s2;
  } else if (f2 > cap * cap) {
    // Sliding: the spring force is scaled to the Coulomb limit; the slip |s| - cap/kt
    // dissipates. (LIGGGHTS zeroes the force if |s| = 0 with cap = 0.)
    const Real len = std::sqrt(s2);
    const Real ratio = cap / (kt * len);
    s *= ratio;
    r = ratio;
    out.force -= kt * s;
    elastic = 0.5 * cap * cap / kt;
  } else {
    out.force -= kt * s + ct * vt;
    out.dampingLoss += ct * vt.squaredNorm() * dt;
    elastic = 0.5 * kt * s2;
  }
  if constexpr (Frame == SpringFrame::Project) {
    // The slip (s0 + u) - r s is sn n + (1 - r) s: the identity in scalars.
    out.frictionLoss += 0.5 * (kt0 * sn * s0n + (1 - r) * (kt0 * s0s + kt * r * s2));
    out.springWork += 0.5 * (kt - kt0) * r * s0s;
  } else {
    out.frictionLoss += 0.5 * (kt0 * s0 + kt * s).dot((s0 + u) - s);
    out.springWork += 0.5 * (kt - kt0) * s0.dot(s);
  }
  out.elasticEnergy += elastic;
  h.spring = s;
}

// Returns the normal relative velocity the step's drift moved with; with synchronized velocities
// (k.velocityLag == 0) sets h.drift to the half-step relative velocity that moved the positions
// in this step's drift, recovered per contact; with half-step velocities that is the velocity
// given (vn returned, h.drift untouched).
//
// With synchronized velocities the law sees vS_{n+1} = v_{n+1/2} + a_n dt/2
// (src/sim/integrator.hpp), ahead of the positions by a dt^2/2 a step: as a spring's increment
// it makes a first-order scheme that damps a stuck contact's vibration numerically
// (scripts/tangential-schemes.py). With D_{n+1} = v_{n+1/2}, D_{n+1} - D_n = a_n dt, so
// D_{n+1} = (2 vS_{n+1} + D_n) / 3, exactly for any linear motion, and an error in D shrinks
// by 3 a step. A contact's first step (no drift yet: NaN) starts from D = vS. (For the relative
// velocity at the contact point the normal's turn and the arms' change enter at O(dt) of an
// O(dt^2) term.) Nothing from the grains: one vector more a contact.
template <int D>
[[gnu::always_inline]] inline Real advanceDrift(const VecD<D>& n, Real vn,
                                                const ContactKinematics<D>& k,
                                                TangentialHistory<D>& h) {
  if (k.velocityLag != 0) return vn;
  const VecD<D>& vS = k.relativeVelocity;
  h.drift = std::isnan(h.drift[0]) ? vS : VecD<D>((2 * vS + h.drift) * (1.0 / 3));
  return h.drift.dot(n);
}

// Returns the fraction of the step a contact that began in it spent touching: its overlap
// over what the step's normal drift added to it (from overlap + vnDrift dt at the start, < 0:
// apart), 1 if it was not apart at the start. A new contact's spring grows from the touch,
// not from the step's start: scaling its first increment by this fraction makes the spring
// second order in dt where a whole step's increment made it first order, the error the
// oblique impacts of doc/verification.md showed (the tangential force's share of a touch).
// Changes nothing.
[[gnu::always_inline]] inline Real touchingFraction(Real overlap, Real vnDrift, Real dt) {
  const Real before = overlap + vnDrift * dt;
  return before < 0 ? overlap / (overlap - before) : Real{1};
}

// Returns true if history h has no drift velocity yet (a contact's first step under the
// synchronized integrator, before advanceDrift). Changes nothing.
template <int D>
[[gnu::always_inline]] inline bool firstStep(const TangentialHistory<D>& h) {
  return std::isnan(h.drift[0]);
}

// Returns the step's tangential displacement for coulombSpringStep: the drift's (h.drift, after
// advanceDrift, less its normal part vnDrift) times dt, or vt dt with half-step velocities.
template <int D>
[[gnu::always_inline]] inline VecD<D> driftDisplacement(const VecD<D>& n, const VecD<D>& vt,
                                                        Real vnDrift,
                                                        const ContactKinematics<D>& k,
                                                        const TangentialHistory<D>& h, Real dt) {
  if (k.velocityLag != 0) return vt * dt;
  return (h.drift - vnDrift * n) * dt;
}

// Returns the normal damper's loss still owed for the last step, and sets what this step's owes
// (h.damperImpulse, h.damperPending). For synchronized velocities only (k.velocityLag == 0: the
// caller tests it). The law books each step's damper loss at the force time's velocity,
// fd vn dt (fd = spring - fn, the damper's share of the normal force); the integrator's own
// work of that force is fd dt times the mean of the drift velocities before and after the force
// time, (D_n + D_{n+1}) / 2 . n, a rectangle against a trapezoid that left damped beds a
// second-order residual with a large constant. D_{n+1} is known a step later, so the difference
// is booked then: this step's pending part fd dt (D_n.n / 2 - vn), the rest fd dt D_{n+1}.n / 2
// at the next. vnDrift: advanceDrift's value this step.
template <int D>
[[gnu::always_inline]] inline Real damperCatchUp(Real fd, Real vn, Real vnDrift, Real dt,
                                                 TangentialHistory<D>& h) {
  const Real owed = h.damperPending + h.damperImpulse * (0.5 * vnDrift);
  h.damperImpulse = fd * dt;
  h.damperPending = h.damperImpulse * (0.5 * vnDrift - vn);
  return owed;
}

}  // namespace demlab::physics
