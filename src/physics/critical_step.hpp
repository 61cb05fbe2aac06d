// Time-step limits for explicit integration of the contact laws.
#pragma once

#include "core/math.hpp"
#include "physics/material.hpp"
#include "physics/pair_params.hpp"

namespace demlab::physics {

// Returns the largest stable step for contacts of this pair between grains of the given mass
// and radius (the smallest grain of the scene gives the scene's limit). Changes nothing.
// Linear law: (2/omega)(sqrt(1 + zeta^2) - zeta), the stability limit of central differences
// for a damped oscillator, with omega the fastest mode of a contact between two such grains
// (faster than a grain on a wall): the normal mode omega^2 = 2 kn/m (m* = m/2, kn at R* = R/2)
// and, when the pair has friction, the tangential-rotational mode of two solid spheres,
// omega^2 = kt (1/m* + 2 R^2/I) = 7 kt/m (discs: 6 kt/m), which is the faster one for the
// Mindlin ratio kt/kn = 0.82. Hertz-Mindlin: the Rayleigh step of the pair's stiffer material,
// pi R rayleighSlowness (a Hertz contact has no fixed frequency). Users take a fraction of it
// (LIGGGHTS advises at most 20 % of the Rayleigh step).
Real criticalTimeStep(const PairParams& params, Real mass, Real radius);

// Returns the Rayleigh time step pi R sqrt(rho/G) / (0.1631 nu + 0.8766), G = E / (2(1+nu)),
// the time a Rayleigh wave takes to cross a grain of radius R of material m. Changes nothing.
Real rayleighTimeStep(const MaterialDef& m, Real radius);

}  // namespace demlab::physics
