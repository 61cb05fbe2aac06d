// Rolling resistance (sim/rolling_resistance.hpp) against analytic answers: a grain rolling on
// a plane stops after the distance the constant couple allows, a grain on a slope flatter than
// the rolling friction stays, one on a steeper slope rolls at the reduced acceleration, and a
// scene without rolling friction runs no rolling module.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_rolling_test {

using testing::grain;
using testing::hasModule;
using testing::material;
using testing::plane;
using testing::up;

constexpr double kG = 9.81;
constexpr double kR = 0.01;

class SimRolling : public ::testing::TestWithParam<int> {};

// The fraction of a grain's rolling deceleration per unit of mu_r g: I/(m R^2) is 2/5 for a
// sphere, 1/2 for a disc, and a = mu_r g / (1 + I/(m R^2)).
double rollingShare(int d) {
  return d == 3 ? 5.0 / 7.0 : 2.0 / 3.0;
}

// A scene with a floor below the origin and one grain resting on it (at its equilibrium
// overlap, nearly), rolling along +x at v0 without slipping, under gravity tilted by theta
// towards +x. Returns the simulation and the grain.
std::pair<std::unique_ptr<Simulation>, ElementId> rollingGrain(int d, double muRolling, double v0,
                                                             double theta) {
  auto s = makeSimulation(d);
  physics::MaterialDef m = material(1e9, 0.5, 0.8);
  m.rollingFriction = muRolling;
  s->addMaterial("m", m);
  Vec3d n{0, 0, 0}, x{0, 0, 0}, g{0, 0, 0};
  n[up(d)] = 1;
  x[up(d)] = kR * (1 - 2e-5);
  g[0] = kG * std::sin(theta);
  g[up(d)] = -kG * std::cos(theta);
  s->addWall(plane({0, 0, 0}, n, "m"));
  ElementDef def = grain(x, kR, "m", {v0, 0, 0});
  // Rolling: the contact point at rest. 3D: w = (0, v/R, 0); 2D: w_z = -v/R.
  if (d == 3) {
    def.angularVelocity = {0, v0 / kR, 0};
  } else {
    def.angularVelocity = {0, 0, -v0 / kR};
  }
  const ElementId id = s->addElement(def);
  s->addGravity(g);
  // A disc is the sphere of its mass for the step (2D density is per area), which makes the 2D
  // step 8.7 times the 3D one here: the checks of rest below (creep under 1e-6 of the distance)
  // take a quarter of it.
  s->setAutoTimeStep(d == 2 ? 0.05 : 0.2);
  return {std::move(s), id};
}

TEST_P(SimRolling, RollingGrainStopsInTheAnalyticDistance) {
  const int d = GetParam();
  const double mu = 0.05, v0 = 0.5;
  auto [s, id] = rollingGrain(d, mu, v0, 0);
  const auto modules = s->listModules();
  EXPECT_NE(std::find(modules.begin(), modules.end(), "rolling"), modules.end());
  const double decel = rollingShare(d) * mu * kG;
  const double tStop = v0 / decel;
  s->runSteps(static_cast<uint64_t>(1.5 * tStop / s->timeStep()));
  const ElementState b = s->element(id);
  const double expected = v0 * v0 / (2 * decel);
  std::cout << "[ figures  ] " << d << "D rolling stop distance " << b.position[0]
            << " m, analytic " << expected << " m, ledger residual " << s->energy().residual
            << "\n";
  EXPECT_NEAR(b.position[0], expected, 0.005 * expected);
  // At rest and staying: no creep, no chatter.
  EXPECT_LT(std::abs(b.velocity[0]), 1e-4 * v0);
  const double x1 = b.position[0];
  s->runSteps(static_cast<uint64_t>(0.2 * tStop / s->timeStep()));
  EXPECT_LT(std::abs(s->element(id).position[0] - x1), 1e-6 * expected);
  // The kinetic energy went to the rolling couple (booked as friction loss): the ledger closes.
  const EnergyLedger e = s->energy();
  const double kinetic0 = 0.5 * b.mass * v0 * v0 * (1 + (d == 3 ? 0.4 : 0.5));
  EXPECT_NEAR(e.frictionLoss, kinetic0, 0.02 * kinetic0);
  EXPECT_LT(e.residual, 1e-3);
}

TEST_P(SimRolling, HoldsOnAFlatterSlopeRollsOnASteeperOne) {
  const int d = GetParam();
  const double mu = 0.1;
  // tan(theta) = mu / 2: the couple mu_r R Fn outweighs the gravity couple; the grain stays.
  {
    auto [s, id] = rollingGrain(d, mu, 0, std::atan(0.5 * mu));
    s->runSteps(static_cast<uint64_t>(0.2 / s->timeStep()));
    EXPECT_LT(std::abs(s->element(id).position[0]), 1e-3 * kR);
  }
  // tan(theta) = 2 mu: it rolls with a = share g (sin - mu cos).
  {
    const double theta = std::atan(2 * mu);
    auto [s, id] = rollingGrain(d, mu, 0, theta);
    const double t = 0.2;
    s->runSteps(static_cast<uint64_t>(t / s->timeStep()));
    const double a = rollingShare(d) * kG * (std::sin(theta) - mu * std::cos(theta));
    const double tt = s->time();
    EXPECT_NEAR(s->element(id).position[0], 0.5 * a * tt * tt, 0.01 * 0.5 * a * tt * tt);
  }
}

TEST_P(SimRolling, NoRollingFrictionNoModule) {
  const int d = GetParam();
  auto [s, id] = rollingGrain(d, 0, 0.5, 0);
  const auto modules = s->listModules();
  EXPECT_EQ(std::find(modules.begin(), modules.end(), "rolling"), modules.end());
  // Without resistance the grain rolls on at its speed.
  s->runSteps(1000);
  EXPECT_NEAR(s->element(id).velocity[0], 0.5, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Dims, SimRolling, ::testing::Values(2, 3),
                         [](const auto& info) { return std::to_string(info.param) + "D"; });

}  // namespace sim_rolling_test
}  // namespace demlab::sim
