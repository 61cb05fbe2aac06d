// criticalTimeStep and rayleighTimeStep.
#include "physics/critical_step.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace demlab::physics {

Real dampedStepFactor(Real zeta, bool synchronized) {
  const Real z = synchronized ? 2 * zeta : zeta;
  return std::sqrt(1 + z * z) - z;
}

Real criticalTimeStep(const PairParams& p, Real mass, Real radius, bool synchronized) {
  if (p.law == LawKind::HertzMindlin) return std::numbers::pi * radius * p.rayleighSlowness;
  // Two equal grains (m* = m/2, R* = R/2) give a faster normal mode than a grain on a wall
  // (m* = m, R* = R): 2 kn(R/2)/m >= kn(R)/m since kn is affine in R* with kn(0) >= 0.
  const Real kn = p.knFixed + p.knPerRadius * radius / 2;
  Real omega2 = 2 * kn / mass;
  if (p.friction > 0) {
    // Tangential-rotational mode of two equal solid spheres (I = 2/5 m R^2):
    // kt (1/m* + R^2/I + R^2/I) = kt (2 + 2.5 + 2.5)/m = 7 kt/m (6 kt/m for discs).
    omega2 = std::max(omega2, 7 * p.shearRatio * kn / mass);
  }
  return 2 / std::sqrt(omega2) * dampedStepFactor(p.dampingRatio, synchronized);
}

Real rayleighTimeStep(const MaterialDef& m, Real radius) {
  const Real g = m.young / (2 * (1 + m.poisson));
  return std::numbers::pi * radius * std::sqrt(m.density / g) / (0.1631 * m.poisson + 0.8766);
}

Real contactDuration(const PairParams& p, Real mass, Real radius, Real speed) {
  const Real mEff = mass / 2, rEff = radius / 2;
  if (p.law == LawKind::HertzMindlin) {
    if (!(speed > 0)) return std::numeric_limits<Real>::infinity();
    const Real k = p.hertzKn * std::sqrt(rEff);
    return 2.9432 * std::pow(5 * mEff / (4 * k), 0.4) * std::pow(speed, -0.2);
  }
  const Real kn = p.knFixed + p.knPerRadius * rEff;
  return linearForceDuration(p.dampingRatio) / std::sqrt(kn / mEff);
}

}  // namespace demlab::physics
