// The superquadric (3D) and superellipse (2D) shape types: their geometry against closed forms
// and brute-force oracles on random shapes, their contacts against the ball's and against a
// brute-force penetration depth, and their physics against analytic answers (the sphere's
// path, an ellipsoid coming to rest on its longest axis, a block on an incline).
#include <cmath>
#include <numbers>
#include <random>

#include "physics/narrow_phase.hpp"
#include "sim/shape.hpp"
#include "sim/shapes/convex_contact.hpp"
#include "sim/shapes/superquadric.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_superquadric_test {

using testing::grain;
using testing::material;
using testing::plane;
using testing::randomQuat;
using testing::randomUnit;

const Real kPi = std::numbers::pi;

// A random superquadric: half axes in [0.5, 2] cm, exponents in [2, 10].
Superquadric<3> randomShape(std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> axis(0.005, 0.02), expo(2, 10);
  Superquadric<3> s;
  s.a = axis(rng), s.b = axis(rng), s.c = axis(rng);
  s.n1 = expo(rng), s.n2 = expo(rng);
  return s;
}


std::vector<double> paramsOf(const Superquadric<3>& s) { return {s.a, s.b, s.c, s.n1, s.n2}; }

// Volume and inertia by quadrature over directions: the body is r <= 1/phi(u) along u.
MassProperties<3> quadrature(const Superquadric<3>& s) {
  MassProperties<3> m;
  const int nt = 400, np = 800;
  for (int i = 0; i < nt; ++i) {
    const Real t = kPi * (i + 0.5) / nt, dt = kPi / nt;
    for (int j = 0; j < np; ++j) {
      const Real p = 2 * kPi * (j + 0.5) / np, dp = 2 * kPi / np;
      const Vec3 u(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      const Real R = 1 / s.gauge(u), w = std::sin(t) * dt * dp;
      m.volume += w * R * R * R / 3;
      m.inertia += w * std::pow(R, 5) / 5 * (Mat3::Identity() - u * u.transpose());
    }
  }
  return m;
}

TEST(SimSuperquadric, MassPropertiesMatchTheSphereAndQuadrature) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const ShapeType<3>& sq = *t.find("superquadric");
  const std::vector<double> ball{0.01, 0.01, 0.01, 2, 2};
  const MassProperties<3> m = sq.massProperties(ball);
  EXPECT_NEAR(m.volume, ballMass<3>(1, 0.01), 1e-14 * m.volume);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(m.inertia(k, k), ballInertia<3>(m.volume, 0.01), 1e-14 * m.inertia(k, k));
  }
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 3; ++trial) {
    const Superquadric<3> s = randomShape(rng);
    const MassProperties<3> exact = sq.massProperties(paramsOf(s)), q = quadrature(s);
    EXPECT_NEAR(exact.volume, q.volume, 3e-5 * q.volume) << trial;
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(exact.inertia(k, k), q.inertia(k, k), 3e-5 * q.inertia(k, k)) << trial;
    }
  }
  // 2D: the superellipse's area and polar moment, the circle's and by quadrature.
  const ShapeType<2>& se = *ShapeTable<2>::get().find("superellipse");
  const MassProperties<2> c = se.massProperties(std::vector<double>{0.01, 0.01, 2});
  EXPECT_NEAR(c.volume, kPi * 1e-4, 1e-14 * c.volume);
  EXPECT_NEAR(c.inertia(2, 2), kPi * 1e-8 / 2, 1e-14 * c.inertia(2, 2));
  for (const double n : {2.5, 4.0, 9.0}) {
    const Superquadric<2> s{0.02, 0.007, 0, n, n};
    Real area = 0, polar = 0;
    const int steps = 200000;
    for (int i = 0; i < steps; ++i) {
      const Real th = 2 * kPi * (i + 0.5) / steps;
      const Real R = 1 / s.gauge(Vec2(std::cos(th), std::sin(th)));
      area += R * R / 2 * 2 * kPi / steps;
      polar += std::pow(R, 4) / 4 * 2 * kPi / steps;
    }
    const MassProperties<2> e = se.massProperties(std::vector<double>{0.02, 0.007, n});
    EXPECT_NEAR(e.volume, area, 1e-8 * area) << n;
    EXPECT_NEAR(e.inertia(2, 2), polar, 1e-8 * polar) << n;
  }
}

