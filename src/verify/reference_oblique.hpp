// The reference for an oblique impact of a grain on a floor under the linear law with its
// Coulomb-capped shear spring (physics/tangential.hpp, criterion "total"), in continuous time
// and independent of the simulation code: the normal law of reference_ode.hpp and the
// tangential spring, translation and spin integrated together by classical RK4.
//
// The grain (mass m, radius r, moment of inertia I) touches the floor at normal speed v0 with
// tangential speed vt0 and no spin. delta is the overlap, u its rate; the contact point sits
// r - delta/2 from the centre (the middle of the overlap, as the narrow phase puts it), so the
// slip speed is w = v - omega (r - delta/2) and the shear force's torque arm is r - delta/2.
// The shear force, from the spring s and the cap mu Fn:
//   stick   |kt s + ct w| <= mu Fn:           Ft = kt s + ct w,  ds/dt = w
//   slide on a short spring, kt |s| <= mu Fn: Ft = kt s,         ds/dt = w
//   slide on the cap:                          Ft = mu Fn sign(s), s = mu Fn / kt sign(s)
// and m dv/dt = -Ft, I domega/dt = Ft (r - delta/2). The rigid-body impulses of Walton are this
// model's limit as kn, kt grow: what they leave out is the spring's stretching right after
// the touch (Ft ramps up over mu Fn / (kt w) seconds) and the arm's shortening by the overlap.
#pragma once

#include "verify/reference_ode.hpp"

namespace demlab::verify {

struct ObliqueLaw {
  ImpactLaw normal;  // linear: kn, cn, m (= m*: a floor), radius = r
  double kt = 0;     // shear spring (N/m)
  double ct = 0;     // shear dashpot (N s/m)
  double friction = 0;
  double inertia = 0;  // I (kg m^2)
};

struct ObliqueAnswer {
  ImpactAnswer normal;    // duration, exit speed, ... of the normal motion
  double tangential = 0;  // v after the contact (m/s)
  double spin = 0;        // omega r after the contact (m/s)
  double stuckTime = 0;   // time spent in the stick branch (s)
};

// Returns the oblique impact of law at normal speed v0 > 0 and tangential speed vt0, with about
// stepsPerContact RK4 steps over the contact; ends when the normal force vanishes. Changes
// nothing.
ObliqueAnswer solveOblique(const ObliqueLaw& law, double v0, double vt0,
                           double stepsPerContact = 2e5);

}  // namespace demlab::verify
