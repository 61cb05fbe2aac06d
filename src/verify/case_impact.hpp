// The impact recorder: one two-body impact (grain on a floor, or grain on grain) run step by
// step through the Simulation API, with its contact time, peak overlap and force, restitution,
// and the tangential velocity and spin after it (for oblique impacts).
#pragma once

#include "sim/simulation.hpp"
#include "verify/case_common.hpp"
#include "verify/reference_ode.hpp"

namespace demlab::verify {

struct ImpactSetup {
  sim::LawKind law = sim::LawKind::Linear;
  bool sphere = false;       // false: grain (radius 0.01 m) on a floor; true: on a grain
  double radiusRatio = 2;    // the second grain's radius over the first's
  double restitution = 0.5;  // of the material
  double friction = 0;       // of the material
  // v_t / v_n at the touch (oblique impacts): the tangential speed over the normal (1 m/s).
  double tangentialRatio = 0;
  // Where in its step the touch falls (0..1). A damped law's force jumps at the touch, which a
  // fixed step resolves only to O(dt) with a sign set by this phase; 0.5 cancels that term.
  double touchPhase = 0.5;
};

struct ImpactMeasure {
  bool valid = false;  // a whole contact was recorded
  ImpactLaw law;       // the reference law of the pair (m*, R*, kn, cn, E*)
  double tc = 0;       // the contact time the time step is a fraction of (s)
  double duration = 0, peakOverlap = 0, peakForce = 0;
  double restitution = 0;  // normal relative velocity after / before
  double tangential = 0;   // tangential relative velocity of the centres after (m/s)
  double spin = 0;         // the contact points' relative surface speed from spin (m/s)
};

// Returns the reference law of the setup for grains of masses massA, massB (massB unused for a
// floor): E* = E / (2 (1 - nu^2)), kn = E* R*, cn = 2 zeta sqrt(m* kn). Changes nothing.
ImpactLaw impactLaw(const ImpactSetup& setup, double massA, double massB);

// Returns the measured impact at dt = tc / spec.stepsPerTime, tc the closed-form contact time
// (linear: damped duration; Hertz: elastic duration at the same speed); books its cost in out.
// The touch falls at setup.touchPhase of a step; the normal approach speed is 1 m/s.
ImpactMeasure measureImpact(const ImpactSetup& setup, const RunSpec& spec, CaseResult& out);

}  // namespace demlab::verify
