// The "inlet" and "sink" groups: elements inserted into a region during runs (the scene's
// sources; the group is not called "source", which would hide Tcl's own command), and removed
// when they enter (or leave) a region or cross a plane (sim/boundaries.hpp). The Defs are built
// and checked by the scene before anything changes.
#include <cmath>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/tag_table.hpp"
#include "sim/boundaries.hpp"

namespace demlab::cmd {

namespace {

const char* const kRegionHelp =
    "{box {lo} {hi}}, {sphere {centre} radius} or {cylinder {centre} {axis} radius halflength}";

// Returns the counters of a source or sink as a dict: count, mass, rate (mass per second since
// it started), start, description.
Dict counterDict(const sim::BoundaryInfo& x, double now) {
  const double elapsed = now - x.start;
  return {{"name", x.name},   {"count", Value(x.count)},
          {"mass", x.mass},   {"rate", elapsed > 0 ? x.mass / elapsed : 0.0},
          {"start", x.start}, {"description", x.description}};
}

// Returns the info named name from list. Throws {LOOKUP NAME}.
const sim::BoundaryInfo& findInfo(const std::vector<sim::BoundaryInfo>& list,
                                  const std::string& name, const char* kind) {
  for (const sim::BoundaryInfo& x : list)
    if (x.name == name) return x;
  throw Error("can't find " + std::string(kind) + " \"" + name + "\"", {"LOOKUP", "NAME"});
}

// Declares `GROUP list`, `GROUP get NAME` and `GROUP remove NAME` for sources or sinks.
void declareCounters(Registry& r, const std::string& group,
                     std::vector<sim::BoundaryInfo> (sim::Simulation::*infos)() const,
                     void (sim::Simulation::*remove)(const std::string&)) {
  Command& list = r.add(group + " list", "Returns the names of the " + group + "s.");
  list.changesScene = false;
  list.run([infos](Call& c) {
    List l;
    for (const sim::BoundaryInfo& x : (session(c).scene().*infos)()) l.emplace_back(x.name);
    return Value(std::move(l));
  });
  Command& get =
      r.add(group + " get", "Returns a " + group +
                                "'s counters as a dict (count, mass, rate since its start, start, "
                                "description), or the one asked for.");
  get.arg("name", name(), "its name");
  for (const char* f : {"count", "mass", "rate", "start", "description"})
    get.flag(f, std::string("the ") + f);
  get.changesScene = false;
  get.run([infos, group](Call& c) {
    auto& s = session(c).scene();
    const Dict d = counterDict(findInfo((s.*infos)(), c.str("name"), group.c_str()), s.time());
    return pickFields(c, d);
  });
  Command& rm = r.add(group + " remove", "Removes a " + group + " (what it did stays done).");
  rm.arg("name", name(), "its name");
  rm.run([remove](Call& c) {
    (session(c).scene().*remove)(c.str("name"));
    return Value();
  });
}

}  // namespace

void registerBoundaryCommands(Registry& r) {
  r.describe("inlet", "Inlets (sources): elements inserted into a region during runs, at a rate.");
  r.describe("sink",
             "Sinks: elements removed during runs where they enter a region or cross a plane.");

  Command& src =
      r.add("inlet add",
            "Adds an inlet (a source) inserting elements into a region from the next step on, "
            "at a mass or number rate, never overlapping what is there by more than "
            "the tolerance.");
  src.arg("name", name(), "its name");
  src.option("region", regionType(), kRegionHelp).require();
  src.option("radius", sizeType(), "a radius or a size distribution, as pack random's").require();
  src.option("massrate", real().positive().withUnit("kg/s"), "mass inserted per second");
  src.option("rate", real().positive().withUnit("1/s"), "elements inserted per second");
  src.oneOf({"massrate", "rate"}, true);
  src.option("mass", real().withUnit("kg"), "stop after this mass (default: never)");
  src.option("count", integer(), "stop after this many elements (default: never)");
  src.option("material", materialRef(), "their material (default: the first material defined)");
  src.option("velocity", vector().withUnit("m/s"), "their mean velocity");
  src.option("jitter", real().withUnit("m/s"), "each velocity component uniform in +-jitter");
  src.option("tolerance", real(),
             "allowed placed overlap, a fraction of the smaller radius (default 0)");
  src.option("seed", integer(), "the seed of its generator (default 1)");
  src.option("tries", integer(), "placement attempts per element per step (default 200)");
  src.option("tags", tagList(), "tags to give each element");
  src.option("orientation", choice({"identity", "random"}),
             "their orientation: identity (the default) or random (uniform over the rotations)");
  src.option("shape", text("shape type"),
             "their shape type (default: the ball); -params gives its shape, scaled about its "
             "centre so that each element's bounding radius is the radius drawn");
  src.option("params", reals(), "the shape's parameters (as element add -params)");
  src.option("every", integer().range(1, sim::kMaxBoundaryEvery),
             "insert what it owes every N steps (default 1); each step that inserts redoes the "
             "force pass, so a large scene inserts in batches (50-200 steps)");
  src.onCheck([](Call& c) {
    const sim::Simulation& s = session(c).scene();
    sim::SourceDef d;
    d.name = c.str("name");
    d.region = c.get<sim::Region>("region");
    d.size = c.get<sim::SizeDistribution>("radius");
    d.material = materialOrFirst(c, s);
    if (c.has("massrate")) d.massRate = c.real("massrate");
    if (c.has("rate")) d.countRate = c.real("rate");
    if (c.has("mass")) {
      d.targetMass = c.real("mass");
      if (!(d.targetMass > 0 && std::isfinite(d.targetMass)))
        c.bad("mass", "must be a positive number");
    }
    if (c.has("count")) {
      if (c.integer("count") <= 0) c.bad("count", "must be a positive integer");
      d.targetCount = std::uint64_t(c.integer("count"));
    }
    if (c.has("velocity")) d.velocity = vec3(c.vec("velocity"));
    if (c.has("jitter")) d.jitter = c.real("jitter");
    if (c.has("tolerance")) d.tolerance = c.real("tolerance");
    if (c.has("seed")) {
      if (c.integer("seed") < 0) c.bad("seed", "must be a non-negative integer");
      d.seed = std::uint64_t(c.integer("seed"));
    }
    if (c.has("tries")) {
      if (c.integer("tries") < 1 || c.integer("tries") > 1000000)
        c.bad("tries", "must be an integer in [1, 1000000]");
      d.tries = std::uint32_t(c.integer("tries"));
    }
    d.tags = tagsOption(c);
    if (c.has("every")) d.every = std::uint32_t(c.integer("every"));
    d.randomOrientation = c.has("orientation") && c.str("orientation") == "random";
    if (c.given("shape") && c.str("shape") != s.shapeNames().front()) d.shape = c.str("shape");
    if (c.given("params")) d.shapeParams = c.get<std::vector<double>>("params");
    c.prepared = d;
  });
  src.run([](Call& c) {
    session(c).scene().addSource(std::any_cast<sim::SourceDef>(c.prepared));
    return Value(c.str("name"));
  });
  declareCounters(r, "inlet", &sim::Simulation::sources, &sim::Simulation::removeSource);

  Command& sink = r.add("sink add",
                        "Adds a sink removing, at the end of each step from the next on, every "
                        "element whose centre is in a region (outside it with -outside 1) or "
                        "beyond a plane (against its normal).");
  sink.arg("name", name(), "its name");
  sink.option("region", regionType(), kRegionHelp);
  sink.option("outside", boolean(), "remove what leaves the region instead of what enters it");
  sink.option("point", vector().withUnit("m"), "a point of the plane");
  sink.option("normal", vector(), "the plane's normal, towards the side that is kept");
  sink.option("every", integer().range(1, sim::kMaxBoundaryEvery),
              "remove what it takes every N steps (default 1); each step that removes redoes "
              "the force pass, so a large scene removes in batches (50-200 steps)");
  sink.onCheck([](Call& c) {
    sim::SinkDef d;
    d.name = c.str("name");
    if (c.has("every")) d.every = std::uint32_t(c.integer("every"));
    const bool region = c.given("region"), plane = c.given("point") || c.given("normal");
    if (region == plane)
      throw Error("bad sink: give either -region or -point and -normal", {"VALUE", "REGION"});
    if (region) {
      d.kind = sim::SinkDef::Region;
      d.region = c.get<sim::Region>("region");
      d.outside = c.flag("outside");
    } else {
      if (!c.has("point") || !c.has("normal"))
        throw Error("bad sink: a plane needs -point and -normal", {"VALUE", "NORMAL"});
      if (c.given("outside")) c.bad("outside", "is for a region");
      d.kind = sim::SinkDef::Plane;
      d.point = vec3(c.vec("point"));
      d.normal = vec3(c.vec("normal"));
    }
    c.prepared = d;
  });
  sink.run([](Call& c) {
    session(c).scene().addSink(std::any_cast<sim::SinkDef>(c.prepared));
    return Value(c.str("name"));
  });
  declareCounters(r, "sink", &sim::Simulation::sinks, &sim::Simulation::removeSink);
}

}  // namespace demlab::cmd
