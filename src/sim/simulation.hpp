// Simulation: the public, dimension-erased face of the simulation core (thesis chapter 9's
// SimulationManager seen from outside). The Tcl command layer, the benchmark and the tests talk
// to a scene only through this class; everything under it is templated on the dimension
// (SimulationManager<2>, SimulationManager<3>) and never seen here.
//
// Conventions of the whole interface:
// - Vectors are std::array<double, 3> (Vec3d). In 2D the z component of a position, velocity,
//   force or point must be 0 and an angular velocity or torque has only a z component (x and y
//   must be 0): a Def that breaks this is rejected with DEMLAB VALUE <FIELD>.
// - Bulk getters return flat std::vector<double> in dense order (elementIds() gives the same
//   order), with dim() components per vector (positions, velocities, forces), 1 (2D) or 3 (3D)
//   per angular quantity, 1 (2D angle) or 4 (3D quaternion w x y z) per orientation.
// - Every mutating call checks its whole input first and either succeeds or throws
//   demlab::Error and changes nothing (stateDigest() is unchanged). Codes are listed per call.
// - Handles are generational (core/handle.hpp): a handle to a removed grain or wall is reported
//   as such (DEMLAB LOOKUP HANDLE), never taken for the object that reuses its slot.
//
// Status: every function declared here is implemented (sim/simulation_manager.cpp: editing;
// sim/simulation_run.cpp: running, queries, digest, clone, save/load) and exercised by
// tests/unit/sim/.
#pragma once

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/handle.hpp"
#include "physics/material.hpp"
#include "physics/pair_params.hpp"
#include "sim/options.hpp"

namespace demlab::physics {
struct TriangleMesh;
}

