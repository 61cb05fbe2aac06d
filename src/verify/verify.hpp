// The verification suite (issue 6): analytic cases run through the public Simulation API
// (sim/simulation.hpp), each at a given time step and integrator, returning what it measured
// beside the answer it should have measured.
//
// A case is one row of the case table (caseTable()). Its run function builds a fresh scene,
// runs it, and returns a CaseResult: the measured quantities with their reference answers, the
// run's cost (steps, wall time of the simulation loop only, from RunReport::wallSeconds, so the
// measuring done between steps is not charged to the scene) and its energy-ledger residual.
// The case's error is the largest relative error over its quantities (Quantity::error()).
//
// References, in order of preference (Quantity::reference):
//   "analytic"  a closed form (Hertz 1882, Schwager-Poeschel's cut-off linear law, rigid-body
//               Coulomb impulses and rolling, Newton's laws on an incline);
//   "ode"       the same contact law integrated as a one-degree-of-freedom ODE by this library's
//               own RK4 at ~1e5 steps per contact with event location (reference_ode.hpp),
//               used where no closed form exists (peak force of the damped linear law, anything
//               of the damped Hertz law, bounces under gravity);
//   "finest"    the same case at the finest time step of the convergence study (convergence.hpp
//               fills it in), where neither exists (the sticking regime of oblique impacts).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace demlab::verify {

// One measured quantity beside its reference answer.
struct Quantity {
  std::string name;      // e.g. "restitution", "contact_time"
  double measured = 0;   // from the simulation
  double reference = 0;  // the answer
  std::string source;    // "analytic", "ode" or "finest"
  double scale = 0;      // the error is |measured - reference| / scale (0: |reference|)

  // Returns the relative error of this quantity. Changes nothing.
  double error() const;
};

// What one run of a case at one time step returns.
struct CaseResult {
  std::vector<Quantity> quantities;
  uint64_t steps = 0;      // steps simulated (all scenes of the run together)
  double wallSeconds = 0;  // sum of RunReport::wallSeconds over the run
  // EnergyLedger::residual (the run's error indicator) at the end of the run (the largest over
  // its scenes), and the largest seen at any step (a contact in progress can hold a transient).
  double energyResidual = 0;
  double energyResidualMax = 0;
  double timeScale = 0;  // the case's natural time (contact time or period), seconds
  std::string note;      // anything the reader should know about this run

  // Returns the largest Quantity::error() (0 if there are none). Changes nothing.
  double error() const;
};

// How to run a case.
struct RunSpec {
  int dim = 3;                              // 2 or 3
  std::string integrator = "synchronized";  // integrators() names
  double stepsPerTime = 50;                 // dt = timeScale / stepsPerTime
  bool shortRun = false;  // the short form (gas: fewer grains and steps); must still be adequate
};

// One verification case (a row of the case table).
struct CaseDef {
  std::string name;         // e.g. "impact-linear-plane"
  std::string title;        // one line for the report
  std::string description;  // the scene, the answer and where it comes from (Markdown)
  std::vector<int> dims;    // the dimensions it applies to
  // The tolerance: the case passes when error() <= tolerance at stepsPerTime = checkSteps.
  double tolerance = 0;
  double checkSteps = 50;
  // The observed order of accuracy the case must show (slope of log error against log dt over
  // the finest levels); 0: not asserted (the error floor is a modelling error, e.g. contact
  // compliance against a rigid-body answer, which dt does not reduce).
  double minOrder = 0;
  std::string timeScaleName;  // what stepsPerTime divides, e.g. "tc" (contact time)
  // Non-empty when the case is known to fail with the default integrator because of a defect
  // found by it and reported to its owner: the reason and the reproduction. The report still
  // says FAIL; demlab_verify's exit status and the unit tests do not count it as a regression.
  std::string knownFailure;
  std::vector<int> knownFailureDims;  // the dimensions it applies to (empty: all)
  // True when the sub-step touch correction (on by default; off in the "-notouch"
  // integrators) removes the known failure: then only the "-notouch" rows may fail.
  bool touchFixes = false;

  // Returns true when knownFailure applies in dimension dim. Changes nothing.
  bool knownToFail(int dim) const;
  // Returns true when knownFailure applies in dimension dim to the named integrator (one with
  // the touch correction on escapes it when touchFixes). Changes nothing.
  bool knownToFail(int dim, const std::string& integrator) const;
  std::function<CaseResult(const RunSpec&)> run;
};

// Returns the case table, in report order. Changes nothing.
const std::vector<CaseDef>& caseTable();

// Returns the case called name. Throws demlab::Error {LOOKUP CASE} for an unknown name:
// `bad case "x": must be a, b, or c`.
const CaseDef& findCase(const std::string& name);

// The integrators the suite runs: those the Simulation API offers (Simulation::setIntegrator),
// the default first, then each with "-notouch": the sub-step touch correction off
// (Simulation::setTouchCorrection).
const std::vector<std::string>& integrators();

// Returns true when a failure of the named integrator counts against the suite (demlab_verify's
// exit status): the default one, with and without the touch correction. Changes nothing.
bool assertedIntegrator(const std::string& integrator);

}  // namespace demlab::verify
