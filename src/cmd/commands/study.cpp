// The "study" group: `study convergence` runs one scene, built afresh by a Tcl command for every
// run, at a ladder of time steps with each integrator; it measures an observable with a script
// after each run, compares it with an exact answer (a list of numbers, or a script evaluated
// after the run) or, when there is none, with the finest run of the same integrator, and reports
// dt, integrator, steps, wall time, energy residual, error and observed order as a table, a list
// of dicts, a CSV file and a work-precision plot (gnuplot, PNG). The user's scene is moved aside
// for the study and put back afterwards, whatever happens, so it is never changed.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/order_fit.hpp"
#include "core/atomic_file.hpp"

namespace demlab::cmd {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const std::vector<std::string> kIntegrators{"synchronized", "verlet"};

std::string fmt(const char* f, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, x);
  return buf;
}

// An exact answer: numbers given in the call, or a script evaluated after each run.
struct Exact {
  std::vector<double> values;
  std::string script;  // empty when values are given
};

// Everything the check phase settled.
struct Plan {
  std::string scene;          // the command that builds a scene
  std::vector<double> dts;    // the -dt list, coarsest first; empty with -refine
  int refine = 4, ratio = 2;  // with -refine
  int repeat = 1;             // runs per case; the shortest wall time is kept
  bool byTime = true;         // -time (else -steps: the coarsest run's step count)
  double time = 0;            // -time
  std::uint64_t steps = 0;    // -steps
  std::vector<std::string> integrators;
  std::string measure;
  bool hasExact = false;
  Exact exact;
  bool relative = false;
  std::string plot, csv, gnuplot;
};

// One run of the study.
struct Row {
  std::string integrator;
  double dt = 0;
  std::uint64_t steps = 0;
  double simulated = 0, time = 0, wall = 0, residual = 0;
  std::vector<double> measured, reference;
  double error = kNaN, order = kNaN;
};

// Returns "synchronized, dt = 0.001": which run a message is about.
std::string runLabel(const std::string& integrator, double dt) {
  return integrator + ", dt = " + formatReal(dt);
}

// Returns the numbers a script result holds, or throws {VALUE <code>} naming what gave it.
std::vector<double> numbers(const std::string& text, const std::string& what,
                            const std::string& code, const std::string& where) {
  std::vector<std::string> items;
  bool ok = true;
  try {
    items = splitList(text);
  } catch (const Error&) {
    ok = false;
  }
  std::vector<double> out;
  for (const std::string& w : items) {
    double x;
    if (!readReal(w, x) || !std::isfinite(x)) {
      ok = false;
      break;
    }
    out.push_back(x);
  }
  if (!ok || out.empty()) {
    throw Error(what + " returned \"" + text + "\" (" + where +
                    "): expected a finite number or a list of finite numbers",
                {"VALUE", code});
  }
  return out;
}

// Evaluates script; returns its result or throws: {INTERRUPTED} when Ctrl-C stopped it,
// {STUDY <code>} with the script's message otherwise.
std::string evaluate(Session& s, const std::string& script, const std::string& what,
                     const std::string& code, const std::string& where) {
  Session::ScriptResult r = s.evalScript(script);
  if (r.ok) return r.result;
  if (r.errorCode.size() >= 2 && r.errorCode[0] == "DEMLAB" && r.errorCode[1] == "INTERRUPTED") {
    throw Error("study interrupted in " + what + " (" + where + "); the scene is restored",
                {"INTERRUPTED"});
  }
  throw Error(what + " failed (" + where + "): " + r.result, {"STUDY", code});
}

// Rethrows e with the run named in its message (same code).
[[noreturn]] void rethrowIn(const Error& e, const std::string& where) {
  std::vector<std::string> code(e.code().begin() + 1, e.code().end());
  throw Error(std::string(e.what()) + " (study run: " + where + ")", code);
}

