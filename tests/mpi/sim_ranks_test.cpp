// Distributed runs of whole scenes (Simulation::distribute) on real ranks: ctest runs this
// program under mpirun on 1, 2 and 3 ranks. Every rank makes the same scene and runs it
// distributed; rank 0 also runs it serially first and compares the gathered elements: the
// same elements, the same contact count, positions and velocities to round-off (the ranks add an
// element's contact forces in another order than the serial run, so bits differ from the first
// step and grow as any perturbation of a granular flow does), the energy ledger's residual
// alike.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "mpi/communicator.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim {
namespace {

const mpi::Communicator& world() { return mpi::Communicator::world(); }

MaterialDef glass(double friction, double rolling = 0, double cohesion = 0) {
  MaterialDef m;
  m.rollingFriction = rolling;
  m.cohesion = cohesion;
  m.density = 2500;
  m.young = 1e7;
  m.poisson = 0.3;
  m.restitution = 0.5;
  m.friction = friction;
  return m;
}

// A bed of n balls of radius r on a jittered lattice in the box [0, side]^3 with walls, falling
// under gravity with random velocities up to 0.3 m/s (seeded: the same on every rank).
std::unique_ptr<Simulation> bed(int n, double r, double side, double friction,
                                double rolling = 0, double cohesion = 0) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", glass(friction, rolling, cohesion));
  for (int k = 0; k < 3; ++k) {
    WallDef w;
    w.shape = WallShape::Plane;
    w.material = "glass";
    w.normal = {0, 0, 0};
    w.normal[k] = 1;
    s->addWall(w);
    w.normal[k] = -1;
    w.point[k] = side;
    s->addWall(w);
  }
  s->addGravity({0, 0, -9.81});
  uint64_t state = 12345;
  const auto uniform = [&] {  // SplitMix64 in [-1, 1)
    state += 0x9E3779B97F4A7C15ull;
    uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return static_cast<double>((z ^ (z >> 31)) >> 11) / 4503599627370496.0 - 1.0;
  };
  const double pitch = 2.3 * r;
  const int perAxis = static_cast<int>((side - 2 * r) / pitch);
  for (int k = 0; k < n; ++k) {
    ElementDef e;
    e.material = "glass";
    e.radius = r * (1 + 0.1 * uniform());
    int c = k;
    for (int a = 0; a < 3; ++a) {
      e.position[a] = 1.2 * r + pitch * (c % perAxis) + 0.05 * r * uniform();
      c /= perAxis;
      e.velocity[a] = 0.3 * uniform();
    }
    s->addElement(e);
  }
  s->setTimeStep(2e-5);
  return s;
}

// Runs the scene serially and distributed over the world for steps steps (in runs of `each`)
// and compares them at the end. tol: the largest position difference allowed over the radius.
// warm: both run `each` steps before the one is distributed (its pairs' springs and touch states
// then go with the elements at the first search).
void compare(int n, double friction, uint64_t steps, uint64_t each, double tol, bool warm = false,
             double rolling = 0, double cohesion = 0) {
  // The serial run on rank 0 alone, first (the others, waiting in distribute(), would each
  // repeat it on the cores the ranks share); it compares.
  const bool judge = world().rank() == 0;
  RunReport a;
  std::vector<Simulation::ElementSnapshot> x;
  if (judge) {
    auto serial = bed(n, 0.005, 0.2, friction, rolling, cohesion);
    // (Distributed runs give every element half the skin: the same searches.)
    serial->setOption("detection", "margins", false);
    for (uint64_t k = 0; k < steps + (warm ? each : 0); k += each) a = serial->runSteps(each);
    x = serial->elementSnapshots();
  }
  // (The others sleep meanwhile: spinning in distribute()'s first collective they would take
  // a core from whatever else runs, another test under ctest -j2.)
  world().idleBarrier();
  auto dist = bed(n, 0.005, 0.2, friction, rolling, cohesion);
  dist->setOption("detection", "margins", false);
  if (warm) dist->runSteps(each);
  dist->distribute();
  RunReport b;
  for (uint64_t k = 0; k < steps; k += each) b = dist->runSteps(each);
  const auto y = dist->elementSnapshots();
  if (judge) {
    EXPECT_EQ(x.size(), y.size());
    double worst = 0, worstV = 0;
    for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
      EXPECT_EQ(x[i].id, y[i].id);
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, std::abs(x[i].position[k] - y[i].position[k]));
        worstV = std::max(worstV, std::abs(x[i].velocity[k] - y[i].velocity[k]));
      }
    }
    EXPECT_LE(worst, tol * 0.005) << "velocities differ by up to " << worstV << " m/s";
    std::printf("%d ranks, friction %g: %zu contacts, positions within %.3g m, velocities %.3g m/s\n",
                world().size(), friction, static_cast<size_t>(b.contacts), worst, worstV);
    EXPECT_EQ(a.contacts, b.contacts);
    EXPECT_NEAR(a.energyResidual, b.energyResidual, 1e-6 + 0.01 * a.energyResidual);
  }
  // (A bed, not a gas: most balls touch others or the floor by the end.)
  EXPECT_GT(b.contacts, static_cast<uint64_t>(n / 2));
  const Simulation::DistributionReport r = dist->distribution();
  EXPECT_EQ(r.ranks, world().size());
  // Every rank owns a fair share and, with several ranks, holds ghosts.
  const double share = static_cast<double>(n) / world().size();
  EXPECT_GT(static_cast<double>(r.owned), 0.7 * share);
  EXPECT_LT(static_cast<double>(r.owned), 1.3 * share);
  if (world().size() > 1) {
    EXPECT_GT(r.ghosts, 0u);
  }
  EXPECT_GT(r.searches, 1u);
}

