// Scripted wall motion (Wall::scriptStep): the skin bound against the true displacement of the
// wall's surface, and the position against the exact integral of the scripted rates.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sim/wall.hpp"

namespace demlab::sim {
namespace sim_wall_script_test {

// A box wall at the origin, still, its motion referenced at t = 0.
Wall<3> box() {
  Wall<3> w;
  w.kind = WallShape::Box;
  physics::BoxShape<3> b;
  b.centre = Vec3::Zero();
  b.axes = Mat3::Identity();
  b.halfExtents = Vec3(0.02, 0.005, 0.01);
  w.shape0 = w.shape = b;
  w.moveTo(0);
  return w;
}

// Returns the eight corners of the box w is now.
std::array<Vec3, 8> corners(const Wall<3>& w) {
  const auto& b = std::get<physics::BoxShape<3>>(w.shape);
  std::array<Vec3, 8> c;
  for (int k = 0; k < 8; ++k) {
    const Vec3 s((k & 1) ? 1 : -1, (k & 2) ? 1 : -1, (k & 4) ? 1 : -1);
    c[k] = b.centre + b.axes * s.cwiseProduct(b.halfExtents);
  }
  return c;
}

// The skin test's bound is at least how far any point of the box has moved since the last
// search, for random rates that speed up, slow down and reverse (a rigid motion moves the
// box's points by an affine field, so its largest displacement is at a corner). Searches are
// redone as the detection does, when the bound passes the skin.
TEST(SimWallScript, SkinBoundCoversTheSurfaceDisplacement) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Wall<3> w = box();
    const double a = 60 * u(rng), b = 60 * u(rng), f = 30 + 200 * std::abs(u(rng));
    const double vx = 0.5 * u(rng), vz = 0.5 * u(rng), g = 100 * std::abs(u(rng));
    w.omegaFn[2] = [=](double t) { return a + b * std::cos(f * t); };
    w.omegaFn[0] = [=](double t) { return 0.3 * b * std::sin(2 * f * t); };
    w.velocityFn[0] = [=](double t) { return vx * std::cos(g * t); };
    w.velocityFn[2] = [=](double t) { return vz * t; };
    w.moving = true;
    const double dt = 1e-5, skin = 2e-4;
    auto atBuild = corners(w);
    int searches = 0;
    for (int n = 0; n < 4000; ++n) {
      const double t = n * dt;
      w.scriptStep(t, dt);
      w.moveTo(t + dt);
      const auto now = corners(w);
      double moved = 0;
      for (int k = 0; k < 8; ++k) moved = std::max(moved, (now[k] - atBuild[k]).norm());
      const double bound = w.displacementSinceBuild(t + dt);
      ASSERT_GE(bound * (1 + 1e-12) + 1e-15, moved) << "trial " << trial << " step " << n;
      if (bound > skin) {
        w.pointAtBuild = w.point;
        w.timeAtBuild = t + dt;
        w.scriptedAngle = 0;
        atBuild = now;
        ++searches;
      }
    }
    EXPECT_GT(searches, 3) << "trial " << trial;
  }
}

// Rates linear in time are integrated exactly: the position is their midpoint-rule integral,
// and a turn about a fixed axis adds up to the integral of its rate.
TEST(SimWallScript, LinearRatesAreIntegratedExactly) {
  Wall<3> w = box();
  w.velocityFn[1] = [](double t) { return 0.2 - 3 * t; };
  w.omegaFn[2] = [](double t) { return 5 + 40 * t; };
  w.moving = true;
  const double dt = 1e-4;
  const int steps = 3000;
  for (int n = 0; n < steps; ++n) {
    w.scriptStep(n * dt, dt);
    w.moveTo((n + 1) * dt);
  }
  const double T = steps * dt;
  EXPECT_NEAR(w.point.y(), 0.2 * T - 1.5 * T * T, 1e-13);
  const Quat q = (w.turned * w.turnedBefore).normalized();
  const double angle = 2 * std::atan2(q.z(), q.w());
  EXPECT_NEAR(std::remainder(angle - (5 * T + 20 * T * T), 2 * M_PI), 0, 1e-10);
}

}  // namespace sim_wall_script_test
}  // namespace demlab::sim
