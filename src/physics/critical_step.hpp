// Time-step limits for explicit integration of the contact laws.
#pragma once

#include <cmath>

#include "core/math.hpp"
#include "physics/material.hpp"
#include "physics/pair_params.hpp"

namespace demlab::physics {

// Returns the stable step of a damped oscillator over 2/omega (damping ratio zeta >= 0):
// sqrt(1 + z^2) - z, with z = zeta where the damper sees the half-step velocity (velocity
// Verlet: central differences' limit) and z = 2 zeta where it sees the synchronized estimate
// v(t+dt/2) + a(t) dt/2 (the default integrator, sim/integrator.hpp): its lagging acceleration
// doubles the damper's part, as the characteristic polynomial shows (scripts/damped-stability.py
// finds both limits by bisection). Changes nothing.
Real dampedStepFactor(Real zeta, bool synchronized);

// Returns the largest stable step for contacts of this pair between grains of the given mass
// and radius (the smallest grain of the scene gives the scene's limit) under the integrator
// (synchronized: dampedStepFactor). Changes nothing.
// Linear law: (2/omega) dampedStepFactor(zeta), the stability limit for a damped oscillator,
// with omega the fastest mode of a contact between two such grains
// (faster than a grain on a wall): the normal mode omega^2 = 2 kn/m (m* = m/2, kn at R* = R/2)
// and, when the pair has friction, the tangential-rotational mode of two solid spheres,
// omega^2 = kt (1/m* + 2 R^2/I) = 7 kt/m (discs: 6 kt/m), which is the faster one for the
// Mindlin ratio kt/kn = 0.82. Hertz-Mindlin: the Rayleigh step of the pair's stiffer material,
// pi R rayleighSlowness (a Hertz contact has no fixed frequency). Users take a fraction of it
// (LIGGGHTS advises at most 20 % of the Rayleigh step).
Real criticalTimeStep(const PairParams& params, Real mass, Real radius, bool synchronized);

// Returns the Rayleigh time step pi R sqrt(rho/G) / (0.1631 nu + 0.8766), G = E / (2(1+nu)),
// the time a Rayleigh wave takes to cross a grain of radius R of material m. Changes nothing.
Real rayleighTimeStep(const MaterialDef& m, Real radius);

// Returns how long a contact of this pair lasts between two grains of the given mass and
// radius (m* = m/2, R* = R/2: shorter than a grain on a wall), what an accuracy target in
// steps per contact divides. Linear law: the cut-off damped oscillator's force duration
// (linearForceDuration), the same at any speed; Hertz-Mindlin: the undamped impact's
// 2.9432 (5 m* / (4 k))^(2/5) v^(-1/5), k = 4/3 E* sqrt(R*), at the approach speed v (+inf at
// v = 0; damping shortens it by less than a fifth at e = 0.5). Changes nothing.
Real contactDuration(const PairParams& params, Real mass, Real radius, Real speed);

// Returns the factor that takes a Rayleigh step computed with a 2D material's areal density
// (kg/m^2) to that of the sphere of the disc's radius and mass: its density is 3 rho / (4 R),
// so the step grows by sqrt(3 / (4 R)) (R in metres; 1 in 3D). Changes nothing.
template <int D>
Real rayleighDimensionFactor(Real radius) {
  if constexpr (D == 2) {
    return std::sqrt(0.75 / radius);
  } else {
    return 1;
  }
}

}  // namespace demlab::physics
