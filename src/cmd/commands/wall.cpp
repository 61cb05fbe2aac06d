// The "wall" group: planes, finite walls, boxes, drums and meshes, with optional prescribed motion.
#include <unordered_set>

#include "cmd/commands/commands.hpp"
#include "cmd/time_vector.hpp"
#include "cmd/words.hpp"
#include "core/validity.hpp"
#include "core/tag_table.hpp"
#include "io/stl.hpp"
#include "physics/triangle_mesh.hpp"
#include "sim/boundaries.hpp"

namespace demlab::cmd {

namespace {

using sim::WallDef;
using sim::WallId;
using sim::WallShape;

const char* shapeName(WallShape s) {
  switch (s) {
    case WallShape::Plane:
      return "plane";
    case WallShape::Finite:
      return "finite";
    case WallShape::Box:
      return "box";
    case WallShape::Drum:
      return "drum";
    case WallShape::Mesh:
      return "mesh";
  }
  return "?";
}

// Declares the options of a prescribed motion (wall add, wall set).
void motionOptions(Command& c) {
  c.option("velocity", timeVector(false).withUnit("m/s"),
           "prescribed velocity of the reference point; a component may be a Tcl expression in "
           "$t (a scripted motion)");
  c.option("angularvelocity", timeVector(true).withUnit("rad/s"),
           "prescribed rotation about the reference point; components may be expressions in $t");
  c.option("amplitude", vector().withUnit("m"), "vibration amplitude (displacement)");
  c.option("frequency", real().nonNegative().withUnit("Hz"), "vibration frequency");
  c.option("phase", real().withUnit("rad"), "vibration phase");
}

const TimeBound kVelocityBound{validity::kMaxSpeed, "wall velocity", "the speeds' bound"};
const TimeBound kSpinBound{validity::kMaxWallSpin, "wall angular velocity",
                           "the wall rotations' bound"};

// Returns the motion the call's motion options give (zero where left out). A scripted
// component's constant is its value now: what the wall reports until its first step.
sim::WallMotion motionOf(Call& c) {
  sim::WallMotion m;
  if (c.has("velocity"))
    timeComponents(c, "velocity", false, kVelocityBound, m.velocity, m.velocityFn, true);
  if (c.has("angularvelocity")) {
    timeComponents(c, "angularvelocity", true, kSpinBound, m.angularVelocity, m.angularVelocityFn,
                   true);
  }
  if (c.has("amplitude")) m.amplitude = vec3(c.vec("amplitude"));
  if (c.has("frequency")) m.frequency = c.real("frequency");
  if (c.has("phase")) m.phase = c.real("phase");
  return m;
}

// Declares what every wall takes: material, name, tags and the prescribed motion.
void commonOptions(Command& c) {
  c.option("point", vector().withUnit("m"),
           "reference point (the centre for finite walls, boxes and drums)");
  c.option("material", materialRef(), "its material (default: the first material defined)");
  c.option("name", name(), "a unique name");
  c.option("tags", tagList(), "tags to give it");
  motionOptions(c);
}

// Builds the Def from the call's options (check phase); shape-specific fields by the caller.
WallDef baseDef(Call& c, WallShape shape) {
  const sim::Simulation& s = session(c).scene();
  WallDef d;
  d.shape = shape;
  if (c.has("point")) d.point = vec3(c.vec("point"));
  d.material = materialOrFirst(c, s);
  if (c.has("name")) d.name = c.str("name");
  d.tags = tagsOption(c);
  if (c.given("velocity") || c.given("angularvelocity") || c.given("amplitude") ||
      c.given("frequency") || c.given("phase")) {
    d.motion = motionOf(c);
  }
  return d;
}

// Checks that -halfextents has n numbers, all positive; returns them as a Vec3d.
sim::Vec3d halfExtents(const Call& c, std::size_t n) {
  const auto& h = c.vec("halfextents");
  if (h.size() != n) {
    c.bad("halfextents", "expected " + std::to_string(n) + (n == 1 ? " number" : " numbers") +
                             " but got " + std::to_string(h.size()));
  }
  for (double x : h)
    if (!(x > 0)) c.bad("halfextents", "each must be a positive number");
  return vec3(h);
}

Value addWall(Call& c) {
  return Value(scriptId(session(c).scene().addWall(std::any_cast<WallDef>(c.prepared))));
}

Dict wallDict(const sim::WallState& w, int d) {
  List tags;
  for (auto& t : w.tags) tags.emplace_back(t);
  Dict out = {{"id", scriptId(w.id)},
          {"name", w.name},
          {"shape", shapeName(w.shape)},
          {"material", w.material},
          {"point", vecValue(w.point, d)},
          {"velocity", vecValue(w.velocity, d)},
          {"angularvelocity", vecValue(w.angularVelocity, d, true)},
          {"orientation", d == 2 ? Value(w.orientation[0])
                                 : Value(Reals{{w.orientation.begin(), w.orientation.end()}, 0})},
          {"force", vecValue(w.force, d)},
          {"torque", vecValue(w.torque, d, true)},
          {"work", w.work},
          {"servo", w.servo},
          {"scripted", w.scripted},
          {"hole", w.hole},
          {"bounds", List{vecValue(w.boundsLo, d), vecValue(w.boundsHi, d)}},
          {"tags", tags}};
  if (w.mesh) {
    out.emplace_back("file", w.mesh->source);
    out.emplace_back("triangles", Value(w.mesh->triangles.size()));
  }
  return out;
}

}  // namespace

void registerWallCommands(Registry& r) {
  r.describe("wall", "Walls: infinite planes, finite walls, boxes, drums and triangle meshes, fixed or moving.");
  r.describe("wall add", "Adds a wall of one shape; returns its id.");

  Command& plane =
      r.add("wall add plane",
            "Adds an infinite plane (a line in 2D); elements stay on the normal's side.");
  plane.option("normal", vector(), "the normal, pointing to the side the elements are on")
      .require();
  commonOptions(plane);
  plane.onCheck([](Call& c) {
    WallDef d = baseDef(c, WallShape::Plane);
    d.normal = vec3(c.vec("normal"));
    c.prepared = d;
  });
  plane.onRanks = OnRanks::Alike;  // (every rank holds every wall)
  plane.run(addWall);

  Command& fin = r.add("wall add finite",
                       "Adds a finite flat wall: a segment in 2D, a rectangle in 3D (two-sided), "
                       "with a hole in its middle or not.");
  fin.option("normal", vector(), "the wall's normal").require();
  fin.option("halfextents", reals().withUnit("m"),
             "half length (2D), or half sizes along -axis and normal x axis (3D)")
      .require();
  fin.option("axis", vector(), "3D: the in-plane direction of the first half size");
  fin.option("hole", real().positive().withUnit("m"),
             "a hole centred at -point: 3D a circle of this radius (an orifice), 2D a gap of "
             "this half width (a slot); less than every half extent")
      .to(&WallDef::hole);
  commonOptions(fin);
  fin.onCheck([](Call& c) {
    int d = session(c).scene().dim();
    WallDef w = baseDef(c, WallShape::Finite);
    w.normal = vec3(c.vec("normal"));
    w.halfExtents = halfExtents(c, d == 2 ? 1 : 2);
    if (c.has("axis")) w.axis = vec3(c.vec("axis"));
    c.fill(w);
    c.prepared = w;
  });
  fin.onRanks = OnRanks::Alike;  // (every rank holds every wall)
  fin.run(addWall);

  Command& box =
      r.add("wall add box", "Adds a solid box (a rectangle in 2D); elements stay outside.");
  box.option("halfextents", reals().withUnit("m"), "half sizes along each axis").require();
  box.option("rotation", spin().withUnit("rad"),
             "rotation vector (axis times angle; an angle in 2D)");
  commonOptions(box);
  box.onCheck([](Call& c) {
    int d = session(c).scene().dim();
    WallDef w = baseDef(c, WallShape::Box);
    w.halfExtents = halfExtents(c, std::size_t(d));
    if (c.has("rotation")) w.rotation = vec3(c.vec("rotation"), true);
    c.prepared = w;
  });
  box.onRanks = OnRanks::Alike;  // (every rank holds every wall)
  box.run(addWall);

  Command& drum = r.add("wall add drum",
                        "Adds a drum: a cylinder (a circle in 2D) holding the elements inside.");
  drum.option("radius", real().positive().withUnit("m"), "inner radius")
      .require()
      .to(&WallDef::radius);
  drum.option("axis", vector(), "3D: the cylinder's axis");
  drum.option("halflength", real().positive().withUnit("m"), "3D: half its length")
      .to(&WallDef::halfLength);
  commonOptions(drum);
  drum.onCheck([](Call& c) {
    WallDef w = baseDef(c, WallShape::Drum);
    c.fill(w);
    if (c.has("axis")) w.axis = vec3(c.vec("axis"));
    c.prepared = w;
  });
  drum.onRanks = OnRanks::Alike;  // (every rank holds every wall)
  drum.run(addWall);

  Command& mesh = r.add("wall add mesh",
                        "Adds a wall of triangles read from an STL file (ASCII or binary), 3D "
                        "only: a hopper, a chute, a mixer's blade. Two-sided; an element meets "
                        "each face, edge or corner it touches once, however many triangles "
                        "share it.");
  mesh.interruptible = true;
  mesh.option("file", text("file"), "the STL file").require();
  mesh.option("scale", real().positive(), "multiply the file's lengths by this (mm to m: 0.001)")
      .byDefault("1");
  mesh.option("rotation", spin().withUnit("rad"),
              "rotation vector (axis times angle) turning the mesh about its file's origin");
  commonOptions(mesh);
  mesh.onCheck([](Call& c) {
    if (session(c).scene().dim() != 3) c.bad("file", "a mesh wall is 3D only");
    WallDef w = baseDef(c, WallShape::Mesh);
    const std::string path = c.str("file");
    io::StlMesh stl = io::readStl(path);
    const double k = c.real("scale");
    for (auto& t : stl.triangles)
      for (double& x : t) x *= k;
    w.mesh = std::make_shared<const physics::TriangleMesh>(physics::TriangleMesh::build(stl.triangles, path));
    if (c.has("rotation")) w.rotation = vec3(c.vec("rotation"), true);
    c.prepared = w;
  });
  mesh.run(addWall);

  Command& get = r.add("wall get", "Returns a wall's state as a dict, or the fields asked for.");
  get.arg("wall", wallRef(), "a wall id or name");
  for (const char* f :
       {"id", "name", "shape", "material", "point", "velocity", "angularvelocity", "orientation",
        "force", "torque", "work", "servo", "scripted", "hole", "bounds", "tags"})
    get.flag(f, std::string("the ") + f);
  get.changesScene = false;
  get.onRanks = OnRanks::Collective;
  get.run([](Call& c) {
    auto& s = session(c).scene();
    sim::WallState w = s.wall(c.get<WallId>("wall"));
    if (s.distributed()) {
      // Each rank holds the force, torque and work of its own elements' contacts with the wall.
      std::vector<double> v{w.force[0],  w.force[1],  w.force[2], w.torque[0],
                            w.torque[1], w.torque[2], w.work};
      ranksOf(s).sum(v);
      w.force = {v[0], v[1], v[2]};
      w.torque = {v[3], v[4], v[5]};
      w.work = v[6];
    }
    return pickFields(c, wallDict(w, s.dim()));
  });

  Command& set = r.add("wall set",
                       "Replaces a wall's motion from now on, keeping its id and its contacts' "
                       "history; the new motion starts where the wall is. Options left out are "
                       "zero: no option stops the wall. Ends a servo. Velocity and angular velocity "
                       "components may be Tcl expressions in $t: each step moves the wall at their "
                       "values at the step's midpoint.");
  set.arg("wall", wallRef(), "a wall id or name");
  set.onRanks = OnRanks::Alike;  // every rank holds every wall
  motionOptions(set);
  set.run([](Call& c) {
    session(c).scene().setWallMotion(c.get<WallId>("wall"), motionOf(c));
    return Value();
  });

  Command& servo = r.add("wall servo",
                         "Moves a plane or finite wall along its normal to hold a normal force "
                         "or stress: v = gain (target - measured), |v| <= maxspeed, measured "
                         "the force the elements push it back with in the last step. Stable "
                         "for gain < 2 / (K dt), K the packing's normal stiffness.");
  servo.arg("wall", wallRef(), "a plane or finite wall, id or name");
  servo.option("force", real().nonNegative().withUnit("N"), "the normal force to hold");
  servo.option("stress", real().nonNegative().withUnit("Pa"),
               "the normal stress to hold (force / area)");
  servo.oneOf({"force", "stress"}, true);
  servo.option("area", real().positive().withUnit("m^2"),
               "the area the stress acts on (default: a finite wall's own; 2D: per unit depth)");
  servo.option("gain", real().withUnit("m/(N s)"), "velocity per newton of error").require();
  servo.option("maxspeed", real().withUnit("m/s"), "the largest speed").require();
  // (Every rank holds every wall; the servo reads the whole force, summed over the ranks.)
  servo.onRanks = OnRanks::Alike;
  servo.run([](Call& c) {
    auto& s = session(c).scene();
    const WallId id = c.get<WallId>("wall");
    sim::WallServoDef d;
    d.gain = c.real("gain");
    d.maxSpeed = c.real("maxspeed");
    if (c.has("force")) {
      if (c.given("area")) c.bad("area", "is for a stress");
      d.target = c.real("force");
    } else {
      const double stress = c.real("stress");
      double area = 0;
      if (c.has("area")) {
        area = c.real("area");
      } else {
        const sim::WallState w = s.wall(id);
        if (w.shape != WallShape::Finite) c.bad("area", "is needed for a plane (it has no extent)");
        area = s.dim() == 2 ? 2 * w.halfExtents[0] : 4 * w.halfExtents[0] * w.halfExtents[1];
      }
      d.target = stress * area;
    }
    s.setWallServo(id, d);
    return Value(d.target);
  });

  Command& torque = r.add("wall torque",
                          "Returns the torque the elements put on a wall in the last recorded "
                          "step, about a point (default: its reference point).");
  torque.arg("wall", wallRef(), "a wall id or name");
  torque.option("about", vector().withUnit("m"), "the point");
  torque.changesScene = false;
  torque.run([](Call& c) {
    auto& s = session(c).scene();
    const sim::WallState w = s.wall(c.get<WallId>("wall"));
    sim::Vec3d t = w.torque;
    if (c.has("about")) {
      // T_p = T_ref + (ref - p) x F
      const sim::Vec3d p = vec3(c.vec("about"));
      const sim::Vec3d r{w.point[0] - p[0], w.point[1] - p[1], w.point[2] - p[2]};
      const sim::Vec3d& f = w.force;
      t[0] += r[1] * f[2] - r[2] * f[1];
      t[1] += r[2] * f[0] - r[0] * f[2];
      t[2] += r[0] * f[1] - r[1] * f[0];
    }
    return vecValue(t, s.dim(), true);
  });

  Command& rm = r.add("wall remove", "Removes walls; returns how many.");
  rm.variadicArg("wall", wallRef(), "wall ids or names");
  rm.onRanks = OnRanks::Alike;  // (every rank holds every wall)
  rm.run([](Call& c) {
    auto& s = session(c).scene();
    std::unordered_set<std::uint64_t> seen;
    std::size_t n = 0;
    for (WallId w : c.all<WallId>("wall"))
      if (seen.insert(w.bits()).second) {
        s.removeWall(w);
        ++n;
      }
    return Value(n);
  });

  Command& list = r.add("wall list", "Returns the ids of all walls, or of those with a tag.");
  list.onRanks = OnRanks::Alike;
  list.option("tag", tagName(), "only walls carrying this tag");
  list.changesScene = false;
  list.run([](Call& c) {
    auto& s = session(c).scene();
    List l;
    for (WallId w : c.given("tag") ? s.wallsTagged(c.str("tag")) : s.wallIds())
      l.emplace_back(scriptId(w));
    return Value(std::move(l));
  });

  Command& count = r.add("wall count", "Returns the number of walls.");
  count.onRanks = OnRanks::Alike;
  count.changesScene = false;
  count.run([](Call& c) { return Value(session(c).scene().wallCount()); });

  // (Every rank holds every wall.)
  addTagCommands<WallId>(r, "wall", "walls", wallRef(), &sim::Simulation::tagWall,
                         &sim::Simulation::untagWall, OnRanks::Alike);
}

}  // namespace demlab::cmd
