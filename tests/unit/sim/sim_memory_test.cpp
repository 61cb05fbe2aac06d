// What a scene holds per grain (Simulation::memory(), issue 3's memory target): exact per-grain
// arrays, no search scratch kept between rare searches (only the grid's between frequent ones),
// contact records and candidate lists sized to what the run needs. Counted from capacities, so the
// figures are deterministic (the settle benchmark's peak RSS is the noisy, whole-process view of
// the same arrays).
#include <gtest/gtest.h>

#include "sim/scene.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim::testing {
namespace sim_memory_test {

// Returns the heap one grain's arrays take: memory().grains of a scene with room for 1000.
double bytesPerGrain() {
  auto s = makeSimulation(3);
  s->reserveElements(1000);
  return static_cast<double>(s->memory().grains) / 1000;
}

// Returns the side of the box that holds pressedBed(side, r).
double boxSide(int side, double r) {
  return 1.98 * r * side;
}

// Returns defs for a frictional bed of side^3 grains of radius r on a cubic lattice whose pitch
// is 1% short of a diameter, in the box [0, boxSide(side, r)]^3: every grain presses on its face
// neighbours and the outer ones on the walls.
std::vector<ElementDef> pressedBed(int side, double r) {
  std::vector<ElementDef> defs;
  const double pitch = 1.98 * r;
  for (int i = 0; i < side; ++i) {
    for (int j = 0; j < side; ++j) {
      for (int k = 0; k < side; ++k) {
        defs.push_back(
            grain({0.99 * r + pitch * i, 0.99 * r + pitch * j, 0.99 * r + pitch * k}, r, "m"));
      }
    }
  }
  return defs;
}

// Returns a scene holding the bed, its grains added in batches of 100 after reserving room for
// all when `reserve` (as bench_sim adds them), one batch after another otherwise.
std::unique_ptr<Simulation> bedScene(int side, double r, bool reserve) {
  auto s = makeSimulation(3);
  s->addMaterial("m", material(1e7, 0.5, 0.5));
  addBox(*s, boxSide(side, r), "m");
  s->addGravity({0, 0, -9.81});
  const std::vector<ElementDef> defs = pressedBed(side, r);
  if (reserve) s->reserveElements(defs.size());
  for (size_t k = 0; k < defs.size(); k += 100) {
    const size_t end = std::min(defs.size(), k + 100);
    s->addElements(std::vector<ElementDef>(defs.begin() + k, defs.begin() + end));
  }
  return s;
}

TEST(SimMemory, ReservedGrainArraysAreExactThroughARun) {
  const double per = bytesPerGrain();
  // The hot state of a 3D grain: 7 vectors, a quaternion, 3 scalars, 2 indices and the handle
  // pool's entries; far more would be a field gone cold but still carried.
  EXPECT_GE(per, 200);
  EXPECT_LE(per, 260);
  auto s = bedScene(10, 1e-3, true);
  const double n = 1000;
  EXPECT_DOUBLE_EQ(static_cast<double>(s->memory().grains), per * n);
  s->runSteps(20);  // the search reorders the grains (sim/reorder.hpp): still exact
  EXPECT_DOUBLE_EQ(static_cast<double>(s->memory().grains), per * n);
}

TEST(SimMemory, BatchesWithoutReserveGrowByHalfNotDouble) {
  const double per = bytesPerGrain();
  auto s = bedScene(10, 1e-3, false);
  const double grains = static_cast<double>(s->memory().grains);
  EXPECT_GE(grains, per * 1000);
  EXPECT_LE(grains, per * 1500);
}

TEST(SimMemory, NoSearchScratchKeptAndRecordsSizedToTheContacts) {
  auto s = bedScene(10, 1e-3, true);
  s->runSteps(20);
  const MemoryReport m = s->memory();
  // One search (the first of the run): CGrid's arrays, the boxes and the raw pairs go back to
  // the heap after it.
  EXPECT_EQ(m.search, 0u);
  // 2700 grain contacts (3 per grain) and the grains on the walls: records for about those, not
  // for a doubled array.
  const size_t contacts = s->contactCount();
  ASSERT_GE(contacts, 2700u);
  EXPECT_LE(m.contacts, contacts * sizeof(ContactRecord<3>) * 5 / 4);
  EXPECT_GE(m.contacts, contacts * sizeof(ContactRecord<3>));
  // Candidates (8 bytes), positions at the search (24) and the wall lists: no doubled arrays.
  EXPECT_LE(m.detection, 1000 * (24 + 8 * 3 + 4 * 2) + 6 * 64);
  // Everything per grain: the state, three candidates with their springs (64 bytes each: the
  // spring, its drift velocity and the damper's owed loss), their records.
  const double perGrain = static_cast<double>(m.total()) / 1000;
  EXPECT_LE(perGrain, 670) << "grains " << m.grains << " detection " << m.detection << " springs "
                           << m.springs << " contacts " << m.contacts << " passes " << m.passes;
}

TEST(SimMemory, FrequentSearchesKeepOnlyTheGrid) {
  // Grains moving fast enough for a search every few steps: the grid's arrays stay (grown anew
  // at each search they would cost about another search), the boxes and raw pairs go.
  auto s = makeSimulation(3);
  s->addMaterial("m", material(1e7, 0.5, 0.5));
  addBox(*s, 0.1, "m");
  s->addElements(latticeGrains(3, 500, 1e-3, 0.1, 2.0, "m", 7));
  s->setTimeStep(1e-5);
  const RunReport r = s->runSteps(100);
  ASSERT_GE(r.neighborRebuilds, 3u);
  const size_t kept = s->memory().search;
  EXPECT_GT(kept, 0u);
  // The grid's arrays only: far less than boxes (48 bytes) and pairs for every grain.
  EXPECT_LT(kept, 500u * 150);
}

}  // namespace sim_memory_test
}  // namespace demlab::sim::testing
