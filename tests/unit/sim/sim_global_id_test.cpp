// Global element ids (ElementArrays::globalId): the creation index, never reused when a slot
// is; carried through reorders, clones and checkpoints (the GIDS section only when an id is not
// its slot); the orientation of every candidate pair (lower id first), so a frictional scene
// whose new elements reuse old slots runs, saves and continues bit-identically.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <sstream>

#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_global_id_test {

using testing::addBox;
using testing::codeOf;
using testing::editCheckpoint;
using testing::grain;
using testing::latticeGrains;
using testing::material;

template <int D>
const Scene<D>& sceneOf(const Simulation& s) {
  return dynamic_cast<const SimulationManager<D>&>(s).scene();
}

// Returns the global id of element h of the 3D scene s.
uint64_t idOf(const Simulation& s, ElementId h) {
  const Scene<3>& sc = sceneOf<3>(s);
  return sc.elements.a.globalId[sc.elements.index(h)];
}

// A frictional 3D bed of n grains in a box, gravity on: 0.2 m side, radius 8 mm.
std::unique_ptr<Simulation> bed(int n, unsigned seed) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0.5));
  addBox(*s, 0.2, "glass");
  s->addGravity({0, 0, -9.81});
  for (const ElementDef& e : latticeGrains(3, n, 0.008, 0.2, 0.5, "glass", seed)) s->addElement(e);
  return s;
}

TEST(SimGlobalId, CreationOrderNeverReused) {
  auto s = bed(20, 1);
  const std::vector<ElementId> ids = s->elementIds();
  for (size_t k = 0; k < ids.size(); ++k) EXPECT_EQ(idOf(*s, ids[k]), k);
  s->removeElement(ids[3]);
  s->removeElement(ids[11]);
  const ElementId a = s->addElement(grain({0.1, 0.1, 0.15}, 0.008, "glass"));
  const ElementId b = s->addElement(grain({0.1, 0.1, 0.18}, 0.008, "glass"));
  // The new elements take freed slots, not freed ids.
  std::vector<uint32_t> slots{a.index, b.index};
  std::sort(slots.begin(), slots.end());
  EXPECT_EQ(slots, (std::vector<uint32_t>{ids[3].index, ids[11].index}));
  EXPECT_EQ(idOf(*s, a), 20u);
  EXPECT_EQ(idOf(*s, b), 21u);
  EXPECT_EQ(sceneOf<3>(*s).elements.nextGlobalId(), 22u);
  // Unchanged by a clone.
  auto c = s->clone();
  EXPECT_EQ(sceneOf<3>(*c).elements.a.globalId, sceneOf<3>(*s).elements.a.globalId);
  EXPECT_EQ(sceneOf<3>(*c).elements.nextGlobalId(), 22u);
}

// A scene whose last elements reuse the slots of removed ones, so that slot order and id order
// disagree for their pairs; run until they are in contact.
std::unique_ptr<Simulation> reusedSlots() {
  auto s = bed(150, 2);
  const std::vector<ElementId> ids = s->elementIds();
  for (size_t k = 0; k < 36; ++k) s->removeElement(ids[k]);
  // Just above the bed (a lattice of 1.5 layers), falling into it.
  for (int k = 0; k < 36; ++k) {
    s->addElement(grain({0.02 + 0.03 * (k % 6), 0.02 + 0.03 * (k / 6), 0.05}, 0.008, "glass"));
  }
  s->runSteps(3000);
  return s;
}

TEST(SimGlobalId, PairsOrientedByGlobalId) {
  auto s = reusedSlots();
  const Scene<3>& sc = sceneOf<3>(*s);
  const ElementArrays<3>& a = sc.elements.a;
  size_t inverted = 0;  // pairs whose slots are in the other order than their ids
  ASSERT_GT(sc.candidates.size(), 100u);
  for (const CandidatePair& c : sc.candidates) {
    EXPECT_LT(a.globalId[c.i], a.globalId[c.j]);
    inverted += a.slot[c.i] > a.slot[c.j];
  }
  EXPECT_GT(inverted, 0u) << "no pair where slot and id orders differ: the test is weak";
}

TEST(SimGlobalId, CheckpointKeepsIds) {
  // Ids equal to slots: no section.
  auto plain = bed(20, 4);
  plain->runSteps(10);
  const std::string plainBytes = unsealCheckpoint(plain->saveBytes(false, nullptr));
  EXPECT_EQ(plainBytes.find(kGlobalIdTag), std::string::npos);
  auto s = reusedSlots();
  const std::string bytes = s->saveBytes(false, nullptr);
  EXPECT_NE(unsealCheckpoint(bytes).find(kGlobalIdTag), std::string::npos);
  auto c = makeSimulation(3);
  c->loadBytes(bytes);
  EXPECT_EQ(sceneOf<3>(*c).elements.a.globalId, sceneOf<3>(*s).elements.a.globalId);
  EXPECT_EQ(sceneOf<3>(*c).elements.nextGlobalId(), sceneOf<3>(*s).elements.nextGlobalId());
  // The loaded scene continues as the saved one does, bit for bit, and new ids go on from the
  // saved counter.
  s->runSteps(500);
  c->runSteps(500);
  EXPECT_EQ(c->positions(), s->positions());
  EXPECT_EQ(c->stateDigest(), s->stateDigest());
  const ElementId e = c->addElement(grain({0.1, 0.1, 0.19}, 0.005, "glass"));
  EXPECT_EQ(idOf(*c, e), 186u);
}

TEST(SimGlobalId, DamagedSectionRefused) {
  auto s = reusedSlots();
  const std::string bytes = s->saveBytes(false, nullptr);
  const auto damaged = [&](auto&& change) {
    return editCheckpoint(bytes, [&](std::string& scene) {
      const size_t at = scene.find(kGlobalIdTag);
      ASSERT_NE(at, std::string::npos);
      // Tag, u64 length, u64 next id, u64 count, then the ids.
      change(scene, at + 4 + 8);
    });
  };
  const auto u64At = [](std::string& b, size_t at, uint64_t v) { std::memcpy(&b[at], &v, 8); };
  const std::string twice = damaged([&](std::string& b, size_t body) {
    uint64_t first;
    std::memcpy(&first, &b[body + 16], 8);
    u64At(b, body + 24, first);
  });
  const std::string beyond = damaged([&](std::string& b, size_t body) { u64At(b, body + 16, 1u << 30); });
  const std::string count = damaged([&](std::string& b, size_t body) { u64At(b, body + 8, 7); });
  for (const std::string& file : {twice, beyond, count}) {
    auto c = makeSimulation(3);
    const uint64_t before = c->stateDigest();
    EXPECT_EQ(codeOf([&] { c->loadBytes(file); }), (std::vector<std::string>{"LOAD", "FORMAT"}));
    EXPECT_EQ(c->stateDigest(), before);
  }
}

}  // namespace sim_global_id_test
}  // namespace demlab::sim