TEST(SimSuperquadric, BoundingRadiusHoldsTheSurfaceTightly) {
  const ShapeType<3>& sq = *ShapeTable<3>::get().find("superquadric");
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Superquadric<3> s = randomShape(rng);
    const Real bound = sq.boundingRadius(paramsOf(s));
    Real far = 0;
    for (int k = 0; k < 20000; ++k) far = std::max(far, 1 / s.gauge(randomUnit(rng)));
    EXPECT_LE(far, bound) << trial;
    EXPECT_GT(far, bound * (1 - 2e-3)) << trial;
  }
  EXPECT_NEAR(sq.boundingRadius(std::vector<double>{0.03, 0.01, 0.02, 2, 2}), 0.03, 1e-10);
}

TEST(SimSuperquadric, SupportPointIsTheFarthestSurfacePoint) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Superquadric<3> s = randomShape(rng);
    for (int k = 0; k < 5; ++k) {
      const Vec3 d = randomUnit(rng), p = s.support(d);
      EXPECT_NEAR(s.gauge(p), 1, 1e-12);
      Real best = -1;
      for (int j = 0; j < 20000; ++j) {
        const Vec3 u = randomUnit(rng);
        best = std::max(best, d.dot(u) / s.gauge(u));
      }
      EXPECT_GE(d.dot(p), best - 1e-15);
      EXPECT_LT(d.dot(p) - best, 1e-2 * s.a);  // the sampling's own resolution
      // The outward normal there is d: the gauge's gradient is parallel to it.
      const Vec3 g = s.gaugeGradient(p).normalized();
      EXPECT_GT(g.dot(d), 1 - 1e-9);
    }
  }
}


TEST(SimSuperquadric, EqualAxesGiveTheBallsContactExactly) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const TypeId sq = *t.id("superquadric");
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> rad(0.005, 0.02), frac(0.0, 0.3);
  for (int trial = 0; trial < 200; ++trial) {
    const Real ra = rad(rng), rb = rad(rng);
    const Vec3 xa = randomUnit(rng) * 0.01, u = randomUnit(rng);
    const Vec3 xb = xa + u * (ra + rb) * (1 - frac(rng) * 0.1);
    const Geometry<3> ga = t.makeGeometry("superquadric", std::vector<double>{ra, ra, ra, 2, 2});
    const Geometry<3> gb = t.makeGeometry("superquadric", std::vector<double>{rb, rb, rb, 2, 2});
    const Geometry<3> ball;  // shape 0: the ball
    const ElementRef<3> A{xa, randomQuat(rng), ga.boundRadius, &ga};
    const ElementRef<3> B{xb, randomQuat(rng), gb.boundRadius, &gb};
    const ElementRef<3> Bball{xb, Quat::Identity(), rb, &ball};
    const auto want = physics::intersect<3>(physics::SphereShape<3>{xa, ra},
                                            physics::SphereShape<3>{xb, rb});
    ASSERT_TRUE(want);
    for (const ElementRef<3>* other : {&B, &Bball}) {
      ContactPoint<3> p[kMaxContactPoints];
      const int n = t.pair(sq, other->g->shape)->fn(A, *other, p);
      ASSERT_EQ(n, 1) << trial;
      EXPECT_NEAR(p[0].g.overlap, want->overlap, 1e-9 * ra) << trial;
      EXPECT_LT((p[0].g.normal - want->normal).norm(), 1e-9) << trial;
      EXPECT_LT((p[0].g.point - want->point).norm(), 1e-9 * ra) << trial;
      EXPECT_NEAR(p[0].effRadius, ra * rb / (ra + rb), 1e-12 * ra);
    }
  }
}

