// Session: what the commands act on. It owns the current Simulation (none until `sim new`),
// the scenes kept by `sim keep`, the stop flag a run checks at step boundaries (set by the
// binding's SIGINT handler), and the hooks through which the binding gives the commands an
// output channel and Tcl callbacks. One Session per interpreter.
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cmd/command.hpp"
#include "mpi/communicator.hpp"
#include "sim/simulation.hpp"

namespace demlab::cmd {

// What a time function's values may reach, and how its errors name it.
struct TimeBound {
  double limit;       // |value| at most this, else the run stops with the callback's error
  std::string noun;   // "load", "wall velocity": "a <noun> expression gave ..."
  std::string bound;  // "the loads' bound": "... beyond <bound> <limit>"
};

struct Session : Context {
  std::unique_ptr<sim::Simulation> sim;
  std::map<std::string, std::unique_ptr<sim::Simulation>> kept;  // `sim keep` / `sim restore`
  std::atomic<bool> stop{false};

  // Set by the binding: whether stdout is a terminal (progress bars only there), where text
  // goes, and how a run is bracketed (the SIGINT handler is installed only during runs).
  bool terminal = false;
  std::function<void(std::string_view)> write = [](std::string_view) {};
  std::function<void()> beginRun = [] {}, endRun = [] {};
  // Install and remove only the SIGINT hook (an interruptible command that is not a run: the
  // scripts it evaluates may still change the scene it works on, as a study's do).
  std::function<void()> catchSigint = [] {}, releaseSigint = [] {};
  // Whether a run is stepping the scene (set between beginRun and endRun by the binding), and
  // what watches a `sim run`: called after every step, from the run's thread, with the scene
  // consistent (the viewer's redraw, which limits itself to its frame rate). It may read the
  // scene, not change it.
  bool running = false;
  std::function<void()> runWatch;
  // Returns a function of time evaluating a Tcl expression in `t`, and its value at t0 in
  // *first when first is given; throws demlab::Error {VALUE <what>} if the expression does not
  // evaluate to a number within bound.limit at time t0. During a run, a failure or a value
  // beyond bound.limit stops the run with callbackError (the value 0).
  std::function<sim::TimeFunction(const std::string& expr, const std::string& what, double t0,
                                  const TimeBound& bound, double* first)>
      timeFunction;
  // The first error a time function met during a run (it then stops the run).
  std::string callbackError;
  // The fixed time step and critical estimate last warned about at a run start (run.cpp):
  // the warning is printed once per pair, not at every run of a loop.
  double warnedStep = 0, warnedCritical = 0;

  // What a script evaluated through evalScript gave: ok (TCL_OK, or a return), its result (the
  // error message when not ok), and its -errorcode words when it failed.
  struct ScriptResult {
    bool ok = false;
    std::string result;
    std::vector<std::string> errorCode;
  };
  // Evaluates a Tcl script in the context of the command being run (the caller's frame, as a
  // loop body is); set by the binding, empty without an interpreter. Used by commands that take
  // scripts (study convergence). Never throws: failures come back in the ScriptResult.
  std::function<ScriptResult(const std::string& script)> evalScript;

  // Clears the stop flag (outermost command only: a query run from a callback must not
  // swallow a Ctrl-C meant for the run), installs the SIGINT hook and points
  // demlab::interruptRequested() at the flag; the end undoes it.
  void beginInterruptible() override;
  void endInterruptible() override;

  int dimension() const override { return sim ? sim->dim() : 3; }
  bool distributed() const override { return sim && sim->distributed(); }
  // Throws demlab::Error {STATE NOSIM}: `no simulation: use "sim new" first`.
  void requireScene() const override;
  // Returns the current simulation; throws {STATE NOSIM} when there is none.
  sim::Simulation& scene() const;

 private:
  int interruptDepth_ = 0;
  const std::atomic<bool>* outerInterruptFlag_ = nullptr;
};


// The Session a command runs in.
inline Session& session(Call& c) {
  return static_cast<Session&>(c.context());
}
inline const Session& session(const Context& c) {
  return static_cast<const Session&>(c);
}

// Distributed scenes (commands declared OnRanks::Collective).
// Returns the ranks scene s is spread over: the MPI world once it is distributed, else this
// process alone (whose sums and gathers are the identity).
const mpi::Communicator& ranksOf(const sim::Simulation& s);
// Returns, on every rank, the value the one rank holding it passes as mine (the others pass
// nothing): its own where it is, elsewhere its string form, which Tcl reads back as the list,
// dict or number it was. Throws `missing` on every rank when no rank holds it. Collective in a
// distributed scene.
Value fromHolder(const sim::Simulation& s, std::optional<Value> mine, const Error& missing);

// Runs work on this rank, then raises on every rank the error of the lowest rank where it
// threw a demlab::Error (a file one rank could not write): no rank goes on while another
// failed. Serial scene: runs work. Collective in a distributed scene.
void togetherOnRanks(const sim::Simulation& s, const std::function<void()>& work);

// Script-visible ids. A handle's first life gets the id of its slot (0, 1, 2, ...); each reuse
// of a slot adds 2^32, so a stale id never names the element that took its slot.
std::int64_t scriptId(std::uint32_t index, std::uint32_t generation);
template <class H>
std::int64_t scriptId(H h) {
  return scriptId(h.index, h.generation);
}
template <class H>
H fromScriptId(std::int64_t id) {
  H h;
  h.index = std::uint32_t(std::uint64_t(id) & 0xffffffffu);
  h.generation = std::uint32_t(2 * (std::uint64_t(id) >> 32) + 1);
  return h;
}

// Pipes over the scene, for the check phase.
// An element by id or name; value: sim::ElementId. {LOOKUP ELEMENT} if there is none.
PipeType elementRef();
// A wall by id or name; value: sim::WallId. {LOOKUP WALL}.
PipeType wallRef();
// An existing material's name; value: std::string. {LOOKUP MATERIAL}.
PipeType materialRef();
// A behavior id; value: sim::BehaviorId. {LOOKUP BEHAVIOR}.
PipeType behaviorRef();
// A contact law name (linear, hertz_mindlin; prefixes such as "hertz"); value: physics::LawKind.
PipeType lawChoice();
// A tag (a letter or "_" first); value: std::string. {VALUE TAG}.
PipeType tagName();
// A list of tags, each checked as tagName's; value: the word (std::string). {VALUE TAG}, or
// {VALUE <PARAM>} when the word is not a list.
PipeType tagList();
// A regular file that can be read and fits in memory; value: the path. {IO OPEN} when it is
// missing, unreadable or not a regular file (a directory, a device), {IO SIZE} when it is larger
// than a quarter of the machine's memory: checked before a byte is read.
PipeType readableFile();
// An angular quantity: one number in 2D (about z), three in 3D; value: std::vector<double>.
PipeType spin();

// Returns the 3-vector of a dimension-long (or spin) vector: missing components are 0, a 2D
// spin goes to z.
sim::Vec3d vec3(const std::vector<double>& v, bool isSpin = false);
// Returns the first d components of x as a Value list (angular quantities: z alone in 2D).
Value vecValue(const sim::Vec3d& x, int d, bool isSpin = false);

}  // namespace demlab::cmd
