// The "pack" group: many elements at once, all or none (Simulation::addElements): a lattice, a
// random non-overlapping packing of a region with a size distribution, or a file. The elements
// are laid out in the check phase, so a failure adds nothing.
#include <algorithm>
#include <cmath>
#include <random>
#include <unordered_map>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/free_aside.hpp"
#include "core/interrupt.hpp"
#include "core/memory_budget.hpp"
#include "core/tag_table.hpp"
#include "core/validity.hpp"
#include "io/lammps_data.hpp"
#include "io/line_reader.hpp"
#include "sim/packing.hpp"
#include "sim/source.hpp"

namespace demlab::cmd {

namespace {

using sim::Vec3d;

using sim::Region;
using SizeDist = sim::SizeDistribution;

}  // namespace

PipeType regionType() {
  PipeType t =
      custom("region", [](std::string_view w, const Param& p, const Context& c) -> std::any {
        auto bad = [&](const std::string& why) -> Error {
          return Error("bad region \"" + std::string(w) + "\": " + why, {"VALUE", "REGION"});
        };
        std::vector<std::string> parts;
        try {
          parts = splitList(w);
        } catch (const Error& e) {
          throw bad(e.what());
        }
        int d = c.dimension();
        Param q = p;
        q.type = vector().range(-validity::kMaxCoordinate, validity::kMaxCoordinate);
        auto length = [&](const std::string& word, double& out) {
          return readReal(word, out) && out > 0 && out <= validity::kMaxCoordinate;
        };
        Region r;
        if (parts.size() == 3 && parts[0] == "box") {
          auto lo = std::any_cast<std::vector<double>>(convertWord(parts[1], q, c));
          auto hi = std::any_cast<std::vector<double>>(convertWord(parts[2], q, c));
          r.lo = vec3(lo), r.hi = vec3(hi);
          for (int k = 0; k < d; ++k)
            if (!(r.hi[k] > r.lo[k]))
              throw bad("the upper corner must exceed the lower one on every axis");
          return r;
        }
        if (parts.size() == 3 && parts[0] == "sphere") {
          r.kind = Region::Sphere;
          r.centre = vec3(std::any_cast<std::vector<double>>(convertWord(parts[1], q, c)));
          if (!length(parts[2], r.radius))
            throw bad("the radius must be a positive number, at most 1e15");
          return r;
        }
        if (parts.size() == 5 && parts[0] == "cylinder") {
          if (d == 2) throw bad("a cylinder is a 3D region");
          r.kind = Region::Cylinder;
          r.centre = vec3(std::any_cast<std::vector<double>>(convertWord(parts[1], q, c)));
          const auto axis = std::any_cast<std::vector<double>>(convertWord(parts[2], q, c));
          const double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
          if (!(n > 0)) throw bad("the axis must be a non-zero vector");
          r.axis = {axis[0] / n, axis[1] / n, axis[2] / n};
          if (!length(parts[3], r.radius) || !length(parts[4], r.halfLength))
            throw bad("the radius and half length must be positive numbers, at most 1e15");
          return r;
        }
        throw bad(
            "must be {box {lo} {hi}}, {sphere {centre} radius} or {cylinder {centre} {axis} "
            "radius halflength}");
      });
  t.choices = {"box", "sphere", "cylinder"};
  return t;
}

PipeType sizeType() {
  PipeType t =
      custom("size distribution", [](std::string_view w, const Param&, const Context&) -> std::any {
        auto bad = [&](const std::string& why) -> Error {
          return Error("bad radius \"" + std::string(w) + "\": " + why, {"VALUE", "RADIUS"});
        };
        std::vector<std::string> parts;
        try {
          parts = splitList(w);
        } catch (const Error& e) {
          throw bad(e.what());
        }
        SizeDist s;
        std::size_t first = 1;
        if (parts.size() == 1) {
          s.kind = "constant";
          first = 0;
        } else if (!parts.empty()) {
          static const std::vector<std::string> kinds{"uniform", "normal", "powerlaw", "discrete"};
          s.kind = matchChoice(parts[0], kinds, "distribution", {"VALUE", "RADIUS"});
        } else {
          throw bad("must be a radius or a distribution");
        }
        for (std::size_t k = first; k < parts.size(); ++k) {
          double x;
          if (!readReal(parts[k], x) || !std::isfinite(x))
            throw bad("expected a number but got \"" + parts[k] + "\"");
          s.p.push_back(x);
        }
        const auto& p = s.p;
        if (s.kind == "constant" && !(p[0] > 0)) throw bad("must be a positive number");
        if (s.kind == "uniform" && (p.size() != 2 || !(p[0] > 0) || !(p[1] >= p[0]))) {
          throw bad("should be {uniform min max} with 0 < min <= max");
        }
        if (s.kind == "powerlaw" &&
            (p.size() != 3 || !(p[0] > 0) || !(p[1] >= p[0]) || !(std::abs(p[2]) <= 1000))) {
          throw bad("should be {powerlaw min max exponent} with 0 < min <= max and an exponent "
                    "from -1000 to 1000");
        }
        if (s.kind == "normal" && (p.size() != 2 || !(p[0] > 0) || !(p[1] >= 0))) {
          throw bad("should be {normal mean sd} with mean > 0 and sd >= 0");
        }
        if (s.kind == "discrete") {
          bool ok = p.size() >= 2 && p.size() % 2 == 0;
          double total = 0;
          for (std::size_t k = 0; ok && k < p.size(); k += 2) {
            ok = p[k] > 0 && p[k + 1] >= 0;
            total += p[k + 1];
          }
          if (!ok || !(total > 0))
            throw bad("should be {discrete r1 w1 r2 w2 ...} with radii > 0 and weights >= 0");
        }
        // Every radius it can draw within the validity policy's range (core/validity.hpp).
        const double lo = s.kind == "discrete" || s.kind == "normal" ? 0 : p[0];
        if (s.maxRadius() > validity::kMaxRadius || (lo > 0 && lo < validity::kMinRadius)) {
          throw bad("radii must be from " + formatReal(validity::kMinRadius) + " to " +
                    formatReal(validity::kMaxRadius) + " m");
        }
        return s;
      });
  t.choices = {"uniform", "normal", "powerlaw", "discrete"};
  return t;
}

namespace {

// A shape parameter of a packing: a number, or {uniform min max} drawn for each element.
struct ParamRange {
  double lo = 0, hi = 0;
};

// The type of pack random -params: a list of numbers or {uniform min max}, {VALUE PARAMS}.
PipeType shapeParamsType() {
  return custom("shape parameters", [](std::string_view w, const Param&, const Context&) -> std::any {
    auto bad = [&](const std::string& why) -> Error {
      return Error("bad params \"" + std::string(w) + "\": " + why, {"VALUE", "PARAMS"});
    };
    std::vector<std::string> items;
    try {
      items = splitList(w);
    } catch (const Error& e) {
      throw bad(e.what());
    }
    std::vector<ParamRange> out;
    for (const std::string& item : items) {
      std::vector<std::string> parts;
      try {
        parts = splitList(item);
      } catch (const Error& e) {
        throw bad(e.what());
      }
      ParamRange r;
      if (parts.size() == 1 && readReal(parts[0], r.lo) && std::isfinite(r.lo)) {
        r.hi = r.lo;
      } else if (parts.size() == 3 && parts[0] == "uniform" && readReal(parts[1], r.lo) &&
                 readReal(parts[2], r.hi) && std::isfinite(r.lo) && std::isfinite(r.hi) &&
                 r.lo <= r.hi) {
      } else {
        throw bad("each must be a finite number or {uniform min max} with min <= max, not \"" +
                  item + "\"");
      }
      out.push_back(r);
    }
    return out;
  });
}

// Declares the options every pack command shares.
void commonOptions(Command& c) {
  c.option("material", materialRef(), "their material (default: the first material defined)");
  c.option("velocity", vector().withUnit("m/s"), "their velocity");
  c.option("tags", tagList(), "tags to give each of them");
}

// Returns the Def every packed element starts from (material, velocity, tags).
sim::ElementDef baseDef(const Call& c, const sim::Simulation& s) {
  sim::ElementDef d;
  d.material = materialOrFirst(c, s);
  if (c.has("velocity")) d.velocity = vec3(c.vec("velocity"));
  d.tags = tagsOption(c);
  return d;
}

using sim::kMaxPack;

// What an element costs while it is made and once it is in the scene (its definition, state
// arrays, search boxes and a few contacts), rounded up: the memory check before a packing.
constexpr double kBytesPerElement = 1024;

// Adds the elements the check phase defined; returns their ids. The definitions are taken
// out of the call (any_cast by value copied them: half a second, unpolled, for half a million)
// and freed on a thread of their own however the commit ends.
Value addAll(Call& c) {
  std::vector<sim::ElementDef> defs =
      std::any_cast<std::vector<sim::ElementDef>>(std::move(c.prepared));
  const FreeAsideOnThrow aside(defs);
  // The result's room made while Ctrl-C is polled: after the commit nothing may stop.
  Ints l;
  l.data.reserve(defs.size());
  touchRoom(l.data, defs.size(), std::int64_t{0}, "adding elements");
  auto ids = session(c).scene().addElements(defs);
  freeAside(std::move(defs));
  for (auto g : ids) l.data.push_back(scriptId(g));
  return l;
}

// Returns the spheres of an xyzr file (one a line: centre, radius, and optionally a velocity;
// # starts a comment) in dimension dim, as a data file's: diameters, positions, velocities (all
// zero when no line gives one) and lines; moving says which lines gave a velocity. Throws
// {IO FORMAT} or {VALUE NUMBER} naming the file and line, {INTERRUPTED}.
io::SphereData readXyzr(const std::string& path, int dim, std::vector<char>& moving) {
  io::SphereData data;
  io::LineReader in(path);
  std::string_view line;
  const std::size_t d = std::size_t(dim);
  bool anyMoving = false;
  while (in.next(line)) {
    std::vector<std::string> f = splitList(std::string(line.substr(0, line.find('#'))));
    if (f.empty()) continue;
    const std::size_t n = f.size();
    if (n != d + 1 && n != 2 * d + 1) {
      throw Error("expected " + std::to_string(d + 1) + " or " + std::to_string(2 * d + 1) +
                      " numbers (centre, radius, ?velocity?) but got " + std::to_string(n),
                  {"IO", "FORMAT"})
          .within(in.where());
    }
    double x[7] = {0, 0, 0, 0, 0, 0, 0};
    for (std::size_t j = 0; j < n; ++j) {
      if (!readReal(f[j], x[j]) || !std::isfinite(x[j])) {
        throw Error("expected floating-point number but got \"" + f[j] + "\"", {"VALUE", "NUMBER"})
            .within(in.where());
      }
    }
    Vec3 p = Vec3::Zero(), v = Vec3::Zero();
    for (std::size_t j = 0; j < d; ++j) p[Eigen::Index(j)] = x[j];
    const bool given = n == 2 * d + 1;
    if (given)
      for (std::size_t j = 0; j < d; ++j) v[Eigen::Index(j)] = x[d + 1 + j];
    data.ids.push_back(std::int64_t(data.ids.size() + 1));
    data.diameters.push_back(2 * x[d]);
    data.positions.push_back(p);
    data.velocities.push_back(v);
    data.lines.push_back(in.lineNumber());
    moving.push_back(given);
    anyMoving = anyMoving || given;
  }
  if (!anyMoving) {
    data.velocities.clear();
    moving.clear();
  }
  return data;
}

}  // namespace

void registerPackCommands(Registry& r) {
  r.describe("pack", "Many elements at once, all or none: a lattice, a random packing, or a file.");

  Command& lat =
      r.add("pack lattice",
            "Fills a region with a regular lattice of equal elements; returns their ids.");
  lat.interruptible = true;
  lat.option("region", regionType(), "{box {lo} {hi}} or {sphere {centre} radius}").require();
  lat.option("radius", real().positive().withUnit("m"), "radius of every element").require();
  lat.option("spacing", real().positive().withUnit("m"),
             "distance between neighbours (default: one diameter)");
  lat.option("kind", choice({"cubic", "hex"}),
             "cubic (square in 2D) or hex (triangular in 2D, FCC in 3D)")
      .byDefault("cubic");
  commonOptions(lat);
  lat.onCheck([](Call& c) {
    auto& s = session(c).scene();
    int d = s.dim();
    Region reg = c.get<Region>("region");
    double rad = c.real("radius");
    double a = c.has("spacing") ? c.real("spacing") : 2 * rad;
    if (a < 2 * rad * (1 - 1e-12))
      c.bad("spacing", "must be at least one diameter, " + formatReal(2 * rad));
    sim::LatticeDef lattice{reg, rad, a, c.str("kind") == "hex"};
    if (sim::latticeCandidates(lattice, d) > double(kMaxPack))
      c.bad("radius", "would make more than 2^27 elements");
    checkMemoryBudget(sim::latticeCandidates(lattice, d) * kBytesPerElement,
                      "a lattice of " + formatReal(sim::latticeCandidates(lattice, d)) + " sites");
    sim::ElementDef base = baseDef(c, s);
    base.radius = rad;
    const std::vector<Vec3d> sites = sim::latticeSites(lattice, d);
    std::vector<sim::ElementDef> defs;
    const FreeAsideOnThrow aside(defs);
    defs.reserve(sites.size());
    InterruptPoll poll("pack");
    for (const Vec3d& p : sites) {
      poll();
      base.position = p;
      defs.push_back(base);
    }
    if (defs.empty()) c.bad("region", "holds no element of radius " + formatReal(rad));
    c.prepared = std::move(defs);
  });
  lat.run(addAll);

  Command& rnd =
      r.add("pack random",
            "Fills a region with randomly placed, non-overlapping elements; returns their ids.");
  rnd.interruptible = true;
  rnd.details =
      "Random sequential addition, largest first, avoiding each other and the elements already in "
      "the "
      "scene. Reproducible: the same -seed gives the same packing. Fails, adding nothing, if some "
      "element "
      "finds no place in -tries attempts.";
  rnd.option("region", regionType(), "{box {lo} {hi}} or {sphere {centre} radius}").require();
  rnd.option("radius", sizeType().withUnit("m"),
             "a radius, or {uniform a b}, {normal mean sd}, {powerlaw a b exponent}, {discrete r1 "
             "w1 ...}")
      .require();
  rnd.option("count", integer().min(1), "number of elements");
  rnd.option("fraction", real().positive().max(0.9),
             "target solid fraction of the region instead of a count");
  rnd.oneOf({"count", "fraction"}, true);
  rnd.option("seed", integer().nonNegative(), "random seed").byDefault("1");
  rnd.option("tries", integer().min(1), "attempts per element before giving up").byDefault("1000");
  rnd.option("shape", text("shape type"),
             "their shape type (default: the ball); -params gives its shape, scaled about its "
             "centre so that each element's bounding radius is the radius drawn");
  rnd.option("params", shapeParamsType(),
             "the shape's parameters (as element add -params), each a number or {uniform min "
             "max} drawn for each element (aspect ratios, blockiness)");
  rnd.option("orientation", choice({"identity", "random"}),
             "their orientation: identity (the default) or random (uniform over the rotations)");
  commonOptions(rnd);
  rnd.onCheck([](Call& c) {
    auto& s = session(c).scene();
    int d = s.dim();
    Region reg = c.get<Region>("region");
    const SizeDist& dist = c.get<SizeDist>("radius");
    std::mt19937_64 rng(std::uint64_t(c.integer("seed")));
    std::size_t count = 0;
    if (c.given("count")) {
      if (std::uint64_t(c.integer("count")) > kMaxPack) c.bad("count", "must be at most 2^27");
      checkMemoryBudget(double(c.integer("count")) * kBytesPerElement,
                        std::to_string(c.integer("count")) + " elements");
      count = std::size_t(c.integer("count"));
    }
    const std::vector<double> radii =
        sim::drawRadii(dist, reg, d, count, c.given("count") ? 0.0 : c.real("fraction"), rng);
    const std::vector<Vec3d> sites = sim::randomSites(reg, d, radii, s.positions(), s.radii(),
                                                      c.integer("tries"), rng, &session(c).stop);
    sim::ElementDef base = baseDef(c, s);
    // A shape other than the ball: its parameters for each radius drawn (the placement keeps
    // the bounding balls apart, a loose start that a settling run compacts).
    const std::string shape = c.given("shape") ? c.str("shape") : s.shapeNames().front();
    const std::vector<ParamRange> ranges =
        c.given("params") ? c.get<std::vector<ParamRange>>("params") : std::vector<ParamRange>{};
    const bool ball = shape == s.shapeNames().front();
    if (ball && !ranges.empty()) c.bad("params", "a " + shape + " takes none (its size is -radius)");
    std::vector<double> params(ranges.size()), hi(ranges.size());
    for (std::size_t k = 0; k < ranges.size(); ++k) params[k] = ranges[k].lo, hi[k] = ranges[k].hi;
    if (!ball) {  // {VALUE SHAPE} before any work, at both ends of every range
      s.shapeParamsForBound(shape, params, 1);
      s.shapeParamsForBound(shape, hi, 1);
    }
    uint64_t turnState = rng();
    sim::SplitMix64 turn{turnState};
    const bool randomTurn = c.has("orientation") && c.str("orientation") == "random";
    std::vector<sim::ElementDef> defs;
    const FreeAsideOnThrow aside(defs);
    defs.reserve(radii.size());
    InterruptPoll poll("pack");
    for (std::size_t k = 0; k < sites.size(); ++k) {
      poll();
      base.position = sites[k];
      if (ball) {
        base.radius = radii[k];
      } else {
        base.shape = shape;
        for (std::size_t j = 0; j < ranges.size(); ++j) {
          params[j] = ranges[j].lo == ranges[j].hi
                          ? ranges[j].lo
                          : std::uniform_real_distribution<double>(ranges[j].lo, ranges[j].hi)(rng);
        }
        base.shapeParams = s.shapeParamsForBound(shape, params, radii[k]);
      }
      if (randomTurn) {
        base.orientation = d == 2 ? sim::randomOrientation<2>(turn) : sim::randomOrientation<3>(turn);
      }
      defs.push_back(base);
    }
    c.prepared = std::move(defs);
  });
  rnd.run(addAll);

  Command& file = r.add("pack file", "Adds the elements listed in a file; returns their ids.");
  file.interruptible = true;
  file.details =
      "Formats: xyzr (one element per line: the centre's coordinates then the radius, optionally "
      "followed "
      "by the velocity; # starts a comment) and lammps (a LAMMPS data file of spheres, atom_style "
      "sphere, "
      "gzip'd or plain; velocities are read when present). auto picks lammps for names ending in "
      ".data, "
      ".data.gz or .lmp.";
  file.arg("file", text("file"), "the file to read");
  file.option("format", choice({"auto", "xyzr", "lammps"}), "the file's format").byDefault("auto");
  file.option("scale", real().positive(), "multiply lengths (and velocities) by this")
      .byDefault("1");
  commonOptions(file);
  file.onCheck([](Call& c) {
    auto& s = session(c).scene();
    int d = s.dim();
    std::string path = c.str("file"), fmtName = c.str("format");
    double k = c.real("scale");
    if (fmtName == "auto") {
      auto ends = [&](std::string_view e) {
        return path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
      };
      fmtName = ends(".data") || ends(".data.gz") || ends(".lmp") ? "lammps" : "xyzr";
    }
    std::vector<char> moving;  // xyzr: whether each line gives a velocity
    const io::SphereData data =
        fmtName == "lammps" ? io::readLammpsData(path) : readXyzr(path, d, moving);
    if (data.size() == 0) throw Error("no elements in \"" + path + "\"", {"IO", "FORMAT"});
    sim::ElementDef base = baseDef(c, s);
    const Vec3d velocity = base.velocity;  // of a line that gives none
    // Made to size (grown by doubling, half a million definitions were moved in unpolled
    // calls) and freed aside when stopped.
    std::vector<sim::ElementDef> defs;
    const FreeAsideOnThrow aside(defs);
    defs.reserve(data.size());
    const std::string origin = "file \"" + path + "\" line ";
    InterruptPoll poll("pack");
    for (std::size_t a = 0; a < data.size(); ++a) {
      poll();
      base.radius = k * data.diameters[a] / 2;
      for (int j = 0; j < 3; ++j) base.position[std::size_t(j)] = k * data.positions[a][j];
      const bool given = !data.velocities.empty() && (moving.empty() || moving[a]);
      for (int j = 0; j < 3; ++j)
        base.velocity[std::size_t(j)] = given ? k * data.velocities[a][j] : velocity[std::size_t(j)];
      if (!data.angularVelocities.empty()) {
        for (int j = 0; j < 3; ++j)
          base.angularVelocity[std::size_t(j)] = data.angularVelocities[a][j];
      }
      base.origin = origin + std::to_string(data.lines[a]);
      defs.push_back(base);
    }
    c.prepared = std::move(defs);
  });
  file.run(addAll);
}

}  // namespace demlab::cmd