// The penetration depth by brute force: the least extent of overlap over directions n,
// n . support_A(n) - n . support_B(-n), minimised over a direction grid and refined.
Real bruteDepth(const PlacedGauge<3>& A, const PlacedGauge<3>& B, Vec3& normal,
                std::mt19937_64& rng) {
  const auto depth = [&](const Vec3& n) { return n.dot(A.support(n)) - n.dot(B.support(-n)); };
  Real best = 1e300;
  for (int k = 0; k < 4000; ++k) {
    const Vec3 n = randomUnit(rng);
    const Real d = depth(n);
    if (d < best) best = d, normal = n;
  }
  for (Real h = 0.05; h > 1e-9; h *= 0.7) {
    for (int k = 0; k < 30; ++k) {
      const Vec3 n = (normal + h * randomUnit(rng)).normalized();
      const Real d = depth(n);
      if (d < best) best = d, normal = n;
    }
  }
  return best;
}

TEST(SimSuperquadric, PairContactAgreesWithBruteForce) {
  std::mt19937_64 rng(9);
  int touching = 0, apart = 0;
  for (int trial = 0; trial < 60; ++trial) {
    PlacedGauge<3> A{randomShape(rng), Vec3::Zero(), randomQuat(rng).toRotationMatrix()};
    PlacedGauge<3> B{randomShape(rng), Vec3::Zero(), randomQuat(rng).toRotationMatrix()};
    // B touching A with the common normal u (their support points along u and -u made one),
    // then moved by a small random amount along u either way.
    const Vec3 u = randomUnit(rng);
    const Real size = std::min({A.shape.a, A.shape.b, A.shape.c, B.shape.a, B.shape.b, B.shape.c});
    const Vec3 touch = A.support(u) - B.support(-u);  // B still at the origin
    B.centre = touch - u * (std::uniform_real_distribution<Real>(-0.01, 0.02)(rng) * size);
    Vec3 bruteNormal;
    const Real want = bruteDepth(A, B, bruteNormal, rng);
    ConvexContact<3> c;
    const bool hit = convexContact(A, B, 0.1, c);
    if (want < -1e-6 * size) {
      EXPECT_FALSE(hit) << trial;
      ++apart;
      continue;
    }
    if (want < 1e-6 * size) continue;  // grazing: either answer is right
    ASSERT_TRUE(hit) << trial << " depth " << want;
    ++touching;
    // The midway point's overlap is along its own normal, not the least one: they agree to
    // first order in overlap / curvature radius.
    EXPECT_NEAR(c.overlap, want, 0.05 * want + 1e-3 * want / size * want) << trial;
    EXPECT_GT(c.normal.dot(bruteNormal), 1 - 1e-2) << trial;
    // The point lies between the surfaces: inside both bodies' slightly grown shapes.
    EXPECT_LT(A.gauge(c.point), 1 + 1e-9) << trial;
    EXPECT_LT(B.gauge(c.point), 1 + 1e-9) << trial;
  }
  EXPECT_GT(touching, 20);
  EXPECT_GT(apart, 5);
}

TEST(SimSuperquadric, NewtonAndItsSafeguardFindTheSameMidwayPoint) {
  std::mt19937_64 rng(13);
  int newton = 0;
  for (int trial = 0; trial < 40; ++trial) {
    PlacedGauge<3> A{randomShape(rng), Vec3::Zero(), randomQuat(rng).toRotationMatrix()};
    PlacedGauge<3> B{randomShape(rng), randomUnit(rng) * 0.03, randomQuat(rng).toRotationMatrix()};
    const MidwayPoint<3> n = convex_detail::newtonMidway(A, B, Vec3(0.5 * B.centre), 0.1);
    const MidwayPoint<3> b = convex_detail::blendMidway(A, B, 0.1);
    ASSERT_TRUE(b.found);
    EXPECT_NEAR(A.gauge(b.x), B.gauge(b.x), 1e-8) << trial;
    if (!n.found) continue;
    ++newton;
    EXPECT_LT((n.x - b.x).norm(), 1e-8 * 0.1) << trial;
    EXPECT_NEAR(n.scale, b.scale, 1e-8) << trial;
  }
  EXPECT_GT(newton, 30);  // Newton's method itself serves nearly every pair
}

