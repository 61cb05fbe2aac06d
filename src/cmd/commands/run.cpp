// `sim run` and `sim step`: running the loop, with a progress bar on a terminal, a stop flag
// checked at step boundaries (Ctrl-C), and the end-of-run report, printed and returned as a
// dict.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/interrupt.hpp"

namespace demlab::cmd {

namespace {

using Clock = std::chrono::steady_clock;

std::string fmt(const char* f, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, x);
  return buf;
}

// Returns seconds as "12 ms", "3.4 s", "2 min 5 s".
std::string duration(double s) {
  if (s < 1e-3) return fmt("%.3g us", s * 1e6);
  if (s < 1) return fmt("%.3g ms", s * 1e3);
  if (s < 120) return fmt("%.3g s", s);
  return std::to_string(int(s / 60)) + " min " + std::to_string(int(std::fmod(s, 60))) + " s";
}

// Draws the progress bar: `[#####.....]  45%  2250/5000 steps  3.1e+03 steps/s  ETA 0.9 s`.
class ProgressBar {
 public:
  explicit ProgressBar(Session& s) : s_(s), start_(Clock::now()) {}
  void update(std::uint64_t done, std::uint64_t total) {
    auto now = Clock::now();
    if (done < total && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    double elapsed = std::chrono::duration<double>(now - start_).count();
    if (elapsed < 0.25 && !drawn_) return;  // short runs draw nothing
    double frac = total ? double(done) / double(total) : 1.0;
    int width = 30, full = int(frac * width);
    std::string bar = "\r[" + std::string(std::size_t(full), '#') +
                      std::string(std::size_t(width - full), '.') + "] ";
    bar += fmt("%3.0f%%  ", frac * 100) + std::to_string(done) + "/" + std::to_string(total) +
           " steps";
    double rate = elapsed > 0 ? double(done) / elapsed : 0;
    bar += fmt("  %.3g steps/s", rate);
    if (rate > 0) bar += "  ETA " + duration(double(total - done) / rate);
    bar += "\033[K";
    s_.write(bar);
    drawn_ = true;
  }
  void finish() {
    if (drawn_) s_.write("\r\033[K");
  }

 private:
  Session& s_;
  Clock::time_point start_, last_{};
  bool drawn_ = false;
};

Value reportValue(const sim::RunReport& r) {
  Dict d;
  d.emplace_back("steps", r.steps);
  d.emplace_back("simulated", r.simulatedTime);
  d.emplace_back("time", r.time);
  d.emplace_back("wall", r.wallSeconds);
  d.emplace_back("residual", r.energyResidual);  // the run's error indicator, beside its cost
  d.emplace_back("per_step", r.steps ? r.wallSeconds / double(r.steps) : 0.0);
  Dict mods;
  for (const auto& m : r.modules)
    mods.emplace_back(m.module, r.steps ? m.seconds / double(r.steps) : 0.0);
  d.emplace_back("modules", mods);
  d.emplace_back("contacts", r.contacts);
  d.emplace_back("rebuilds", r.neighborRebuilds);
  d.emplace_back("interrupted", r.interrupted);
  return d;
}

std::string reportText(const sim::RunReport& r) {
  double per = r.steps ? r.wallSeconds / double(r.steps) : 0;
  std::string s = "run: " + std::to_string(r.steps) + " steps, " + fmt("%.6g", r.simulatedTime) +
                  " s simulated (t = " + fmt("%.6g", r.time) + " s), wall " +
                  duration(r.wallSeconds) + " (" + duration(per) + "/step), energy residual " +
                  fmt("%.3g", r.energyResidual) + "\n";
  if (!r.modules.empty() && r.steps) {
    s += "  per step:";
    for (std::size_t k = 0; k < r.modules.size(); ++k) {
      s += (k ? ", " : " ") + r.modules[k].module + " " +
           duration(r.modules[k].seconds / double(r.steps));
    }
    s += "\n";
  }
  s += "  contacts " + std::to_string(r.contacts) + ", neighbour searches " +
       std::to_string(r.neighborRebuilds) + "\n";
  return s;
}

// Returns the message about a fixed time step above the scene's critical estimate, or "" when
// the step is automatic or below it.
std::string stepAboveCritical(const sim::Simulation& sim, double& dt, double& crit) {
  dt = sim.timeStep();
  crit = sim.criticalTimeStep();
  if (!(dt > crit)) return "";  // an automatic step is at most the estimate
  return "the time step " + fmt("%.3g", dt) + " s is " + fmt("%.3g", dt / crit) +
         " times the critical estimate " + fmt("%.3g", crit) +
         " s of the scene (stiffest contact against the lightest element)";
}

// Prints the warning about a fixed step above the critical estimate, once per step and
// estimate (a script running in chunks sees it once).
void warnStep(Session& s) {
  double dt = 0, crit = 0;
  const std::string m = stepAboveCritical(s.scene(), dt, crit);
  if (m.empty() || (dt == s.warnedStep && crit == s.warnedCritical)) return;
  s.warnedStep = dt;
  s.warnedCritical = crit;
  s.write("warning: " + m +
          "; the run may blow up: use sim timestep auto (0.2 of the estimate), or sim run "
          "-strict to make this an error\n");
}

// Returns the watchdog's stop as the Tcl-level error, naming elements and walls by script id.
Error watchdogError(const sim::RunStopped& e) {
  const sim::WatchdogTrip& t = e.trip();
  auto g = [](sim::ElementId id) { return std::to_string(scriptId(id)); };
  auto w = [](sim::WallId id) { return std::to_string(scriptId(id)); };
  return Error(t.message(g, w), {"WATCHDOG", t.check});
}

// Runs `steps` steps on the session's scene (duration > 0: a run of that simulated time, the
// steps counted again if the automatic step changes during it); returns the report. Installs
// the SIGINT hook for the run's duration and draws progress on a terminal. Throws
// {INTERRUPTED} when stopped; {WATCHDOG <check>} when the watchdog stopped the run, after
// printing the report of the steps done unless quiet.
sim::RunReport runSteps(Session& s, std::uint64_t steps, bool progress, bool quiet,
                        double duration = 0) {
  sim::Simulation& sim = s.scene();
  // Under mpirun the first run spreads the scene, which every rank built alike, over the ranks
  // (MPI UNSUPPORTED, on every rank, when it has what distributed runs lack).
  if (mpi::Communicator::world().distributed() && !sim.distributed()) sim.distribute();
  warnStep(s);
  // s.stop is not cleared here: the outermost command's bracket cleared it, and a Ctrl-C that
  // came since (before this run, or between the runs of a study) must stop this run too.
  s.callbackError.clear();
  ProgressBar bar(s);
  sim::RunOptions o;
  o.steps = steps;
  if (duration > 0) o.endTime = sim.time() + duration;
  o.stop = &s.stop;
  o.failed = [&s] { return !s.callbackError.empty(); };
  const bool drawBar = progress && s.terminal;
  if (drawBar || s.runWatch) {
    o.progress = [&s, &bar, drawBar](std::uint64_t done, std::uint64_t total) {
      if (drawBar) bar.update(done, total);
      if (s.runWatch) s.runWatch();
    };
    // The bar redraws at most every 0.1 s, the watcher at its own rate; both check the clock.
    o.progressEvery = s.runWatch ? 1 : 16;
  }
  sim::RunReport rep;
  s.beginRun();
  // The run stops at step boundaries through o.stop: outputs written during it (a dump, a
  // snapshot) must finish, not throw from their own polls.
  struct Unpolled {
    const std::atomic<bool>* outer = setInterruptFlag(nullptr);
    ~Unpolled() { setInterruptFlag(outer); }
  } unpolled;
  try {
    rep = sim.run(o);
  } catch (const sim::RunStopped& e) {
    s.endRun();
    bar.finish();
    if (!quiet) s.write(reportText(e.report()));
    throw watchdogError(e);
  } catch (...) {
    s.endRun();
    bar.finish();
    throw;
  }
  s.endRun();
  bar.finish();
  return rep;
}

// Throws the error that ended a run early, if any, after printing the report.
void raiseIfStopped(Session& s, const sim::RunReport& rep) {
  if (!s.callbackError.empty()) {
    std::string msg = s.callbackError;
    s.callbackError.clear();
    // The run is undone (RunOptions::failed): the scene is where the command found it.
    throw Error("run undone: a script callback failed after " + std::to_string(rep.steps) +
                    " steps: " + msg + "; the scene is as it was before the run",
                {"CALLBACK"});
  }
  if (rep.interrupted) {
    // A long step stopped part way: the run went back to its copy of an earlier step.
    const std::string back =
        rep.abandoned ? "; a step was stopped part way and the scene went back to the run's copy "
                        "at that step (" + std::to_string(rep.dropped) + " finished step" +
                            (rep.dropped == 1 ? "" : "s") + " dropped)"
                      : "";
    throw Error("run interrupted at step " + std::to_string(s.sim->stepCount()) +
                    " (t = " + formatReal(s.sim->time()) + " s) after " +
                    std::to_string(rep.steps) + " steps" + back +
                    "; the scene is consistent and can be run on",
                {"INTERRUPTED"});
  }
}

}  // namespace

void registerRunCommands(Registry& r) {
  Command& run = r.add("sim run", "Runs the scene for a number of steps or a simulated time.");
  run.onRanks = OnRanks::Collective;
  run.interruptible = true;
  run.details =
      "Shows a progress bar with rate and ETA when output is a terminal, prints a report at the "
      "end "
      "(steps, simulated and wall time with beside it the run's error indicator, the "
      "energy-balance "
      "residual relative to the scene's energy scale; time per step by module) and returns it as a "
      "dict (keys steps simulated time wall residual per_step modules contacts rebuilds "
      "interrupted). Ctrl-C stops the run at a step boundary with an error (code DEMLAB "
      "INTERRUPTED); "
      "the scene stays consistent. Where one step takes over 50 ms (a very large scene), the "
      "run keeps a copy of the scene at a recent step and answers within the step, going back "
      "to that copy (the error says how many finished steps that dropped). A fixed time step above the scene's critical estimate "
      "prints a warning once (an error with -strict). The watchdog (module watchdog) stops the "
      "run at the step where it fires, after printing the report of the steps done, with an "
      "error DEMLAB WATCHDOG NAN, SPEED, OVERLAP or ENERGY naming the elements, the step, the "
      "likely cause and the fix; the scene stays at that step, inspectable.";
  run.option("steps", integer().min(0), "number of steps");
  run.option("time", real().positive().withUnit("s"),
             "simulated time to run (rounded up to whole steps)");
  run.oneOf({"steps", "time"}, true);
  run.flag("quiet", "print no report");
  run.option("progress", boolean(), "show a progress bar on a terminal").byDefault("1");
  run.flag("strict",
           "a fixed time step above the critical estimate is an error (DEMLAB VALUE TIMESTEP) "
           "instead of a warning");
  run.onCheck([](Call& c) {
    auto& s = session(c).scene();
    if (c.flag("strict")) {
      double dt = 0, crit = 0;
      const std::string m = stepAboveCritical(s, dt, crit);
      if (!m.empty())
        throw Error(m + ": use sim timestep auto, or a fixed step below the estimate",
                    {"VALUE", "TIMESTEP"});
    }
    if (c.given("steps")) {
      c.prepared = std::uint64_t(c.integer("steps"));
    } else {
      double dt = s.timeStep();  // throws VALUE TIMESTEP when no step can be chosen
      double n = std::ceil(c.real("time") / dt * (1 - 1e-12));
      if (n > 1e15) c.bad("time", "needs more than 10^15 steps at dt = " + formatReal(dt));
      c.prepared = std::uint64_t(std::max(1.0, n));
    }
  });
  run.run([](Call& c) {
    Session& s = session(c);
    sim::RunReport rep = runSteps(s, std::any_cast<std::uint64_t>(c.prepared),
                                  c.get<bool>("progress"), c.flag("quiet"),
                                  c.given("time") ? c.real("time") : 0.0);
    if (!c.flag("quiet")) s.write(reportText(rep));
    raiseIfStopped(s, rep);
    return reportValue(rep);
  });

  Command& step = r.add("sim step", "Runs one step (or n) quietly; returns the report dict.");
  step.onRanks = OnRanks::Collective;
  step.interruptible = true;
  step.optionalArg("n", integer().min(1), "number of steps").byDefault("1");
  step.run([](Call& c) {
    Session& s = session(c);
    sim::RunReport rep = runSteps(s, std::uint64_t(c.integer("n")), false, true);
    raiseIfStopped(s, rep);
    return reportValue(rep);
  });
}

}  // namespace demlab::cmd