// 1200 balls fall 0.06 s (about 950-1 200 contacts at the end), in runs of 1000 steps.
TEST(SimRanks, FrictionalBedAgreesWithTheSerialRun) { compare(1200, 0.5, 3000, 1000, 1e-6); }

TEST(SimRanks, FrictionlessBedAgreesWithTheSerialRun) { compare(1200, 0, 3000, 1000, 1e-6); }

// Rolling resistance and cohesion: their torques and forces on ghosts go back with the rest.
TEST(SimRanks, RollingCohesiveBedAgreesWithTheSerialRun) {
  compare(1200, 0.5, 3000, 1000, 1e-6, false, 0.1, 2.0);
}

TEST(SimRanks, BedDistributedAfterARunAgreesWithTheSerialRun) {
  compare(1200, 0.5, 3000, 1000, 1e-6, true);
}

// A checkpoint of a distributed scene holds the whole scene (sim/simulation_gather.cpp): loaded
// alone after 1000 steps it is the serial run's scene to round-off, under the same handles, with
// the same pool (the next element added gets the serial scene's next handle), the ledger's sums
// and the walls' work whole; and it goes on as the distributed run does.
TEST(SimRanks, CheckpointOfRanksLoadsAlone) {
  const auto make = [] {
    auto s = bed(600, 0.005, 0.2, 0.5);
    // Removed elements: free slots in the pool, and handles that are not their global ids.
    for (uint32_t k : {3u, 40u, 41u}) s->removeElement(s->elementIds().at(k));
    s->setOption("detection", "margins", false);
    return s;
  };
  const bool judge = world().rank() == 0;
  std::unique_ptr<Simulation> serial;
  if (judge) {
    serial = make();
    serial->runSteps(1000);
  }
  world().idleBarrier();
  auto dist = make();
  dist->distribute();
  dist->runSteps(1000);
  std::vector<std::string> skipped;
  const std::string bytes = dist->saveBytes(false, &skipped);
  EXPECT_TRUE(skipped.empty());
  EXPECT_EQ(bytes.empty(), !judge);  // rank 0 alone gets the file
  const EnergyLedger distLedger = dist->energy();
  dist->runSteps(500);
  const auto wentOn = dist->elementSnapshots();
  if (!judge) return;
  auto loaded = makeSimulation(3);
  loaded->loadBytes(bytes);
  EXPECT_FALSE(loaded->distributed());
  std::vector<ElementId> a = serial->elementIds(), b = loaded->elementIds();
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
  for (ElementId id : a) {
    const ElementState x = serial->element(id), y = loaded->element(id);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(x.position[k], y.position[k], 1e-9);
  }
  const EnergyLedger es = serial->energy(), el = loaded->energy();
  EXPECT_NEAR(es.dampingLoss, el.dampingLoss, 1e-6 * es.dampingLoss);
  EXPECT_NEAR(es.frictionLoss, el.frictionLoss, 1e-6 * es.frictionLoss);
  EXPECT_NEAR(es.wallWork, el.wallWork, 1e-9 + 1e-6 * std::abs(es.wallWork));
  EXPECT_NEAR(distLedger.residual, el.residual, 1e-9);
  // Loaded alone it goes on as the distributed scene did.
  loaded->runSteps(500);
  const auto y = loaded->elementSnapshots();
  ASSERT_EQ(wentOn.size(), y.size());
  double worst = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    EXPECT_EQ(wentOn[i].id, y[i].id);
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(wentOn[i].position[k] - y[i].position[k]));
  }
  EXPECT_LE(worst, 1e-12);
  // The pool as the serial scene's: the same next handles (its free slots, last freed first).
  ElementDef e;
  e.material = "glass";
  e.radius = 0.005;
  e.position = {0.1, 0.1, 0.18};
  for (int k = 0; k < 4; ++k) EXPECT_EQ(serial->addElement(e), loaded->addElement(e));
}

