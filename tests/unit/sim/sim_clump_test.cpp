// The clump (a rigid assembly of balls): the union's mass properties against closed forms and a
// slice-by-slice integral, its contacts against the ball's, and its physics (a one-member clump
// is the sphere; a dumbbell rests on both members).
#include <cmath>
#include <numbers>
#include <random>

#include "physics/narrow_phase.hpp"
#include "sim/shape.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_clump_test {

using testing::grain;
using testing::material;
using testing::plane;

const Real kPi = std::numbers::pi;

// Two overlapping spheres along x as a solid of revolution: volume and the moments about the
// centroid, by Simpson's rule over a million slices (each a disc of the larger chord's radius).
struct Revolution {
  Real volume, centroid, axial, transverse;
};
Revolution revolution(Real r1, Real r2, Real d) {
  const auto radius2 = [&](Real x) {
    return std::max({0.0, r1 * r1 - x * x, r2 * r2 - (x - d) * (x - d)});
  };
  const Real lo = -r1, hi = d + r2;
  const int n = 1000000;
  const Real h = (hi - lo) / n;
  Real v = 0, mx = 0, mxx = 0, ax = 0;
  for (int k = 0; k <= n; ++k) {
    const Real x = lo + k * h, w = (k == 0 || k == n ? 1 : k % 2 ? 4 : 2) * h / 3;
    const Real a = kPi * radius2(x);
    v += w * a, mx += w * a * x, mxx += w * a * x * x;
    ax += w * kPi * radius2(x) * radius2(x) / 2;
  }
  const Real c = mx / v;
  return {v, c, ax, ax / 2 + (mxx - v * c * c)};
}

TEST(SimClump, MassPropertiesOfTheUnion) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  // Apart: the balls' closed forms and the parallel-axis theorem, exact.
  const Geometry<3> apart =
      t.makeGeometry("clump", std::vector<double>{0, 0, 0, 0.01, 0.03, 0, 0, 0.01});
  const Real v1 = ballMass<3>(1, 0.01);
  EXPECT_NEAR(apart.volume, 2 * v1, 1e-15);
  EXPECT_NEAR(apart.params[0], -0.015, 1e-15);  // moved about the centroid
  const Real axial = 2 * ballInertia<3>(v1, 0.01);
  const Vec3 pm = apart.principalMoments;
  EXPECT_NEAR(pm.minCoeff(), axial, 1e-12 * axial);
  EXPECT_NEAR(pm.maxCoeff(), axial + 2 * v1 * 0.015 * 0.015, 1e-12 * axial);
  // Overlapping, unequal: against the solid of revolution.
  for (const double d : {0.004, 0.012, 0.016}) {
    const Geometry<3> g =
        t.makeGeometry("clump", std::vector<double>{0, 0, 0, 0.01, d, 0, 0, 0.007});
    const Revolution want = revolution(0.01, 0.007, d);
    EXPECT_NEAR(g.volume, want.volume, 5e-5 * want.volume) << d;
    EXPECT_NEAR(g.params[0], -want.centroid, 5e-5 * 0.01) << d;
    EXPECT_NEAR(g.principalMoments.minCoeff(), want.axial, 1e-4 * want.axial) << d;
    EXPECT_NEAR(g.principalMoments.maxCoeff(), want.transverse, 1e-4 * want.transverse) << d;
  }
  // 2D: two overlapping discs, the lens's closed form.
  const Geometry<2> g2 = ShapeTable<2>::get().makeGeometry("clump", std::vector<double>{0, 0, 0.01, 0.01, 0, 0.01});
  const Real lens = 2 * 0.01 * 0.01 * std::acos(0.5) - 0.5 * 0.01 * std::sqrt(4 * 0.01 * 0.01 - 0.01 * 0.01);
  EXPECT_NEAR(g2.volume, 2 * kPi * 1e-4 - lens, 1e-7 * g2.volume);
}

TEST(SimClump, OneMemberIsTheBallOnEveryWallAndBall) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const TypeId clump = *t.id("clump");
  const Geometry<3> g = t.makeGeometry("clump", std::vector<double>{0.3, -0.2, 0.1, 0.01});
  const Geometry<3> ball;
  physics::PlaneShape<3> pl{Vec3::Zero(), Vec3(0, 0, 1)};
  physics::FlatWallShape<3> plate{Vec3::Zero(), {Vec3::UnitX(), Vec3::UnitY()}, {0.03, 0.02}, 0.012};
  physics::BoxShape<3> box{Vec3::Zero(), Mat3::Identity(), Vec3(0.02, 0.01, 0.015)};
  physics::DrumShape<3> drum{Vec3::Zero(), Vec3::UnitZ(), 0.05, 0.1};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> u(-0.05, 0.05);
  int hits = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Vec3 x(u(rng), u(rng), 0.4 * u(rng));
    const ElementRef<3> e{x, Quat(AngleAxis(u(rng) * 60, Vec3(1, 2, 3).normalized())), g.boundRadius, &g};
    const physics::SphereShape<3> s{x, 0.01};
    const auto check = [&](int n, const ContactPoint<3>* p, const auto& want) {
      ASSERT_EQ(n, want ? 1 : 0) << trial;
      if (!want) return;
      ++hits;
      EXPECT_NEAR(p[0].g.overlap, want->overlap, 1e-15);
      EXPECT_LT((p[0].g.normal - want->normal).norm(), 1e-15);
      EXPECT_NEAR(p[0].effRadius, 0.01, 1e-15);
    };
    ContactPoint<3> p[kMaxContactPoints];
    check(t.wall(clump, WallShape::Plane)->fn(e, &pl, p), p, physics::intersect<3>(s, pl));
    check(t.wall(clump, WallShape::Finite)->fn(e, &plate, p), p, physics::intersect<3>(s, plate));
    check(t.wall(clump, WallShape::Box)->fn(e, &box, p), p, physics::intersect<3>(s, box));
    check(t.wall(clump, WallShape::Drum)->fn(e, &drum, p), p, physics::intersect<3>(s, drum));
    const Vec3 y(u(rng), u(rng), u(rng));
    const ElementRef<3> b{y, Quat::Identity(), 0.012, &ball};
    const auto want = physics::intersect<3>(s, physics::SphereShape<3>{y, 0.012});
    ASSERT_EQ(t.pair(clump, ball.shape)->fn(e, b, p), want ? 1 : 0);
    if (want) {
      EXPECT_NEAR(p[0].g.overlap, want->overlap, 1e-15);
    }
  }
  EXPECT_GT(hits, 200);
}

