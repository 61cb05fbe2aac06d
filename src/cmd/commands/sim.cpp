// The "sim" group: the scene as a whole (new, reset, info, time step, digest, save and load,
// kept copies). Running is in run.cpp.
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/atomic_file.hpp"
#include "core/free_aside.hpp"
#include "core/thread_pool.hpp"
#include "core/validity.hpp"

namespace demlab::cmd {

namespace {

std::string hex64(std::uint64_t x) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(x));
  return buf;
}

Value info(const sim::Simulation& s) {
  Dict d;
  d.emplace_back("dimension", s.dim());
  d.emplace_back("time", s.time());
  d.emplace_back("steps", s.stepCount());
  double dt = 0;
  try {
    dt = s.timeStep();
  } catch (const Error&) {
  }
  d.emplace_back("timestep", dt);
  d.emplace_back("elements", s.elementCount());
  d.emplace_back("walls", s.wallCount());
  d.emplace_back("materials", s.materialNames().size());
  d.emplace_back("behaviors", s.behaviors().size());
  d.emplace_back("integrator", std::get<std::string>(s.option("integrator", "name")));
  List mods;
  for (const auto& m : s.listModules()) mods.emplace_back(m);
  d.emplace_back("modules", mods);
  return d;
}

// The longest time step: a grain at the largest allowed speed moves at most the coordinate
// bound in one step (a step of 1e300 s put Inf into the positions at the first step).
constexpr double kMaxTimeStep = validity::kMaxCoordinate / validity::kMaxSpeed;

// A time step word: a positive real up to kMaxTimeStep, or "auto".
PipeType stepWord() {
  PipeType t =
      custom("real|auto", [](std::string_view w, const Param& p, const Context& c) -> std::any {
        if (w == "auto") return std::string("auto");
        Param q = p;
        q.type = real().positive().max(kMaxTimeStep);
        return convertWord(w, q, c);
      });
  t.choices = {"auto"};
  return t;
}


}  // namespace