namespace demlab::sim {

using Vec3d = std::array<double, 3>;
using MaterialDef = physics::MaterialDef;
using LawKind = physics::LawKind;

struct ElementKind {};
struct WallKind {};
struct BehaviorKind {};
struct OutputKind {};
using ElementId = Handle<ElementKind>;
using WallId = Handle<WallKind>;
using BehaviorId = Handle<BehaviorKind>;
using OutputId = Handle<OutputKind>;

class Simulation;
struct SourceDef;
struct SinkDef;
struct BoundaryInfo;
struct WallServoDef;

// A function of simulated time (seconds) giving one component of a time-varying load; the Tcl
// layer wraps a script callback in it. It must be deterministic for runs to be reproducible.
using TimeFunction = std::function<double(double t)>;

// Returns the law named name, as physics::lawName spells it ("linear", "hertz_mindlin").
// Throws {VALUE LAW} otherwise: `bad law "x": must be linear or hertz_mindlin`.
LawKind lawFromName(std::string_view name);

// Returns the names of the degrees of freedom in a dof:: mask, space separated ("x y rz").
std::string dofNames(unsigned mask);
// Returns the dof:: bit named name (x y z rx ry rz). Throws {VALUE DOF}.
unsigned dofFromName(std::string_view name);

// ---- definitions (checked before anything is created) ------------------------------------

// Coefficients of one pair of materials that replace what the mixing rules give (as
// LIGGGHTS's peratomtypepair tables): restitution in (0, 1], friction, rolling friction and
// cohesion >= 0, each finite (VALUE <FIELD>); NaN: the mixing rule's value.
struct PairCoefficients {
  double restitution = std::numeric_limits<double>::quiet_NaN();
  double friction = std::numeric_limits<double>::quiet_NaN();
  double rolling = std::numeric_limits<double>::quiet_NaN();
  double cohesion = std::numeric_limits<double>::quiet_NaN();
  // The pair's effective Young's modulus E* = 1 / ((1 - nu_a^2) / E_a + (1 - nu_b^2) / E_b)
  // (Pa, > 0): the normal stiffness of both laws; the shear modulus follows with the Poisson
  // ratios.
  double young = std::numeric_limits<double>::quiet_NaN();
};

// The degrees of freedom of an element, as bits of a mask: translation along x, y, z and
// rotation about x, y, z. A 2D element has X, Y and Rz (a mask with Z, Rx or Ry is refused
// there: VALUE DOF). A blocked degree of freedom keeps its velocity whatever the forces: the
// force (or torque) component along it is cancelled each step, as YADE's blockedDOFs and
// LIGGGHTS's fix freeze do; its mass still enters the contacts' effective mass.
namespace dof {
inline constexpr unsigned X = 1, Y = 2, Z = 4, Rx = 8, Ry = 16, Rz = 32;
// Returns every degree of freedom of an element in dim dimensions.
inline constexpr unsigned all(int dim) {
  return dim == 2 ? X | Y | Rz : X | Y | Z | Rx | Ry | Rz;
}
}  // namespace dof

// One element, of uniform density (mass and inertia from the material's density and the
// shape: sim/shape.hpp).
struct ElementDef {
  Vec3d position{};
  Vec3d velocity{};
  Vec3d angularVelocity{};        // 2D: z only
  double radius = 0;              // > 0, finite: else VALUE RADIUS
  std::string material;           // an existing material: else LOOKUP MATERIAL
  std::vector<std::string> tags;  // each a valid tag: else VALUE TAG
  std::string name;               // optional, unique: else EXISTS NAME / VALUE NAME
  // The element's shape type, a name in the dimension's ShapeTable (sim/shape.hpp: the ball,
  // "sphere" in 3D and "disc" in 2D, first; else VALUE SHAPE); "": the ball. The ball takes no
  // parameters and is sized by radius; any other type takes shapeParams (checked by the type:
  // VALUE SHAPE) and no radius (VALUE RADIUS), its bounding radius following from them.
  std::string shape;
  std::vector<double> shapeParams;
  // The orientation: 3D a quaternion {w x y z} (normalised; VALUE ORIENTATION if zero or not
  // finite), 2D {angle}; empty: the identity.
  std::vector<double> orientation;
  unsigned blocked = 0;  // dof:: mask of blocked degrees of freedom (VALUE DOF)
  // Where the definition came from, for errors: `file "x" line 3` (pack file). A check that
  // fails appends it to its message in parentheses, as Tcl names a script's file and line.
  std::string origin;
};

enum class WallShape {
  Plane,   // infinite plane (a line in 2D) through point with normal; grains on the + side
  Finite,  // a finite flat wall: 2D a segment, 3D a rectangle; two-sided
  Box,     // a solid oriented box; grains outside
  Drum,    // a cylinder (a circle in 2D); grains inside
  Mesh     // a triangle mesh (3D only), two-sided
};

// Prescribed rigid motion of a wall, all parts optional and summed: the wall's reference point
// (the Def's point) moves as p0 + velocity t + amplitude sin(2 pi frequency t + phase), and the
// wall turns about that moving point at the constant angularVelocity. The motion is evaluated
// exactly at each time (no drift): a drum turns, a shaker table vibrates, a piston advances.
struct WallMotion {
  Vec3d velocity{};
  Vec3d angularVelocity{};  // 2D: z only; rad/s
  // A scripted motion: a component with a TimeFunction takes, each step, its value at the
  // step's midpoint instead of the constant (then the value at creation, for reports). A wall
  // with one cannot be saved in a checkpoint (as loads with TimeFunctions).
  std::array<TimeFunction, 3> velocityFn{}, angularVelocityFn{};
  Vec3d amplitude{};        // vibration displacement amplitude (m), along its own direction
  double frequency = 0;     // Hz, >= 0 (0 with a non-zero amplitude: VALUE FREQUENCY)
  double phase = 0;         // rad
};

// One wall. Fields used per shape (the others must stay at their defaults, else VALUE <FIELD>):
//   Plane : point, normal
//   Finite: point (centre), normal, halfExtents[0] (2D: half length along perp(normal));
//           3D also axis (in-plane, perpendicular to normal) and halfExtents[1] along
//           normal x axis
//   Box   : point (centre), halfExtents (2D: [0], [1]; 3D: all three), rotation: a rotation
//           vector (axis times angle, 2D: z only) turning the box from axis-aligned
//   Drum  : point (centre), radius; 3D also axis (the cylinder's axis) and halfLength
//   Mesh  : mesh (its triangles in their own frame), point (where the frame's origin goes),
//           rotation (a rotation vector turning the frame); 3D only
// A finite wall may also have a hole centred at its point: 3D a circular hole of radius hole,
// 2D a gap of half width hole; 0 < hole < every half extent (VALUE HOLE).
struct WallDef {
  WallShape shape = WallShape::Plane;
  Vec3d point{};
  Vec3d normal{};
  Vec3d axis{};
  Vec3d halfExtents{};
  Vec3d rotation{};
  double radius = 0;
  double halfLength = 0;
  double hole = 0;       // Finite only; 0: none
  std::shared_ptr<const physics::TriangleMesh> mesh;  // Mesh only
  std::string material;  // LOOKUP MATERIAL
  std::vector<std::string> tags;
  std::string name;
  std::optional<WallMotion> motion;
};

// A load on one grain or on every grain of a tag group (the same force and torque on each).
// For each component a TimeFunction, when set, replaces the constant. Exactly one of grain and
// tag must be given (VALUE TARGET). Loads with a TimeFunction cannot be saved in a checkpoint.
struct LoadDef {
  ElementId grain;    // null: use tag
  std::string tag;  // GroupBehavior over the grains carrying it at each step
  Vec3d force{};
  Vec3d torque{};  // 2D: z only
  std::array<TimeFunction, 3> forceFn{};
  std::array<TimeFunction, 3> torqueFn{};
};

// ---- results ---------------------------------------------------------------------------

struct ElementState {
  ElementId id;
  std::string name;
  std::vector<std::string> tags;
  std::string material;
  double radius = 0, mass = 0, inertia = 0;  // inertia: the largest principal moment
  std::array<double, 3> principalInertia{};  // 2D: {I, I, I}, the moment about z
  Vec3d position{}, velocity{}, angularVelocity{}, force{}, torque{};
  std::array<double, 4> orientation{};  // 3D: quaternion w x y z; 2D: {angle, 0, 0, 0}
  std::string shape;                // its shape type's name
  std::vector<double> shapeParams;  // its parameters (none for the ball)
  unsigned blocked = 0;             // dof:: mask
  Vec3d unwrapped{};                // position before periodic wraps (= position without)
};

// Periodic boundaries (sim/periodic.hpp): the periodic axes (bit k: axis k; none: no periodic
// boundaries), the cell [lo, hi) on those axes, and Lees-Edwards shear: the rate (1/s; 0: none)
// of the flow axis's velocity across the gradient axis (both periodic, distinct). offset: the
// images' displacement now (reported; setPeriodic keeps it when only the rate changes).
struct PeriodicDef {
  unsigned axes = 0;
  Vec3d lo{}, hi{};
  double shearRate = 0;
  int flow = 0, gradient = 1;
  double offset = 0;
};

struct WallState {
  WallId id;
  std::string name;
  std::vector<std::string> tags;
  std::string material;
  WallShape shape = WallShape::Plane;
  Vec3d point{};     // reference point now
  Vec3d velocity{};  // of the reference point now
  Vec3d angularVelocity{};
  std::array<double, 4> orientation{};  // as ElementState
  Vec3d force{};                        // total force the grains exert on the wall in the last step
  // Torque of those forces about the reference point (from the last step's contact records:
  // what the last step recorded, so after a run or at a sampled step; balls only), and the
  // work the wall has done on the grains since it was made (J).
  Vec3d torque{};
  double work = 0;
  bool servo = false;     // under a servo (WallServoDef)
  bool scripted = false;  // moved by TimeFunctions (WallMotion)
  Vec3d boundsLo{}, boundsHi{};
  // The geometry now (after any prescribed motion), for renderers and writers. Unit vectors.
  //   Plane : centre (a point on it), normal.
  //   Finite: centre, normal, axes[0] (and 3D axes[1]) along halfExtents[0] (and [1]); hole
  //           the radius of its hole (2D: the gap's half width), 0 for none.
  //   Box   : centre, axes[0..dim-1] its axes, halfExtents along them.
  //   Drum  : centre, radius; 3D axes[0] its axis and halfLength.
  //   Mesh  : centre (where its frame's origin is), axes[0..2] its frame's axes, mesh.
  Vec3d centre{}, normal{};
  std::array<Vec3d, 3> axes{};
  Vec3d halfExtents{};
  double radius = 0, halfLength = 0, hole = 0;
  std::shared_ptr<const physics::TriangleMesh> mesh;
};

// The heap a scene holds, in bytes, by part (capacities, so room reserved counts): what grows
// with the grains and contacts, for the memory per grain of a run (issue 3). Names, tags,
// materials, walls and behaviors (a few hundred bytes in a benchmark scene) are left out.
struct MemoryReport {
  size_t grains = 0;     // the per-grain state arrays and the grain handle pool
  size_t detection = 0;  // candidate pairs (grain and wall), positions at the last search
  size_t search = 0;     // the neighbor search's scratch kept between searches (0: freed)
  size_t springs = 0;    // tangential springs: per candidate pair, per wall candidate, parked
  size_t contacts = 0;   // the contact records of the last step
  size_t passes = 0;     // the other modules' scratch: the contact passes' per-group sums, ...
  size_t total() const { return grains + detection + search + springs + contacts + passes; }
};

// Every element's state at once, in dense order, for writers of whole scenes (dumps): one
// call, not one ElementState (with its strings) per element.
struct ElementTable {
  std::vector<ElementId> ids;
  // 3 per element; 2D: z = 0, and the angular ones (angular velocity, torque) about z only.
  std::vector<double> position, velocity, angularVelocity, force, torque;
  std::vector<double> orientation;  // 4 per element: quaternion w x y z (2D: about z)
  std::vector<double> radius;       // a non-ball's bounding radius
  std::vector<double> mass;
  std::vector<uint32_t> material;  // into materialNames
  std::vector<std::string> materialNames;
  std::vector<uint32_t> shape;  // into shapeNames (0: the ball)
  std::vector<std::string> shapeNames;
  size_t shapeParamCount = 0;      // the most parameters any element's shape has
  std::vector<double> shapeParams;  // shapeParamCount per element, 0 beyond its own
  std::vector<std::string> tagNames;         // every tag an element carries, sorted
  std::vector<std::vector<uint8_t>> tagged;  // per tag, per element: 1 if it carries it
};

struct ContactInfo {
  ElementId a;  // always a grain
  ElementId b;  // the other grain, or null when the contact is with wall
  WallId wall;
  Vec3d point{}, normal{};  // normal from a towards b (or the wall)
  double overlap = 0;
  Vec3d force{};  // force on b (or the wall); a receives its opposite
  Vec3d centreA{}, centreB{};  // the elements' centres (centreB zero for a wall)
};

// The energy ledger (joules). balance = kinetic + gravitational + elastic + damping + friction
// - wallWork - behaviorWork - springWork - (the same sum at the reference, the scene's first step)
// is zero for exact integration; residual = |balance| / scale, with scale the largest of the
// energies seen, is the run's error indicator.
struct EnergyLedger {
  double kineticTranslational = 0, kineticRotational = 0, gravitational = 0, elastic = 0;
  double dampingLoss = 0, frictionLoss = 0;  // cumulated, >= 0
  double wallWork = 0, behaviorWork = 0;     // cumulated work done on the grains
  double springWork = 0;  // cumulated energy given to Hertz-Mindlin tangential springs by
                          // their stiffening (physics/contact.hpp ContactForce::springWork)
  double bondReleased = 0;  // cumulated elastic energy of bonds when they broke
  double balance = 0, scale = 0, residual = 0;
};

struct ModuleTime {
  std::string module;
  double seconds = 0;
};

struct RunReport {
  uint64_t steps = 0;        // steps done by this run
  double simulatedTime = 0;  // seconds simulated by this run
  double time = 0;           // scene time at the end
  double wallSeconds = 0;
  bool interrupted = false;         // the stop flag ended the run early
  // Steps done and then dropped: the stop flag came during a long step, and the run went back
  // to its copy of the scene at an earlier step boundary (RunOptions::longStep).
  uint64_t dropped = 0;
  bool abandoned = false;  // a step was abandoned part way and the run went back to its copy
  // The run failed (RunOptions::failed) and the scene is back as it was before it.
  bool undone = false;
  std::vector<ModuleTime> modules;  // wall time per module, in loop order
  uint64_t contacts = 0;            // at the end
  uint64_t neighborRebuilds = 0;    // CGrid searches done by this run
  double energyResidual = 0;        // EnergyLedger::residual at the end
};

// The watchdog (sim/watchdog.hpp): cheap checks after every step of a run (and once at its
// start, before the first step) that stop the run at that step boundary with RunStopped:
//   NAN     a position, velocity or angular velocity is not finite;
//   SPEED   a grain moves more in one step than the larger of half the skin and half the
//           smallest radius (a contact would begin deep, a thin wall could be crossed);
//   OVERLAP a contact overlaps by more than `overlap` x the smaller radius (a wall: the grain's),
//           or, before the scene's first step, by more than `placed` x it (grains placed
//           overlapping), as do, before a later run, the contacts of what edits placed since
//           the last step;
//   ENERGY  the ledger's balance has grown (energy created) by more than `energy` x the energy
//           scale (EnergyLedger::scale).
// Part of the scene (digest, clone and checkpoint carry it). Defaults: on, 2, 0.5, 0.5, on.
struct WatchdogOptions {
  bool enabled = true;
  double overlap = 2;   // >= 0, finite; 0: no overlap check during runs. Else VALUE OVERLAP
  double placed = 0.5;  // >= 0, finite; 0: no check of placed overlaps. Else VALUE PLACED
  double energy = 0.5;  // > 0 and finite; 0: no energy check. Else VALUE ENERGY
  bool speed = true;
  bool operator==(const WatchdogOptions&) const = default;
};

// What stopped a run: the check that fired (NAN, SPEED, OVERLAP, ENERGY), where and why.
struct WatchdogTrip {
  std::string check;
  uint64_t step = 0;  // the scene's step count at the boundary where the run stopped
  double time = 0;
  bool atStart = false;         // found before the first step of the run (the scene as set up)
  std::vector<ElementId> grains;  // the elements concerned (one or two)
  WallId wall;                  // the wall concerned, if any
  std::string what;             // e.g. "overlap by 45% of the smaller radius (limit 20%)"
  std::string cause, fix;       // the likely cause and the fix, in words
  // Returns "run stopped at step N (t = T s) by the watchdog: <subject> <what>; likely cause:
  // ...; fix: ...", naming the elements and the wall with the given functions (the core passes
  // handles, the Tcl layer its script ids).
  std::string message(const std::function<std::string(ElementId)>& grainName,
                      const std::function<std::string(WallId)>& wallName) const;
};

// Thrown by Simulation::run when the watchdog fires: {WATCHDOG <check>}, the message naming the
// grains by handle. The scene stays at the step boundary where the run stopped (consistent and
// inspectable, nothing rolled back); report() covers the steps done up to there. A check that
// fires before the run's first step leaves the scene exactly as it was (trip().atStart).
class RunStopped : public Error {
 public:
  RunStopped(WatchdogTrip trip, RunReport report);
  const WatchdogTrip& trip() const { return trip_; }
  const RunReport& report() const { return report_; }

