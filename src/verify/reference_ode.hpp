// Reference answers for a head-on (normal) impact, independent of the simulation code: the
// closed forms where they exist and, for everything else, the contact law integrated as a
// one-degree-of-freedom ODE by classical RK4 with very small steps and event location.
//
// The impact: two bodies (or a body and a wall) of effective mass m* and radius R* meet at
// relative normal speed v0; delta is the overlap, u = d delta/dt. The normal force is
//   linear: F = kn delta + cn u
//   Hertz : F = (4/3) E* a delta + gn(a) u,  a = sqrt(R* delta),
//           gn = 2 sqrt(5/6) (-beta) sqrt(2 E* a m*), beta calibrated so that the cut-off
//           impact rebounds with e (physics::hertzDampingFactor, demlab's default; checked
//           against its own integration in physics_restitution_test.cpp) or LIGGGHTS's
//           ln e / sqrt(ln^2 e + pi^2) (LIGGGHTS's hertz model)
// cut off at F >= 0, and m* d^2 delta/dt^2 = -F + m* g (g > 0 pushes the bodies together: a
// grain falling on a floor under gravity). The contact ends when F returns to 0.
#pragma once

namespace demlab::verify {

struct ImpactLaw {
  bool hertz = false;
  double mass = 0;         // m* (kg)
  double radius = 0;       // R* (m)
  double kn = 0;           // linear: N/m
  double cn = 0;           // linear: N s/m
  double youngEff = 0;     // Hertz: E* (Pa)
  double restitution = 1;  // Hertz: the material e (sets beta)
  // Hertz: beta as `law damping liggghts` sets it (ln e / sqrt(ln^2 e + pi^2)), else as the
  // default, calibrated (-physics::hertzDampingFactor(e) / sqrt(5)).
  bool liggghtsDamping = false;
  double gravity = 0;      // m/s^2 along the approach
};

struct ImpactAnswer {
  double duration = 0;     // from touch until the force vanishes (s)
  double peakOverlap = 0;  // m
  double peakForce = 0;    // N
  double exitSpeed = 0;    // -u when the force vanishes (m/s)
  double endOverlap = 0;   // delta when the force vanishes (m)
};

// Returns the force of law at overlap delta > 0 and rate u, not cut off. Changes nothing.
double impactForce(const ImpactLaw& law, double delta, double u);

// Returns the impact of law at approach speed v0 > 0, by RK4 with about stepsPerContact steps
// over the contact (finer near the touch, where the Hertz damper is singular) and bisection
// for the events (peak overlap: u = 0; end: F = 0; peak force: golden section). Relative
// accuracy ~1e-9 at the default. Changes nothing.
ImpactAnswer solveImpact(const ImpactLaw& law, double v0, double stepsPerContact = 2e5);

// Closed forms. Returns the answer of the elastic Hertz impact (Hertz 1882; Johnson, Contact
// Mechanics, 11.4): peak overlap (15 m* v0^2 / (16 E* sqrt(R*)))^(2/5), duration
// 2 (delta_max / v0) integral_0^1 (1 - x^(5/2))^(-1/2) dx = 2.9432 delta_max / v0, peak force
// (4/3) E* sqrt(R*) delta_max^(3/2), exit speed v0. Ignores law.restitution and gravity.
ImpactAnswer hertzElastic(const ImpactLaw& law, double v0);

// Returns the answer of the cut-off linear spring-dashpot without gravity (Schwager and
// Poeschel, Granular Matter 9 (2007) 465), for damping ratio zeta = cn / (2 sqrt(m* kn)) < 1:
// duration 2 acos(zeta)... as the force zero of delta(t) = (v0/wd) exp(-zeta wn t) sin(wd t),
// peak overlap (v0/wn) exp(-zeta acos(zeta)/sqrt(1 - zeta^2)), exit speed from delta(t); the
// peak force is left at 0 (no closed form: use solveImpact).
ImpactAnswer linearDamped(const ImpactLaw& law, double v0);

}  // namespace demlab::verify
