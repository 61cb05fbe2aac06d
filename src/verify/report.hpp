// doc/verification.md: the suite's report, written from the convergence studies.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "verify/convergence.hpp"

namespace demlab::verify {

struct ReportInfo {
  std::string command;     // how the report was made, e.g. "scripts/verify"
  std::string plotPrefix;  // path from the report to the plots, e.g. "../bench/results-verify/"
  std::string date;        // UTC time of the run
  bool shortRun = false;
  std::vector<std::string> plotted;  // cases whose PNG was written
};

// Writes the Markdown report of studies (grouped by case, in case-table order) to out: a
// summary table, then per case its description, stated tolerance, verdicts, the convergence
// table (dt, steps, wall time, error, energy residual, order), the plot, and the measured
// quantities at the checked time step; last the restitution section (restitution_table.hpp).
// Returns nothing.
void writeReport(std::ostream& out, const std::vector<Study>& studies, const ReportInfo& info);

}  // namespace demlab::verify