// Moves the user's scene aside for the study and puts it back when the study ends, however.
class SceneGuard {
 public:
  explicit SceneGuard(Session& s) : s_(s), saved_(std::move(s.sim)) {}
  ~SceneGuard() {
    s_.sim = std::move(saved_);
    s_.stop = false;
    s_.callbackError.clear();
  }
  SceneGuard(const SceneGuard&) = delete;
  SceneGuard& operator=(const SceneGuard&) = delete;

 private:
  Session& s_;
  std::unique_ptr<sim::Simulation> saved_;
};

// Builds a fresh scene with the plan's scene command; returns it. Throws {STUDY SCENE}.
sim::Simulation& buildScene(Session& s, const Plan& p, const std::string& where) {
  s.sim.reset();
  evaluate(s, p.scene, "scene \"" + p.scene + "\"", "SCENE", where);
  if (!s.sim) {
    throw Error("scene \"" + p.scene + "\" built no scene (" + where +
                    "): it must make one, with sim new (or sim load, sim restore)",
                {"STUDY", "SCENE"});
  }
  return *s.sim;
}

// Returns the path's problem as Tcl words it ("no such file or directory"), or "" if a file can
// be written there. Creates nothing.
std::string unwritable(const std::string& path) {
  if (path.empty()) return "no file name";
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) return "it is a directory";
    if (::access(path.c_str(), W_OK) != 0) return "permission denied";
    return "";
  }
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  if (::stat(dir.c_str(), &st) != 0) return "no such file or directory";
  if (!S_ISDIR(st.st_mode)) return "not a directory";
  if (::access(dir.c_str(), W_OK | X_OK) != 0) return "permission denied";
  return "";
}

void requireWritable(const std::string& path) {
  std::string why = unwritable(path);
  if (!why.empty()) {
    throw Error("couldn't open \"" + path + "\" for writing: " + why, {"IO", "OPEN"});
  }
}

