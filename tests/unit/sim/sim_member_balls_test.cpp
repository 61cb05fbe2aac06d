// Clumps and balls meeting member by member through the ball kernel (sim/member_balls.hpp),
// against the clump's rows point by point (the shape pass, which serves the same pairs when no
// kernel runs): the same forces, springs and paths to round-off, on randomized beds.
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <sstream>

#include "core/thread_pool.hpp"
#include "sim/contact_kernel.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_member_balls_test {

using testing::grain;
using testing::material;
using testing::plane;

using testing::KernelChoice;

// A box of five planes holding `clumps` clumps of 1 to 5 members (radii 2-5 mm, overlapping
// and apart) and `balls` balls, placed at random in a 4 cm square column, their bounding balls
// overlapping by up to a quarter of their radii's sum (so that members touch from the start),
// with random velocities and spins; Hertz-Mindlin with friction, two materials, gravity.
std::unique_ptr<Simulation> randomBed(uint64_t seed, int clumps, int balls) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  auto s = makeSimulation(3);
  s->addMaterial("grain", material(1e7, 0.5, 0.4));
  s->addMaterial("soft", material(3e6, 0.3, 0.6));
  s->addWall(plane({0, 0, 0}, {0, 0, 1}, "grain"));
  s->addWall(plane({0, 0, 0}, {1, 0, 0}, "grain"));
  s->addWall(plane({0.04, 0, 0}, {-1, 0, 0}, "grain"));
  s->addWall(plane({0, 0, 0}, {0, 1, 0}, "grain"));
  s->addWall(plane({0, 0.04, 0}, {0, -1, 0}, "grain"));
  s->addGravity({0, 0, -9.81});
  std::vector<ElementDef> defs;
  std::vector<std::pair<Vec3d, double>> bounds;  // placed so far: centre, bounding radius
  while (defs.size() < static_cast<size_t>(clumps + balls)) {
    const bool isClump = defs.size() < static_cast<size_t>(clumps);
    const Vec3d x{0.008 + 0.024 * u(rng), 0.008 + 0.024 * u(rng), 0.008 + 0.04 * u(rng)};
    const Vec3d v{u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
    ElementDef e = grain(x, isClump ? 0 : 0.002 + 0.003 * u(rng), u(rng) < 0.7 ? "grain" : "soft", v);
    e.angularVelocity = {20 * (u(rng) - 0.5), 20 * (u(rng) - 0.5), 20 * (u(rng) - 0.5)};
    double bound = e.radius;
    if (isClump) {
      e.shape = "clump";
      const int members = 1 + static_cast<int>(5 * u(rng));
      for (int m = 0; m < members; ++m) {
        Vec3 c;
        for (int d = 0; d < 3; ++d) c[d] = 0.006 * (u(rng) - 0.5), e.shapeParams.push_back(c[d]);
        e.shapeParams.push_back(0.002 + 0.003 * u(rng));
        bound = std::max(bound, c.norm() + e.shapeParams.back());
      }
      const Quat q = testing::randomQuat(rng);
      e.orientation = {q.w(), q.x(), q.y(), q.z()};
    }
    // Bounding balls may overlap by a quarter of their radii's sum: many members touch.
    bool apart = true;
    for (const auto& [y, b] : bounds) {
      const double dx = x[0] - y[0], dy = x[1] - y[1], dz = x[2] - y[2];
      apart = apart && std::sqrt(dx * dx + dy * dy + dz * dz) >= 0.75 * (bound + b);
    }
    if (!apart) continue;
    bounds.emplace_back(x, bound);
    defs.push_back(e);
  }
  WatchdogOptions w;
  w.placed = 0;  // members placed overlapping: the point of the bed
  testing::setWatchdog(*s, w);
  s->addElements(defs);
  s->setTimeStep(5e-6);
  return s;
}

// Runs s for steps and returns it.
std::unique_ptr<Simulation> ran(std::unique_ptr<Simulation> s, uint64_t steps) {
  RunOptions o;
  o.steps = steps;
  const RunReport r = s->run(o);
  EXPECT_EQ(r.steps, steps);
  return s;
}

