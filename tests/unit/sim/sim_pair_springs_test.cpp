// PairSprings (sim/pair_springs.hpp), the grain pairs' spring pool, against the model it
// replaces: one spring per candidate, zero while the pair does not touch. Random sequences of
// contacts opening and closing and springs set must read back as the model's, the pool must
// never hold more springs than were in contact at once, and a checkpoint and a neighbor search
// must carry the springs over.
#include <algorithm>
#include <cstdint>
#include <random>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "sim/pair_springs.hpp"
#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_pair_springs_test {

TEST(PairSprings, RandomOpeningsAndClosingsReadBackAsOneSpringPerCandidate) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const size_t n = 1 + rng() % 300;
    PairSprings<3> springs;
    springs.reset(n, seed % 2 == 0);
    std::vector<Vec3> model(n, Vec3::Zero());
    std::vector<bool> slotted(n, false);  // what the model expects to hold a slot
    size_t mostLive = 0;
    for (int step = 0; step < 2000; ++step) {
      const size_t k = rng() % n;
      switch (rng() % 4) {
        case 0:  // the pair stops touching
          springs.release(k);
          model[k].setZero();
          slotted[k] = false;
          break;
        case 1: {  // the contact law writes a new spring
          const Vec3 sp(u(rng), u(rng), u(rng));
          springs.at(k)->spring = sp;
          model[k] = sp;
          slotted[k] = true;
          break;
        }
        case 2: {  // a checkpoint or a search sets it (zero gives the slot back)
          const Vec3 sp = rng() % 3 == 0 ? Vec3(Vec3::Zero()) : Vec3(u(rng), u(rng), u(rng));
          springs.set(k, sp);
          model[k] = sp;
          slotted[k] = !sp.isZero(0);
          break;
        }
        default:  // a touching pair without a spring reads zero and takes a zeroed slot
          if (!slotted[k]) {
            EXPECT_TRUE(springs.at(k)->spring.isZero(0));
            slotted[k] = true;
          }
          break;
      }
      mostLive = std::max<size_t>(mostLive, std::count(slotted.begin(), slotted.end(), true));
      ASSERT_EQ(springs.live(),
                static_cast<size_t>(std::count(slotted.begin(), slotted.end(), true)));
    }
    const std::vector<physics::TangentialHistory<3>> out = springs.perCandidate();
    ASSERT_EQ(out.size(), n);
    for (size_t k = 0; k < n; ++k) {
      EXPECT_EQ(out[k].spring, model[k]) << k;
      EXPECT_EQ(springs.spring(k), model[k]) << k;
    }
    // Given-back slots are reused: the pool is never larger than the most contacts at once.
    kernel::SpringSlots view = springs.slots();
    size_t highest = 0;
    for (size_t k = 0; k < n; ++k) {
      if (view.slotOf[k] != kernel::SpringSlots::kNoSlot) {
        highest = std::max<size_t>(highest, view.slotOf[k] + size_t{1});
      }
    }
    EXPECT_LE(highest, mostLive);
  }
}

TEST(PairSprings, TheKernelViewGivesAndTakesSlotsThroughTheOwner) {
  PairSprings<3> springs;
  springs.reset(5, true);
  kernel::SpringSlots view = springs.slots();
  double* data = view.acquire(view.owner, 3);
  EXPECT_EQ(view.slotOf[3], 0u);
  data[0] = 1.5;
  EXPECT_EQ(springs.spring(3), Vec3(1.5, 0, 0));
  view.release(view.owner, 3);
  EXPECT_EQ(view.slotOf[3], kernel::SpringSlots::kNoSlot);
  EXPECT_TRUE(springs.spring(3).isZero(0));
  // The slot given back is the next one handed out, zeroed.
  view.data = view.acquire(view.owner, 1);
  EXPECT_EQ(view.slotOf[1], 0u);
  EXPECT_TRUE(springs.spring(1).isZero(0));
  EXPECT_EQ(springs.live(), 1u);
}

// A sheared frictional pile keeps contacts opening and closing; its springs must survive the
// neighbor searches and a checkpoint: a run in one piece and the same run split by a save and a
// load end in the same state.
TEST(PairSprings, SpringsCrossSearchesAndCheckpointsUnchanged) {
  auto build = [] {
    auto s = makeSimulation(3);
    s->addMaterial("m", testing::material(1e7, 0.5, 0.5));
    s->setContactLaw(LawKind::HertzMindlin);
    WallDef floor;
    floor.shape = WallShape::Plane;
    floor.normal = {0, 0, 1};
    floor.material = "m";
    s->addWall(floor);
    s->addGravity({0, 0, -9.81});
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<ElementDef> grains;
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) {
        for (int k = 0; k < 4; ++k) {
          ElementDef g;
          g.radius = 1e-3 * (0.8 + 0.3 * u(rng));
          g.position = {2.3e-3 * i, 2.3e-3 * j, 1.2e-3 + 2.3e-3 * k};
          g.velocity = {0.05 * (u(rng) - 0.5), 0.05 * (u(rng) - 0.5), 0};
          g.material = "m";
          grains.push_back(g);
        }
      }
    }
    s->addElements(grains);
    s->setTimeStep(0.1 * s->criticalTimeStep());
    return s;
  };
  auto whole = build();
  RunOptions ro;
  ro.steps = 3000;
  const RunReport all = whole->run(ro);
  ASSERT_GT(all.neighborRebuilds, 2u);
  ASSERT_GT(all.contacts, 50u);

  auto split = build();
  ro.steps = 1500;
  split->run(ro);
  std::stringstream saved;
  split->save(saved);
  auto loaded = build();
  loaded->load(saved);
  loaded->run(ro);
  EXPECT_EQ(loaded->stateDigest(), whole->stateDigest());
}

}  // namespace sim_pair_springs_test
}  // namespace demlab::sim