// Returns the full path of an executable on PATH, or "".
std::string findProgram(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return "";
  std::string all = path;
  std::size_t start = 0;
  while (start <= all.size()) {
    std::size_t end = all.find(':', start);
    if (end == std::string::npos) end = all.size();
    std::string dir = all.substr(start, end - start);
    if (!dir.empty()) {
      std::string file = dir + "/" + name;
      struct stat st;
      if (::stat(file.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
          ::access(file.c_str(), X_OK) == 0) {
        return file;
      }
    }
    start = end + 1;
  }
  return "";
}

std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// A gnuplot single-quoted string ('' is a quote inside).
std::string gnuplotQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

// Returns the least-squares slope of log(error) against log(dt) over the rows with error > 0
// (NaN with fewer than two).
double fitOrder(const std::vector<const Row*>& rows) {
  std::vector<std::pair<double, double>> pts;
  for (const Row* r : rows) {
    if (r->error > 0 && std::isfinite(r->error)) pts.emplace_back(r->dt, r->error);
  }
  return logLogSlope(pts);
}

std::string num(double x) {
  return std::isnan(x) ? std::string() : fmt("%.10g", x);
}

std::string csvText(const std::vector<Row>& rows) {
  std::string s = "integrator,dt,steps,simulated,wall_seconds,residual,error,observed_order\n";
  for (const Row& r : rows) {
    s += r.integrator + "," + num(r.dt) + "," + std::to_string(r.steps) + "," + num(r.simulated) +
         "," + num(r.wall) + "," + num(r.residual) + "," + num(r.error) + "," + num(r.order) + "\n";
  }
  return s;
}

// Draws the work-precision plot into path through gnuplot: error against wall time (left) and
// against dt (right), log-log, one line per integrator. Throws {STUDY PLOT} if gnuplot fails;
// leaves no partial file.
void plot(const Plan& p, const std::vector<Row>& rows,
          const std::vector<std::pair<std::string, double>>& orders) {
  namespace fs = std::filesystem;
  std::string dir = fs::path(p.plot).parent_path().string();
  if (dir.empty()) dir = ".";
  std::string tmpPng = dir + "/.demlab-study-XXXXXX";
  std::vector<char> buf(tmpPng.begin(), tmpPng.end());
  buf.push_back('\0');
  int fd = ::mkstemp(buf.data());
  if (fd < 0) {
    throw Error("couldn't open \"" + p.plot + "\" for writing: " + std::strerror(errno),
                {"IO", "OPEN"});
  }
  ::close(fd);
  tmpPng = buf.data();
  fs::path tmpDir = fs::temp_directory_path();
  std::string script = (tmpDir / "demlab-study-XXXXXX").string();
  std::vector<char> sbuf(script.begin(), script.end());
  sbuf.push_back('\0');
  int sfd = ::mkstemp(sbuf.data());
  if (sfd < 0) {
    std::remove(tmpPng.c_str());
    throw Error(std::string("couldn't write the gnuplot script: ") + std::strerror(errno),
                {"STUDY", "PLOT"});
  }
  ::close(sfd);
  script = sbuf.data();
  std::string errFile = script + ".err";

  std::ostringstream g;
  g << "set terminal pngcairo size 1100,450 font ',10'\nset output " << gnuplotQuote(tmpPng)
    << "\n";
  std::vector<std::string> drawn;  // integrators with a point to draw
  for (std::size_t k = 0; k < p.integrators.size(); ++k) {
    std::ostringstream d;
    int n = 0;
    for (const Row& r : rows) {
      // A zero error (the finest run against itself) has no place on a log axis.
      if (r.integrator == p.integrators[k] && r.error > 0 && r.wall > 0) {
        d << fmt("%.10g", r.wall) << ' ' << fmt("%.10g", r.error) << ' ' << fmt("%.10g", r.dt)
          << '\n';
        ++n;
      }
    }
    if (n == 0) continue;
    g << "$d" << drawn.size() << " << EOD\n" << d.str() << "EOD\n";
    drawn.push_back(p.integrators[k]);
  }
  std::string ylabel = std::string(p.relative ? "relative error" : "error") + " against " +
                       (p.hasExact ? "the exact answer" : "the finest run");
  g << "set logscale xy\nset grid\nset format x '%.0e'\nset format y '%.0e'\n"
    << "set multiplot layout 1,2 title "
    << gnuplotQuote("study convergence: " + p.scene + " (error against wall time and dt)") << "\n"
    << "set key bottom left\nset xlabel 'wall time of the run (s)'\nset ylabel "
    << gnuplotQuote(ylabel) << "\n";
  auto plotLine = [&](const char* using_, bool withOrder) {
    if (drawn.empty()) {
      g << "unset logscale\nset label 1 'every error is zero: nothing to draw on log axes' at "
           "graph 0.5,0.5 center\nplot [0:1][0:1] NaN notitle\n";
      return;
    }
    g << "plot ";
    for (std::size_t k = 0; k < drawn.size(); ++k) {
      std::string title = drawn[k];
      if (withOrder) {
        for (auto& [name, o] : orders) {
          if (name == drawn[k] && !std::isnan(o)) title += " (order " + fmt("%.2f", o) + ")";
        }
      }
      g << (k ? ", " : "") << "$d" << k << " using " << using_ << " with linespoints pt 7 title "
        << gnuplotQuote(title);
    }
    g << "\n";
  };
  plotLine("1:2", false);
  g << "set key top left\nset xlabel 'time step dt (s)'\n";
  plotLine("3:2", true);
  g << "unset multiplot\nset output\n";
  {
    std::ofstream f(script);
    f << g.str();
  }
  std::string cmd =
      shellQuote(p.gnuplot) + " " + shellQuote(script) + " > /dev/null 2> " + shellQuote(errFile);
  int rc = std::system(cmd.c_str());
  std::string err;
  {
    std::ifstream e(errFile);
    std::stringstream ss;
    ss << e.rdbuf();
    err = ss.str();
  }
  std::remove(script.c_str());
  std::remove(errFile.c_str());
  while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
  if (rc != 0) {
    std::remove(tmpPng.c_str());
    throw Error("gnuplot failed to draw \"" + p.plot + "\"" + (err.empty() ? "" : ": " + err),
                {"STUDY", "PLOT"});
  }
  if (std::rename(tmpPng.c_str(), p.plot.c_str()) != 0) {
    std::remove(tmpPng.c_str());
    throw Error("couldn't rename \"" + tmpPng + "\" to \"" + p.plot + "\"", {"IO", "WRITE"});
  }
}

std::string tableText(const Plan& p, const std::vector<Row>& rows,
                      const std::vector<std::pair<std::string, double>>& orders) {
  std::string s = "study convergence: scene \"" + p.scene + "\", " +
                  fmt("%.6g", rows.empty() ? 0 : rows.front().simulated) + " s simulated, " +
                  (p.relative ? "relative " : "") + "error against " +
                  (p.hasExact ? "the exact answer" : "the finest run of each integrator") +
                  " (max over " + std::to_string(rows.empty() ? 0 : rows.front().measured.size()) +
                  " measured value" +
                  (!rows.empty() && rows.front().measured.size() == 1 ? "" : "s") + ")\n";
  char line[256];
  std::snprintf(line, sizeof line, "  %-12s %10s %9s %10s %10s %10s %6s\n", "integrator", "dt (s)",
                "steps", "wall (s)", "residual", "error", "order");
  s += line;
  for (const Row& r : rows) {
    std::string order = std::isnan(r.order) ? "-" : fmt("%.2f", r.order);
    std::snprintf(line, sizeof line, "  %-12s %10.4g %9llu %10.3g %10.3g %10.3g %6s\n",
                  r.integrator.c_str(), r.dt, static_cast<unsigned long long>(r.steps), r.wall,
                  r.residual, r.error, order.c_str());
    s += line;
  }
  s += "  observed order (least squares over the runs with a non-zero error):";
  for (std::size_t k = 0; k < orders.size(); ++k) {
    s += (k ? ", " : " ") + orders[k].first + " " +
         (std::isnan(orders[k].second) ? std::string("-") : fmt("%.2f", orders[k].second));
  }
  s += "\n";
  if (!p.plot.empty()) s += "  plot: " + p.plot + "\n";
  if (!p.csv.empty()) s += "  table: " + p.csv + "\n";
  return s;
}

// A list of integrator names; value: the full names, in order, without repeats.
PipeType integratorList() {
  PipeType t = custom(
      "list of integrators", [](std::string_view w, const Param&, const Context&) -> std::any {
        std::vector<std::string> items = splitList(w);
        if (items.empty()) {
          throw Error("bad integrators \"" + std::string(w) + "\": must name at least one of " +
                          alternatives(kIntegrators, "and"),
                      {"VALUE", "INTEGRATORS"});
        }
        std::vector<std::string> out;
        for (const std::string& i : items) {
          const std::string& full =
              matchChoice(i, kIntegrators, "integrator", {"VALUE", "INTEGRATOR"});
          if (std::find(out.begin(), out.end(), full) != out.end()) {
            throw Error("bad integrators \"" + std::string(w) + "\": " + full + " is given twice",
                        {"VALUE", "INTEGRATORS"});
          }
          out.push_back(full);
        }
        return out;
      });
  t.choices = kIntegrators;
  return t;
}

// An exact answer: a number or a list of numbers, or else a script; value: Exact.
PipeType exactAnswer() {
  return custom("numbers|script", [](std::string_view w, const Param&, const Context&) -> std::any {
    Exact e;
    std::vector<std::string> items;
    bool isList = true;
    try {
      items = splitList(w);
    } catch (const Error&) {
      isList = false;
    }
    bool allNumbers = isList && !items.empty();
    for (const std::string& i : items) {
      double x;
      if (!allNumbers || !readReal(i, x)) {
        allNumbers = false;
        break;
      }
      if (!std::isfinite(x)) {
        throw Error("bad exact \"" + std::string(w) + "\": must be finite numbers",
                    {"VALUE", "EXACT"});
      }
      e.values.push_back(x);
    }
    if (!allNumbers) {
      e.values.clear();
      e.script = std::string(w);
      if (e.script.find_first_not_of(" \t\n\r") == std::string::npos) {
        throw Error(
            "bad exact \"" + std::string(w) + "\": must be a number, a list of numbers or a script",
            {"VALUE", "EXACT"});
      }
    }
    return e;
  });
}

void checkPlan(Call& c) {
  Session& s = session(c);
  if (!s.evalScript) {
    throw Error("study convergence needs a Tcl interpreter (it evaluates scripts)",
                {"STATE", "NOTCL"});
  }
  Plan p;
  p.scene = c.str("scene");
  std::vector<std::string> words;
  try {
    words = splitList(p.scene);
  } catch (const Error& e) {
    c.bad("scene", e.what());
  }
  if (words.empty()) c.bad("scene", "must name a command that builds the scene");
  Session::ScriptResult which = s.evalScript("namespace which -command " + quoteElement(words[0]));
  if (!which.ok || which.result.empty()) {
    c.bad("scene", "no command named \"" + words[0] + "\"");
  }
  p.byTime = c.given("time");
  if (p.byTime) {
    p.time = c.real("time");
  } else {
    p.steps = std::uint64_t(c.integer("steps"));
  }
  if (c.given("dt")) {
    p.dts = c.vec("dt");
    if (p.dts.empty()) c.bad("dt", "must be a non-empty list of positive numbers");
    std::sort(p.dts.begin(), p.dts.end(), std::greater<>());
    for (std::size_t k = 1; k < p.dts.size(); ++k) {
      if (p.dts[k] == p.dts[k - 1]) c.bad("dt", formatReal(p.dts[k]) + " is given twice");
    }
    double total = p.byTime ? p.time : double(p.steps) * p.dts.front();
    for (double dt : p.dts) {
      double x = total / dt;
      double n = std::round(x);
      std::string what = p.byTime ? "-time " + formatReal(p.time)
                                  : "-steps " + std::to_string(p.steps) + " of the coarsest (" +
                                        formatReal(total) + " s)";
      if (n < 1) c.bad("dt", formatReal(dt) + " is longer than " + what);
      if (n > 1e12) c.bad("dt", formatReal(dt) + " needs more than 10^12 steps for " + what);
      if (std::fabs(x - n) > 1e-6 * std::max(1.0, n)) {
        c.bad("dt", what + " is not a whole number of steps of " + formatReal(dt) + " (" +
                        fmt("%.6g", x) + "): every run must end at the same time");
      }
    }
  } else if (c.given("refine")) {
    p.refine = int(c.integer("refine"));
  }
  p.ratio = int(c.integer("ratio"));
  p.repeat = int(c.integer("repeat"));
  if (c.given("ratio") && c.given("dt")) c.bad("ratio", "goes with -refine, not -dt");
  p.integrators = c.get<std::vector<std::string>>("integrators");
  p.measure = c.str("measure");
  if (p.measure.find_first_not_of(" \t\n\r") == std::string::npos) {
    c.bad("measure", "must be a script that returns the measured number(s)");
  }
  p.hasExact = c.given("exact");
  if (p.hasExact) {
    p.exact = c.get<Exact>("exact");
  }
  p.relative = c.flag("relative");
  if (p.relative && p.hasExact && p.exact.script.empty()) {
    double m = 0;
    for (double x : p.exact.values) m = std::max(m, std::fabs(x));
    if (m == 0) c.bad("exact", "is zero: -relative needs a non-zero reference");
  }
  if (!p.hasExact && p.dts.size() == 1) {
    c.bad("dt", "a study against the finest run needs at least two time steps (or give -exact)");
  }
  if (c.given("plot")) {
    p.plot = c.str("plot");
    std::string ext = std::filesystem::path(p.plot).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char ch) { return char(std::tolower(ch)); });
    requireWritable(p.plot);
    if (ext != ".png") c.bad("plot", "must be a .png file");
    p.gnuplot = findProgram("gnuplot");
    if (p.gnuplot.empty()) {
      throw Error("can't draw \"" + p.plot +
                      "\": gnuplot is not installed (not found on PATH); install it "
                      "(apt-get install gnuplot-nox) or leave out -plot",
                  {"STUDY", "GNUPLOT"});
    }
  }
  if (c.given("csv")) {
    p.csv = c.str("csv");
    requireWritable(p.csv);
  }
  c.prepared = std::move(p);
}

