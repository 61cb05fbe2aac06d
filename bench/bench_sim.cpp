// bench_sim: the "settle" benchmark of ../shared/bench/ in demlab. Reads a LAMMPS data file of
// spheres (the same starting state the peers read), builds the scene the peers' decks describe
// through the Simulation API, runs it and prints one CSV row per run, in the peers' format:
//
//   code,scene,n,steps,seconds,particle_steps_per_s,contacts,peak_rss_mb
//
// The scene (the decks in/settle.liggghts and in/settle.lammps): one material per distinct
// density in the file, E = 5e6 Pa, Poisson 0.3, restitution 0.5, friction 0.5, Hertz-Mindlin
// with tangential history; gravity -9.81 z; five infinite planes on the box faces (x = xlo, xhi;
// y = ylo, yhi; z = zlo), the walls of the same material; the deck's dt and Verlet skin.
//
// Measurement model, chosen to match the peers' "Loop time":
//   - seconds: wall time of Simulation::run over the timed steps (building the scene and
//     reading the file are not timed; the first contact search is, where LAMMPS does it in its
//     untimed setup: a small handicap for demlab);
//   - contacts: particle-particle contacts with overlap > 0 after the run, as LAMMPS's compute
//     contact/atom counts them (walls excluded);
//   - peak_rss_mb: the process's peak resident set (getrusage) after the run, in MiB. It is a
//     high-water mark, so it describes one run only when the process does one run:
//     scripts/bench-sim starts one process per scene and variant.
// Variants ("leave out what a scene does not need", issue 3): "full" is the scene above in the
// peers' own physics, the like-for-like mode: plain velocity Verlet (LIGGGHTS's integrator),
// the Coulomb test on the spring force alone and LIGGGHTS's Hertz damping; "nofriction" sets
// friction 0 (no tangential history kept); "norotation" turns grain rotation off; "touch" adds
// the touch module (the sub-step correction of contact onset and release, sim/touch.hpp), so
// its cost is measured; "default" is the same scene in demlab's defaults (the synchronized
// integrator, the Coulomb test on the whole force, the calibrated damping, the default modules,
// the touch module among them) at the same step, so the cost of the defaults shows beside the
// like-for-like figure; "default-notouch" leaves the touch module out of the defaults. Their
// scene names get the suffix "-nofriction", "-norotation", "-touch", "-default" or
// "-default-notouch".
//
// Under mpirun on several ranks the scene is distributed (Simulation::distribute): every rank
// reads the file and builds the scene, each keeps its part, and rank 0 prints the row with the
// scene name suffixed "@rN" (N ranks): seconds the slowest rank's, contacts and peak RSS summed
// over the ranks (the run's whole memory), the module times rank 0's.
//
// On stderr: the modules the scene runs and the wall time of each (RunReport::modules), the
// contact-search rebuilds and the energy-balance residual; with --digest the state digest after
// the run (equal digests: bit-identical runs). --breakdown FILE appends the module
// times as CSV rows `scene,module,seconds,share` (share of the run's wall time). --cpu FILE
// appends `demlab,scene,n,steps,cpu_seconds,particle_steps_per_cpu_s,load1`: the process's CPU
// time (user + system) over the run and the 1-minute load average before it, the steadier
// figure on a crowded machine (scripts/peer-settle --cpu writes the same for the peers).
#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "io/lammps_data.hpp"
#include "mpi/communicator.hpp"
#include "sim/simulation.hpp"