 private:
  WatchdogTrip trip_;
  RunReport report_;
};

// The result of Simulation::relax.
struct RelaxReport {
  uint64_t iterations = 0;  // passes made
  uint64_t moved = 0;       // grains moved at least once
  double before = 0;        // the largest overlap / smaller radius before
  double after = 0;         // and after
  bool interrupted = false; // the stop flag ended it between two passes
};

struct RunOptions {
  uint64_t steps = 0;
  // A run asked for a simulated time: the time it ends at. When the automatic step changes
  // during the run, the steps left are counted again to reach it (rounded up to whole steps);
  // NaN: a run of `steps` steps.
  double endTime = std::numeric_limits<double>::quiet_NaN();
  // Checked at every step boundary; when it reads true the run stops there, consistent.
  const std::atomic<bool>* stop = nullptr;
  // Called with (steps done, steps asked) about every progressEvery steps (0: every 1/100 of
  // the run, at least 1) and once at the end. It may read the scene, not change it.
  std::function<void(uint64_t, uint64_t)> progress;
  uint64_t progressEvery = 0;
  // Asked when the run stops early through `stop`: true when the stop came from a failure (a
  // script callback's error) rather than an interrupt. A run that failed is undone: the scene
  // goes back to its state before the run (RunReport::undone). Only scenes with script
  // callbacks can fail so, and only they pay for the copy this keeps.
  std::function<bool()> failed;
  // With `stop`: once a step takes longer than this (s), the run keeps a copy of the scene at a
  // recent step boundary and polls `stop` inside its steps too; stopped part way, it goes back
  // to the copy (RunReport::dropped). A step then answers Ctrl-C within a fraction of its own
  // time, however large the scene. Copies are taken again once the run has spent ten times the
  // last copy's time since, so they cost at most a tenth of the run.
  double longStep = 0.05;
};

// One named parameter of a behavior: what `behavior add TYPE -NAME VALUE` gives, what a query
// shows and what a checkpoint stores for every behavior type but the two original ones. Which
// field is used follows the kind the type's registry row declares for the name.
struct BehaviorParam {
  std::string name;
  std::vector<double> numbers;  // Number: 1; Vector: 3 (2D: z = 0); Angular: 3 (2D: z only)
  std::string text;             // Tag
  ElementId grain;                // Element
};

enum class BehaviorParamKind : uint8_t { Number, Vector, Angular, Element, Tag };

// One option of a behavior type, declared once in its registry row (sim/behavior_registry.hpp):
// the command layer builds `behavior add TYPE` from it, help shows it, checkpoints name it.
struct BehaviorOption {
  std::string name;
  BehaviorParamKind kind = BehaviorParamKind::Number;
  std::string unit;  // e.g. "N m"; empty for none
  std::string help;
  bool required = false;
};

// The public face of one registry row.
struct BehaviorTypeInfo {
  std::string name;     // `behavior add NAME`, BehaviorInfo::kind, the checkpoint's type name
  std::string summary;  // one line for help
  std::string module;   // the loop module running it ("gravity", "loads", "torque-ramp")
  std::vector<BehaviorOption> options;
  bool targeted = false;  // needs exactly one of the options "element" and "tag"
};

// Returns the behavior types, in registry order.
const std::vector<BehaviorTypeInfo>& behaviorTypes();

struct BehaviorInfo {
  BehaviorId id;
  std::string kind;          // the type's registry name: "gravity", "load", "torque-ramp"
  std::string description;   // e.g. `load on tag "bed": force (0 0 -1) N`
  bool serializable = true;  // false when it holds TimeFunctions
  std::vector<BehaviorParam> params;  // its named parameters (a time-varying part shows as 0)
};

// An output module (thesis chapter 9: a SimModule at the output level of the SimLoop): a
// callback run on the finished step every everySteps steps (when the scene's step count is a
// multiple of it), or every everyTime simulated seconds (at the step whose end time is nearest
// each multiple of everyTime: fires when (t - dt/2, t + dt/2] holds one). Exactly one of the
// two must be set. Outputs belong to the Simulation object, not to the scene: they are not in
// the state digest, not cloned, not saved (a checkpoint never holds them; save writes the
// scene without complaint) and survive load(). The callback may read the scene, never change
// it, and must not add or remove outputs; an exception it throws ends the run after that
// (complete, consistent) step and propagates out of run().
// A named set of bond parameters (`bond model TYPE NAME`): its type and values by option name.
struct BondModelInfo {
  std::string name, type;
  std::vector<std::pair<std::string, double>> values;
};

// One bond as queries see it (sim/bond.hpp). Force and moment act on b (a takes the opposite);
// normalForce > 0 is tension; sigma and tau are what the model's criterion compares with the
// strengths; strain is (length - restLength) / restLength.
struct BondInfo {
  uint32_t id = 0;
  ElementId a, b;
  std::string model;
  bool intact = true;
  double restLength = 0, length = 0, strain = 0;
  Vec3d force{0, 0, 0}, moment{0, 0, 0};
  double normalForce = 0, sigma = 0, tau = 0, energy = 0;
  double tensile = 0, shear = 0;  // the bond's own strengths
  std::string breakMode;          // "" while intact, else "tension" or "shear"
  double breakTime = 0;
};

// How many bonds there are, how many of them are intact, and how the others broke.
struct BondCount {
  uint64_t bonds = 0, intact = 0, tension = 0, shear = 0;
};

// One breakage: when, where (the bond's centre), how and which pair.
struct BondBreakInfo {
  uint32_t bond = 0;
  ElementId a, b;
  std::string mode;
  double time = 0;
  uint64_t step = 0;
  Vec3d point{0, 0, 0};
  double energy = 0;   // the elastic energy the bond held, released
  double measure = 0;  // sigma (tension) or tau (shear) when it broke, above the strength
};

struct OutputDef {
  std::string name;         // what outputs() shows, e.g. "snapshot frames/"; may be empty
  uint64_t everySteps = 0;  // > 0, or 0 when everyTime is used
  double everyTime = 0;     // > 0 and finite (seconds), or 0 when everySteps is used
  std::function<void(const Simulation&)> callback;  // required
  // Whether the callback reads the step's contacts (contacts(), contactCount()): the passes
  // then keep contact records at the steps the output is due at (and only those, unless
  // something else reads them).
  bool needsContacts = true;
  // Whether the callback works in a distributed scene: every rank calls it at the same steps,
  // and it writes once (pieces a rank and one index, or from rank 0). distribute() refuses the
  // outputs that do not.
  bool distributable = false;
};

struct OutputInfo {
  OutputId id;
  std::string name;
  uint64_t everySteps = 0;
  double everyTime = 0;
};

// ---- the scene -----------------------------------------------------------------------------

class Simulation {
 public:
  virtual ~Simulation() = default;

