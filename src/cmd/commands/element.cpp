// The "element" group: one element at a time (add, get, set, clone, remove, tags) and bulk
// queries that return Tcl lists (ids, positions, ...). Many at once: pack.cpp.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "cmd/commands/commands.hpp"
#include "cmd/words.hpp"
#include "core/tag_table.hpp"
#include "core/validity.hpp"
#include "io/stl.hpp"
#include "sim/shapes/assembly.hpp"
#include "sim/shapes/level_set.hpp"

namespace demlab::cmd {

namespace {

using sim::ElementId;

// Returns the words of a space-separated string as a Tcl list.
List wordList(const std::string& words) {
  List out;
  for (auto& w : splitList(words)) out.emplace_back(w);
  return out;
}

Dict stateDict(const sim::ElementState& g, int d) {
  List tags;
  for (auto& t : g.tags) tags.emplace_back(t);
  Dict out{{"id", scriptId(g.id)},
           {"name", g.name},
           {"material", g.material},
           {"radius", g.radius},
           {"mass", g.mass},
           {"inertia", g.inertia},
           {"position", vecValue(g.position, d)},
           {"velocity", vecValue(g.velocity, d)},
           {"angularvelocity", vecValue(g.angularVelocity, d, true)},
           {"orientation", d == 2 ? Value(g.orientation[0])
                                  : Value(Reals{{g.orientation.begin(), g.orientation.end()}, 0})},
           {"force", vecValue(g.force, d)},
           {"torque", vecValue(g.torque, d, true)},
           {"tags", tags},
           {"shape", g.shape},
           {"params", Value(Reals{g.shapeParams, 0})},
           {"principalinertia",
            Value(Reals{{g.principalInertia.begin(), g.principalInertia.end()}, 0})},
           {"fixed", static_cast<int64_t>(g.blocked == sim::dof::all(d))},
           {"blocked", wordList(sim::dofNames(g.blocked))},
           {"unwrapped", vecValue(g.unwrapped, d)}};
  return out;
}

const char* const kStateFields[] = {
    "id",       "name",     "material",        "radius",      "mass",  "inertia",
    "position", "velocity", "angularvelocity", "orientation", "force", "torque",
    "tags",     "shape",    "params",          "principalinertia", "fixed", "blocked",
    "unwrapped"};

// Returns the dof:: mask of the -block list (names x y z rx ry rz), or every degree of
// freedom of the dimension with -fixed 1, or nothing when neither is given. Throws {VALUE DOF}
// for a name that is not one, {VALUE FIXED} when both are given.
std::optional<unsigned> blockedMask(const Call& c, int dim) {
  if (c.given("fixed") && c.given("block")) {
    throw Error(
        "-fixed and -block can't be given together: -fixed 1 blocks every degree of "
        "freedom",
        {"VALUE", "FIXED"});
  }
  if (c.given("fixed")) return c.get<bool>("fixed") ? sim::dof::all(dim) : 0u;
  if (!c.given("block")) return std::nullopt;
  unsigned mask = 0;
  for (const std::string& w : splitList(c.str("block"))) mask |= sim::dofFromName(w);
  return mask;
}

// Declares -fixed and -block on cmd.
void blockOptions(Command& cmd) {
  cmd.option("fixed", boolean(),
             "1: every degree of freedom blocked (it keeps its velocity, zero unless given); "
             "0: none");
  cmd.option("block", text("list of x y z rx ry rz").asList(),
             "the degrees of freedom to block (their velocities stay as they are whatever the "
             "forces); the others are freed. 2D: x y rz");
}

// The elements a command targets: every element with -tag, or all.
std::vector<ElementId> targets(const Call& c, const sim::Simulation& s) {
  if (c.given("tag")) return s.elementsTagged(c.str("tag"));
  return s.elementIds();
}

// Throws {EXISTS NAME} in the element's words if name is taken (the core says "grain").
void checkNameFree(const sim::Simulation& s, const std::string& name) {
  if (name.empty()) return;
  bool taken = true;
  try {
    s.findElement(name);
  } catch (const Error&) {
    taken = false;
  }
  if (taken) throw Error("element \"" + name + "\" already exists", {"EXISTS", "NAME"});
}

// Returns the members of `element assembly -members`: each a list of a shape type's name and
// options (-radius, -params, -position, -orientation). Throws demlab::Error saying which member
// and word is wrong (the caller names the option). Changes nothing.
std::vector<sim::AssemblyMemberDef> readAssemblyMembers(const std::string& text) {
  std::vector<sim::AssemblyMemberDef> out;
  const auto bad = [&](size_t k, const std::string& why) {
    throw Error("member " + std::to_string(k + 1) + ": " + why, {"VALUE", "MEMBERS"});
  };
  const std::vector<std::string> items = splitList(text);
  if (items.empty()) throw Error("an assembly needs at least one member", {"VALUE", "MEMBERS"});
  for (size_t k = 0; k < items.size(); ++k) {
    const std::vector<std::string> w = splitList(items[k]);
    if (w.empty() || w.size() % 2 == 0) {
      bad(k, "must be a shape type then option-value pairs (-radius, -params, -position, "
             "-orientation)");
    }
    sim::AssemblyMemberDef m;
    m.shape = w[0];
    for (size_t i = 1; i < w.size(); i += 2) {
      std::vector<double> numbers;
      for (const std::string& x : splitList(w[i + 1])) {
        double v = 0;
        if (!readReal(x, v) || !std::isfinite(v)) {
          bad(k, "expected a finite number in " + w[i] + " but got \"" + x + "\"");
        }
        numbers.push_back(v);
      }
      if (w[i] == "-radius") {
        if (numbers.size() != 1 || !(numbers[0] > 0)) bad(k, "-radius must be one positive number");
        m.radius = numbers[0];
      } else if (w[i] == "-params") {
        m.params = std::move(numbers);
      } else if (w[i] == "-position") {
        m.position = std::move(numbers);
      } else if (w[i] == "-orientation") {
        m.orientation = std::move(numbers);
      } else {
        bad(k, "unknown option \"" + w[i] + "\": must be -orientation, -params, -position, or -radius");
      }
    }
    out.push_back(std::move(m));
  }
  return out;
}

Value idList(const std::vector<ElementId>& ids) {
  Ints l;
  l.data.reserve(ids.size());
  for (ElementId g : ids) l.data.push_back(scriptId(g));
  return l;
}

// Returns the ids of a distributed scene's elements, or with stride > 0 their rows of data
// (stride numbers an element, in the order of s.elementIds()), gathered from every rank and
// sorted by id; flat: one list of numbers. With `only` (the scripts' ids of live elements,
// alike on every rank) the rows of those elements alone, in its order. Collective.
Value gatheredElements(const sim::Simulation& s, const std::vector<double>& data, int stride,
                       bool flat, const std::vector<ElementId>& only = {}) {
  const std::vector<ElementId> all = s.elementIds();
  const std::size_t n = s.distribution().owned;  // the owned first, then the ghosts
  const std::size_t row = sizeof(std::int64_t) + std::size_t(stride) * sizeof(double);
  std::unordered_set<std::int64_t> wanted;
  for (ElementId g : only) wanted.insert(scriptId(g));
  std::vector<char> mine;
  mine.reserve(n * row);
  for (std::size_t k = 0; k < n; ++k) {
    const std::int64_t id = scriptId(s.originalHandle(all[k]));
    if (!only.empty() && !wanted.contains(id)) continue;
    const std::size_t at = mine.size();
    mine.resize(at + row);
    std::memcpy(mine.data() + at, &id, sizeof id);
    if (stride > 0) {
      std::memcpy(mine.data() + at + sizeof id, data.data() + k * std::size_t(stride),
                  std::size_t(stride) * sizeof(double));
    }
  }
  std::vector<std::pair<std::int64_t, const char*>> rows;
  const std::vector<std::vector<char>> parts = ranksOf(s).gatherBytes(mine);
  for (const std::vector<char>& p : parts) {
    for (std::size_t at = 0; at + row <= p.size(); at += row) {
      std::int64_t id;
      std::memcpy(&id, p.data() + at, sizeof id);
      rows.emplace_back(id, p.data() + at + sizeof id);
    }
  }
  std::sort(rows.begin(), rows.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  if (!only.empty()) {
    // (Each listed element is a live one: its owner sent its row.)
    std::vector<std::pair<std::int64_t, const char*>> listed;
    listed.reserve(only.size());
    for (ElementId g : only) {
      const auto it = std::lower_bound(rows.begin(), rows.end(), scriptId(g),
                                       [](const auto& r, std::int64_t id) { return r.first < id; });
      if (it == rows.end() || it->first != scriptId(g)) {
        throw Error("no rank holds element " + std::to_string(scriptId(g)), {"LOOKUP", "ELEMENT"});
      }
      listed.push_back(*it);
    }
    rows.swap(listed);
  }
  if (stride == 0) {
    Ints ids;
    for (const auto& r : rows) ids.data.push_back(r.first);
    return ids;
  }
  std::vector<double> out(rows.size() * std::size_t(stride));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    std::memcpy(out.data() + k * std::size_t(stride), rows[k].second,
                std::size_t(stride) * sizeof(double));
  }
  return Value(Reals{std::move(out), (flat || stride == 1) ? 0 : stride});
}

}  // namespace

void registerElementCommands(Registry& r) {
  r.describe("element", "Elements (grains): spheres in 3D, discs in 2D.");

  Command& add = r.add("element add", "Adds one element; returns its id.");
  add.details =
      "The shape is a type of the dimension's shape table: the ball (sphere in 3D, disc in 2D), "
      "sized by -radius, or a type registered by a plug-in, described by -params (its bounding "
      "radius follows from them) and oriented by -orientation. `element shapes` lists them. In a "
      "distributed run (a ball) it gets "
      "the id the serial scene would give and the rank whose box holds it takes it.";
  add.option("radius", real().positive().withUnit("m"), "radius (the ball's; required for it)")
      .to(&sim::ElementDef::radius);
  add.option("material", materialRef(), "its material (default: the first material defined)")
      .to(&sim::ElementDef::material);
  add.option("position", vector().withUnit("m"), "centre (default: the origin)");
  add.option("velocity", vector().withUnit("m/s"), "velocity");
  add.option("angularvelocity", spin().withUnit("rad/s"), "angular velocity (a number in 2D)");
  add.option("tags", tagList(), "tags to give it");
  add.option("name", name(), "a unique name").to(&sim::ElementDef::name);
  add.option("shape", text("shape type"),
             "its shape type: sphere (3D) or disc (2D), the default, or another of `element "
             "shapes`");
  add.option("params", reals(), "the shape's parameters (none for the ball)");
  add.option("orientation", reals(),
             "3D a quaternion {w x y z} (normalised), 2D an angle (rad); default: the identity");
  blockOptions(add);
  add.onCheck([](Call& c) {
    auto& s = session(c).scene();
    sim::ElementDef d;
    c.fill(d);
    if (!c.given("material")) {
      auto names = s.materialNames();
      if (names.empty())
        throw Error("no material defined: use \"material add\" first", {"LOOKUP", "MATERIAL"});
      d.material = names.front();
    }
    if (c.has("position")) d.position = vec3(c.vec("position"));
    checkNameFree(s, d.name);
    if (c.has("velocity")) d.velocity = vec3(c.vec("velocity"));
    if (c.has("angularvelocity")) d.angularVelocity = vec3(c.vec("angularvelocity"), true);
    if (c.given("shape")) d.shape = c.str("shape");
    if (c.given("params")) d.shapeParams = c.get<std::vector<double>>("params");
    if (c.given("orientation")) d.orientation = c.get<std::vector<double>>("orientation");
    const auto names = s.shapeNames();
    if (!c.given("radius") && (d.shape.empty() || d.shape == names.front())) {
      throw Error("missing required option -radius: a " + names.front() +
                      " needs it (the other shapes take -params)",
                  {"ARGS"});
    }
    if (auto mask = blockedMask(c, s.dim())) d.blocked = *mask;
    if (c.has("tags")) {
      for (auto& t : splitList(c.str("tags"))) {
        checkTagName(t);
        d.tags.push_back(t);
      }
    }
    c.prepared = d;
  });
  // (Distributed: the id the serial scene would give; the rank whose box holds it takes it.)
  add.onRanks = OnRanks::Collective;
  add.run([](Call& c) {
    return Value(scriptId(session(c).scene().addElement(std::any_cast<sim::ElementDef>(c.prepared))));
  });

  Command& shapes = r.add("element shapes",
                          "Returns the shape types of the scene's dimension as a dict: name, "
                          "then what its -params are.");
  shapes.changesScene = false;
  shapes.run([](Call& c) {
    Dict d;
    for (auto& [name, params] : session(c).scene().shapeTypes()) d.emplace_back(name, params);
    return Value(d);
  });

  Command& levelset = r.add(
      "element levelset",
      "Returns the -params of a level-set shape (`element add -shape levelset -params ...`): the "
      "signed distance, on a grid of spacing -spacing, to the body inside a closed STL mesh "
      "(-file, 3D) or to where sampled function values are negative (-values).");
  levelset.details =
      "From a mesh the grid reaches two and a half nodes beyond the mesh's bounds; the mesh must "
      "be closed (each edge in two triangles). From values, one per node of the grid of -dims "
      "nodes from -origin (x fastest), negative inside and positive on the grid's border: the "
      "distance is recomputed exactly to the surface where they cross zero, so any implicit "
      "function serves (demlab::levelset samples one). The body may be given about any point: "
      "`element add` moves it about its centroid.";
  levelset.changesScene = false;
  levelset.needsScene = true;
  levelset.interruptible = true;
  levelset.option("spacing", real().positive().withUnit("m"), "the grid's node spacing").require();
  levelset.option("file", text("file"), "a closed STL mesh (3D only)");
  levelset.option("scale", real().positive(), "multiply the file's lengths by this (mm to m: 0.001)")
      .byDefault("1");
  levelset.option("values", reals(), "the function's value at each node, x fastest, negative inside");
  levelset.option("dims", ints(), "{nx ny [nz]}: the nodes per axis of -values");
  levelset.option("origin", vector().withUnit("m"), "the position of -values's first node");
  levelset.onCheck([](Call& c) {
    const int dim = session(c).scene().dim();
    if (c.given("file") == c.given("values")) {
      throw Error("element levelset: give either -file (a mesh) or -values (samples)", {"ARGS"});
    }
    if (c.given("file")) {
      if (dim != 3) c.bad("file", "a mesh level set is 3D only (in 2D give -values)");
      for (const char* o : {"dims", "origin"}) {
        if (c.given(o)) c.bad(o, "goes with -values, not -file");
      }
      return;
    }
    if (!c.given("dims") || !c.given("origin")) c.bad("values", "needs -dims and -origin");
    const auto& dims = c.get<std::vector<std::int64_t>>("dims");
    if (dims.size() != static_cast<size_t>(dim)) {
      c.bad("dims", "needs " + std::to_string(dim) + " node counts");
    }
    size_t total = 1;
    for (std::int64_t k : dims) {
      if (k < sim::kLevelSetMinNodes || k > sim::kLevelSetMaxNodesPerAxis) {
        c.bad("dims", "each count must lie in [" + std::to_string(sim::kLevelSetMinNodes) + ", " +
                          std::to_string(sim::kLevelSetMaxNodesPerAxis) + "]");
      }
      total *= static_cast<size_t>(k);
    }
    if (c.get<std::vector<double>>("values").size() != total) {
      c.bad("values", "needs one value per node: " + std::to_string(total));
    }
  });
  levelset.run([](Call& c) {
    const double h = c.real("spacing");
    std::vector<double> params;
    if (c.given("file")) {
      io::StlMesh stl = io::readStl(c.str("file"));
      const double k = c.real("scale");
      for (auto& t : stl.triangles)
        for (double& x : t) x *= k;
      params = sim::levelSetFromMesh(stl.triangles, h);
    } else {
      const auto& dims = c.get<std::vector<std::int64_t>>("dims");
      const auto& values = c.get<std::vector<double>>("values");
      const auto& o = c.vec("origin");
      if (session(c).scene().dim() == 3) {
        params = sim::levelSetFromValues<3>(h, {int(dims[0]), int(dims[1]), int(dims[2])},
                                            Vec3(o[0], o[1], o[2]), values);
      } else {
        params = sim::levelSetFromValues<2>(h, {int(dims[0]), int(dims[1])}, Vec2(o[0], o[1]), values);
      }
    }
    return Value(Reals{std::move(params), 0});
  });

  Command& assembly = r.add(
      "element assembly",
      "Returns the -params of an assembly (`element add -shape assembly -params ...`): a rigid "
      "body made of members of the other shape types, each placed and turned in its frame.");
  assembly.details =
      "Each member is a list: a shape type of `element shapes` (not an assembly), then -radius "
      "(a ball's) or -params (the others'), -position in the assembly's frame (default the "
      "origin) and -orientation (3D a quaternion {w x y z}, 2D an angle in rad). A member given "
      "about another point than its centroid is moved about it and its position with it, so it "
      "stays where it was given. The mass is the members' sum, so members may touch but not "
      "overlap (a clump takes overlapping balls; a level set any union). `element add` then moves "
      "the whole about its centre of mass.";
  assembly.changesScene = false;
  assembly.needsScene = true;
  assembly.option("members", text("list of members"), "the members: {shape ?-radius r? ?-params "
                  "{...}? ?-position {...}? ?-orientation {...}?} ...").require();
  assembly.onCheck([](Call& c) {
    try {
      c.prepared = readAssemblyMembers(c.str("members"));
    } catch (const Error& e) {
      c.bad("members", e.what());  // a list that does not split, say: named as the option
    }
  });
  assembly.run([](Call& c) {
    auto members = std::any_cast<std::vector<sim::AssemblyMemberDef>>(c.prepared);
    const int dim = session(c).scene().dim();
    for (auto& m : members) {
      if (m.position.empty()) m.position.assign(static_cast<size_t>(dim), 0.0);
    }
    std::vector<double> params = dim == 3 ? sim::assemblyParams<3>(members)
                                          : sim::assemblyParams<2>(members);
    return Value(Reals{std::move(params), 0});
  });

  Command& get =
      r.add("element get", "Returns an element's state as a dict, or the fields asked for.");
  get.onRanks = OnRanks::Collective;
  get.details = "With one field flag the value alone is returned; with several, a dict of them.";
  get.arg("element", elementRef(), "an element id or name");
  for (const char* f : kStateFields) get.flag(f, std::string("the ") + f);
  get.changesScene = false;
  get.run([](Call& c) {
    auto& s = session(c).scene();
    const ElementId e = c.get<ElementId>("element");
    // A distributed scene: the rank owning the element answers, under the id the script knows.
    const ElementId here = s.ownedElement(e);
    std::optional<Value> mine;
    if (!here.isNull()) {
      sim::ElementState g = s.element(here);
      g.id = e;
      mine = pickFields(c, stateDict(g, s.dim()));
    }
    return fromHolder(s, std::move(mine),
                      Error("no element with id " + std::to_string(scriptId(e)),
                            {"LOOKUP", "ELEMENT"}));
  });

  Command& set = r.add("element set",
                       "Changes an element's position, velocity, angular velocity, orientation "
                       "or blocked degrees of freedom.");
  set.details =
      "A blocked degree of freedom keeps its velocity whatever the forces (the force or torque "
      "along it is cancelled each step: the constraints module). -fixed 1 blocks all of them "
      "and, unless -velocity or -angularvelocity is given too, stops the element.";
  set.arg("element", elementRef(), "an element id or name");
  set.option("position", vector().withUnit("m"), "new centre");
  set.option("velocity", vector().withUnit("m/s"), "new velocity");
  set.option("angularvelocity", spin().withUnit("rad/s"), "new angular velocity");
  set.option("orientation", reals(),
             "new orientation: 3D a quaternion {w x y z} (normalised), 2D an angle (rad)");
  blockOptions(set);
  set.onRanks = OnRanks::Collective;
  set.onCheck([](Call& c) {
    auto& s = session(c).scene();
    // LOOKUP before changes (distributed: the rank owning it answers, on every rank).
    const ElementId e = c.get<ElementId>("element");
    const ElementId here = s.ownedElement(e);
    std::optional<Value> mine;
    if (!here.isNull()) mine = Value(s.element(here).radius);
    const double r = std::stod(toString(fromHolder(
        s, std::move(mine),
        Error("no element with id " + std::to_string(scriptId(e)), {"LOOKUP", "ELEMENT"}))));
    // The setters each check their own value, but run one after another: a velocity refused
    // after the position was set would leave the position changed. The validity policy's
    // bounds are checked here, before any of them runs.
    auto largest = [](const std::vector<double>& v) {
      double m = 0;
      for (double x : v) m = std::max(m, std::fabs(x));
      return m;
    };
    auto length = [](const std::vector<double>& v) {
      double m = 0;
      for (double x : v) m = std::hypot(m, x);
      return m;
    };
    const double reach = std::min(validity::kMaxCoordinate, validity::kMaxRadiiFromOrigin * r);
    if (c.has("position") && !(largest(c.vec("position")) <= reach))
      c.bad("position", "must be within " + formatReal(reach) + " m of the origin on each axis");
    if (c.has("velocity") && !(length(c.vec("velocity")) <= validity::kMaxSpeed))
      c.bad("velocity", "must be at most " + formatReal(validity::kMaxSpeed) + " m/s in magnitude");
    if (c.has("angularvelocity") &&
        !(length(c.get<std::vector<double>>("angularvelocity")) * r <= validity::kMaxSpeed)) {
      c.bad("angularvelocity", "must be at most " + formatReal(validity::kMaxSpeed) +
                                   " m/s at the surface (|w| r)");
    }
    c.prepared = blockedMask(c, s.dim());
  });
  set.run([](Call& c) {
    auto& s = session(c).scene();
    ElementId g = c.get<ElementId>("element");
    const auto mask = std::any_cast<std::optional<unsigned>>(c.prepared);
    // The pipes made every vector the right size, the check read the mask and checked the
    // values against the validity policy, so none of these calls can fail half-way.
    // The orientation first: the one setter that checks its value (VALUE ORIENTATION), so a
    // bad one fails before anything has changed.
    if (c.given("orientation")) s.setElementOrientation(g, c.get<std::vector<double>>("orientation"));
    if (c.has("position")) s.setElementPosition(g, vec3(c.vec("position")));
    const bool fixing = c.given("fixed") && c.get<bool>("fixed");
    if (c.has("velocity")) {
      s.setElementVelocity(g, vec3(c.vec("velocity")));
    } else if (fixing) {
      s.setElementVelocity(g, {0, 0, 0});
    }
    if (c.has("angularvelocity")) {
      s.setElementAngularVelocity(g, vec3(c.vec("angularvelocity"), true));
    } else if (fixing) {
      s.setElementAngularVelocity(g, {0, 0, 0});
    }
    if (mask) s.setElementBlocked(g, *mask);
    return Value();
  });

  Command& clone = r.add(
      "element clone",
      "Adds a copy of an element (radius, material, tags, motion, blocked degrees of freedom); "
      "returns its id.");
  clone.arg("element", elementRef(), "the element to copy");
  clone.option("position", vector().withUnit("m"), "the copy's centre").require();
  clone.option("velocity", vector().withUnit("m/s"),
               "the copy's velocity (default: the original's)");
  clone.option("name", name(), "a unique name for the copy");
  clone.run([](Call& c) {
    auto& s = session(c).scene();
    sim::ElementState g = s.element(c.get<ElementId>("element"));
    sim::ElementDef d;
    // The same shape, size and orientation (a shape's radius is its bound: not given).
    d.shape = g.shape;
    d.shapeParams = g.shapeParams;
    d.radius = g.shapeParams.empty() ? g.radius : 0;
    d.orientation.assign(g.orientation.begin(), g.orientation.begin() + (s.dim() == 2 ? 1 : 4));
    d.material = g.material;
    d.tags = g.tags;
    d.position = vec3(c.vec("position"));
    d.velocity = c.has("velocity") ? vec3(c.vec("velocity")) : g.velocity;
    d.angularVelocity = g.angularVelocity;
    d.blocked = g.blocked;
    if (c.has("name")) d.name = c.str("name");
    checkNameFree(s, d.name);
    return Value(scriptId(s.addElement(d)));
  });

  Command& rm = r.add("element remove",
                      "Removes elements (ids, names, or every one with -tag); returns how many.");
  rm.variadicArg("element", elementRef(), "element ids or names").optional = true;
  rm.option("tag", tagName(), "remove every element carrying this tag");
  rm.onCheck([](Call& c) {
    if (c.given("element") == c.given("tag")) {
      throw Error("wrong # args: should be \"" + c.command().usage() +
                      "\" with element ids or -tag, not both",
                  {"ARGS"});
    }
  });
  rm.onRanks = OnRanks::Collective;
  rm.run([](Call& c) {
    auto& s = session(c).scene();
    if (c.given("tag")) return Value(s.removeElements(c.str("tag")));
    // (Serial: each id was checked to exist. Distributed: the ranks owning them check, together.)
    try {
      return Value(s.removeElementList(c.all<ElementId>("element")));
    } catch (const Error& e) {
      if (e.code().size() < 2 || e.code()[1] != "LOOKUP") throw;
      throw Error(e.what(), {"LOOKUP", "ELEMENT"});  // (as the serial check words it)
    }
  });

  Command& resize = r.add("element resize",
                          "Multiplies the radii of elements (ids, names, every one with -tag, or "
                          "all) by a factor; returns how many.");
  resize.details =
      "Radius expansion: mass and inertia follow the material's density; positions, velocities "
      "and bonds stay, so overlaps grow (or shrink) by the change. demlab::sample grows a "
      "random packing until it jams with it. Balls only; all or none.";
  resize.variadicArg("element", elementRef(), "element ids or names").optional = true;
  resize.option("tag", tagName(), "every element carrying this tag");
  resize.option("factor", real().positive(), "the factor on every radius").require();
  resize.onCheck([](Call& c) {
    if (c.given("element") && c.given("tag")) {
      throw Error("wrong # args: should be \"" + c.command().usage() +
                      "\" with element ids or -tag, not both",
                  {"ARGS"});
    }
  });
  resize.run([](Call& c) {
    auto& s = session(c).scene();
    std::vector<ElementId> ids;
    if (c.given("element")) {
      std::unordered_set<std::uint64_t> seen;
      for (ElementId g : c.all<ElementId>("element"))
        if (seen.insert(g.bits()).second) ids.push_back(g);
    } else {
      ids = targets(c, s);
    }
    try {
      s.scaleElementRadii(ids, c.get<double>("factor"));
    } catch (const Error& e) {  // a radius out of the validity range: the factor is what was typed
      if (e.code().size() < 3 || e.code()[2] != "RADIUS") throw;
      c.bad("factor", std::string("makes a ") + e.what());
    }
    return Value(ids.size());
  });

  Command& list = r.add("element list", "Returns the ids of all elements, or of those with a tag.");
  list.option("tag", tagName(), "only elements carrying this tag");
  list.changesScene = false;
  list.details =
      "In a distributed scene, in the order of the ids; a tag's in the tag's order, as in a "
      "serial scene.";
  list.onRanks = OnRanks::Collective;
  list.run([](Call& c) {
    auto& s = session(c).scene();
    // (A tag's members are the same list of the scripts' ids on every rank.)
    if (!s.distributed() || c.given("tag")) return idList(targets(c, s));
    return gatheredElements(s, {}, 0, false);
  });

  Command& count =
      r.add("element count", "Returns the number of elements, or of those with a tag.");
  count.onRanks = OnRanks::Collective;
  count.option("tag", tagName(), "only elements carrying this tag");
  count.changesScene = false;
  count.run([](Call& c) {
    auto& s = session(c).scene();
    // A tag's members, listed alike on every rank; else every rank's own elements (a
    // distributed scene's, not its ghosts), summed.
    if (c.given("tag")) return Value(std::int64_t(s.elementsTagged(c.str("tag")).size()));
    return Value(ranksOf(s).sum(std::int64_t(s.distribution().owned)));
  });

  Command& arr =
      r.add("element array", "Returns one field of every element (or of a tag) as a list.");
  arr.details =
      "Vectors come as a list of lists ({x y z} {x y z} ...) unless -flat; the order is that of "
      "element list with the same -tag.";
  arr.onRanks = OnRanks::Collective;
  arr.arg(
      "field",
      choice({"id", "position", "velocity", "angularvelocity", "orientation", "force", "radius"}),
      "the field");
  arr.option("tag", tagName(), "only elements carrying this tag");
  arr.flag("flat", "one flat list of numbers");
  arr.changesScene = false;
  arr.run([](Call& c) {
    auto& s = session(c).scene();
    const std::string& f = c.str("field");
    std::vector<ElementId> all = s.elementIds();
    if (f == "id") {
      if (c.given("tag")) return idList(s.elementsTagged(c.str("tag")));
      return s.distributed() ? gatheredElements(s, {}, 0, false) : idList(all);
    }
    int d = s.dim();
    int stride = d;
    std::vector<double> data;
    if (f == "position")
      data = s.positions();
    else if (f == "velocity")
      data = s.velocities();
    else if (f == "force")
      data = s.forces();
    else if (f == "radius")
      data = s.radii(), stride = 1;
    else if (f == "angularvelocity")
      data = s.angularVelocities(), stride = d == 2 ? 1 : 3;
    else if (f == "orientation")
      data = s.orientations(), stride = d == 2 ? 1 : 4;
    if (s.distributed()) {
      if (!c.given("tag")) return gatheredElements(s, data, stride, c.flag("flat"));
      return gatheredElements(s, data, stride, c.flag("flat"), s.elementsTagged(c.str("tag")));
    }
    if (c.given("tag")) {
      std::vector<double> picked;
      for (std::uint32_t k : s.taggedIndices(c.str("tag"))) {
        picked.insert(picked.end(), data.begin() + long(k) * stride,
                      data.begin() + long(k + 1) * stride);
      }
      data.swap(picked);
    }
    return Value(Reals{std::move(data), (c.flag("flat") || stride == 1) ? 0 : stride});
  });

  // (A distributed scene's tags are alike on every rank; the element's owner answers whether
  // it exists, to every rank.)
  addTagCommands<ElementId>(r, "element", "elements", elementRef(), &sim::Simulation::tagElement,
                            &sim::Simulation::untagElement, OnRanks::Collective);
}

}  // namespace demlab::cmd
