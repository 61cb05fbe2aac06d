// Spatial reordering of the grains at neighbor searches (sim/reorder.hpp): the Morton order
// against a brute-force oracle, handles and slots after a reorder, and a frictional scene run
// with a reorder at every search against the same scene never reordered: same contacts (by
// handle), same springs and motion to rounding, and save/load continuation bit-identity.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <sstream>
#include <tuple>

#include "sim/reorder.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_reorder_test {

using testing::addBox;
using testing::latticeGrains;
using testing::material;

// Returns the scene behind s, writable (tests only: the reorder knob is not in the public API).
template <int D>
Scene<D>& sceneOf(Simulation& s) {
  return const_cast<Scene<D>&>(dynamic_cast<SimulationManager<D>&>(s).scene());
}

void setReorderEvery(Simulation& s, uint32_t every) {
  if (s.dim() == 2) {
    sceneOf<2>(s).elements.reorderEvery = every;
  } else {
    sceneOf<3>(s).elements.reorderEvery = every;
  }
}

TEST(SimReorder, SpreadBitsInterleaves) {
  // Oracle: bit k of x goes to bit D*k.
  std::mt19937_64 rng(5);
  for (int t = 0; t < 200; ++t) {
    const uint64_t x = rng();
    uint64_t want2 = 0, want3 = 0;
    for (int k = 0; k < 32; ++k) want2 |= ((x >> k) & 1u) << (2 * k);
    for (int k = 0; k < 21; ++k) want3 |= ((x >> k) & 1u) << (3 * k);
    EXPECT_EQ(spreadBits<2>(x), want2);
    EXPECT_EQ(spreadBits<3>(x), want3);
  }
}

TEST(SimReorder, MortonOrderSortsByCellKey) {
  // Random grains: the permutation visits every grain once, in non-decreasing Morton key of
  // the grain's cell (cell 2 r_max from the lowest corner), ties in the old order.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  ElementArrays<3> a;
  for (uint32_t i = 0; i < 500; ++i) {
    a.push(Vec3(u(rng), u(rng), u(rng)), Vec3::Zero(), Vec3::Zero(), 0.01 + 0.02 * u(rng), 1, 1, 0,
           i);
  }
  const std::vector<uint32_t> perm = mortonOrder(a);
  std::vector<uint32_t> seen(perm);
  std::sort(seen.begin(), seen.end());
  for (uint32_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], i);
  Vec3 lo = a.x[0];
  Real rMax = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    lo = lo.cwiseMin(a.x[i]);
    rMax = std::max(rMax, a.r[i]);
  }
  auto key = [&](uint32_t i) {
    uint64_t k = 0;
    for (int d = 0; d < 3; ++d) {
      const auto c = static_cast<uint64_t>((a.x[i][d] - lo[d]) / (2 * rMax));
      for (int b = 0; b < 21; ++b) k |= ((c >> b) & 1u) << (3 * b + d);
    }
    return k;
  };
  for (size_t k = 1; k < perm.size(); ++k) {
    const auto prev = std::make_pair(key(perm[k - 1]), perm[k - 1]);
    const auto cur = std::make_pair(key(perm[k]), perm[k]);
    EXPECT_LT(prev, cur) << "at " << k;
  }
}

double radius(int d) {
  return d == 3 ? 0.004 : 0.002;
}

// A frictional, rotating 3D or 2D bed in a box under gravity, grains added in lattice order;
// polydisperse: radii spread over 0.6-1 of radius(d) (a golden-ratio sequence).
std::unique_ptr<Simulation> bed(int d, bool polydisperse = false) {
  auto s = makeSimulation(d);
  s->addMaterial("glass", material(1e7, 0.5, 0.5));
  auto grains =
      latticeGrains(d, d == 3 ? 300 : 200, radius(d), 0.08, 0.3, "glass", polydisperse ? 23 : 17);
  if (polydisperse) {
    for (size_t k = 0; k < grains.size(); ++k) {
      grains[k].radius *= 0.6 + 0.4 * std::fmod(0.6180339887 * static_cast<double>(k), 1.0);
    }
  }
  s->addElements(grains);
  addBox(*s, 0.08, "glass");
  s->addGravity({0, -9.81, 0});
  s->setAutoTimeStep(0.2);
  return s;
}

// Contacts keyed by (grain a, grain b or wall) handles, in the order the pair's law sees them.
using ContactKey = std::tuple<uint64_t, uint64_t, uint64_t>;
std::map<ContactKey, ContactInfo> contactsByHandle(const Simulation& s) {
  std::map<ContactKey, ContactInfo> out;
  for (const ContactInfo& c : s.contacts()) {
    out[{c.a.bits(), c.b.bits(), c.wall.bits()}] = c;
  }
  return out;
}