// A clump's member meets a superquadric as a ball does: a one-member clump against random turned
// superquadrics gives the superquadric-ball row's contact, the normal reversed.
TEST(SimClump, MembersMeetSuperquadricsAsBalls) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const TypeId clump = *t.id("clump"), sq = *t.id("superquadric");
  const Geometry<3> c = t.makeGeometry("clump", std::vector<double>{0, 0, 0, 0.006});
  const Geometry<3> ball;
  const Geometry<3> g = t.makeGeometry("superquadric", std::vector<double>{0.012, 0.008, 0.005, 4, 3});
  std::mt19937_64 rng(8);
  std::normal_distribution<Real> n;
  int hits = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Vec3 x = Vec3(n(rng), n(rng), n(rng)).normalized() * 0.014 * (0.7 + 0.1 * std::abs(n(rng)));
    const Quat q = Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
    const ElementRef<3> S{Vec3::Zero(), q, g.boundRadius, &g};
    const ElementRef<3> C{x, Quat::Identity(), c.boundRadius, &c};
    const ElementRef<3> B{x, Quat::Identity(), 0.006, &ball};
    ContactPoint<3> pc[kMaxContactPoints], pb[kMaxContactPoints];
    const int nc = t.pair(clump, sq)->fn(C, S, pc);
    const int nb = t.pair(sq, ball.shape)->fn(S, B, pb);
    ASSERT_EQ(nc, nb) << trial;
    if (nc == 0) continue;
    ++hits;
    EXPECT_NEAR(pc[0].g.overlap, pb[0].g.overlap, 1e-12) << trial;
    EXPECT_LT((pc[0].g.normal + pb[0].g.normal).norm(), 1e-9) << trial;
    EXPECT_LT((pc[0].g.point - pb[0].g.point).norm(), 1e-12) << trial;
  }
  EXPECT_GT(hits, 100);
}

// A one-member clump is the sphere: the same path through impacts with a plane and a sphere.
TEST(SimClump, OneMemberFollowsTheSpherePath) {
  testing::expectSamePath(testing::dropIntoBall(makeSimulation(3), "clump", {0, 0, 0, 0.01}),
                          testing::dropIntoBall(makeSimulation(3)), 1e-12);
}

// A dumbbell of unequal balls dropped tilted comes to rest on both, the floor carrying its weight
// at two points, its centre at the height the geometry gives.
TEST(SimClump, DumbbellRestsOnBothMembers) {
  auto s = makeSimulation(3);
  MaterialDef m = material(1e7, 0.3, 0.5);
  m.rollingFriction = 0.05;
  s->addMaterial("glass", m);
  const WallId floor = s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
  s->addGravity({0, 0, -9.81});
  ElementDef e = grain({0, 0, 0.05}, 0, "glass");
  e.shape = "clump";
  e.shapeParams = {0, 0, 0, 0.01, 0.03, 0, 0, 0.006};
  e.orientation = {0.95, 0.1, 0.2, 0.05};
  const ElementId id = s->addElement(e);
  RunOptions o;
  o.steps = static_cast<uint64_t>(3 / s->timeStep());
  s->run(o);
  const ElementState g = s->element(id);
  EXPECT_LT(std::hypot(g.velocity[0], g.velocity[1], g.velocity[2]), 1e-4);
  EXPECT_EQ(s->contactCount(), 2u);
  EXPECT_NEAR(s->wall(floor).force[2], -g.mass * 9.81, 1e-4 * g.mass * 9.81);
  // Both members on the floor: the axis tilted by asin((r1 - r2) / d), the centroid between.
  const Real r1 = 0.01, r2 = 0.006, d = 0.03, v1 = r1 * r1 * r1, v2 = r2 * r2 * r2;
  const Real tilt = std::asin((r1 - r2) / d), xc = d * v2 / (v1 + v2);
  const Real want = r1 - xc * std::sin(tilt);
  EXPECT_NEAR(g.position[2], want, 5e-5);
}

TEST(SimClump, BadParametersAreRefusedAndChangeNothing) {
  testing::expectShapesRefused("clump", {{},
                                         {0, 0, 0},
                                         {0, 0, 0, -0.01},
                                         {0, 0, 0, 0.01, 1, 0, 0, 1e-9},
                                         {0, 0, 0, NAN}});
}

}  // namespace sim_clump_test
}  // namespace demlab::sim