  // Returns 2 or 3.
  virtual int dim() const = 0;

  // -- time --
  // Sets a fixed time step. Throws VALUE TIMESTEP unless dt > 0 and finite.
  virtual void setTimeStep(double dt) = 0;
  // Makes the step automatic: fraction x criticalTimeStep(), recomputed whenever grains or
  // materials change and, during a run, after every neighbour search (the contacts' stiffness
  // at their overlaps then), and at most the duration of the shortest contact over
  // stepsPerContact (0: no accuracy target; linear pairs from their stiffness, Hertz pairs at
  // twice the fastest element's speed, taken again as it grows). Throws VALUE FRACTION unless
  // 0 < fraction <= 1, VALUE STEPSPERCONTACT unless 0 <= stepsPerContact <= 1e6.
  virtual void setAutoTimeStep(double fraction, double stepsPerContact) = 0;
  void setAutoTimeStep(double fraction) { setAutoTimeStep(fraction, kDefaultStepsPerContact); }
  // Returns the step the next run uses. Throws VALUE TIMESTEP if automatic with no grains, and
  // {INTERRUPTED} when Ctrl-C stops its estimate (a pass over the bonds). Distributed:
  // collective, the whole scene's step on every rank.
  virtual double timeStep() const = 0;
  // Returns the scene's critical step: the least of the static estimate over the materials and
  // grain sizes in the scene (physics::criticalTimeStep, Rayleigh step for Hertz; bonds) and
  // the ball contacts' at their overlaps at the last neighbour search
  // (sim/contact_stiffness.hpp); +inf when there are no grains. Throws {INTERRUPTED} as
  // timeStep.
  virtual double criticalTimeStep() const = 0;
  // Returns the ball contacts' critical step at their overlaps now (sim/contact_stiffness.hpp:
  // the candidates of the last search, the pair table of the last run), recomputed; +inf when
  // none touches or before a run. What the automatic step takes after each search.
  virtual double contactCriticalTimeStep() const = 0;
  // Returns the scene time and the number of steps taken.
  virtual double time() const = 0;
  virtual uint64_t stepCount() const = 0;

