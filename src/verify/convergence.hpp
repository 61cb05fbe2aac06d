// The convergence-study driver: one case, one dimension, one integrator, at a ladder of time
// steps halving from the coarsest; errors against the reference answers (against the finest run
// for quantities that have no other reference), wall time, steps, energy residual and the
// observed order of accuracy. Output as CSV rows and as a gnuplot work-precision plot.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "verify/verify.hpp"

namespace demlab::verify {

struct StudyRow {
  double stepsPerTime = 0;  // dt = timeScale / stepsPerTime
  double dt = 0;
  uint64_t steps = 0;
  double wallSeconds = 0;
  double error = 0;              // CaseResult::error() after the finest-run references are set
  double energyResidual = 0;     // the run's ledger residual at its end (CaseResult)
  double energyResidualMax = 0;  // the largest at any step
  double order = 0;              // log(error_prev / error) / log(dt_prev / dt); NaN for the first
  CaseResult result;
};

struct Study {
  std::string caseName;
  int dim = 3;
  std::string integrator;
  std::vector<StudyRow> rows;  // coarsest first
  double observedOrder = 0;    // least-squares slope over the finest three rows with error > 0
  double checkError = 0;       // the error at the case's checkSteps
  bool pass = false;           // checkError <= tolerance and, if asserted, order >= minOrder
  std::string verdict;         // "PASS" or "FAIL: <why>"
};

// Returns the study of def in dimension dim with integrator at stepsPerTime = each of levels
// (ascending; def.checkSteps must be one of them); shortRun is passed to the case. Changes
// nothing outside the scenes it builds. Throws demlab::Error {VALUE LEVELS} if checkSteps is not
// among levels.
Study runStudy(const CaseDef& def, int dim, const std::string& integrator,
               const std::vector<double>& levels, bool shortRun);

// Returns the time-step ladder of def: checkSteps x 2^k for k = kmin..kmax. Changes nothing.
std::vector<double> ladder(const CaseDef& def, int kmin, int kmax);

// Writes the CSV header "case,dim,integrator,dt,steps,wall_seconds,error,energy_residual,
// energy_residual_max,observed_order" (and a newline) to out.
void writeCsvHeader(std::ostream& out);
// Writes one line per row of study to out (observed_order empty for the first row).
void writeCsvRows(std::ostream& out, const Study& study);

// Writes the per-quantity CSV (case,dim,integrator,steps_per_time,quantity,measured,reference,
// source,error) of study's rows to out; header first when header is true.
void writeQuantityCsv(std::ostream& out, const Study& study, bool header);

// Returns true when it wrote dir/<case>.png: the work-precision plot of studies (all of one
// case), error against wall time (left) and against dt (right), log-log, one line per
// dimension and integrator, through gnuplot (with its data and script beside it). Returns false
// (writing the data and script only) when gnuplot is missing or fails.
bool plotStudies(const std::string& dir, const std::vector<Study>& studies);

}  // namespace demlab::verify