// A superquadric of equal half axes and exponents 2 is the sphere: dropped with spin onto a
// plane and into a sphere at rest, it follows the sphere's path.
TEST(SimSuperquadric, EqualAxesFollowTheSpherePath) {
  testing::expectSamePath(testing::dropIntoBall(makeSimulation(3), "superquadric", {0.01, 0.01, 0.01, 2, 2}),
                 testing::dropIntoBall(makeSimulation(3)), 1e-9);
}

// Returns the z component of the body axis k of an element in world coordinates.
double axisZ(const ElementState& g, int k) {
  const Quat q(g.orientation[0], g.orientation[1], g.orientation[2], g.orientation[3]);
  return (q.normalized() * Vec3::Unit(k)).z();
}

TEST(SimSuperquadric, EllipsoidComesToRestOnItsLongestAxis) {
  std::mt19937_64 rng(21);
  for (int trial = 0; trial < 4; ++trial) {
    auto s = makeSimulation(3);
    // Rolling without slip dissipates nothing: without rolling resistance a rocking ellipsoid
    // rocks on (the ledger shows its energy constant), as the model says.
    MaterialDef m = material(1e7, 0.3, 0.5);
    m.rollingFriction = 0.05;
    s->addMaterial("glass", m);
    s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
    s->addGravity({0, 0, -9.81});
    ElementDef e = grain({0, 0, 0.04}, 0, "glass");
    e.shape = "superquadric";
    e.shapeParams = {0.02, 0.013, 0.008, 2, 2};
    const Quat q = randomQuat(rng);
    e.orientation = {q.w(), q.x(), q.y(), q.z()};
    const ElementId id = s->addElement(e);
    s->runTime(5);
    const ElementState g = s->element(id);
    // Lying on its flattest side: the shortest axis vertical, the longest horizontal, the
    // centre at the shortest half axis (less the overlap).
    EXPECT_LT(std::abs(axisZ(g, 0)), 1e-3) << trial;
    EXPECT_GT(std::abs(axisZ(g, 2)), 1 - 1e-6) << trial;
    EXPECT_NEAR(g.position[2], 0.008, 5e-5) << trial;
    EXPECT_LT(std::hypot(g.velocity[0], g.velocity[1], g.velocity[2]), 1e-4) << trial;
  }
}