  // -- materials and contact laws --
  // Adds a material. Throws VALUE NAME, EXISTS MATERIAL, or the MaterialDef::check() error.
  virtual void addMaterial(const std::string& name, const MaterialDef& def) = 0;
  // Replaces an existing material's properties (grain masses follow the density).
  // Throws LOOKUP MATERIAL or the check() error.
  virtual void setMaterial(const std::string& name, const MaterialDef& def) = 0;
  virtual MaterialDef material(const std::string& name) const = 0;  // LOOKUP MATERIAL
  virtual std::vector<std::string> materialNames() const = 0;       // in creation order
  // Returns the dimension's shape types (sim/shape.hpp) as {name, parameters' description},
  // the ball first.
  virtual std::vector<std::pair<std::string, std::string>> shapeTypes() const = 0;
  // Returns the parameters of the shape type named shape with params, scaled about its centroid
  // so that its bounding radius is bound. Throws {VALUE SHAPE} as ElementDef's shape would, or
  // when the type cannot be scaled (the ball: use its radius). Changes nothing.
  virtual std::vector<double> shapeParamsForBound(const std::string& shape,
                                                  const std::vector<double>& params,
                                                  double bound) const = 0;
  // Returns the names of shapeTypes(), the ball first.
  std::vector<std::string> shapeNames() const {
    std::vector<std::string> out;
    for (auto& t : shapeTypes()) out.push_back(t.first);
    return out;
  }
  // Sets the law for every pair that has no pair-specific law (default: Hertz-Mindlin).
  virtual void setContactLaw(LawKind law) = 0;
  virtual LawKind contactLaw() const = 0;
  // Sets what the Coulomb limit caps in every pair's tangential force: Total (spring and
  // dashpot, the default) or Spring (the spring alone, LIGGGHTS's convention); see
  // physics/tangential.hpp. Takes effect at the next run; returns nothing.
  virtual void setCoulombCriterion(physics::CoulombCriterion c) = 0;
  virtual physics::CoulombCriterion coulombCriterion() const = 0;
  // Sets how every Hertz-Mindlin pair's restitution becomes its dampers: Calibrated (the
  // default: a head-on impact rebounds with e) or Liggghts (LIGGGHTS's beta, whose rebound is
  // not e); see physics/pair_params.hpp. Takes effect at the next run; returns nothing.
  virtual void setHertzDamping(physics::HertzDamping d) = 0;
  virtual physics::HertzDamping hertzDamping() const = 0;
  // Sets the law of one pair of materials (order irrelevant). LOOKUP MATERIAL.
  virtual void setPairLaw(const std::string& a, const std::string& b, LawKind law) = 0;
  // Returns the law the pair uses. LOOKUP MATERIAL.
  virtual LawKind pairLaw(const std::string& a, const std::string& b) const = 0;
  // Sets the coefficients of one pair (order irrelevant) that c gives (not NaN), replacing its
  // earlier ones; the others follow the mixing rules again. LOOKUP MATERIAL, VALUE <FIELD>.
  virtual void setPairCoefficients(const std::string& a, const std::string& b,
                                   const PairCoefficients& c) = 0;
  // Returns the pair's coefficients: its own where set, the mixing rules' elsewhere (so no
  // field is NaN). LOOKUP MATERIAL.
  virtual PairCoefficients pairCoefficients(const std::string& a, const std::string& b) const = 0;
  // Returns the pair's own coefficients (NaN where the mixing rule applies). LOOKUP MATERIAL.
  virtual PairCoefficients pairOverrides(const std::string& a, const std::string& b) const = 0;

