// Per-pair coefficients (Simulation::setPairCoefficients) on top of the mixing rules: a pair's
// own restitution gives its rebound (linear law: exact), its own friction decides sticking on a
// slope, its own rolling friction and cohesion switch their modules on; they survive a
// checkpoint, and bad values are refused changing nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_pair_coefficients_test {

using testing::codeOf;
using testing::grain;
using testing::hasModule;
using testing::material;
using testing::plane;
using testing::up;

class SimPairCoefficients : public ::testing::TestWithParam<int> {};

// Returns the rebound speed over the impact speed of a grain of material "a" dropped with
// speed 1 on a plane of material "b", no gravity, linear law.
double rebound(Simulation& s, ElementId id) {
  s.runSteps(static_cast<uint64_t>(0.02 / s.timeStep()));
  return s.element(id).velocity[static_cast<size_t>(up(s.dim()))];
}

TEST_P(SimPairCoefficients, OwnRestitutionGivesTheRebound) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("a", material(1e7, 0.9, 0.0));
  s->addMaterial("b", material(1e7, 0.5, 0.0));
  s->setContactLaw(LawKind::Linear);
  Vec3d n{0, 0, 0}, x{0, 0, 0}, v{0, 0, 0};
  n[up(d)] = 1;
  x[up(d)] = 0.0101;
  v[up(d)] = -1;
  s->addWall(plane({0, 0, 0}, n, "b"));
  const ElementId id = s->addElement(grain(x, 0.01, "a", v));
  s->setAutoTimeStep(0.02);
  auto t = s->clone();
  EXPECT_NEAR(s->pairCoefficients("a", "b").restitution, std::sqrt(0.9 * 0.5), 1e-15);
  PairCoefficients c;
  c.restitution = 0.2;
  t->setPairCoefficients("b", "a", c);
  EXPECT_EQ(t->pairCoefficients("a", "b").restitution, 0.2);
  EXPECT_TRUE(std::isnan(t->pairOverrides("a", "b").friction));
  // The mixed pair rebounds at sqrt(0.45), the pair with its own value at 0.2: the linear law's
  // damping is calibrated to the asked restitution (pair_params.hpp). The tolerance is the
  // damped impact's integration error at this step (first order: doc/verification.md).
  EXPECT_NEAR(rebound(*s, id), std::sqrt(0.45), 0.02 * std::sqrt(0.45));
  EXPECT_NEAR(rebound(*t, id), 0.2, 0.02 * 0.2);
}

TEST_P(SimPairCoefficients, OwnFrictionAndModulesFollow) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("a", material(1e7, 0.5, 0.0));
  s->addMaterial("b", material(1e7, 0.5, 0.0));
  Vec3d n{0, 0, 0}, x{0, 0, 0};
  n[up(d)] = 1;
  x[up(d)] = 0.01;
  s->addWall(plane({0, 0, 0}, n, "b"));
  s->addElement(grain(x, 0.01, "a"));
  EXPECT_FALSE(hasModule(*s, "rotation"));  // frictionless: no rotation, no history
  PairCoefficients c;
  c.friction = 0.4;
  s->setPairCoefficients("a", "b", c);
  EXPECT_TRUE(hasModule(*s, "rotation"));
  EXPECT_FALSE(hasModule(*s, "rolling"));
  c.rolling = 0.1;
  c.cohesion = 1e3;
  s->setPairCoefficients("a", "b", c);
  EXPECT_TRUE(hasModule(*s, "rolling"));
  EXPECT_TRUE(hasModule(*s, "cohesion"));
  // A pair of other materials keeps the mixing rules.
  EXPECT_EQ(s->pairCoefficients("a", "a").friction, 0.0);
  // Checkpoints keep them.
  std::stringstream ck;
  s->save(ck);
  auto b = makeSimulation(d);
  b->load(ck);
  EXPECT_EQ(b->pairOverrides("a", "b").cohesion, 1e3);
  EXPECT_EQ(b->stateDigest(), s->stateDigest());
  // Setting none gives the pair back to the mixing rules.
  s->setPairCoefficients("a", "b", {});
  EXPECT_FALSE(hasModule(*s, "rolling"));
  EXPECT_EQ(s->pairCoefficients("a", "b").friction, 0.0);
}