// law -curvature local: the Hertz radius from the surfaces' curvature. An ellipsoid of half
// axes 2, 1, 1 cm against a plane on its tip has the tip's radius b^2 / a; on its side the
// Gaussian radius sqrt((a^2 / c) (b^2 / c)) = a b / c; a sphere as a superquadric against a
// ball, the two radii's r1 r2 / (r1 + r2); an ellipse's tip in 2D b^2 / a. With the option on,
// an ellipsoid resting on its tip sinks by Hertz's overlap for the tip's radius.
TEST(SimSuperquadric, LocalCurvatureGivesTheSurfacesRadii) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const Geometry<3> ell = t.makeGeometry("superquadric", std::vector<double>{0.02, 0.01, 0.01, 2, 2});
  const physics::PlaneShape<3> floor{Vec3::Zero(), Vec3::UnitZ()};
  ContactPoint<3> p[kMaxContactPoints];
  // On its tip: the long axis (x) turned to vertical, sunk by 1 um.
  const Quat up(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()));
  ASSERT_EQ(shapeWallPoints<3>({Vec3(0, 0, 0.02 - 1e-6), up, ell.boundRadius, &ell, true}, WallShape::Plane, &floor, p), 1);
  EXPECT_NEAR(p[0].localRadius, 0.01 * 0.01 / 0.02, 1e-4 * 0.005);
  // On its side (z vertical).
  ASSERT_EQ(shapeWallPoints<3>({Vec3(0, 0, 0.01 - 1e-6), Quat::Identity(), ell.boundRadius, &ell, true}, WallShape::Plane, &floor, p), 1);
  EXPECT_NEAR(p[0].localRadius, 0.02 * 0.01 / 0.01, 1e-4 * 0.02);
  // A sphere as a superquadric against a ball, and against itself.
  const Geometry<3> sq = t.makeGeometry("superquadric", std::vector<double>{0.01, 0.01, 0.01, 2, 2});
  const Geometry<3> ball = t.makeGeometry("sphere", std::vector<double>{});
  ASSERT_EQ(shapePairPoints<3>({Vec3::Zero(), Quat::Identity(), sq.boundRadius, &sq, true},
                               {Vec3(0.0149, 0.001, 0), Quat::Identity(), 0.005, &ball, true}, p), 1);
  EXPECT_NEAR(p[0].localRadius, 0.01 * 0.005 / 0.015, 1e-9);
  ASSERT_EQ(shapePairPoints<3>({Vec3::Zero(), Quat::Identity(), sq.boundRadius, &sq, true},
                               {Vec3(0, 0.0199, 0), Quat::Identity(), sq.boundRadius, &sq, true}, p), 1);
  EXPECT_NEAR(p[0].localRadius, 0.005, 1e-9);
  // 2D: an ellipse on its tip.
  const Geometry<2> e2 = ShapeTable<2>::get().makeGeometry("superellipse", std::vector<double>{0.02, 0.01, 2});
  const physics::PlaneShape<2> floor2{Vec2::Zero(), Vec2::UnitY()};
  ContactPoint<2> p2[kMaxContactPoints];
  ASSERT_EQ(shapeWallPoints<2>({Vec2(0, 0.02 - 1e-6), Rotation2{M_PI / 2}, e2.boundRadius, &e2, true}, WallShape::Plane, &floor2, p2), 1);
  EXPECT_NEAR(p2[0].localRadius, 0.005, 1e-4 * 0.005);
  // Resting on its tip (held upright), with the option: Hertz's overlap for R = b^2 / a.
  for (const bool local : {false, true}) {
    auto s = makeSimulation(3);
    s->addMaterial("glass", material(1e7, 0.3, 0.5));
    s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
    s->addGravity({0, 0, -9.81});
    if (local) s->setOption("law", "curvature", std::string("local"));
    ElementDef e = grain({0, 0, 0.02}, 0, "glass");
    e.shape = "superquadric";
    e.shapeParams = {0.02, 0.01, 0.01, 2, 2};
    e.orientation = {up.w(), up.x(), up.y(), up.z()};
    e.blocked = dof::Rx | dof::Ry | dof::Rz | dof::X | dof::Y;
    const ElementId id = s->addElement(e);
    s->runTime(0.5);
    const ElementState g = s->element(id);
    const double young = 1e7 / (2 * (1 - 0.3 * 0.3));  // E* of two equal materials
    const double radius = local ? 0.005 : std::cbrt(0.02 * 0.01 * 0.01);
    const double want = std::pow(3 * g.mass * 9.81 / (4 * young * std::sqrt(radius)), 2.0 / 3);
    EXPECT_NEAR(0.02 - g.position[2], want, 0.01 * want) << local;
  }
}