  // -- grains --
  virtual ElementId addElement(const ElementDef& def) = 0;
  // Adds all or none: every Def is checked (and names checked against each other) first.
  virtual std::vector<ElementId> addElements(const std::vector<ElementDef>& defs) = 0;
  // Makes room for n grains in all (those present included), exactly: adding them then, in
  // batches or one by one, reallocates no per-grain array (grown as they come, the arrays
  // would hold up to half as much again as they use). Changes nothing observable.
  virtual void reserveElements(size_t n) = 0;
  // Removes a grain (its tags, name and contact histories go with it). LOOKUP HANDLE.
  virtual void removeElement(ElementId id) = 0;
  // Removes the grains ids (a repeated id once), one after another as removeElement does;
  // returns how many. In a distributed scene collective, all or none: LOOKUP HANDLE on every
  // rank, nothing removed, when an id names no element.
  virtual size_t removeElementList(const std::vector<ElementId>& ids) = 0;
  // Removes every grain carrying tag; returns how many.
  virtual size_t removeElements(const std::string& tag) = 0;
  virtual ElementState element(ElementId id) const = 0;                // LOOKUP HANDLE
  virtual ElementId findElement(const std::string& name) const = 0;  // LOOKUP NAME
  // Changes a grain's state; unset fields stay. LOOKUP HANDLE, VALUE <FIELD>.
  virtual void setElementPosition(ElementId id, const Vec3d& p) = 0;
  virtual void setElementVelocity(ElementId id, const Vec3d& v) = 0;
  virtual void setElementAngularVelocity(ElementId id, const Vec3d& w) = 0;
  // Turns the element to orientation o (as ElementDef::orientation; VALUE ORIENTATION).
  virtual void setElementOrientation(ElementId id, const std::vector<double>& o) = 0;
  // Blocks the degrees of freedom in mask (dof::) and frees the others; the velocities stay as
  // they are. LOOKUP HANDLE, VALUE DOF (a bit the dimension does not have).
  virtual void setElementBlocked(ElementId id, unsigned mask) = 0;
  // Multiplies the radii of the balls ids (distinct) by factor, their mass and inertia following
  // at their material's density; positions, velocities and bonds' rest lengths stay, so the
  // overlaps between them grow or shrink (radius expansion, as sample generators compact a
  // packing). All or none: LOOKUP HANDLE, VALUE FACTOR (not > 0 and finite), VALUE SHAPE (an
  // element that is not a ball), VALUE RADIUS (a new radius out of range). Returns nothing;
  // the ledger is rebased (an edit, like relax).
  virtual void scaleElementRadii(const std::vector<ElementId>& ids, double factor) = 0;
  virtual size_t elementCount() const = 0;

  // -- walls --
  virtual WallId addWall(const WallDef& def) = 0;
  virtual void removeWall(WallId id) = 0;                      // LOOKUP HANDLE
  virtual WallState wall(WallId id) const = 0;                 // LOOKUP HANDLE
  virtual WallId findWall(const std::string& name) const = 0;  // LOOKUP NAME
  virtual std::vector<WallId> wallIds() const = 0;
  virtual size_t wallCount() const = 0;
  // Replaces a wall's motion from now on, keeping its id, candidates and contact springs: the
  // new motion starts from where the wall is (no jump); a servo ends. LOOKUP HANDLE, VALUE
  // <FIELD> as addWall's motion.
  virtual void setWallMotion(WallId id, const WallMotion& m) = 0;
  // Puts a plane or finite wall under a servo (sim/boundaries.hpp), from now on. LOOKUP HANDLE,
  // VALUE SHAPE (another shape), VALUE TARGET / GAIN / MAXSPEED.
  virtual void setWallServo(WallId id, const WallServoDef& servo) = 0;

  // -- periodic boundaries (sim/periodic.hpp) --
  // Makes the axes of def periodic with its cell and shear, from the next step on (elements
  // are wrapped into the cell at the next neighbour search); def.axes = 0 removes them. Throws
  // VALUE AXES (an axis the scene lacks), VALUE CELL (lo < hi, finite, within the coordinate
  // bound), VALUE RATE (finite; a shear needs flow and gradient periodic and distinct),
  // UNSUPPORTED PERIODIC (bonds or shape elements in the scene). Each periodic length must
  // exceed twice the largest pair reach: checked at every run start (VALUE CELL).
  virtual void setPeriodic(const PeriodicDef& def) = 0;
  virtual PeriodicDef periodic() const = 0;

  // -- sources and sinks (sim/boundaries.hpp) --
  // Adds a source; it inserts from the next step on. VALUE NAME, EXISTS NAME, LOOKUP MATERIAL,
  // VALUE RATE / TARGET / REGION / RADIUS / VELOCITY / JITTER / TOLERANCE / TRIES / TAG.
  virtual void addSource(const SourceDef& def) = 0;
  virtual void removeSource(const std::string& name) = 0;  // LOOKUP NAME
  virtual std::vector<BoundaryInfo> sources() const = 0;   // in creation order
  // Adds a sink; it removes from the next step on. VALUE NAME, EXISTS NAME, VALUE REGION,
  // VALUE NORMAL, VALUE POINT.
  virtual void addSink(const SinkDef& def) = 0;
  virtual void removeSink(const std::string& name) = 0;  // LOOKUP NAME
  virtual std::vector<BoundaryInfo> sinks() const = 0;   // in creation order

  // -- tags (Tk canvas model: idempotent; an unknown tag is empty) --
  virtual void tagElement(ElementId id, const std::string& tag) = 0;    // LOOKUP HANDLE, VALUE TAG
  virtual void untagElement(ElementId id, const std::string& tag) = 0;  // LOOKUP HANDLE
  virtual std::vector<ElementId> elementsTagged(const std::string& tag) const = 0;
  // Returns the dense indices (those of elementIds() and the per-element arrays) of the
  // elements carrying tag, in the tag's order: a distributed scene's among this rank's own.
  virtual std::vector<uint32_t> taggedIndices(const std::string& tag) const = 0;
  // Every name of the kind given (elements, walls) and every tag an element or wall carries,
  // sorted: what the console completes.
  virtual std::vector<std::string> elementNames() const = 0;
  virtual std::vector<std::string> wallNames() const = 0;
  virtual std::vector<std::string> tagNames() const = 0;
  virtual void tagWall(WallId id, const std::string& tag) = 0;
  virtual void untagWall(WallId id, const std::string& tag) = 0;
  virtual std::vector<WallId> wallsTagged(const std::string& tag) const = 0;

