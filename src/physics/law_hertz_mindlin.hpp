// Hertz-Mindlin with restitution-based damping, exactly as LIGGGHTS's
// `pair gran model hertz tangential history` (normal_model_hertz.h, tangential_model_history.h,
// global_properties.cpp of LIGGGHTS-PUBLIC 3.8), with limitForce on:
//   a = sqrt(R* delta)
//   Sn = 2 E* a,  St = 8 G* a,  kn = 4/3 E* a,  kt = St
//   gamma_n = -2 sqrt(5/6) beta sqrt(Sn m*),  gamma_t = -2 sqrt(5/6) beta sqrt(St m*)
//   beta = ln e / sqrt(ln^2 e + pi^2)   (with `law damping liggghts`; by default beta is
//          calibrated so that a head-on impact rebounds with e: pair_params.hpp)
//   Fn = kn delta - gamma_n vn, clamped at >= 0 (LIGGGHTS: only with limitForce on)
//   shear += vt dt, projected onto the tangent plane; Ft = -kt shear - gamma_t vt while
//   kt |shear| <= mu Fn, else Ft = -mu Fn shear/|shear| with shear rescaled to -Ft/kt.
// That Coulomb test is LIGGGHTS's with PairParams::coulomb = Spring; the default, Total, tests
// the whole sticking force instead, so |Ft| <= mu Fn holds at every step (tangential.hpp).
// Verified, with Spring, against LIGGGHTS 3.8.0 itself (physics_liggghts_test.cpp): an
// oblique sphere-sphere and a sliding sphere-wall collision replayed in LIGGGHTS's nve/sphere
// scheme agree with its dumps to 1e-15 relative. E* and G* are mixed in mixPair. The normal spring
// stores the Hertz energy (2/5) kn delta^2 = (8/15) E* sqrt(R*) delta^(5/2).
//
// Cost per contact: two sqrt (a, and sqrt(a m*) shared by both dampers), one more with
// friction while the spring is loaded (the spring's stiffening), and one while sliding; no pow,
// no allocation; always inlined into the contact loops.
#pragma once

#include <algorithm>
#include <cmath>

#include "physics/contact.hpp"
#include "physics/tangential.hpp"

namespace demlab::physics {

// The square roots of a contact that depend only on its overlap, effective radius and
// effective mass, apart so that a contact loop can take them for a batch of contacts first
// (their latencies then overlap) and the law proper after: a = sqrt(R* delta), sqrt(a m*).
struct HertzMindlinRoots {
  Real a, sqrtAm;
};
[[gnu::always_inline]] inline HertzMindlinRoots hertzMindlinRoots(Real overlap, Real effectiveMass,
                                                                  Real effectiveRadius) {
  const Real a = std::sqrt(effectiveRadius * overlap);
  return {a, std::sqrt(a * effectiveMass)};
}

// Returns the force on B and the step's energy figures (contact.hpp); changes *history (when
// not null and the pair has friction) to the spring after this step. Requires g.overlap > 0,
// k.effectiveMass > 0, k.effectiveRadius > 0; roots = hertzMindlinRoots(g.overlap,
// k.effectiveMass, k.effectiveRadius).
template <int D>
[[gnu::always_inline]] inline ContactForce<D> hertzMindlinContactWith(
    const PairParams& p, const ContactGeometry<D>& g, const ContactKinematics<D>& k,
    TangentialHistory<D>* history, Real dt, const HertzMindlinRoots& roots) {
  const Real a = roots.a;
  const Real kn = p.hertzKn * a;
  const Real sqrtAm = roots.sqrtAm;
  const Real gn = p.hertzGammaN * sqrtAm;
  const VecD<D>& n = g.normal;
  const Real vn = k.relativeVelocity.dot(n);
  const Real spring = kn * g.overlap;
  Real fn = spring - gn * vn;
  ContactForce<D> out;
  if (fn < 0) fn = 0;  // no attraction (contact.hpp)
  // Damping loss: minus the damper's power, (fn - spring) times the normal velocity at the
  // force time, vn plus the lagging part of the force's own kick (contact.hpp, velocityLag;
  // fn/m* is the relative normal acceleration of two spheres). Clamped, the damper takes the
  // spring's unworked energy, spring vn dt.
  // (The lag term is left out, not multiplied by zero, when the velocities are synchronized.)
  const Real vForce = k.velocityLag != 0 ? vn + k.velocityLag * dt * fn / k.effectiveMass : vn;
  out.dampingLoss = (spring - fn) * vForce * dt;
  out.force = fn * n;
  out.cutOff = fn == 0;
  out.elasticEnergy = 0.4 * spring * g.overlap;
  out.frictionLoss = 0;
  out.springWork = 0;
  if (history != nullptr) {
    // The drift velocity (tangential.hpp).
    const bool first = k.velocityLag == 0 && firstStep(*history);
    const Real vnDrift = advanceDrift<D>(n, vn, k, *history);
    if (p.friction > 0) {
      const VecD<D> vt = k.relativeVelocity - vn * n;
      const Real kt = p.hertzKt * a;
      VecD<D> u = driftDisplacement<D>(n, vt, vnDrift, k, *history, dt);
      if (first) u *= touchingFraction(g.overlap, vnDrift, dt);  // (tangential.hpp)
      // kt = 8 G* sqrt(R* delta) at the overlap before the step's normal displacement (what
      // the booking needs of a loaded spring; an unloaded one's terms vanish).
      const Real before = std::max<Real>(0, g.overlap + vnDrift * dt);
      const Real kt0 = p.hertzKt * std::sqrt(k.effectiveRadius * before);
      coulombSpringStep<SpringFrame::Project, D>(n, vt, u, kt, kt0, p.hertzGammaT * sqrtAm,
                                                 p.friction * fn, dt, p.coulomb, *history, out);
    } else {
      history->spring.setZero();
    }
    // The damper's loss by the integrator's own work (tangential.hpp).
    if (k.velocityLag == 0) {
      out.dampingLoss += damperCatchUp<D>(spring - fn, vn, vnDrift, dt, *history);
    }
  }
  return out;
}

// Returns hertzMindlinContactWith(p, g, k, history, dt, its roots); changes *history as it does.
template <int D>
[[gnu::always_inline]] inline ContactForce<D> hertzMindlinContact(const PairParams& p,
                                                                  const ContactGeometry<D>& g,
                                                                  const ContactKinematics<D>& k,
                                                                  TangentialHistory<D>* history,
                                                                  Real dt) {
  return hertzMindlinContactWith<D>(
      p, g, k, history, dt, hertzMindlinRoots(g.overlap, k.effectiveMass, k.effectiveRadius));
}

}  // namespace demlab::physics
