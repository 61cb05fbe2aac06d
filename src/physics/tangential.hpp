// The Coulomb-capped tangential spring shared by the contact laws (law_linear.hpp,
// law_hertz_mindlin.hpp): one step of the incremental shear spring of a contact.
//
// Per step: carry the stored spring into the current tangent plane, add the tangential
// displacement of the step (vt dt), form the spring force -kt s, and if it exceeds the Coulomb
// limit mu Fn, scale the force down to the limit and the spring with it (the excess elongation
// is slip; the energy it held goes to frictionLoss). The tangential dashpot -ct vt acts only
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
//    normal component is dropped; the spring energy it held is booked as frictionLoss.
#pragma once

#include <cmath>

#include "core/math.hpp"
#include "physics/contact.hpp"

namespace demlab::physics {

enum class SpringFrame { Rotate, Project };

// Returns nothing. Changes h.spring to the spring after this step and adds to out: the
// tangential force on B (out.force), the spring's energy ½ kt |s|^2 (out.elasticEnergy), and
// the step's tangential damping and friction losses. n: unit normal; vt: tangential relative
// velocity (B minus A, orthogonal to n); kt > 0, ct >= 0: spring and dashpot; cap = mu Fn >= 0;
// criterion: what is compared with the cap (above).
template <SpringFrame Frame, int D>
[[gnu::always_inline]] inline void coulombSpringStep(const VecD<D>& n, const VecD<D>& vt, Real kt,
                                                     Real ct, Real cap, Real dt,
                                                     CoulombCriterion criterion,
                                                     TangentialHistory<D>& h,
                                                     ContactForce<D>& out) {
  VecD<D> s = h.spring;
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
    s += vt * dt;
  } else {
    s += vt * dt;
    const Real sn = s.dot(n);
    s -= sn * n;
    out.frictionLoss += 0.5 * kt * sn * sn;
  }
  const Real s2 = s.squaredNorm();
  const Real f2 = kt * kt * s2;  // |spring force|^2
  if (criterion == CoulombCriterion::Total && f2 <= cap * cap &&
      (kt * s + ct * vt).squaredNorm() > cap * cap) {
    // Spring within the limit, spring and dashpot together beyond it: the contact slides on
    // a spring shorter than the limit's (just after a touch, or a reversal). The dashpot is
    // off while sliding, so the force is the spring's alone; the spring keeps the step's
    // elongation u, and the work the motion did beyond the spring's gain (before + kt s.u
    // - after = 1/2 kt |u|^2) is the slip's loss.
    const VecD<D> u = vt * dt;
    out.force -= kt * s;
    out.frictionLoss += 0.5 * kt * u.squaredNorm();
    out.elasticEnergy += 0.5 * kt * s2;
    h.spring = s;
    return;
  }
  if (f2 > cap * cap) {
    // Sliding: the spring force is scaled to the Coulomb limit; the slip |s| - cap/kt
    // dissipates cap per unit length. (LIGGGHTS zeroes the force if |s| = 0 with cap = 0.)
    const Real len = std::sqrt(s2);
    const Real ratio = cap / (kt * len);
    const VecD<D> u = vt * dt;
    const Real before = 0.5 * kt * (s - u).squaredNorm();
    s *= ratio;
    out.force -= kt * s;
    out.frictionLoss += before + kt * s.dot(u) - 0.5 * cap * cap / kt;
    out.elasticEnergy += 0.5 * cap * cap / kt;
  } else {
    out.force -= kt * s + ct * vt;
    out.dampingLoss += ct * vt.squaredNorm() * dt;
    out.elasticEnergy += 0.5 * kt * s2;
  }
  h.spring = s;
}

}  // namespace demlab::physics