// Expects a and b (the same elements) at the same state to tol (m, m/s, rad/s, N).
void expectClose(const Simulation& a, const Simulation& b, double tol) {
  ASSERT_EQ(a.contactCount(), b.contactCount());
  const std::vector<ElementId> ids = a.elementIds();
  for (const ElementId id : ids) {
    const ElementState x = a.element(id), y = b.element(id);
    for (int d = 0; d < 3; ++d) {
      ASSERT_NEAR(x.position[d], y.position[d], tol) << d;
      ASSERT_NEAR(x.velocity[d], y.velocity[d], tol) << d;
      ASSERT_NEAR(x.angularVelocity[d], y.angularVelocity[d], 1e3 * tol) << d;
      ASSERT_NEAR(x.force[d], y.force[d], 1e3 * tol) << d;
      ASSERT_NEAR(x.torque[d], y.torque[d], 10 * tol) << d;
    }
  }
  const EnergyLedger ea = a.energy(), eb = b.energy();
  EXPECT_NEAR(ea.elastic, eb.elastic, 1e-9 * (ea.elastic + 1e-12));
  EXPECT_NEAR(ea.frictionLoss, eb.frictionLoss, 1e-9 * (ea.frictionLoss + 1e-12));
  EXPECT_NEAR(ea.dampingLoss, eb.dampingLoss, 1e-9 * (ea.dampingLoss + 1e-12));
}

// Returns a bed of randomBed(seed) settled for 0.2 s through the member pass (dense, its
// springs loaded), settled once per seed for all the tests. The settling is most of their time,
// so it takes steps of 2e-5 s (0.12 of the smallest member's Rayleigh step, 1.7e-4 s) and the
// comparisons the bed's own 5e-6 s.
const Simulation& settledBed(uint64_t seed) {
  static std::map<uint64_t, std::unique_ptr<Simulation>> beds;
  std::unique_ptr<Simulation>& bed = beds[seed];
  if (bed == nullptr) {
    auto s = randomBed(seed, 30, 20);
    const double dt = s->timeStep();
    s->setTimeStep(4 * dt);
    bed = ran(std::move(s), 10000);
    bed->setTimeStep(dt);
  }
  return *bed;
}

// Returns a clone of s run for steps with the kernel isa (none: the rows serve the clumps).
std::unique_ptr<Simulation> runWith(const Simulation& s, bool use, kernel::Isa isa, uint64_t steps) {
  EXPECT_TRUE(kernel::setActive(use, isa));
  return ran(s.clone(), steps);
}

// The kernel's member pass and the rows, from the same settled randomized beds: the same
// contacts and states after one step (the forces of the bed's overlaps and springs) and after
// 2000 (contacts made and lost on the way) to round-off, with every kernel the machine has.
TEST(SimMemberBalls, TheKernelAgreesWithTheRowsOnRandomBeds) {
  const KernelChoice keep;
  for (const uint64_t seed : {1u, 2u}) {
    const Simulation* bed = &settledBed(seed);
    ASSERT_TRUE(testing::hasModule(*bed, "shape-contacts"));
    ASSERT_GE(bed->contactCount(), 40u) << "the bed must be packed";
    const auto rows1 = runWith(*bed, false, kernel::Isa::Sse2, 1);
    const auto rows = runWith(*bed, false, kernel::Isa::Sse2, 2000);
    for (const kernel::Isa isa : {kernel::Isa::Sse2, kernel::Isa::Avx2, kernel::Isa::Avx512}) {
      if (!kernel::supported(isa)) continue;
      SCOPED_TRACE("seed " + std::to_string(seed) + " isa " + std::to_string(static_cast<int>(isa)));
      expectClose(*runWith(*bed, true, isa, 1), *rows1, 1e-12);
      const auto kernelRun = runWith(*bed, true, isa, 2000);
      expectClose(*kernelRun, *rows, 1e-10);
      // Two paths ran: their roundings differ somewhere in 2000 steps.
      EXPECT_NE(kernelRun->stateDigest(), rows->stateDigest());
    }
  }
}

// A run through the member pass continues bit for bit from a checkpoint (its springs are the
// shape pass's, saved by key) and from a clone, and gives the same bits on 1 to 3 threads.
TEST(SimMemberBalls, CheckpointsAndThreadsKeepTheBits) {
  const Simulation* bed = &settledBed(1);
  auto whole = ran(bed->clone(), 600);
  auto half = ran(bed->clone(), 300);
  std::stringstream file;
  half->save(file);
  auto loaded = makeSimulation(3);
  loaded->load(file);
  EXPECT_EQ(ran(std::move(loaded), 300)->stateDigest(), whole->stateDigest());
  EXPECT_EQ(ran(half->clone(), 300)->stateDigest(), whole->stateDigest());
  const unsigned before = ThreadPool::global().threads();
  for (const unsigned threads : {2u, 3u}) {
    ThreadPool::global().setThreads(threads);
    EXPECT_EQ(ran(bed->clone(), 600)->stateDigest(), whole->stateDigest()) << threads;
  }
  ThreadPool::global().setThreads(before);
}

}  // namespace sim_member_balls_test
}  // namespace demlab::sim