namespace demlab::bench {
namespace {

// The fraction of the smallest sphere's Rayleigh time the README's dt values are (used when
// --dt is not given).
constexpr double kRayleighFraction = 0.196;
// Grains are handed to the scene in batches, so the GrainDefs (168 bytes each) never all
// exist at once.
constexpr std::size_t kBatch = 1024;

struct Variant {
  std::string_view name;
  std::string_view suffix;
  bool friction;
  bool rotation;
  bool touch;
  bool peerPhysics;  // the peers' integrator, Coulomb test and damping (else demlab's defaults)
};

// One row per variant; --variant takes these names.
constexpr Variant kVariants[] = {
    {"full", "", true, true, false, true},
    {"nofriction", "-nofriction", false, true, false, true},
    {"norotation", "-norotation", true, false, false, true},
    {"touch", "-touch", true, true, true, true},
    {"default", "-default", true, true, true, false},
    {"default-notouch", "-default-notouch", true, true, false, false},
};

struct Options {
  std::vector<std::string> data;
  std::vector<const Variant*> variants;
  uint64_t steps = 1000;
  double dt = 0;  // 0: kRayleighFraction x the scene's critical step
  double skin = 2.5e-4;
  double cellFactor = 0;
  std::string integrator;  // empty: the Simulation's default
  std::string breakdown;
  std::string cpu;
  bool header = true;
  bool digest = false;
  bool contactStep = false;
  int tile = 1;  // copies of the file's bed side by side along x
  bool allRanks = false;  // under mpirun, every rank's stderr, not only rank 0's
};

void usage(std::FILE* f) {
  std::fprintf(f,
               "usage: bench_sim [options] DATAFILE...\n"
               "  DATAFILE          LAMMPS data file of spheres (gzip'd or plain); the scene is\n"
               "                    named after it (mono_10k_dense.data.gz -> mono_10k_dense)\n"
               "  --steps N         timed steps (default 1000)\n"
               "  --dt S            time step (default 0.196 x the Rayleigh step of the\n"
               "                    smallest sphere, which gives the README's values)\n"
               "  --skin M          Verlet skin in metres (default 2.5e-4, as the decks)\n"
               "  --cell-factor F   CGrid cell factor (default: CGrid's own)\n"
               "  --all-ranks       under mpirun: every rank writes its breakdown on stderr\n"
               "                    (its own module times: the ranks' balance)\n"
               "  --tile N          N copies of the bed side by side along x, the box N times\n"
               "                    as wide (scene SCENExN), a two-sided wall between each\n"
               "                    two copies: weak scaling with N ranks\n"
               "  --integrator NAME verlet or synchronized (default: verlet, the peers', in\n"
               "                    the like-for-like variants; the Simulation's in default)\n"
               "  --variant LIST    comma-separated: full, nofriction, norotation, touch,\n"
               "                    default, default-notouch\n"
               "                    (default full)\n"
               "  --breakdown FILE  append per-module times as CSV scene,module,seconds,share\n"
               "  --cpu FILE        append code,scene,n,steps,cpu_seconds,\n"
               "                    particle_steps_per_cpu_s,load1 (CPU time of the run)\n"
               "  --no-header       leave out the CSV header line\n"
               "  --digest          print the state digest after each run on stderr\n"
               "  --contact-step    after each run, time the contacts' critical step (what the\n"
               "                    automatic step measures every 100 steps) against the\n"
               "                    run's mean step, on stderr\n");
}

// Returns the value of a numeric option; exits with status 2 on a bad value.
double numberArg(const char* opt, const char* s) {
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (end == s || *end != '\0' || !std::isfinite(v) || v < 0) {
    std::fprintf(stderr, "bench_sim: bad value \"%s\" for %s: must be a non-negative number\n", s,
                 opt);
    std::exit(2);
  }
  return v;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string_view a = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_sim: %s needs a value\n", argv[i]);
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--steps") {
      o.steps = static_cast<uint64_t>(numberArg("--steps", value()));
    } else if (a == "--dt") {
      o.dt = numberArg("--dt", value());
    } else if (a == "--skin") {
      o.skin = numberArg("--skin", value());
    } else if (a == "--all-ranks") {
      o.allRanks = true;
    } else if (a == "--tile") {
      const double t = numberArg("--tile", value());
      if (!(t >= 1 && t <= 1000 && t == std::floor(t))) {
        std::fprintf(stderr, "bench_sim: --tile must be a whole number from 1 to 1000\n");
        std::exit(2);
      }
      o.tile = static_cast<int>(t);
    } else if (a == "--cell-factor") {
      o.cellFactor = numberArg("--cell-factor", value());
    } else if (a == "--integrator") {
      o.integrator = value();
    } else if (a == "--breakdown") {
      o.breakdown = value();
    } else if (a == "--cpu") {
      o.cpu = value();
    } else if (a == "--no-header") {
      o.header = false;
    } else if (a == "--digest") {
      o.digest = true;
    } else if (a == "--contact-step") {
      o.contactStep = true;
    } else if (a == "--variant") {
      std::string_view list = value();
      while (!list.empty()) {
        const auto comma = list.find(',');
        const std::string_view name = list.substr(0, comma);
        const auto it = std::find_if(std::begin(kVariants), std::end(kVariants),
                                     [&](const Variant& v) { return v.name == name; });
        if (it == std::end(kVariants)) {
          std::fprintf(stderr,
                       "bench_sim: bad variant \"%.*s\": must be full, nofriction, "
                       "norotation, touch, default or default-notouch\n",
                       static_cast<int>(name.size()), name.data());
          std::exit(2);
        }
        o.variants.push_back(&*it);
        list = comma == std::string_view::npos ? std::string_view() : list.substr(comma + 1);
      }
    } else if (a == "-h" || a == "--help") {
      usage(stdout);
      std::exit(0);
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "bench_sim: unknown option %s\n", argv[i]);
      usage(stderr);
      std::exit(2);
    } else {
      o.data.emplace_back(a);
    }
  }
  if (o.data.empty()) {
    usage(stderr);
    std::exit(2);
  }
  if (o.variants.empty()) o.variants.push_back(&kVariants[0]);
  return o;
}

