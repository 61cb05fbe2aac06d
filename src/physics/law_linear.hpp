// The thesis's incremental linear contact law (Perkins 2001, section 1.1.1, after Cundall and
// Strack 1979):
//   delta f_n = k_n delta u_n + beta k_n delta(du_n/dt)
//   delta f_s = k_s delta u_s + beta k_s delta(du_s/dt)
// normal and shear springs with stiffness-proportional viscous damping (one beta for both),
// and Coulomb friction on the shear spring. The normal force is kept in total form,
// f_n = k_n delta - c_n v_n (the sum of the increments of a constant-stiffness spring, without
// its rounding drift); the shear spring is incremental (tangential.hpp, Rotate frame).
//
// Damping: beta = 2 zeta sqrt(m*/k_n), so c_n = beta k_n = 2 zeta sqrt(m* k_n) is zeta times
// the critical damping of the normal oscillator, and c_t = beta k_t. zeta is chosen in mixPair
// so that a head-on impact rebounds with the pair's restitution e exactly, given that the
// normal force is cut off at zero (pair_params.hpp: linearDampingRatio; for an oscillator
// without the cut-off it would be e = exp(-pi zeta / sqrt(1 - zeta^2)) and contact time
// pi/omega_d, omega_d = omega_n sqrt(1 - zeta^2), omega_n = sqrt(k_n/m*)).
//
// Cost per contact: one sqrt (sqrt(m*/kn)), plus one while sliding, no allocation, no call.
#pragma once

#include <cmath>

#include "physics/contact.hpp"
#include "physics/tangential.hpp"

namespace demlab::physics {

// The stiffness and damping factor of a contact, which depend only on its effective radius
// and effective mass, apart so that a contact loop can take them (and their sqrt) for a batch
// of contacts first: kn = knFixed + knPerRadius R*, beta = 2 zeta sqrt(m*/kn).
struct LinearRoots {
  Real kn, beta;
};
[[gnu::always_inline]] inline LinearRoots linearRoots(const PairParams& p, Real effectiveMass,
                                                      Real effectiveRadius) {
  const Real kn = p.knFixed + p.knPerRadius * effectiveRadius;
  return {kn, 2 * p.dampingRatio * std::sqrt(effectiveMass / kn)};
}

// Returns the force on B and the step's energy figures (contact.hpp); changes *history (when
// not null and the pair has friction) to the spring after this step. Requires g.overlap > 0,
// k.effectiveMass > 0, k.effectiveRadius > 0; roots = linearRoots(p, k.effectiveMass,
// k.effectiveRadius).
template <int D>
[[gnu::always_inline]] inline ContactForce<D> linearContactWith(const PairParams& p,
                                                                const ContactGeometry<D>& g,
                                                                const ContactKinematics<D>& k,
                                                                TangentialHistory<D>* history,
                                                                Real dt, const LinearRoots& roots) {
  const Real kn = roots.kn;
  const Real beta = roots.beta;
  const VecD<D>& n = g.normal;
  const Real vn = k.relativeVelocity.dot(n);
  const Real spring = kn * g.overlap;
  Real fn = spring - beta * kn * vn;
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
  out.elasticEnergy = 0.5 * spring * g.overlap;
  out.frictionLoss = 0;
  out.springWork = 0;
  if (history != nullptr) {
    // The drift velocity (tangential.hpp).
    const bool first = k.velocityLag == 0 && firstStep(*history);
    const Real vnDrift = advanceDrift<D>(n, vn, k, *history);
    if (p.friction > 0) {
      const VecD<D> vt = k.relativeVelocity - vn * n;
      const Real kt = p.shearRatio * kn;
      VecD<D> u = driftDisplacement<D>(n, vt, vnDrift, k, *history, dt);
      if (first) u *= touchingFraction(g.overlap, vnDrift, dt);  // (tangential.hpp)
      coulombSpringStep<SpringFrame::Rotate, D>(n, vt, u, kt, kt, beta * kt, p.friction * fn, dt,
                                                p.coulomb, *history, out);
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

// Returns linearContactWith(p, g, k, history, dt, its roots); changes *history as it does.
template <int D>
[[gnu::always_inline]] inline ContactForce<D> linearContact(const PairParams& p,
                                                            const ContactGeometry<D>& g,
                                                            const ContactKinematics<D>& k,
                                                            TangentialHistory<D>* history,
                                                            Real dt) {
  return linearContactWith<D>(p, g, k, history, dt,
                              linearRoots(p, k.effectiveMass, k.effectiveRadius));
}

}  // namespace demlab::physics