// A blocky superquadric (exponents 10) on a slope, as gravity tilted by theta: below
// tan(theta) = mu it stays where it is; above, it slides at g (sin theta - mu cos theta)
// without rolling over.
TEST(SimSuperquadric, BlockOnAnInclineSticksOrSlidesByCoulomb) {
  const double mu = 0.4, g0 = 9.81;
  for (const double theta : {0.25, 0.55}) {
    ElementDef b = grain({0, 0, 0.01}, 0, "glass");
    b.shape = "superquadric";
    b.shapeParams = {0.01, 0.01, 0.01, 10, 10};
    const testing::InclineRun r = testing::runIncline(b, theta, mu, 0.2, 0.3);
    if (std::tan(theta) < mu) {
      EXPECT_LT(std::abs(r.moved), 1e-5) << theta;
    } else {
      const double want = g0 * (std::sin(theta) - mu * std::cos(theta));
      EXPECT_NEAR(r.acceleration, want, 0.02 * want) << theta;
    }
    EXPECT_GT(std::abs(axisZ(r.end, 2)), 0.99) << theta;  // still face down
  }
}

// Inside a drum, the deepest point is the farthest from the axis: against sampled surface
// points of random turned superquadrics.
TEST(SimSuperquadric, DrumContactIsTheFarthestPointFromTheAxis) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const TypeId sq = *t.id("superquadric");
  std::mt19937_64 rng(17);
  physics::DrumShape<3> drum{Vec3::Zero(), Vec3::UnitZ(), 0.2, 1.0};
  for (int trial = 0; trial < 20; ++trial) {
    const Superquadric<3> shape = randomShape(rng);
    const Geometry<3> g = t.makeGeometry("superquadric", paramsOf(shape));
    const Quat q = randomQuat(rng);
    const Vec3 x = Vec3(0.2 - 0.5 * shape.a, 0, 0.1);
    ElementRef<3> e{x, q, g.boundRadius, &g};
    Real far = 0;
    for (int k = 0; k < 50000; ++k) {
      const Vec3 u = randomUnit(rng), p = x + q * (u / shape.gauge(u));
      far = std::max(far, std::hypot(p.x(), p.y()));
    }
    ContactPoint<3> p[kMaxContactPoints];
    const int n = t.wall(sq, WallShape::Drum)->fn(e, &drum, p);
    if (far < 0.2) {
      EXPECT_EQ(n, 0) << trial;
      continue;
    }
    ASSERT_EQ(n, 1) << trial;
    EXPECT_NEAR(p[0].g.overlap, far - 0.2, 1e-3 * (far - 0.2) + 1e-9) << trial;
    EXPECT_GE(p[0].g.overlap, far - 0.2 - 1e-12) << trial;
  }
}

// Equal half axes and exponents 2: against a finite wall with a hole (over the face, its edges
// and its rim), a solid box and a drum, the ball's own contact.
TEST(SimSuperquadric, EqualAxesMeetEveryWallAsTheBall) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const TypeId sq = *t.id("superquadric");
  const Real r = 0.01;
  const Geometry<3> g = t.makeGeometry("superquadric", std::vector<double>{r, r, r, 2, 2});
  physics::FlatWallShape<3> plate{Vec3(0, 0, 0), {Vec3::UnitX(), Vec3::UnitY()}, {0.03, 0.02}, 0.012};
  const Mat3 turn = AngleAxis(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  physics::BoxShape<3> box{Vec3(0, 0, 0), turn, Vec3(0.02, 0.01, 0.015)};
  physics::DrumShape<3> drum{Vec3::Zero(), Vec3::UnitZ(), 0.05, 0.1};
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<Real> box3(-0.05, 0.05);
  int hits[3] = {0, 0, 0};
  for (int trial = 0; trial < 3000; ++trial) {
    const Vec3 x(box3(rng), box3(rng), box3(rng) * 0.4);
    const ElementRef<3> e{x, randomQuat(rng), g.boundRadius, &g};
    const physics::SphereShape<3> ball{x, r};
    const auto check = [&](int kind, WallShape shape, const void* wall,
                           const std::optional<physics::ContactGeometry<3>>& want) {
      ContactPoint<3> p[kMaxContactPoints];
      const int n = t.wall(sq, shape)->fn(e, wall, p);
      if (!want || want->overlap < 1e-9) return;  // grazing: either answer
      ASSERT_EQ(n, 1) << kind << " " << trial;
      ++hits[kind];
      EXPECT_NEAR(p[0].g.overlap, want->overlap, 1e-9) << kind << " " << trial;
      EXPECT_LT((p[0].g.normal - want->normal).norm(), 1e-6) << kind << " " << trial;
      EXPECT_LT((p[0].g.point - want->point).norm(), 1e-8) << kind << " " << trial;
    };
    check(0, WallShape::Finite, &plate, physics::intersect<3>(ball, plate));
    check(1, WallShape::Box, &box, physics::intersect<3>(ball, box));
    check(2, WallShape::Drum, &drum, physics::intersect<3>(ball, drum));
  }
  EXPECT_GT(hits[0], 100);
  EXPECT_GT(hits[1], 100);
  EXPECT_GT(hits[2], 20);
}