// Returns the CPU time (user + system) the process has used so far, in seconds.
double cpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Returns the 1-minute load average, or -1 when it cannot be read.
double loadAverage() {
  double l[1] = {-1};
  return getloadavg(l, 1) == 1 ? l[0] : -1;
}

// Returns the process's peak resident set size in MiB.
double peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

// Returns d with n copies of its bed side by side along x (each shifted by the box's width), the
// box n times as wide; n = 1: d.
io::SphereData tiled(io::SphereData d, int n) {
  const std::size_t one = d.size();
  // Room made exactly: grown by doubling, the copies of 10^7 grains held 1.7 times their size.
  const std::size_t all = one * static_cast<std::size_t>(n);
  d.ids.reserve(all), d.types.reserve(all), d.diameters.reserve(all), d.densities.reserve(all);
  d.positions.reserve(all), d.lines.reserve(all);
  if (!d.velocities.empty()) d.velocities.reserve(all), d.angularVelocities.reserve(all);
  const Real width = d.boxHi.x() - d.boxLo.x();
  for (int k = 1; k < n; ++k) {
    for (std::size_t i = 0; i < one; ++i) {
      d.ids.push_back(d.ids[i] + static_cast<std::int64_t>(k * one));
      d.types.push_back(d.types[i]);
      d.diameters.push_back(d.diameters[i]);
      d.densities.push_back(d.densities[i]);
      d.positions.push_back(d.positions[i] + Vec3(k * width, 0, 0));
      d.lines.push_back(d.lines[i]);
      if (!d.velocities.empty()) {
        d.velocities.push_back(d.velocities[i]);
        d.angularVelocities.push_back(d.angularVelocities[i]);
      }
    }
  }
  d.boxHi.x() = d.boxLo.x() + n * width;
  return d;
}