  // -- behaviors --
  // Adds uniform gravity g (m/s^2) on every grain. VALUE GRAVITY.
  virtual BehaviorId addGravity(const Vec3d& g) = 0;
  // Adds a load. VALUE TARGET, LOOKUP HANDLE, VALUE FORCE / VALUE TORQUE.
  virtual BehaviorId addLoad(const LoadDef& def) = 0;
  // Adds a behavior of a registered type from its named parameters (see behaviorTypes()).
  // Throws LOOKUP BEHAVIORTYPE (unknown type), VALUE OPTION (a name the type does not declare,
  // or a required one missing), VALUE TARGET, LOOKUP HANDLE, VALUE <NAME>; changes nothing then.
  virtual BehaviorId addBehavior(const std::string& type,
                                 const std::vector<BehaviorParam>& params) = 0;
  virtual void removeBehavior(BehaviorId id) = 0;  // LOOKUP HANDLE
  virtual std::vector<BehaviorInfo> behaviors() const = 0;

  // -- options (sim/options.hpp: the modules' options and the law's sub-model choices) --
  // Sets the options given, all or none: every setting is checked first (its group, its name,
  // its value against the option's type and range). Takes effect at the next step; returns
  // nothing. Throws LOOKUP MODULE, VALUE OPTION, VALUE <NAME> (`bad skin "inf": must be a
  // finite number`) and changes nothing then.
  virtual void setOptions(const std::vector<OptionSetting>& settings) = 0;
  // Returns the value of option name of group. Throws LOOKUP MODULE, VALUE OPTION.
  virtual OptionValue option(std::string_view group, std::string_view name) const = 0;
  // Sets one option (setOptions with one setting).
  void setOption(std::string_view group, std::string_view name, OptionValue value) {
    setOptions({{std::string(group), std::string(name), std::move(value)}});
  }

  // -- modules --
  // Returns the names of the modules the next step runs, in loop order (e.g. "behaviors",
  // "integrate", "rotation", "walls", "detection", "contacts" or "contacts-friction",
  // "wall-contacts" or "wall-contacts-friction", "gravity", "loads" and one module per other
  // behavior type present (e.g. "torque-ramp"), "touch" when the touch
  // correction is on, "integrate-correct",
  // "watchdog" unless it is off).
  virtual std::vector<std::string> listModules() const = 0;

  // -- outputs (see OutputDef) --
  // Adds an output; the loop then runs the "outputs" module last in each step. Throws VALUE
  // OUTPUT (neither or both of everySteps and everyTime, or everyTime not positive and
  // finite), VALUE CALLBACK (no callback), STATE BUSY (called from an output callback).
  virtual OutputId addOutput(const OutputDef& def) = 0;
  // Removes an output; with none left the loop runs no output code. LOOKUP HANDLE, STATE BUSY.
  virtual void removeOutput(OutputId id) = 0;
  // Returns the outputs in the order they fire (creation order).
  virtual std::vector<OutputInfo> outputs() const = 0;

  // -- bonds (sim/bond.hpp) --
  // Defines the bond model name of type type (sim/bond_model.hpp's table) from values by option
  // name; an option left out takes its default. Checks everything first: VALUE NAME, EXISTS
  // BONDMODEL, LOOKUP BONDTYPE, VALUE OPTION (an unknown or missing option), VALUE <OPTION> (a
  // value out of range or not a number).
  virtual void addBondModel(const std::string& name, const std::string& type,
                            const std::vector<std::pair<std::string, double>>& values) = 0;
  virtual std::vector<BondModelInfo> bondModels() const = 0;  // creation order
  // Bonds each pair (a, b) with the model named model, at its present distance; returns the new
  // bonds' ids. All or none: LOOKUP BONDMODEL, LOOKUP HANDLE (an element not there), VALUE PAIR
  // (an element with itself, or a pair given twice or already bonded).
  virtual std::vector<uint32_t> addBonds(const std::vector<std::pair<ElementId, ElementId>>& pairs,
                                         const std::string& model) = 0;
  // Bonds every pair of the elements among (every element when empty) whose surfaces are at
  // most gap apart (an overlap counts) and that have no bond yet; returns the new ids in
  // creation order (pairs by their ids' dense order). VALUE GAP (not >= 0 and finite), as
  // addBonds otherwise.
  virtual std::vector<uint32_t> addBondsWithin(const std::vector<ElementId>& among, double gap,
                                               const std::string& model) = 0;
  // Removes the bonds ids (intact or broken). LOOKUP BOND when one is not there (none removed).
  virtual void removeBonds(const std::vector<uint32_t>& ids) = 0;
  virtual std::vector<BondInfo> bonds() const = 0;            // creation order
  virtual std::optional<BondInfo> bond(uint32_t id) const = 0;  // nullopt: no such bond
  virtual BondCount bondCount() const = 0;
  virtual std::vector<BondBreakInfo> bondBreaks() const = 0;  // in the order they broke

  // -- running --
  // Runs options.steps steps (stopping early at a step boundary when *stop reads true).
  // Throws VALUE TIMESTEP when no step can be chosen; RunStopped {WATCHDOG NAN|SPEED|OVERLAP|
  // ENERGY} when the watchdog fires (at the start, before any step, or after the step where it
  // fired; the scene stays there). With the watchdog off, INTEGRATION NAN (checked every 1024
  // steps and at the end; the state is not rolled back) when a grain's state stops being finite.
  virtual RunReport run(const RunOptions& options) = 0;
  // Moves overlapping grains apart (walls stay) until no contact overlaps by more than
  // fraction x the smaller radius, or maxIterations passes: each pass pushes every pair
  // overlapping by more than that back to half of it, shared by inverse mass (a grain on a wall
  // moves alone). Velocities are kept; the ledger is rebased (the change is an edit). Throws
  // VALUE FRACTION unless 0 < fraction <= 1, VALUE ITERATIONS unless maxIterations >= 1, VALUE
  // TIMESTEP as run. When *stop reads true between two passes it returns with interrupted set:
  // the passes made stay made, the scene consistent. A pass that may take longer than longPass
  // seconds (the last one did; the first, on a scene of 10^5 elements or more) starts from a
  // copy of the scene, and *stop abandons it part way: the scene is then the last whole pass's.
  virtual RelaxReport relax(double fraction, uint64_t maxIterations,
                            const std::atomic<bool>* stop = nullptr,
                            double longPass = RunOptions{}.longStep) = 0;
  // Runs one step; returns its report.
  virtual RunReport step() = 0;
  // Runs n steps with no stop flag and no progress callback; returns the report.
  RunReport runSteps(uint64_t n) {
    RunOptions o;
    o.steps = n;
    return run(o);
  }
  // Runs for `seconds` of simulated time as `sim run -time` does (the steps counted again
  // when the automatic step changes); returns the report.
  RunReport runTime(double seconds) {
    RunOptions o;
    o.steps = static_cast<uint64_t>(std::ceil(seconds / timeStep() * (1 - 1e-12)));
    o.endTime = time() + seconds;
    return run(o);
  }