// Runs the scene s holds for n steps with the stop flag and SIGINT hook; returns the report.
sim::RunReport runOnce(Session& s, std::uint64_t n, const std::string& where) {
  // s.stop is not cleared: a Ctrl-C between two of the study's runs must stop the next one.
  s.callbackError.clear();
  sim::RunOptions o;
  o.steps = n;
  o.stop = &s.stop;
  sim::RunReport rep;
  s.beginRun();
  try {
    rep = s.sim->run(o);
  } catch (const Error& e) {
    s.endRun();
    rethrowIn(e, where);
  } catch (...) {
    s.endRun();
    throw;
  }
  s.endRun();
  if (!s.callbackError.empty()) {
    throw Error("run stopped at step " + std::to_string(s.sim->stepCount()) + " (" + where +
                    "): " + s.callbackError,
                {"CALLBACK"});
  }
  if (rep.interrupted) {
    throw Error("study interrupted at step " + std::to_string(s.sim->stepCount()) + " (" + where +
                    "); the scene is restored",
                {"INTERRUPTED"});
  }
  return rep;
}

Value execute(Call& c) {
  Session& s = session(c);
  const Plan& p = std::any_cast<const Plan&>(c.prepared);
  SceneGuard guard(s);

  // The ladder: (dt, steps), coarsest first.
  std::vector<std::pair<double, std::uint64_t>> ladder;
  if (!p.dts.empty()) {
    double total = p.byTime ? p.time : double(p.steps) * p.dts.front();
    for (double dt : p.dts) ladder.emplace_back(dt, std::uint64_t(std::llround(total / dt)));
  } else {
    double dt0 = 0;
    {
      sim::Simulation& base = buildScene(s, p, "to read its time step");
      try {
        dt0 = base.timeStep();
      } catch (const Error& e) {
        throw Error("scene \"" + p.scene + "\" has no time step for -refine: " + e.what(),
                    {"STUDY", "SCENE"});
      }
    }
    std::uint64_t n0 = p.steps;
    if (p.byTime) {
      // The largest step not above the scene's own that divides -time into whole steps.
      const double steps = std::ceil(p.time / dt0 * (1 - 1e-12));
      if (!(steps <= 1e12)) {  // before the conversion to an integer, which would overflow
        throw Error("bad time \"" + formatReal(p.time) + "\": needs more than 10^12 steps at the "
                    "scene's time step " + formatReal(dt0),
                    {"VALUE", "TIME"});
      }
      n0 = std::uint64_t(std::max(1.0, steps));
      dt0 = p.time / double(n0);
    }
    if (double(n0) * std::pow(double(p.ratio), p.refine - 1) > 1e12) {
      throw Error("bad refine \"" + std::to_string(p.refine) +
                      "\": the finest run would need more than 10^12 steps (" + std::to_string(n0) +
                      " x " + std::to_string(p.ratio) + "^" + std::to_string(p.refine - 1) + ")",
                  {"VALUE", "REFINE"});
    }
    std::uint64_t factor = 1;
    for (int k = 0; k < p.refine; ++k) {
      ladder.emplace_back(dt0 / double(factor), n0 * factor);
      factor *= std::uint64_t(p.ratio);
    }
  }

  const std::size_t total = ladder.size() * p.integrators.size();
  std::size_t done = 0;
  bool progress = s.terminal && !c.flag("quiet");
  std::vector<Row> rows;
  for (const std::string& integ : p.integrators) {
    for (auto [dt, n] : ladder) {
      const std::string where = runLabel(integ, dt);
      if (progress) {
        s.write("\rstudy: run " + std::to_string(done + 1) + "/" + std::to_string(total) + " (" +
                where + ", " + std::to_string(n) + " steps)\033[K");
      }
      Row r;
      r.integrator = integ;
      r.dt = dt;
      r.steps = n;
      for (int rep = 0; rep < p.repeat; ++rep) {
        sim::Simulation& sc = buildScene(s, p, where);
        try {
          sc.setOption("integrator", "name", integ);
          sc.setTimeStep(dt);
        } catch (const Error& e) {
          rethrowIn(e, where);
        }
        sim::RunReport report = runOnce(s, n, where);
        if (rep == 0 || report.wallSeconds < r.wall) r.wall = report.wallSeconds;
        r.simulated = report.simulatedTime;
        r.time = report.time;
        r.residual = report.energyResidual;
      }
      r.measured = numbers(evaluate(s, p.measure, "measure script", "MEASURE", where),
                           "measure script", "MEASURE", where);
      if (!rows.empty() && r.measured.size() != rows.front().measured.size()) {
        throw Error("measure script returned " + std::to_string(r.measured.size()) + " numbers (" +
                        where + ") but " + std::to_string(rows.front().measured.size()) +
                        " in the first run",
                    {"VALUE", "MEASURE"});
      }
      if (p.hasExact) {
        r.reference = p.exact.script.empty()
                          ? p.exact.values
                          : numbers(evaluate(s, p.exact.script, "exact script", "EXACT", where),
                                    "exact script", "EXACT", where);
        if (r.reference.size() != r.measured.size()) {
          throw Error("the exact answer has " + std::to_string(r.reference.size()) +
                          " numbers but the measure script returned " +
                          std::to_string(r.measured.size()) + " (" + where + ")",
                      {"VALUE", "EXACT"});
        }
      }
      rows.push_back(std::move(r));
      ++done;
    }
  }
  if (progress) s.write("\r\033[K");

  // Errors (max norm; relative to the reference's max norm), then orders, per integrator.
  std::vector<std::pair<std::string, double>> orders;
  for (const std::string& integ : p.integrators) {
    std::vector<Row*> mine;
    for (Row& r : rows) {
      if (r.integrator == integ) mine.push_back(&r);
    }
    if (!p.hasExact) {
      for (Row* r : mine) r->reference = mine.back()->measured;
    }
    for (Row* r : mine) {
      double e = 0, scale = 0;
      for (std::size_t k = 0; k < r->measured.size(); ++k) {
        e = std::max(e, std::fabs(r->measured[k] - r->reference[k]));
        scale = std::max(scale, std::fabs(r->reference[k]));
      }
      if (p.relative) {
        if (scale == 0) {
          throw Error(
              "can't use -relative: the reference answer is zero (" + runLabel(integ, r->dt) + ")",
              {"VALUE", "RELATIVE"});
        }
        e /= scale;
      }
      r->error = e;
    }
    for (std::size_t k = 1; k < mine.size(); ++k) {
      const Row& a = *mine[k - 1];
      Row& b = *mine[k];
      if (a.error > 0 && b.error > 0) b.order = std::log(a.error / b.error) / std::log(a.dt / b.dt);
    }
    std::vector<const Row*> fit(mine.begin(), mine.end());
    orders.emplace_back(integ, fitOrder(fit));
  }

  if (!p.csv.empty()) writeFileAtomically(p.csv, csvText(rows));
  if (!c.flag("quiet")) s.write(tableText(p, rows, orders));
  if (!p.plot.empty()) plot(p, rows, orders);

  List out;
  for (const Row& r : rows) {
    Dict d;
    d.emplace_back("integrator", r.integrator);
    d.emplace_back("dt", r.dt);
    d.emplace_back("steps", r.steps);
    d.emplace_back("simulated", r.simulated);
    d.emplace_back("wall", r.wall);
    d.emplace_back("residual", r.residual);
    d.emplace_back("error", r.error);
    d.emplace_back("order", std::isnan(r.order) ? Value(std::string()) : Value(r.order));
    d.emplace_back("measured", Reals{r.measured, 0});
    d.emplace_back("reference", Reals{r.reference, 0});
    d.emplace_back("against", p.hasExact ? "exact" : "finest");
    out.emplace_back(std::move(d));
  }
  return out;
}

}  // namespace