// Adds a 5 mm glass ball at `position` with `velocity` to s after adding and removing one
// there, so that its handle reuses a slot (generation 2): not the handle its global id would
// give. Returns its handle.
ElementId addInAReusedSlot(Simulation& s, Vec3d position, Vec3d velocity) {
  ElementDef e;
  e.material = "glass";
  e.radius = 0.005;
  e.position = position;
  s.removeElement(s.addElement(e));
  e.velocity = velocity;
  const ElementId id = s.addElement(e);
  EXPECT_GT(id.generation, 1u);
  return id;
}

// Runs s for steps steps, expecting the watchdog's speed check to stop the run on every rank
// with the same message, which names the element scripts call `id`. Returns the message.
std::string expectSpeedTripOnEveryRank(Simulation& s, uint64_t steps, ElementId id) {
  std::vector<std::string> code;
  std::string message;
  try {
    s.runSteps(steps);
  } catch (const Error& e) {
    code = e.code();
    message = e.what();
  }
  EXPECT_EQ(code, (std::vector<std::string>{"DEMLAB", "WATCHDOG", "SPEED"})) << message;
  EXPECT_NE(message.find("element " + toString(id) + " moves"), std::string::npos) << message;
  for (const std::vector<char>& m : world().gatherBytes({message.begin(), message.end()})) {
    EXPECT_EQ(std::string(m.begin(), m.end()), message);
  }
  return message;
}

// One element far too fast for the step: the watchdog stops the run before its first step on
// every rank alike, none left waiting in a collective, with the same message on every rank (the
// description of the rank holding it), naming it by the handle the scene gave it.
TEST(SimRanks, WatchdogStopsEveryRank) {
  auto s = bed(600, 0.005, 0.2, 0.5);
  const ElementId fast = addInAReusedSlot(*s, {0.15, 0.15, 0.15}, {0, 0, -400});
  s->distribute();
  expectSpeedTripOnEveryRank(*s, 10, fast);
  EXPECT_EQ(s->stepCount(), 0u);
}

// Returns the rank that holds the element scripts call `id` (every rank learns it). Collective.
int holderOf(const Simulation& s, ElementId id) {
  const char mine = s.ownedElement(id).isNull() ? 0 : 1;
  const auto all = world().gatherBytes({mine});
  for (size_t r = 0; r < all.size(); ++r) {
    if (all[r] == std::vector<char>{1}) return static_cast<int>(r);
  }
  return -1;
}

// An element pushed diagonally across the domain by a load (which holds it against gravity)
// goes over to another rank and trips the speed check there: every rank's message names it by
// the handle scripts hold, not by the handle of the pool of the rank it went to.
TEST(SimRanks, WatchdogNamesAnElementThatChangedRanks) {
  auto s = bed(600, 0.005, 0.2, 0.5);
  const ElementId fast = addInAReusedSlot(*s, {0.02, 0.02, 0.15}, {0, 0, 0});
  s->distribute();
  const int before = holderOf(*s, fast);
  // The speed limit (half the smallest radius a step, 112 m/s at this step) reached after
  // 0.15 m of the 0.23 m diagonal: past the middle, where the bed's grains (16 by 16 across
  // x and y, two layers deep) are cut between the ranks.
  const double mass = 2500 * 4.0 / 3.0 * M_PI * std::pow(0.005, 3);
  const double accel = std::pow(0.5 * 0.0045 / 2e-5, 2) / (2 * 0.15);
  LoadDef push;
  push.grain = fast;
  push.force = {mass * accel / std::sqrt(2.0), mass * accel / std::sqrt(2.0), mass * 9.81};
  s->addLoad(push);
  expectSpeedTripOnEveryRank(*s, 400, fast);
  EXPECT_GT(s->stepCount(), 50u);
  if (world().size() > 1) {
    EXPECT_NE(holderOf(*s, fast), before);
  }
}

}  // namespace
}  // namespace demlab::sim