  // -- queries --
  virtual EnergyLedger energy() const = 0;
  virtual size_t contactCount() const = 0;  // contacts found in the last step
  // In a distributed scene: the contacts this rank computed (those whose a it owns; b may be
  // another rank's), with the ids scripts know.
  virtual std::vector<ContactInfo> contacts() const = 0;
  // Returns the heap the scene holds now, by part (see MemoryReport).
  virtual MemoryReport memory() const = 0;
  // Returns the box holding every grain and finite wall {lo, hi}; empty scene: zeros. In a
  // distributed scene the whole scene's box, on every rank: collective.
  virtual std::array<Vec3d, 2> bounds() const = 0;
  virtual std::vector<ElementId> elementIds() const = 0;  // dense order
  virtual std::vector<double> positions() const = 0;
  virtual std::vector<double> velocities() const = 0;
  virtual std::vector<double> angularVelocities() const = 0;
  virtual std::vector<double> orientations() const = 0;
  virtual std::vector<double> forces() const = 0;
  virtual std::vector<double> radii() const = 0;
  virtual ElementTable elementTable() const = 0;
  // Returns how the renderer draws the elements (sim/shape.hpp, ShapeType::renderTriangles):
  // per element in dense order the index of its mesh in meshes, or -1 for a ball (drawn as a
  // sphere or disc). meshOf is empty when no element has a mesh.
  struct ElementMeshes {
    std::vector<int32_t> meshOf;
    std::vector<std::vector<Vec3d>> meshes;  // body-frame triangles, 3 points each
  };
  virtual ElementMeshes elementMeshes() const = 0;

  // -- distributed runs (sim/distribution.hpp, doc/plans/mpi.md) --
  // Spreads the scene over the ranks of the MPI world (one rank: itself): every rank keeps
  // the elements of its box of a recursive coordinate bisection; the runs after it are the
  // ranks' runs together. Collective: every rank calls it on the same scene (the same script
  // made it). Throws MPI UNSUPPORTED naming the first feature distributed runs do not have yet
  // (2D, element shapes, bonds, mesh walls, periodic boundaries, sources, sinks, blocked
  // degrees of freedom, loads other than gravity, servo walls, outputs, named or tagged
  // elements) or MPI DISTRIBUTED when it already is, changing nothing. After it, edits of the
  // elements are refused (the first step of a run takes the place of a neighbour search),
  // and every query but elementSnapshots(), energy() and the run reports answers for this
  // rank's elements only.
  virtual void distribute() = 0;
  // Returns true once distribute() has been called.
  virtual bool distributed() const = 0;
  // Returns this rank's handle of the element a script names by `original`, the handle it had
  // when the scene was distributed (elements keep it as they move between ranks), or a null
  // handle when another rank owns it or none. A serial scene: original itself, or LOOKUP
  // HANDLE. Not collective.
  virtual ElementId ownedElement(ElementId original) const = 0;
  // Returns the handle scripts know the element by that this rank holds as `local` (the
  // inverse of ownedElement). Throws LOOKUP HANDLE when local names no element here.
  virtual ElementId originalHandle(ElementId local) const = 0;
  // One element as elementSnapshots() gathers it.
  struct ElementSnapshot {
    uint64_t id;  // its global id: its creation index in the scene
    Vec3d position, velocity, angularVelocity;
  };
  // Returns every element of the scene, gathered from every rank, by increasing global id.
  // Collective in a distributed scene.
  virtual std::vector<ElementSnapshot> elementSnapshots() const = 0;
  // What a distributed run did so far (zeros in a serial scene): this rank's owned elements and
  // ghosts, the searches, bisections and elements it sent to other ranks, and the copies of its
  // elements it sends the other ranks each step.
  struct DistributionReport {
    int rank = 0, ranks = 1;
    uint64_t owned = 0, ghosts = 0, searches = 0, bisections = 0, migrated = 0, copiesSent = 0;
  };
  virtual DistributionReport distribution() const = 0;

  // -- whole scene --
  // Returns a 64-bit hash of everything that determines the future of the scene (state,
  // materials, laws, walls, behaviors' parameters, pair histories, time, options, handle
  // pools): equal digests mean equal scenes.
  virtual uint64_t stateDigest() const = 0;
  // Returns a deep copy that runs bit-identically to this scene (TimeFunctions are shared).
  virtual std::unique_ptr<Simulation> clone() const = 0;
  // Writes a binary checkpoint of the whole scene. Throws SAVE CALLBACK naming the behaviors
  // holding TimeFunctions, writing nothing, unless skipCallbacks: then they are left out and
  // their descriptions returned. Continuing from load() is bit-identical to never stopping.
  virtual std::vector<std::string> save(std::ostream& out, bool skipCallbacks = false) const = 0;
  // The same as the checkpoint file's bytes, without a copy; the descriptions go to *skipped.
  // Polls Ctrl-C as it serializes (throws {INTERRUPTED}, having changed nothing). Distributed:
  // collective; rank 0 gets the whole scene's checkpoint, which loads on any number of ranks
  // (its elements, springs, ledger and walls gathered; candidates and touch states not kept,
  // so the loaded run searches first and agrees with the one saved to round-off), the other
  // ranks an empty string.
  virtual std::string saveBytes(bool skipCallbacks, std::vector<std::string>* skipped) const = 0;
  // Replaces this scene by the checkpoint read from in. Throws LOAD FORMAT (not a demlab
  // checkpoint, truncated, damaged: the checksum save appends does not match, or a value out
  // of range) or LOAD DIMENSION (another dimension), changing nothing.
  virtual void load(std::istream& in) = 0;
  // The same from the file's bytes, without a copy.
  virtual void loadBytes(std::string fileBytes) = 0;
};

// Returns the dimension a checkpoint's header names (2 or 3), or 0 when the bytes do not start
// with a demlab checkpoint header (the loader then says what is wrong).
int checkpointDimension(std::string_view fileBytes);

// Returns a new, empty scene of dimension dim. Throws VALUE DIMENSION unless dim is 2 or 3.
std::unique_ptr<Simulation> makeSimulation(int dim);

}  // namespace demlab::sim