// Random superquadrics against a finite wall and a solid box: the overlap against the least
// penetration by brute force over directions (the walls' support: their corners).
TEST(SimSuperquadric, FiniteAndBoxWallsAgreeWithBruteForce) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const TypeId sq = *t.id("superquadric");
  const Mat3 turn = AngleAxis(0.5, Vec3(3, 1, 2).normalized()).toRotationMatrix();
  physics::FlatWallShape<3> plate{Vec3::Zero(), {turn.col(0), turn.col(1)}, {0.04, 0.03}, 0};
  physics::BoxShape<3> box{Vec3::Zero(), turn, Vec3(0.04, 0.03, 0.02)};
  std::mt19937_64 rng(37);
  int touching = 0;
  for (int trial = 0; trial < 80; ++trial) {
    const bool isBox = trial % 2 == 1;
    std::vector<Vec3> corners;
    for (int c = 0; c < 8; ++c) {
      const Vec3 h = isBox ? box.halfExtents : Vec3(0.04, 0.03, 0);
      corners.push_back(turn * Vec3(c & 1 ? h.x() : -h.x(), c & 2 ? h.y() : -h.y(), c & 4 ? h.z() : -h.z()));
    }
    const Superquadric<3> shape = randomShape(rng);
    const Quat q = randomQuat(rng);
    PlacedGauge<3> B{shape, Vec3::Zero(), q.toRotationMatrix()};
    // Touching the wall at a point of it farthest along a direction u (a corner, or for every
    // third trial a face's normal and a point of that face), then pushed in a little.
    Vec3 u = randomUnit(rng), at = Vec3::Zero();
    if (trial % 3 == 0) {
      const int k = isBox ? trial % 9 / 3 : 2;
      u = (trial % 2 == 0 ? 1 : -1) * turn.col(k);
      std::uniform_real_distribution<Real> in(-0.5, 0.5);
      const Vec3 h = isBox ? box.halfExtents : Vec3(0.04, 0.03, 0);
      Vec3 local(in(rng) * h.x(), in(rng) * h.y(), in(rng) * h.z());
      local[k] = (turn.col(k).dot(u) > 0 ? 1 : -1) * h[k];
      at = turn * local;
    } else {
      Real reach = -1e300;
      for (const Vec3& c : corners) {
        if (u.dot(c) > reach) reach = u.dot(c), at = c;
      }
    }
    const Real size = std::min({shape.a, shape.b, shape.c});
    B.centre = at - B.support(-u) - u * 0.01 * size;  // B.support with B still at the origin
    // The least penetration: over directions n, B's extent along -n past the wall's along -n.
    const auto extent = [&](const Vec3& n) {
      Real wall = -1e300;
      for (const Vec3& c : corners) wall = std::max(wall, n.dot(c));
      return wall - n.dot(B.support(-n));
    };
    Real want = 1e300;
    Vec3 best;
    for (int k = 0; k < 4000; ++k) {
      const Vec3 n = randomUnit(rng);
      if (extent(n) < want) want = extent(n), best = n;
    }
    for (Real h = 0.05; h > 1e-10; h *= 0.8) {
      for (int k = 0; k < 40; ++k) {
        const Vec3 n = (best + h * randomUnit(rng)).normalized();
        if (extent(n) < want) want = extent(n), best = n;
      }
    }
    const Geometry<3> g = t.makeGeometry("superquadric", paramsOf(shape));
    const ElementRef<3> e{B.centre, q, g.boundRadius, &g};
    ContactPoint<3> p[kMaxContactPoints];
    const int n = isBox ? t.wall(sq, WallShape::Box)->fn(e, &box, p)
                        : t.wall(sq, WallShape::Finite)->fn(e, &plate, p);
    if (want < 1e-3 * size) continue;  // grazing or sampled too coarsely to say
    ASSERT_EQ(n, 1) << trial;
    ++touching;
    // The deepest point's normal is not the least penetration's: they agree to first order.
    EXPECT_NEAR(p[0].g.overlap, want, 0.01 * want) << trial;
  }
  EXPECT_GT(touching, 40);
}