void registerSimCommands(Registry& r) {
  r.describe("sim", "The scene as a whole: create, inspect, time step, run, save and load.");

  Command& n = r.add("sim new", "Starts a new, empty scene, replacing the current one.");
  n.onRanks = OnRanks::Alike;
  n.option("dim", integer().range(2, 3), "dimension: 2 (discs) or 3 (spheres)").byDefault("3");
  n.needsScene = false;
  n.run([](Call& c) {
    session(c).sim = sim::makeSimulation(int(c.integer("dim")));
    return Value();
  });

  Command& rk = r.add("sim ranks",
                      "Returns this process's rank of an MPI run (mpirun -np N demlab script.tcl), "
                      "the number of ranks, and this rank's part of the scene.");
  rk.details =
      "A dict: rank, ranks, distributed (1 once the first run spread the scene over the ranks), "
      "owned and ghosts (the elements this rank steps, and the copies of other ranks' elements it "
      "holds within reach of its own). Without mpirun: rank 0 of 1. A script writes its own "
      "files on one rank: if {[dict get [sim ranks] rank] == 0} {...}.";
  rk.needsScene = false;
  rk.changesScene = false;
  rk.onRanks = OnRanks::Alike;
  rk.run([](Call& c) {
    const Session& s = session(c);
    const mpi::Communicator& world = mpi::Communicator::world();
    sim::Simulation::DistributionReport d;
    if (s.sim) d = s.sim->distribution();
    return Value(Dict{{"rank", world.rank()},
                      {"ranks", world.size()},
                      {"distributed", s.sim && s.sim->distributed()},
                      {"owned", std::int64_t(d.owned)},
                      {"ghosts", std::int64_t(d.ghosts)}});
  });

  Command& reset = r.add("sim reset", "Empties the scene, keeping its dimension.");
  reset.run([](Call& c) {
    Session& s = session(c);
    s.sim = sim::makeSimulation(s.sim->dim());
    return Value();
  });

  Command& dim = r.add("sim dimension", "Returns the dimension of the scene (2 or 3).");
  dim.onRanks = OnRanks::Alike;
  dim.changesScene = false;
  dim.run([](Call& c) { return Value(session(c).scene().dim()); });

  Command& inf =
      r.add("sim info", "Returns a dict describing the scene: time, steps, counts, modules.");
  inf.changesScene = false;
  inf.run([](Call& c) { return info(session(c).scene()); });

  Command& t =
      r.add("sim time", "Returns the simulated time (s) and, with -steps, the step count.");
  t.onRanks = OnRanks::Alike;
  t.flag("steps", "return the number of steps taken instead");
  t.changesScene = false;
  t.run([](Call& c) {
    auto& s = session(c).scene();
    return c.flag("steps") ? Value(s.stepCount()) : Value(s.time());
  });

  Command& ts = r.add("sim timestep", "Sets the time step, or returns the one the next run uses.");
  ts.details =
      "With a number, the step is fixed; with \"auto\" (the default of a new scene) it follows "
      "the scene: fraction x the static critical step (the Rayleigh step for Hertz-Mindlin; "
      "recomputed when grains or materials change), and at most fraction x 2.5 x the step the "
      "contacts' overlaps allow, taken again after every neighbour search during a run (a bed "
      "stiffens as it is loaded): at the default fraction 0.2, half the contacts' stability "
      "limit. It is also at most the duration of the shortest contact over -stepspercontact: "
      "a linear pair's from its stiffness, a Hertz pair's at twice the fastest element's speed, "
      "and the fastest element moves at most half the watchdog's step limit in a step (taken "
      "again as it speeds up). In 2D the Rayleigh step takes the sphere of a disc's radius and "
      "mass. A run of -time counts its steps again when the step changes. A fixed step above "
      "the critical estimate makes sim run warn (an error with sim run -strict).";
  ts.onRanks = OnRanks::Collective;  // (the automatic step is the whole scene's)
  ts.optionalArg("dt", stepWord(), "the time step in seconds, or auto").type.unit = "s";
  ts.option("fraction", real().positive().max(1), "with auto: the fraction of the critical step")
      .byDefault("0.2");
  ts.option("stepspercontact", real().nonNegative().max(1e6),
            "with auto: the fewest steps a contact lasts (0: no accuracy target)")
      .byDefault("20");
  ts.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("dt")) {
      const std::any& v = c.stack().slot("dt").value;
      if (std::any_cast<std::string>(&v))
        s.setAutoTimeStep(c.real("fraction"), c.real("stepspercontact"));
      else
        s.setTimeStep(std::any_cast<double>(v));
      return Value();
    }
    return Value(s.timeStep());
  });

  Command& th = r.add("sim threads", "Sets the threads a step runs on, or returns their number.");
  th.onRanks = OnRanks::Alike;
  th.details =
      "The step's stages run on this many threads (the calling one included). The default is "
      "$DEMLAB_THREADS, else every core of the machine. A scene gives the same bits for any "
      "number of threads: the forces are summed in an order fixed by the scene, never by the "
      "threads, so digests, checkpoints and results do not depend on it (doc/design.md). More "
      "threads than cores run correctly but slower.";
  th.optionalArg("count", integer().min(1).max(ThreadPool::kMaxThreads), "the number of threads");
  th.changesScene = false;
  th.needsIdle = true;
  th.needsScene = false;
  th.run([](Call& c) {
    ThreadPool& pool = ThreadPool::global();
    if (c.given("count")) {
      pool.setThreads(static_cast<unsigned>(c.integer("count")));
      return Value();
    }
    return Value(static_cast<int64_t>(pool.threads()));
  });

  Command& rel = r.add("sim relax", "Moves overlapping elements apart; returns what it did.");
  rel.interruptible = true;
  rel.details =
      "Deep overlaps placed by a script (the watchdog reports them before the first step) are "
      "relaxed geometrically: each pass pushes every contact overlapping by more than the "
      "fraction of the smaller radius back to half of it, shared by inverse mass (walls stay), "
      "until none does or the passes run out. Velocities are kept. Returns a dict: iterations, "
      "moved (elements), before and after (the largest overlap / smaller radius).";
  rel.option("overlap", real().positive().max(1),
             "the largest overlap left, as a fraction of the smaller radius")
      .byDefault("0.01");
  rel.option("iterations", integer().min(1), "the most passes").byDefault("1000");
  rel.run([](Call& c) {
    auto& s = session(c).scene();
    sim::RelaxReport r =
        s.relax(c.real("overlap"), std::uint64_t(c.integer("iterations")), &session(c).stop);
    if (r.interrupted) {
      throw Error("relax interrupted after " + std::to_string(r.iterations) +
                      " passes; the elements moved so far stay moved and the scene is consistent",
                  {"INTERRUPTED"});
    }
    return Value(Dict{{"iterations", r.iterations},
                      {"moved", r.moved},
                      {"before", r.before},
                      {"after", r.after}});
  });

  Command& crit = r.add("sim critical", "Returns the critical time step of the scene (s).");
  crit.details =
      "The least of the static estimate (materials, the smallest grains, bonds) and the step "
      "the ball contacts allow at their overlaps of the last neighbour search: each contact's "
      "normal and tangential-rotational modes at its Hertz tangent stiffness, their damping "
      "included, summed per element (the static estimate alone until a run has searched).";
  crit.flag("contacts", "only the contacts' step, recomputed at their overlaps now (inf when none touch)");
  crit.changesScene = false;
  crit.run([](Call& c) {
    const sim::Simulation& s = session(c).scene();
    return Value(c.flag("contacts") ? s.contactCriticalTimeStep() : s.criticalTimeStep());
  });

  Command& dig =
      r.add("sim digest", "Returns a hash of everything that determines the scene's future.");
  dig.details =
      "Equal digests mean equal scenes: the tests compare digests before and after failing calls.";
  dig.changesScene = false;
  dig.run([](Call& c) { return Value(hex64(session(c).scene().stateDigest())); });

  Command& save = r.add("sim save", "Writes the whole scene to a checkpoint file.");
  save.details =
      "In a distributed run every rank gives its part and rank 0 writes the whole scene, which "
      "loads on any number of ranks (the loaded run searches first and goes on as the saved "
      "one would, to round-off).";
  save.interruptible = true;
  save.arg("file", text("file"), "the file to write");
  save.flag("skipcallbacks", "leave out loads defined by scripts instead of failing");
  save.changesScene = false;
  save.onRanks = OnRanks::Collective;
  save.run([](Call& c) {
    auto& s = session(c).scene();
    std::vector<std::string> skipped;
    std::string bytes;
    const FreeAsideOnThrow aside(bytes);
    // Distributed: rank 0 writes the whole scene, gathered; a failure is every rank's.
    togetherOnRanks(s, [&] {
      bytes = s.saveBytes(c.flag("skipcallbacks"), &skipped);
      if (ranksOf(s).rank() == 0) writeFileAtomically(c.str("file"), bytes);
    });
    List l;
    for (auto& d : skipped) l.emplace_back(d);
    return Value(std::move(l));
  });

  Command& load = r.add("sim load", "Replaces the scene by the one in a checkpoint file.");
  load.onRanks = OnRanks::Alike;
  load.interruptible = true;
  load.arg("file", readableFile(), "a file written by sim save");
  load.needsScene = false;
  load.run([](Call& c) {
    Session& s = session(c);
    const std::string& path = c.str("file");
    std::string bytes = readFileBytes(path);
    const int dim = sim::checkpointDimension(bytes);
    auto fresh = sim::makeSimulation(dim ? dim : s.sim ? s.sim->dim() : 3);
    try {
      fresh->loadBytes(std::move(bytes));
    } catch (const Error& e) {
      std::vector<std::string> code(e.code().begin() + 1, e.code().end());
      throw Error("couldn't load \"" + path + "\": " + e.what(), std::move(code));
    }
    s.sim = std::move(fresh);
    return Value();
  });

  Command& keep =
      r.add("sim keep", "Keeps a deep copy of the scene under a name (see sim restore).");
  keep.details =
      "The copy runs bit-identically to the scene it was taken from: convergence studies start "
      "every run from it.";
  keep.arg("name", name("name"), "the name of the copy (an existing copy is replaced)");
  keep.changesScene = false;
  keep.onRanks = OnRanks::Collective;  // (each rank keeps its part, with its Distribution)
  keep.run([](Call& c) {
    Session& s = session(c);
    auto copy = s.sim->clone();
    s.kept[c.str("name")] = std::move(copy);
    return Value();
  });

  auto keptRef = [] {
    PipeType t =
        custom("kept scene", [](std::string_view w, const Param&, const Context& c) -> std::any {
          if (!session(c).kept.count(std::string(w))) {
            throw Error("no kept scene named \"" + std::string(w) + "\"", {"LOOKUP", "SCENE"});
          }
          return std::string(w);
        });
    return t.complete([](const Context& c) {
      std::vector<std::string> out;
      for (auto& [k, v] : session(c).kept) out.push_back(k);
      return out;
    });
  };
  Command& restore = r.add("sim restore", "Replaces the scene by a copy of a kept one.");
  restore.onRanks = OnRanks::Alike;
  restore.arg("name", keptRef(), "a name given to sim keep");
  restore.needsScene = false;
  restore.run([](Call& c) {
    Session& s = session(c);
    s.sim = s.kept.at(c.str("name"))->clone();
    return Value();
  });

  Command& kl = r.add("sim kept", "Returns the names of the kept scenes.");
  kl.onRanks = OnRanks::Alike;
  kl.needsScene = false;
  kl.changesScene = false;
  kl.run([](Call& c) {
    List l;
    for (auto& [k, v] : session(c).kept) l.emplace_back(k);
    return Value(std::move(l));
  });

  Command& drop = r.add("sim forget", "Drops a kept scene.");
  drop.onRanks = OnRanks::Alike;
  drop.arg("name", keptRef(), "a name given to sim keep");
  drop.needsScene = false;
  drop.run([](Call& c) {
    session(c).kept.erase(c.str("name"));
    return Value();
  });
}

}  // namespace demlab::cmd
