// The laboratory's boundaries as the public API sees them: sources that insert elements during
// a run, sinks that remove them, and servo-controlled walls. Checked before anything changes
// (SimulationManager: sim/simulation_boundaries.cpp); the scene's side is sim/source.hpp and
// sim/sink.hpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/packing.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim {

// A source: inserts elements of a size distribution into a region during runs, at a mass or a
// number rate, never overlapping what is there by more than tolerance x the smaller radius.
// Deterministic: its own generator, seeded by seed, is part of the scene.
struct SourceDef {
  std::string name;  // unique among the sources (VALUE NAME, EXISTS NAME)
  Region region;     // box, sphere or (3D) cylinder; must hold the largest element (VALUE REGION)
  SizeDistribution size;  // as pack's; a normal one needs mean > 3 sd (VALUE RADIUS)
  std::string material;   // LOOKUP MATERIAL
  std::vector<std::string> tags;
  // Exactly one rate is > 0 (VALUE RATE): kg/s or elements/s.
  double massRate = 0;
  double countRate = 0;
  // Where it stops: a total mass (kg) or count; 0: never. Not negative (VALUE TARGET).
  double targetMass = 0;
  uint64_t targetCount = 0;
  Vec3d velocity{};      // the mean velocity of an inserted element
  double jitter = 0;     // each velocity component uniform in +-jitter (m/s, >= 0)
  double tolerance = 0;  // allowed placed overlap, a fraction of the smaller radius, in [0, 1)
  uint64_t seed = 1;
  uint32_t tries = 200;  // placement attempts per element per step (>= 1)
  // Places what it owes every `every` steps, in [1, kMaxEvery]: each step that inserts
  // redoes the force pass, so large scenes insert in batches (the debt carries over).
  uint32_t every = 1;
  // Each element turned at random, uniformly over the rotations (3D: a uniform unit
  // quaternion, Shoemake's; 2D: an angle uniform in [-pi, pi)); else the identity.
  bool randomOrientation = false;
  // A shape type other than the ball (empty: the ball) and its parameters, scaled about its
  // centre for each element so that its bounding radius is the radius drawn (VALUE SHAPE).
  std::string shape;
  std::vector<double> shapeParams;
};

// The longest interval of steps between a source's or a sink's actions (VALUE EVERY).
inline constexpr uint32_t kMaxBoundaryEvery = 1000000;

// Returns true if a source or sink acting every `every` steps acts at the end of the step that
// brings the scene to `steps` steps.
inline bool boundaryActs(uint32_t every, uint64_t steps) {
  return every <= 1 || steps % every == 0;
}

// A sink: removes at the end of each step every element whose centre lies in its region (or
// outside it, with outside), or beyond its plane (on the side opposite the normal).
struct SinkDef {
  std::string name;
  enum Kind : uint8_t { Region, Plane } kind = Region;
  sim::Region region;
  bool outside = false;     // Region: remove what leaves the region instead of what enters it
  Vec3d point{}, normal{};  // Plane (normal non-zero: VALUE NORMAL)
  // Removes what it takes every `every` steps, in [1, kMaxBoundaryEvery] (as SourceDef's).
  uint32_t every = 1;
};

// A servo on a plane or finite wall: each step the wall moves along its normal (the side of the
// grains for a plane) at v = gain (target - measured), measured = the force the grains push
// it back with in the last step (-F . n), capped at maxSpeed. Stable while gain K dt < 2 for a
// packing of normal stiffness K (doc/design.md, "Sources, sinks and moving boundaries").
struct WallServoDef {
  double target = 0;    // N, >= 0 (VALUE TARGET)
  double gain = 0;      // m/(N s), > 0 (VALUE GAIN)
  double maxSpeed = 0;  // m/s, > 0 (VALUE MAXSPEED)
};

// What a source has done (elements and mass inserted) or a sink (removed), and the scene time
// it was added at.
struct BoundaryInfo {
  std::string name;
  std::string description;
  uint64_t count = 0;
  double mass = 0;
  double start = 0;
};

}  // namespace demlab::sim