void registerStudyCommands(Registry& r) {
  r.describe("study", "Studies over many runs of a scene: convergence in the time step.");

  Command& cv = r.add("study convergence",
                      "Runs a scene at several time steps with each integrator; returns the "
                      "errors, observed orders and costs.");
  cv.interruptible = true;
  cv.details =
      "For every integrator and every time step (coarsest first), the -scene command builds a "
      "fresh scene (it must start with sim new, or sim load or sim restore); the study then sets "
      "the integrator and the time step (overriding the scene's), runs it for -time (or for "
      "-steps steps of the coarsest dt: every run ends at the same time, so each dt must divide "
      "it into whole steps), and evaluates -measure, which returns the observed number(s). The "
      "error of a run is the largest difference over the numbers between what was measured and "
      "the reference: -exact (numbers, or a script evaluated after each run, which may read "
      "`sim time`), or else the finest run of the same integrator. With -relative it is divided "
      "by the reference's largest magnitude. The order of a run is log(e_prev/e)/log(dt_prev/dt) "
      "against the next coarser run of the same integrator; the observed order of an integrator "
      "is the least-squares slope of log e against log dt over its runs with a non-zero error. "
      "Wall time and energy residual are the run's own (as sim run reports them), without "
      "building and measuring; with -repeat n each case runs n times, from a fresh scene each "
      "time, and keeps the shortest wall time. Scripts are evaluated in the caller's context, like "
      "a loop body. "
      "Prints a table unless -quiet, writes -csv and, with -plot, a work-precision PNG (error "
      "against wall time and against dt, log-log) through gnuplot. Returns a list of dicts, one "
      "per run: integrator dt steps simulated wall residual error order (empty for the first run "
      "of an integrator) measured reference against (exact or finest). The current scene (or "
      "the absence of one) is set aside during the study and is unchanged after it, whether it "
      "succeeds or fails.";
  cv.option("scene", text("command"),
            "a command (a proc with any leading arguments) that builds a fresh scene")
      .require();
  cv.option("time", real().positive().withUnit("s"), "simulated time of every run");
  cv.option("steps", integer().min(1), "steps of the coarsest run (the others run as long)");
  cv.oneOf({"time", "steps"}, true);
  cv.option("dt", reals().positive().withUnit("s"), "the time steps, any order");
  cv.option("refine", integer().range(2, 30),
            "number of time steps: the scene's own (with -time, shortened to divide it), then "
            "divided by -ratio again and again (default: 4)");
  cv.oneOf({"dt", "refine"}, false);
  cv.option("ratio", integer().range(2, 16), "with -refine: ratio of successive time steps")
      .byDefault("2");
  cv.option("integrators", integratorList(), "the integrators to study")
      .byDefault("synchronized verlet");
  cv.option("measure", text("script"), "returns the observed number or list of numbers after a run")
      .require();
  cv.option("exact", exactAnswer(),
            "the exact answer: numbers, or a script returning them after each run (default: "
            "the finest run)");
  cv.flag("relative", "errors relative to the reference's largest magnitude");
  cv.option("plot", text("file.png"), "write the work-precision plot (gnuplot) to this PNG");
  cv.option("csv", text("file"), "write the table as CSV");
  cv.option("repeat", integer().range(1, 100),
            "run each case this many times and keep the shortest wall time (the runs are "
            "bit-identical; the last is measured)")
      .byDefault("1");
  cv.flag("quiet", "print no table");
  cv.needsScene = false;
  cv.changesScene = false;
  cv.onCheck(checkPlan);
  cv.run(execute);
}

}  // namespace demlab::cmd