// Returns the scene of `d` for variant v, ready to run; changes nothing else. Throws
// demlab::Error from the Simulation API when the scene is refused.
std::unique_ptr<sim::Simulation> buildScene(const io::SphereData& d, const Options& o,
                                            const Variant& v) {
  auto s = sim::makeSimulation(3);
  sim::MaterialDef m;
  m.young = 5e6;
  m.poisson = 0.3;
  m.restitution = 0.5;
  m.friction = v.friction ? 0.5 : 0.0;
  // One material per distinct density (the benchmark files have one: 2500 kg/m^3).
  std::map<double, std::string> materialOf;
  for (double rho : d.densities) {
    if (materialOf.contains(rho)) continue;
    const std::string name = "rho" + std::to_string(materialOf.size());
    m.density = rho;
    s->addMaterial(name, m);
    materialOf.emplace(rho, name);
  }
  m.density = d.densities.empty() ? 2500 : d.densities.front();
  s->addMaterial("wall", m);
  s->setContactLaw(sim::LawKind::HertzMindlin);
  if (v.peerPhysics) {
    // LIGGGHTS's Coulomb test (the spring force alone), so the scene is the peers' scene.
    s->setCoulombCriterion(demlab::physics::CoulombCriterion::Spring);
    // And LIGGGHTS's Hertz damping, not the calibrated default: the peers' physics, so the
    // contact counts and digests stay comparable with theirs and with earlier records.
    s->setHertzDamping(demlab::physics::HertzDamping::Liggghts);
  }

  // Five walls on the box faces, normals pointing into the box; the top stays open.
  const sim::Vec3d lo{d.boxLo.x(), d.boxLo.y(), d.boxLo.z()};
  const sim::Vec3d hi{d.boxHi.x(), d.boxHi.y(), d.boxHi.z()};
  struct Face {
    const char* name;
    int axis;
    bool high;
  };
  for (const Face f : {Face{"xlo", 0, false}, Face{"xhi", 0, true}, Face{"ylo", 1, false},
                       Face{"yhi", 1, true}, Face{"zlo", 2, false}}) {
    sim::WallDef w;
    w.shape = sim::WallShape::Plane;
    w.point = f.high ? hi : lo;
    w.normal[f.axis] = f.high ? -1.0 : 1.0;
    w.material = "wall";
    w.name = f.name;
    s->addWall(w);
  }
  // A tiled scene is that many copies of the bed, each in its own box: a two-sided rectangle
  // where two copies meet takes the place of their side walls there (without it the grains at
  // the seam would move, and the copies search far more often than one bed does).
  const double width = (hi[0] - lo[0]) / o.tile;
  for (int k = 1; k < o.tile; ++k) {
    sim::WallDef w;
    w.shape = sim::WallShape::Finite;
    w.point = {lo[0] + k * width, 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    w.normal = {1, 0, 0};
    w.axis = {0, 1, 0};
    w.halfExtents = {0.5 * (hi[1] - lo[1]), 0.5 * (hi[2] - lo[2]), 0};
    w.material = "wall";
    w.name = "seam" + std::to_string(k);
    s->addWall(w);
  }
  s->addGravity({0, 0, -9.81});
  s->setOptions({{"rotation", "on", v.rotation},
                 {"touch", "on", v.touch},
                 {"detection", "cellfactor", o.cellFactor},
                 {"detection", "skin", o.skin}});
  if (!o.integrator.empty()) {
    s->setOption("integrator", "name", o.integrator);
  } else if (v.peerPhysics) {
    s->setOption("integrator", "name", std::string("verlet"));  // LIGGGHTS's nve/sphere
  }

  s->reserveElements(d.size());
  std::vector<sim::ElementDef> batch;
  batch.reserve(std::min(kBatch, d.size()));
  for (std::size_t i = 0; i < d.size(); ++i) {
    sim::ElementDef g;
    g.position = {d.positions[i].x(), d.positions[i].y(), d.positions[i].z()};
    if (!d.velocities.empty()) {
      const auto& u = d.velocities[i];
      const auto& w = d.angularVelocities[i];
      g.velocity = {u.x(), u.y(), u.z()};
      g.angularVelocity = {w.x(), w.y(), w.z()};
    }
    g.radius = d.diameters[i] / 2;
    g.material = materialOf.at(d.densities[i]);
    batch.push_back(std::move(g));
    if (batch.size() == kBatch || i + 1 == d.size()) {
      s->addElements(batch);
      batch.clear();
    }
  }
  s->setTimeStep(o.dt > 0 ? o.dt : kRayleighFraction * s->criticalTimeStep());
  return s;
}

// Returns the number of grain-grain contacts with positive overlap.
uint64_t grainContacts(const sim::Simulation& s) {
  uint64_t n = 0;
  for (const auto& c : s.contacts()) {
    if (!c.b.isNull() && c.overlap > 0) ++n;
  }
  return n;
}

// The process's peak resident set before any scene was read: the program, its libraries and
// the C++ runtime, which a per-particle memory figure should leave out.
double baselineRssMb = 0;

// Runs one scene variant of the data file at path; prints its CSV row on stdout and its
// breakdown on stderr. Throws demlab::Error when the file cannot be read or the scene is refused.
void runOne(const std::string& path, const Options& o, const Variant& v) {
  // The file's contents go once the scene is built: they are not part of what a run holds.
  std::unique_ptr<sim::Simulation> s;
  std::size_t n = 0;
  {
    const io::SphereData d = tiled(io::readLammpsData(path), o.tile);
    s = buildScene(d, o, v);
    n = d.size();
  }
  const mpi::Communicator& comm = mpi::Communicator::world();
  if (comm.distributed()) s->distribute();
  // Rank 0 alone writes, the others' stdout (and stderr, unless --all-ranks) go nowhere.
  if (comm.rank() != 0) {
    std::fflush(stdout);
    std::fflush(stderr);
    (void)!std::freopen("/dev/null", "w", stdout);
    if (!o.allRanks) (void)!std::freopen("/dev/null", "w", stderr);
  }
  // The reader's and the scene builder's small blocks (the file's ids, types and radii, the
  // checked Defs of each batch) were freed below blocks still in use, where the allocator
  // keeps their pages resident: returned to the system now, before the run.
  malloc_trim(0);
  // (Appended piece by piece: GCC 12 warns of an overlap that is not there in "@r" + string.)
  std::string name = io::sceneName(path);
  if (o.tile > 1) name.append(1, 'x').append(std::to_string(o.tile));
  name += v.suffix;
  if (comm.distributed()) name.append("@r").append(std::to_string(comm.size()));
  std::string modules;
  for (const auto& m : s->listModules()) modules += (modules.empty() ? "" : " ") + m;

  // What reading, building and distributing the scene held at most, before the run.
  const double rssBuilt = comm.sum(peakRssMb());
  sim::RunOptions ro;
  ro.steps = o.steps;
  const double load1 = loadAverage();
  const double cpu0 = cpuSeconds();
  comm.barrier();
  const auto t0 = std::chrono::steady_clock::now();
  const sim::RunReport r = s->run(ro);
  const double cpu = cpuSeconds() - cpu0;
  const double seconds = comm.max(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  const double rss = comm.sum(peakRssMb());
  const uint64_t contacts =
      static_cast<uint64_t>(comm.sum(static_cast<int64_t>(grainContacts(*s))));
  const double perGrain = static_cast<double>(std::max<std::size_t>(n, 1));

  std::printf("demlab,%s,%zu,%llu,%.4f,%.0f,%llu,%.1f\n", name.c_str(), n,
              static_cast<unsigned long long>(r.steps), seconds,
              static_cast<double>(n) * static_cast<double>(r.steps) / seconds,
              static_cast<unsigned long long>(contacts), rss);
  std::fflush(stdout);

  std::fprintf(stderr, "# demlab %s: dt %.4g s, %llu steps, modules: %s\n", name.c_str(),
               s->timeStep(), static_cast<unsigned long long>(r.steps), modules.c_str());
  std::fprintf(stderr,
               "#   %.4f s (CPU %.4f s: a shared machine may have taken the rest), %llu contacts "
               "(RunReport: %llu), %llu searches, energy residual "
               "%.3g, peak RSS %.0f bytes/grain (%.0f above the %.1f MB before reading)\n",
               seconds, cpu, static_cast<unsigned long long>(contacts),
               static_cast<unsigned long long>(r.contacts),
               static_cast<unsigned long long>(r.neighborRebuilds), r.energyResidual,
               rss * 1048576.0 / perGrain, (rss - baselineRssMb) * 1048576.0 / perGrain,
               baselineRssMb);
  std::fprintf(stderr, "#   peak RSS before the run (reading, building%s): %.0f bytes/grain\n",
               comm.distributed() ? ", distributing; summed over the ranks" : "",
               rssBuilt * 1048576.0 / perGrain);
  if (comm.distributed()) {
    // The step's messages: each copy a rank sends carries x, v, w (and fPrev with the touch
    // correction), each ghost's answer f, t (and the velocity change).
    const sim::Simulation::DistributionReport dr = s->distribution();
    const bool touch = modules.find("touch") != std::string::npos;
    const double owned = comm.max(static_cast<double>(dr.owned));
    const double ghosts = comm.max(static_cast<double>(dr.ghosts));
    const double copies = comm.max(static_cast<double>(dr.copiesSent));
    const double forward = copies * (touch ? 96 : 72), back = ghosts * (touch ? 72 : 48);
    std::fprintf(stderr,
                 "#   ranks %d: the largest owns %.0f elements and holds %.0f ghosts (%.3f of its "
                 "own), sends %.0f copies a step: %.0f bytes forward, %.0f back; %llu searches, "
                 "%llu bisections, %llu elements migrated (rank 0)\n",
                 comm.size(), owned, ghosts, ghosts / std::max(owned, 1.0), copies, forward, back,
                 static_cast<unsigned long long>(dr.searches),
                 static_cast<unsigned long long>(dr.bisections),
                 static_cast<unsigned long long>(dr.migrated));
  }
  const sim::MemoryReport m = s->memory();
  std::fprintf(stderr,
               "#   heap per grain: %.0f bytes (grains %.0f, detection %.0f, search scratch %.0f, "
               "springs %.0f, contact records %.0f, pass scratch %.0f)\n",
               static_cast<double>(m.total()) / perGrain, static_cast<double>(m.grains) / perGrain,
               static_cast<double>(m.detection) / perGrain,
               static_cast<double>(m.search) / perGrain, static_cast<double>(m.springs) / perGrain,
               static_cast<double>(m.contacts) / perGrain, static_cast<double>(m.passes) / perGrain);
  if (o.contactStep && r.steps > 0) {
    // Repeated for at least 0.2 s: one call is a pass over the candidates.
    int calls = 0;
    double value = 0;
    const auto c0 = std::chrono::steady_clock::now();
    double spent = 0;
    while (spent < 0.2 || calls < 3) {
      value = s->contactCriticalTimeStep();
      ++calls;
      spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count();
    }
    const double call = spent / calls, step = seconds / static_cast<double>(r.steps);
    // The automatic step measures it every kContactStepEvery (100) steps.
    std::fprintf(stderr,
                 "#   contacts' critical step %.4g s (%.3g of the static estimate): %.1f us a "
                 "measure, %.2f steps' time, %.2f %% of a run measuring every 100 steps\n",
                 value, value / s->criticalTimeStep(), 1e6 * call, call / step,
                 100 * call / (call + 100 * step));
  }
  // After the peak RSS is read: the digest serializes the whole scene.
  if (o.digest) {
    std::fprintf(stderr, "#   state digest %016llx\n",
                 static_cast<unsigned long long>(s->stateDigest()));
  }
  std::FILE* bd = o.breakdown.empty() ? nullptr : std::fopen(o.breakdown.c_str(), "a");
  if (!o.breakdown.empty() && bd == nullptr) {
    std::fprintf(stderr, "bench_sim: couldn't open \"%s\" for appending\n", o.breakdown.c_str());
  }
  double accounted = 0;
  for (const auto& m : r.modules) {
    const double share = seconds > 0 ? m.seconds / seconds : 0;
    accounted += m.seconds;
    std::fprintf(stderr, "#   %-18s %9.4f s %5.1f%%\n", m.module.c_str(), m.seconds, 100 * share);
    if (bd != nullptr)
      std::fprintf(bd, "%s,%s,%.6f,%.4f\n", name.c_str(), m.module.c_str(), m.seconds, share);
  }
  std::fprintf(stderr, "#   %-18s %9.4f s %5.1f%%\n", "(other)", seconds - accounted,
               seconds > 0 ? 100 * (seconds - accounted) / seconds : 0);
  if (bd != nullptr) std::fclose(bd);
  if (!o.cpu.empty()) {
    std::FILE* f = std::fopen(o.cpu.c_str(), "a");
    if (f == nullptr) {
      std::fprintf(stderr, "bench_sim: couldn't open \"%s\" for appending\n", o.cpu.c_str());
    } else {
      std::fprintf(f, "demlab,%s,%zu,%llu,%.3f,%.0f,%.2f\n", name.c_str(), n,
                   static_cast<unsigned long long>(r.steps), cpu,
                   static_cast<double>(n) * static_cast<double>(r.steps) / cpu, load1);
      std::fclose(f);
    }
  }
}

int main(int argc, char** argv) {
  // Blocks of 128 KiB and more (every per-grain array of these scenes) get a mapping of their
  // own, which goes back to the system when freed. glibc otherwise raises that threshold to
  // the largest block freed so far (the reader's 256 KiB line and zlib buffers), and the grain,
  // search and contact arrays are then carved from one heap, where the holes the file's data
  // and each search's scratch leave stay resident: 1.4 MB of the 10k bed's peak (140 bytes a
  // grain), measured.
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
  const Options o = parse(argc, argv);
  baselineRssMb = peakRssMb();
  if (o.header && mpi::Communicator::world().rank() == 0)
    std::printf("code,scene,n,steps,seconds,particle_steps_per_s,contacts,peak_rss_mb\n");
  int status = 0;
  for (const auto& path : o.data) {
    try {
      for (const Variant* v : o.variants) runOne(path, o, *v);
    } catch (const Error& e) {
      std::string code;
      for (const auto& w : e.code()) code += (code.empty() ? "" : " ") + w;
      std::fprintf(stderr, "bench_sim: %s [%s]\n", e.what(), code.c_str());
      status = 1;
    }
  }
  return status;
}

}  // namespace
}  // namespace demlab::bench

int main(int argc, char** argv) {
  const demlab::mpi::Session mpi(&argc, &argv);
  return demlab::bench::main(argc, argv);
}