TEST(SimSuperquadric, SuperellipseMeetsDiscsAsADisc) {
  const ShapeTable<2>& t = ShapeTable<2>::get();
  const TypeId se = *t.id("superellipse");
  const Geometry<2> gc = t.makeGeometry("superellipse", std::vector<double>{0.01, 0.01, 2});
  const Geometry<2> ball;
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<Real> ang(0, 2 * kPi);
  for (int trial = 0; trial < 50; ++trial) {
    const Real th = ang(rng);
    const Vec2 xb = Vec2(std::cos(th), std::sin(th)) * 0.0195;
    const ElementRef<2> A{Vec2::Zero(), Rotation2{ang(rng)}, gc.boundRadius, &gc};
    const ElementRef<2> B{xb, Rotation2{0}, 0.01, &ball};
    ContactPoint<2> p[kMaxContactPoints];
    ASSERT_EQ(t.pair(se, ball.shape)->fn(A, B, p), 1);
    EXPECT_NEAR(p[0].g.overlap, 0.0005, 1e-12);
    EXPECT_LT((p[0].g.normal - xb / xb.norm()).norm(), 1e-10);
  }
  // A flat superellipse rests on a plane on its long side.
  auto s = makeSimulation(2);
  s->addMaterial("glass", material(1e7, 0.3, 0.5));
  s->addWall(plane({0, 0, 0}, {0, 1, 0}, "glass"));
  s->addGravity({0, -9.81, 0});
  ElementDef e = grain({0, 0.05, 0}, 0, "glass");
  e.shape = "superellipse";
  e.shapeParams = {0.02, 0.008, 4};
  e.orientation = {0.9};  // 2D: the angle
  const ElementId id = s->addElement(e);
  s->runTime(3);
  const ElementState g = s->element(id);
  EXPECT_NEAR(std::remainder(g.orientation[0], kPi), 0, 1e-3);
  EXPECT_LT(g.position[1], 0.008);
  EXPECT_GT(g.position[1], 0.007);
}

TEST(SimSuperquadric, BadParametersAreRefusedAndChangeNothing) {
  testing::expectShapesRefused("superquadric", {{0.01, 0.01, 0.01, 2},
                                                {0.01, 0.01, -0.01, 2, 2},
                                                {0.01, 0.01, 0.01, 1.5, 2},
                                                {0.01, 0.01, 0.01, 2, 30},
                                                {0.01, 1e5, 0.01, 2, 2},
                                                {0.01, NAN, 0.01, 2, 2}});
}

}  // namespace sim_superquadric_test
}  // namespace demlab::sim