// Returns the rest overlap of a sphere (3D) of radius 0.01 on a plane under gravity, Hertz.
double restOverlap(Simulation& s, ElementId id) {
  s.runSteps(static_cast<uint64_t>(0.3 / s.timeStep()));
  return 0.01 - s.element(id).position[2];
}

TEST(SimPairCoefficients3D, OwnModulusSetsTheHertzStiffness) {
  // delta = (3 m g / (4 E* sqrt(R)))^(2/3) at rest (Hertz, F = 4/3 E* sqrt(R) delta^(3/2)).
  auto s = makeSimulation(3);
  s->addMaterial("a", material(1e7, 0.3, 0.0));
  s->addMaterial("b", material(1e9, 0.3, 0.0));
  s->addWall(plane({0, 0, 0}, {0, 0, 1}, "b"));
  s->addGravity({0, 0, -9.81});
  const ElementId id = s->addElement(grain({0, 0, 0.01}, 0.01, "a"));
  auto t = s->clone();
  PairCoefficients c;
  c.young = 5e8;  // stiffer than the mixed pair's 1.08e7
  t->setPairCoefficients("a", "b", c);
  EXPECT_EQ(t->pairCoefficients("b", "a").young, 5e8);
  const double mixed = 1 / ((1 - 0.09) / 1e7 + (1 - 0.09) / 1e9);
  EXPECT_NEAR(s->pairCoefficients("a", "b").young, mixed, 1e-6 * mixed);
  // The step follows the stiffer pair.
  EXPECT_LT(t->timeStep(), 0.5 * s->timeStep());
  const double mg = s->element(id).mass * 9.81;
  for (auto [sim, e] : {std::pair{s.get(), mixed}, std::pair{t.get(), 5e8}}) {
    const double want = std::pow(3 * mg / (4 * e * std::sqrt(0.01)), 2.0 / 3.0);
    EXPECT_NEAR(restOverlap(*sim, id), want, 1e-3 * want);
  }
  // A checkpoint keeps it.
  std::stringstream ck;
  t->save(ck);
  auto b = makeSimulation(3);
  b->load(ck);
  EXPECT_EQ(b->pairOverrides("a", "b").young, 5e8);
  EXPECT_EQ(b->stateDigest(), t->stateDigest());
}

TEST_P(SimPairCoefficients, BadValuesChangeNothing) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("a", material(1e7, 0.5, 0.3));
  s->addElement(grain({0, 0, 0}, 0.01, "a"));
  const uint64_t digest = s->stateDigest();
  using Code = std::vector<std::string>;
  PairCoefficients c;
  c.restitution = 0;
  EXPECT_EQ(codeOf([&] { s->setPairCoefficients("a", "a", c); }), (Code{"VALUE", "RESTITUTION"}));
  c.restitution = 0.5;
  c.friction = -1;
  EXPECT_EQ(codeOf([&] { s->setPairCoefficients("a", "a", c); }), (Code{"VALUE", "FRICTION"}));
  c.friction = INFINITY;
  EXPECT_EQ(codeOf([&] { s->setPairCoefficients("a", "a", c); }), (Code{"VALUE", "FRICTION"}));
  c.friction = NAN;
  c.cohesion = -2;
  EXPECT_EQ(codeOf([&] { s->setPairCoefficients("a", "a", c); }), (Code{"VALUE", "COHESION"}));
  c.cohesion = NAN;
  c.young = 0;
  EXPECT_EQ(codeOf([&] { s->setPairCoefficients("a", "a", c); }), (Code{"VALUE", "YOUNG"}));
  EXPECT_EQ(codeOf([&] { s->setPairCoefficients("a", "zz", {}); }), (Code{"LOOKUP", "MATERIAL"}));
  EXPECT_EQ(s->stateDigest(), digest);
  EXPECT_TRUE(std::isnan(s->pairOverrides("a", "a").restitution));
}

INSTANTIATE_TEST_SUITE_P(Dims, SimPairCoefficients, ::testing::Values(2, 3),
                         [](const auto& info) { return std::to_string(info.param) + "D"; });

}  // namespace sim_pair_coefficients_test
}  // namespace demlab::sim
