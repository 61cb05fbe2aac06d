// The convergence-study driver: runs, errors, observed orders, CSV and gnuplot output.
#include "verify/convergence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <ostream>
#include <sstream>

#include "core/error.hpp"
#include "core/order_fit.hpp"

namespace demlab::verify {

namespace {

// Returns the least-squares slope of log(error) against log(dt) over the finest three rows with
// a positive error (NaN if fewer than two).
double fitOrder(const std::vector<StudyRow>& rows) {
  std::vector<std::pair<double, double>> pts;
  for (auto it = rows.rbegin(); it != rows.rend() && pts.size() < 3; ++it) {
    if (it->error > 0 && std::isfinite(it->error)) pts.emplace_back(it->dt, it->error);
  }
  return logLogSlope(pts);
}

std::string num(double x) {
  if (std::isnan(x)) return "";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

}  // namespace

std::vector<double> ladder(const CaseDef& def, int kmin, int kmax) {
  std::vector<double> out;
  for (int k = kmin; k <= kmax; ++k) out.push_back(def.checkSteps * std::ldexp(1.0, k));
  return out;
}

Study runStudy(const CaseDef& def, int dim, const std::string& integrator,
               const std::vector<double>& levels, bool shortRun) {
  if (std::find(levels.begin(), levels.end(), def.checkSteps) == levels.end()) {
    throw Error("bad levels for case \"" + def.name + "\": must include " + num(def.checkSteps),
                {"VALUE", "LEVELS"});
  }
  Study st;
  st.caseName = def.name;
  st.dim = dim;
  st.integrator = integrator;
  for (double spt : levels) {
    RunSpec spec;
    spec.dim = dim;
    spec.integrator = integrator;
    spec.stepsPerTime = spt;
    spec.shortRun = shortRun;
    StudyRow row;
    row.stepsPerTime = spt;
    row.result = def.run(spec);
    row.dt = row.result.timeScale / spt;
    row.steps = row.result.steps;
    row.wallSeconds = row.result.wallSeconds;
    row.energyResidual = row.result.energyResidual;
    row.energyResidualMax = row.result.energyResidualMax;
    st.rows.push_back(std::move(row));
  }
  // Quantities without another reference are compared with the finest run.
  const CaseResult& finest = st.rows.back().result;
  for (StudyRow& row : st.rows) {
    for (size_t q = 0; q < row.result.quantities.size(); ++q) {
      Quantity& x = row.result.quantities[q];
      if (x.source == "finest" && q < finest.quantities.size()) {
        x.reference = finest.quantities[q].measured;
      }
    }
    row.error = row.result.error();
  }
  for (size_t k = 0; k < st.rows.size(); ++k) {
    StudyRow& r = st.rows[k];
    r.order = std::numeric_limits<double>::quiet_NaN();
    if (k > 0 && r.error > 0 && st.rows[k - 1].error > 0) {
      r.order = std::log(st.rows[k - 1].error / r.error) / std::log(st.rows[k - 1].dt / r.dt);
    }
    if (r.stepsPerTime == def.checkSteps) st.checkError = r.error;
  }
  st.observedOrder = fitOrder(st.rows);
  std::ostringstream why;
  if (!(st.checkError <= def.tolerance)) {
    why << "error " << num(st.checkError) << " > tolerance " << num(def.tolerance) << " at "
        << def.timeScaleName << "/" << num(def.checkSteps);
  }
  if (def.minOrder > 0 && !(st.observedOrder >= def.minOrder)) {
    if (!why.str().empty()) why << "; ";
    why << "observed order " << num(st.observedOrder) << " < " << num(def.minOrder);
  }
  st.pass = why.str().empty();
  st.verdict = st.pass ? "PASS" : "FAIL: " + why.str();
  if (!st.pass && assertedIntegrator(integrator) && def.knownToFail(dim, integrator)) {
    st.verdict += " (known failure, see the case's notes)";
  }
  return st;
}

void writeCsvHeader(std::ostream& out) {
  out << "case,dim,integrator,dt,steps,wall_seconds,error,energy_residual,energy_residual_max,"
         "observed_order\n";
}

void writeCsvRows(std::ostream& out, const Study& st) {
  for (const StudyRow& r : st.rows) {
    out << st.caseName << ',' << st.dim << ',' << st.integrator << ',' << num(r.dt) << ','
        << r.steps << ',' << num(r.wallSeconds) << ',' << num(r.error) << ','
        << num(r.energyResidual) << ',' << num(r.energyResidualMax) << ',' << num(r.order) << '\n';
  }
}

void writeQuantityCsv(std::ostream& out, const Study& st, bool header) {
  if (header) {
    out << "case,dim,integrator,steps_per_time,quantity,measured,reference,source,error\n";
  }
  for (const StudyRow& r : st.rows) {
    for (const Quantity& q : r.result.quantities) {
      char m[32], ref[32];
      std::snprintf(m, sizeof m, "%.10g", q.measured);
      std::snprintf(ref, sizeof ref, "%.10g", q.reference);
      out << st.caseName << ',' << st.dim << ',' << st.integrator << ',' << num(r.stepsPerTime)
          << ',' << q.name << ',' << m << ',' << ref << ',' << q.source << ',' << num(q.error())
          << '\n';
    }
  }
}

bool plotStudies(const std::string& dir, const std::vector<Study>& studies) {
  if (studies.empty()) return false;
  const std::string name = studies.front().caseName;
  const std::string dat = dir + "/" + name + ".dat", gp = dir + "/" + name + ".gp";
  {
    std::ofstream d(dat);
    for (const Study& st : studies) {
      d << "# " << st.dim << "D " << st.integrator << "\n# dt wall_seconds error\n";
      for (const StudyRow& r : st.rows) {
        // A zero error (the finest run against itself) has no place on a log axis.
        if (r.error > 0 && r.wallSeconds > 0) {
          d << num(r.dt) << ' ' << num(r.wallSeconds) << ' ' << num(r.error) << '\n';
        }
      }
      d << "\n\n";
    }
  }
  {
    std::ofstream g(gp);
    g << "set terminal pngcairo size 1100,450 font ',10'\n"
      << "set output '" << dir << "/" << name << ".png'\n"
      << "set logscale xy\nset grid\nset key bottom left\nset format y '%.0e'\n"
      << "set multiplot layout 1,2 title '" << name << ": error against run time and dt'\n"
      << "set xlabel 'wall time of the simulation loop (s)'\nset ylabel 'relative error'\n"
      << "plot ";
    for (size_t k = 0; k < studies.size(); ++k) {
      g << (k ? ", " : "") << "'" << dat << "' index " << k
        << " using 2:3 with linespoints pt 7 title '" << studies[k].dim << "D "
        << studies[k].integrator << "'";
    }
    g << "\nset xlabel 'time step dt (s)'\nplot ";
    for (size_t k = 0; k < studies.size(); ++k) {
      g << (k ? ", " : "") << "'" << dat << "' index " << k
        << " using 1:3 with linespoints pt 7 title '" << studies[k].dim << "D "
        << studies[k].integrator << " (order "
        << num(std::round(studies[k].observedOrder * 100) / 100) << ")'";
    }
    g << "\nunset multiplot\n";
  }
  const std::string cmd = "gnuplot '" + gp + "' > /dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

}  // namespace demlab::verify