Vec3 e(const Vec3d& v) {
  return Vec3(v[0], v[1], v[2]);
}

class SimReorderScene : public ::testing::TestWithParam<int> {};

TEST_P(SimReorderScene, ReorderEverySearchMatchesNeverToRounding) {
  const int d = GetParam();
  auto never = bed(d), always = bed(d);
  setReorderEvery(*never, 0);
  setReorderEvery(*always, 1);
  const std::vector<ElementId> ids = never->elementIds();
  ASSERT_EQ(always->elementIds(), ids);
  // (Long enough for the bed to land at the step the contacts' stiffness sets.)
  const auto r1 = never->runSteps(2500);
  const auto r2 = always->runSteps(2500);
  EXPECT_EQ(r1.neighborRebuilds, r2.neighborRebuilds);
  EXPECT_GT(r2.neighborRebuilds, 2u);
  // The reorder did happen (the lattice order is not a Morton order) and kept every handle
  // on its grain.
  EXPECT_NE(always->elementIds(), ids);
  EXPECT_EQ(never->elementIds(), ids);
  double vScale = 0;
  for (ElementId id : ids) vScale = std::max(vScale, e(never->element(id).velocity).norm());
  ASSERT_GT(vScale, 0);
  for (ElementId id : ids) {
    const ElementState a = never->element(id), b = always->element(id);
    EXPECT_NEAR((e(a.position) - e(b.position)).norm(), 0, 1e-9) << toString(id);
    EXPECT_NEAR((e(a.velocity) - e(b.velocity)).norm(), 0, 1e-6 * vScale) << toString(id);
    EXPECT_NEAR((e(a.angularVelocity) - e(b.angularVelocity)).norm(), 0, 1e-6 * vScale / radius(d));
  }
  // The same contacts between the same grains, with the same forces to rounding: the
  // tangential springs followed their pairs through every renumbering.
  const auto ca = contactsByHandle(*never), cb = contactsByHandle(*always);
  ASSERT_GT(ca.size(), ids.size() / 2);
  ASSERT_EQ(ca.size(), cb.size());
  double fScale = 0;
  for (const auto& [k, c] : ca) fScale = std::max(fScale, e(c.force).norm());
  size_t sheared = 0;
  for (const auto& [k, c] : ca) {
    const auto it = cb.find(k);
    ASSERT_NE(it, cb.end()) << "contact missing after reordering";
    EXPECT_NEAR((e(c.force) - e(it->second.force)).norm(), 0, 1e-6 * fScale);
    const Vec3 tangential = e(c.force) - e(c.force).dot(e(c.normal)) * e(c.normal);
    if (tangential.norm() > 1e-3 * fScale) ++sheared;
  }
  EXPECT_GT(sheared, ca.size() / 10) << "friction hardly loaded: the spring check is weak";
}

TEST_P(SimReorderScene, ReorderingRunsAreDeterministicAndContinueAfterLoad) {
  const int d = GetParam();
  auto a = bed(d), b = bed(d);
  setReorderEvery(*a, 1);
  setReorderEvery(*b, 1);
  a->runSteps(600);
  b->runSteps(600);
  EXPECT_EQ(a->stateDigest(), b->stateDigest());
  std::stringstream ck;
  a->save(ck);
  a->runSteps(600);
  auto c = makeSimulation(d);
  c->load(ck);
  setReorderEvery(*c, 1);
  c->runSteps(600);
  EXPECT_EQ(c->positions(), a->positions());
  EXPECT_EQ(c->stateDigest(), a->stateDigest());
}

// Polydisperse radii with the automatic skin: the skin is a mean of the radii, and the
// dense order reordering leaves behind must not change it by an ulp when a load recomputes
// it (it did: the loaded run searched once more and its digest differed).
TEST_P(SimReorderScene, PolydisperseAutoSkinContinuesAfterLoad) {
  const int d = GetParam();
  auto make = [&] {
    auto s = bed(d, true);
    setReorderEvery(*s, 1);
    return s;
  };
  auto a = make();
  a->runSteps(400);
  std::stringstream ck;
  a->save(ck);
  a->runSteps(400);
  auto c = makeSimulation(d);
  c->load(ck);
  setReorderEvery(*c, 1);
  c->runSteps(400);
  EXPECT_NE(a->elementIds(), make()->elementIds()) << "no reordering happened: the test is weak";
  EXPECT_EQ(c->positions(), a->positions());
  EXPECT_EQ(c->stateDigest(), a->stateDigest());
}

INSTANTIATE_TEST_SUITE_P(Dims, SimReorderScene, ::testing::Values(2, 3));

}  // namespace sim_reorder_test
}  // namespace demlab::sim
