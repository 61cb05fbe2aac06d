// MaterialDef: the constants of one material, as the user gives them (SI units), checked before
// anything is built from them. Pair constants are mixed from two MaterialDefs once, when a run
// starts (pair_params.hpp); the force loop never looks at a MaterialDef.
#pragma once

#include <limits>
#include <string>

#include "core/math.hpp"

namespace demlab::physics {

struct MaterialDef {
  // The required fields start as NaN, so a field left unset fails check() by name.
  Real density = std::numeric_limits<Real>::quiet_NaN();      // kg/m^3 (kg/m^2 for 2D discs)
  // Young's modulus E, Pa; +Inf: a rigid material (walls only), whose side of a pair adds no
  // compliance, so the pair's moduli are the partner's alone (isRigid()).
  Real young = std::numeric_limits<Real>::quiet_NaN();
  Real poisson = std::numeric_limits<Real>::quiet_NaN();      // Poisson's ratio, in (-1, 0.5)
  Real restitution = std::numeric_limits<Real>::quiet_NaN();  // normal restitution e, in (0, 1]
  Real friction = std::numeric_limits<Real>::quiet_NaN();     // Coulomb mu, >= 0 (0: frictionless)
  // Rolling friction mu_r, >= 0: the lever arm of the rolling-resistance couple per unit of
  // effective radius (sim/rolling_resistance.hpp); 0: none.
  Real rollingFriction = 0;
  // Cohesion k_c (Pa: an energy per volume), >= 0: overlapping surfaces attract with k_c times
  // their intersection's area (sim/cohesion.hpp); 0: none.
  Real cohesion = 0;
  // Linear law only: explicit contact spring constants (N/m). 0 derives them from young,
  // poisson and the effective radius of each contact (see PairParams). A shear stiffness needs
  // a normal stiffness; a normal stiffness alone gets its shear stiffness from the Mindlin
  // ratio 2(1-nu)/(2-nu).
  Real normalStiffness = 0;
  Real shearStiffness = 0;

  // Returns nothing; changes nothing. Throws demlab::Error for the first bad field, in field
  // order, with a Tcl-worded message and the code {VALUE <FIELD>}: DENSITY, YOUNG (each must be
  // a positive finite number), POISSON (in (-1, 0.5)), RESTITUTION (in (0, 1]), FRICTION (a
  // non-negative finite number), ROLLINGFRICTION, COHESION (non-negative finite numbers), NORMALSTIFFNESS, SHEARSTIFFNESS
  // (non-negative finite; a shear stiffness without a normal stiffness is rejected). NaN and
  // infinities are rejected everywhere.
  void check() const;
  // Returns true for a rigid material (young = +Inf): infinitely stiff, for walls.
  bool isRigid() const { return young == std::numeric_limits<Real>::infinity(); }
};

// Returns x formatted the way Tcl prints a double: the shortest string that reads back as x,
// "NaN", "Inf" or "-Inf". Used in error messages.
std::string formatReal(Real x);

}  // namespace demlab::physics
