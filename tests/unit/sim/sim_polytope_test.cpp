// The polygon (2D) and polyhedron (3D) shape types: their hulls and mass properties against
// closed forms and Monte Carlo, their contacts against brute-force intersection and
// penetration depth on random poses (parallel faces and edge on edge among them), and their
// physics against analytic answers (a box at rest face down, a cube on an incline, a tall block
// tipping at atan(width / height)).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "physics/shapes.hpp"
#include "sim/shape.hpp"
#include "sim/shapes/convex_contact.hpp"
#include "sim/shapes/polytope.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_polytope_test {

using testing::grain;
using testing::material;
using testing::plane;
using testing::randomQuat;
using testing::randomUnit;


std::vector<double> flatten(const std::vector<Vec3>& pts) {
  std::vector<double> out;
  for (const Vec3& p : pts) out.insert(out.end(), {p.x(), p.y(), p.z()});
  return out;
}

// The corners of a box of half extents h, turned by q and moved by x.
std::vector<Vec3> boxCorners(const Vec3& h, const Quat& q = Quat::Identity(),
                             const Vec3& x = Vec3::Zero()) {
  std::vector<Vec3> c;
  for (int k = 0; k < 8; ++k) {
    c.push_back(x + q * Vec3(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(), k & 4 ? h.z() : -h.z()));
  }
  return c;
}

// A random convex polyhedron: a box, or 6 to 20 random points on an ellipsoid (every one a
// corner of their hull), 0.5 to 2 cm across.
std::vector<double> randomPolyhedron(std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> size(0.005, 0.02);
  if (rng() % 3 == 0) return flatten(boxCorners(Vec3(size(rng), size(rng), size(rng))));
  const Vec3 axes(size(rng), size(rng), size(rng));
  std::vector<Vec3> pts(6 + rng() % 15);
  for (Vec3& p : pts) p = randomUnit(rng).cwiseProduct(axes);
  return flatten(pts);
}

struct Body {
  Geometry<3> g;
  Vec3 x;
  Quat q;
  ElementRef<3> ref() const { return {x, q, g.boundRadius, &g}; }
  const Polytope<3>& poly() const { return *static_cast<const Polytope<3>*>(g.data.get()); }
  std::vector<Vec3> corners() const {
    std::vector<Vec3> c;
    for (const Vec3& v : poly().vertices) c.push_back(x + q * v);
    return c;
  }
  // Returns true if p lies inside (to tol).
  bool holds(const Vec3& p, Real tol = 0) const {
    const Vec3 l = q.conjugate() * (p - x);
    for (const auto& f : poly().faces) {
      if (f.normal.dot(l) - f.offset > tol) return false;
    }
    return true;
  }
};

// Intersection of two convex polyhedra by brute force: a corner of one inside the other, or an
// edge of one through a face of the other (sampled at `samples` points along the edge).
bool intersect(const Body& a, const Body& b, int samples = 100) {
  for (const Vec3& c : a.corners()) if (b.holds(c)) return true;
  for (const Vec3& c : b.corners()) if (a.holds(c)) return true;
  for (const Body* p : {&a, &b}) {
    const Body& o = p == &a ? b : a;
    const std::vector<Vec3> c = p->corners();
    for (const auto& e : p->poly().edges) {
      for (int k = 1; k < samples; ++k) {
        if (o.holds(c[e.a] + (c[e.b] - c[e.a]) * (double(k) / samples))) return true;
      }
    }
  }
  return false;
}

// The least overlap of the projections of a and b over every face normal and every cross
// product of two edges' directions (the separating-axis theorem's candidates, all of them).
Real leastOverlap(const Body& a, const Body& b);

// The overlap of the projections of a and b along n.
Real overlapAlong(const Body& a, const Body& b, const Vec3& n) {
  Real hiA = -1e300, loB = 1e300;
  for (const Vec3& c : a.corners()) hiA = std::max(hiA, n.dot(c));
  for (const Vec3& c : b.corners()) loB = std::min(loB, n.dot(c));
  return hiA - loB;
}

Real leastOverlap(const Body& a, const Body& b) {
  Real least = 1e300;
  const std::vector<Vec3> ca = a.corners(), cb = b.corners();
  for (const Body* p : {&a, &b}) {
    for (const auto& f : p->poly().faces) {
      const Vec3 n = p->q * f.normal;
      least = std::min({least, overlapAlong(a, b, n), overlapAlong(a, b, Vec3(-n))});
    }
  }
  for (const auto& ea : a.poly().edges) {
    for (const auto& eb : b.poly().edges) {
      const Vec3 n = (ca[ea.b] - ca[ea.a]).cross(cb[eb.b] - cb[eb.a]);
      if (n.norm() < 1e-9 * (ca[ea.b] - ca[ea.a]).norm() * (cb[eb.b] - cb[eb.a]).norm()) continue;
      least = std::min({least, overlapAlong(a, b, n.normalized()), overlapAlong(a, b, Vec3(-n.normalized()))});
    }
  }
  return least;
}

TEST(SimPolytope, MassPropertiesMatchClosedFormsAndMonteCarlo) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    // A box given turned and away from the origin: the table moves it about its centroid.
    std::uniform_real_distribution<Real> h(0.002, 0.02);
    const Vec3 half(h(rng), h(rng), h(rng));
    const Quat q = randomQuat(rng);
    const Geometry<3> g = t.makeGeometry("polyhedron", flatten(boxCorners(half, q, Vec3(0.1, -0.2, 0.3))));
    const Real V = 8 * half.prod();
    EXPECT_NEAR(g.volume, V, 1e-12 * V);
    std::array<Real, 3> want = {V * 4 * (half.y() * half.y() + half.z() * half.z()) / 12,
                                V * 4 * (half.x() * half.x() + half.z() * half.z()) / 12,
                                V * 4 * (half.x() * half.x() + half.y() * half.y()) / 12};
    std::sort(want.begin(), want.end());
    std::array<Real, 3> got = {g.principalMoments[0], g.principalMoments[1], g.principalMoments[2]};
    std::sort(got.begin(), got.end());
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 1e-9 * want[2]) << trial;
  }
  // A random hull against Monte Carlo sampling of its volume and second moments.
  for (int trial = 0; trial < 3; ++trial) {
    Body b{t.makeGeometry("polyhedron", randomPolyhedron(rng)), Vec3::Zero(), Quat::Identity()};
    const Real R = b.g.boundRadius;
    std::uniform_real_distribution<Real> u(-R, R);
    const int n = 400000;
    Real inside = 0;
    Mat3 second = Mat3::Zero();
    Vec3 first = Vec3::Zero();
    for (int k = 0; k < n; ++k) {
      const Vec3 p(u(rng), u(rng), u(rng));
      if (!b.holds(p)) continue;
      inside += 1, first += p, second += p * p.transpose();
    }
    const Real box = std::pow(2 * R, 3);
    EXPECT_NEAR(b.g.volume, box * inside / n, 0.02 * b.g.volume) << trial;
    EXPECT_LT((first / inside).norm(), 0.02 * R) << trial;  // the centroid is the origin
    const Mat3 c = second * (box / n);
    const Real trace = c.trace();
    // The principal moments are those of trace(C) I - C.
    Eigen::SelfAdjointEigenSolver<Mat3> eig(trace * Mat3::Identity() - c);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(b.g.principalMoments[k], eig.eigenvalues()[k], 0.04 * b.g.principalMoments[2]);
    }
  }
  // 2D: a rectangle and a right triangle.
  const ShapeTable<2>& t2 = ShapeTable<2>::get();
  const Geometry<2> rect = t2.makeGeometry("polygon", std::vector<double>{0, 0, 0.04, 0, 0.04, 0.02, 0, 0.02});
  EXPECT_NEAR(rect.volume, 8e-4, 1e-15);
  EXPECT_NEAR(rect.principalMoments[2], 8e-4 * (0.04 * 0.04 + 0.02 * 0.02) / 12, 1e-18);
  const Geometry<2> tri = t2.makeGeometry("polygon", std::vector<double>{0, 0, 0.03, 0, 0, 0.03});
  EXPECT_NEAR(tri.volume, 4.5e-4, 1e-15);
  // A right triangle of legs a: polar moment about its centroid a^4 / 18.
  EXPECT_NEAR(tri.principalMoments[2], std::pow(0.03, 4) / 18, 1e-16);
}

TEST(SimPolytope, BadCornersAreRefusedAndChangeNothing) {
  testing::expectShapesRefused("polyhedron", {
      {},                                               // no corners
      {0, 0, 0, 1, 0, 0, 0, 1, 0},                      // three corners
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.1},        // not whole corners
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0},             // flat
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.2, 0.2, 0.2},  // a point inside
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5, 0, 0},  // a point on an edge
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1},    // the same corner twice
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, NAN},
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1e10},
      {0, 0, 0, 1e-13, 0, 0, 0, 1e-13, 0, 0, 0, 1e-13},
  });
  EXPECT_THROW(ShapeTable<3>::get().makeGeometry("polyhedron", std::vector<double>(65 * 3, 1.0)), Error);
  EXPECT_THROW(ShapeTable<2>::get().makeGeometry("polygon", std::vector<double>{0, 0, 1, 0, 2, 0}), Error);
  EXPECT_THROW(ShapeTable<2>::get().makeGeometry("polygon", std::vector<double>{0, 0, 1, 0, 1, 1, 0.5, 0.2}), Error);
}

// Random pairs placed touching along a random direction, then pushed together or pulled
// apart a little; every fourth pair turned so that two faces are parallel or two edges meet.
TEST(SimPolytope, PairContactAgreesWithBruteForce) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const TypeId id = *t.id("polyhedron");
  std::mt19937_64 rng(11);
  int touching = 0, apart = 0;
  for (int trial = 0; trial < 80; ++trial) {
    Body a{t.makeGeometry("polyhedron", randomPolyhedron(rng)), Vec3::Zero(), randomQuat(rng)};
    Body b{t.makeGeometry("polyhedron", randomPolyhedron(rng)), Vec3::Zero(), randomQuat(rng)};
    Vec3 u = randomUnit(rng);
    if (trial % 4 == 0) {
      // Face to face: b's first face turned to oppose a's first face.
      const Vec3 na = a.q * a.poly().faces[0].normal, nb = b.q * b.poly().faces[0].normal;
      b.q = (Quat::FromTwoVectors(nb, -na) * b.q).normalized();
      u = na;
    } else if (trial % 4 == 1) {
      // Edge across edge: b's first edge crossing a's first edge.
      const auto& ea = a.poly().edges[0];
      const Vec3 da = a.q * (a.poly().vertices[ea.b] - a.poly().vertices[ea.a]);
      u = da.unitOrthogonal();
    }
    const Real size = std::min(a.g.boundRadius, b.g.boundRadius);
    // Touching along u (bisection on the brute-force test), then moved a little either way.
    Real lo = 0, hi = a.g.boundRadius + b.g.boundRadius;
    for (int it = 0; it < 22; ++it) {
      b.x = u * (0.5 * (lo + hi));
      (intersect(a, b, 30) ? lo : hi) = 0.5 * (lo + hi);
    }
    b.x = u * (hi - std::uniform_real_distribution<Real>(-0.02, 0.03)(rng) * size);
    const bool want = intersect(a, b);
    ContactPoint<3> p[kMaxContactPoints];
    const int n = t.pair(id, id)->fn(a.ref(), b.ref(), p);
    if (!want) {
      // Apart by the brute force: the routine agrees unless they graze within its sampling.
      if (n > 0) {
        for (int k = 0; k < n; ++k) EXPECT_LT(p[k].g.overlap, 1e-3 * size) << trial;
      }
      ++apart;
      continue;
    }
    ASSERT_GT(n, 0) << trial;
    ++touching;
    // The least overlap over every candidate axis and the routine's axis: the routine's is the
    // least up to its preference for faces (5 %).
    const Real least = leastOverlap(a, b);
    const Vec3 normal = p[0].g.normal;
    const Real along = overlapAlong(a, b, normal);
    EXPECT_LT(along, least * 1.06 + 1e-12) << trial;
    for (int k = 0; k < n; ++k) {
      EXPECT_LT((p[k].g.normal - normal).norm(), 1e-12) << trial;
      EXPECT_GT(p[k].g.overlap, 0) << trial;
      EXPECT_LE(p[k].g.overlap, along * (1 + 1e-9)) << trial;
      // The point lies halfway into both bodies' overlap: inside both, grown by the overlap.
      EXPECT_TRUE(a.holds(p[k].g.point, along) && b.holds(p[k].g.point, along)) << trial;
    }
    // Swapped, the same points with the normals reversed.
    ContactPoint<3> s[kMaxContactPoints];
    const int m = t.pair(id, id)->fn(b.ref(), a.ref(), s);
    ASSERT_GT(m, 0) << trial;
    EXPECT_LT(overlapAlong(b, a, s[0].g.normal), least * 1.06 + 1e-12) << trial;
  }
  EXPECT_GT(touching, 25);
  EXPECT_GT(apart, 10);
}

// A polyhedron against a superquadric: with equal axes and exponents 2 (a ball) the ball's
// answer; for random pairs, contact exactly when the least overlap of their extents over
// directions is positive, at a normal whose overlap is within 5 % of that least.
TEST(SimPolytope, SuperquadricContactAgreesWithBruteForce) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const TypeId poly = *t.id("polyhedron"), sq = *t.id("superquadric");
  std::mt19937_64 rng(23);
  const Geometry<3> ball;
  for (int trial = 0; trial < 100; ++trial) {
    const Body a{t.makeGeometry("polyhedron", randomPolyhedron(rng)), Vec3::Zero(), randomQuat(rng)};
    const Real r = std::uniform_real_distribution<Real>(0.003, 0.01)(rng);
    const Geometry<3> g = t.makeGeometry("superquadric", std::vector<double>{r, r, r, 2, 2});
    const Vec3 u = testing::randomUnit(rng);
    Real hi = -1e300;
    for (const Vec3& c : a.corners()) hi = std::max(hi, u.dot(c));
    const Vec3 x = u * (hi + r - std::uniform_real_distribution<Real>(0.0, 0.2)(rng) * r);
    ContactPoint<3> p[kMaxContactPoints], q[kMaxContactPoints];
    const int n = t.pair(poly, sq)->fn(a.ref(), {x, randomQuat(rng), g.boundRadius, &g}, p);
    const int m = t.pair(poly, TypeId{0})->fn(a.ref(), {x, Quat::Identity(), r, &ball}, q);
    ASSERT_EQ(n, m) << trial;
    if (n == 0) continue;
    EXPECT_NEAR(p[0].g.overlap, q[0].g.overlap, 1e-7 * r) << trial;  // the edge search's precision
    EXPECT_LT((p[0].g.normal - q[0].g.normal).norm(), 1e-6) << trial;
  }
  int touching = 0, apart = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Body a{t.makeGeometry("polyhedron", randomPolyhedron(rng)), Vec3::Zero(), randomQuat(rng)};
    std::uniform_real_distribution<Real> axis(0.004, 0.015), expo(2, 6);
    const Geometry<3> g =
        t.makeGeometry("superquadric", std::vector<double>{axis(rng), axis(rng), axis(rng), expo(rng), expo(rng)});
    ElementRef<3> b{Vec3::Zero(), randomQuat(rng), g.boundRadius, &g};
    PlacedGauge<3> G = placedGauge(b);
    // Touching at a's corner farthest along u (g's point farthest along -u put there), then
    // moved along u by -2 % to 4 % of the size.
    const Vec3 u = testing::randomUnit(rng);
    Vec3 top = a.corners()[0];
    for (const Vec3& c : a.corners()) {
      if (u.dot(c) > u.dot(top)) top = c;
    }
    const Real size = std::min(a.g.boundRadius, g.boundRadius);
    b.x = top - G.support(Vec3(-u)) - u * (std::uniform_real_distribution<Real>(-0.02, 0.04)(rng) * size);
    G = placedGauge(b);
    const auto overlap = [&](const Vec3& n) {
      Real h = -1e300;
      for (const Vec3& c : a.corners()) h = std::max(h, n.dot(c));
      return h - n.dot(G.support(Vec3(-n)));
    };
    Real least = 1e300;
    Vec3 best = u;
    for (int k = 0; k < 4000; ++k) {
      const Vec3 n = testing::randomUnit(rng);
      const Real d = overlap(n);
      if (d < least) least = d, best = n;
    }
    for (Real h = 0.05; h > 1e-9; h *= 0.7) {
      for (int k = 0; k < 30; ++k) {
        const Vec3 n = (best + h * testing::randomUnit(rng)).normalized();
        const Real d = overlap(n);
        if (d < least) least = d, best = n;
      }
    }
    ContactPoint<3> p[kMaxContactPoints];
    const int n = t.pair(poly, sq)->fn(a.ref(), b, p);
    if (least < -1e-6 * size) {
      EXPECT_EQ(n, 0) << trial << " least " << least;
      ++apart;
      continue;
    }
    if (least < 1e-6 * size) continue;  // grazing
    ASSERT_EQ(n, 1) << trial << " least " << least;
    ++touching;
    // The overlap along the normal (an upper bound of the depth whatever the normal) is the
    // least to 5 %.
    EXPECT_LT(p[0].g.overlap, least * 1.05 + 1e-9 * size) << trial;
    EXPECT_NEAR(overlap(p[0].g.normal), p[0].g.overlap, 1e-12) << trial;
  }
  EXPECT_GT(touching, 20);
  EXPECT_GT(apart, 5);
}

// A ball against a cube: the plane's answer on a face, the distance to the corner at a corner.
TEST(SimPolytope, BallMeetsFacesAndCornersExactly) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const Geometry<3> cube = t.makeGeometry("polyhedron", flatten(boxCorners(Vec3(0.01, 0.01, 0.01))));
  const Geometry<3> ball;
  const TypeId id = *t.id("polyhedron");
  const Quat q(AngleAxis(0.3, Vec3(1, 2, 3).normalized()));
  const ElementRef<3> c{Vec3(0.1, 0.2, 0.3), q, cube.boundRadius, &cube};
  // Over the middle of the +x face, 1 mm in.
  const Real r = 0.005;
  ElementRef<3> b{Vec3(c.x + q * Vec3(0.01 + r - 0.001, 0.002, -0.003)), Quat::Identity(), r, &ball};
  ContactPoint<3> p[kMaxContactPoints];
  ASSERT_EQ(t.pair(id, TypeId{0})->fn(c, b, p), 1);
  EXPECT_NEAR(p[0].g.overlap, 0.001, 1e-15);
  EXPECT_LT((p[0].g.normal - q * Vec3::UnitX()).norm(), 1e-12);
  // Beyond the corner (1, 1, 1) along its diagonal.
  const Vec3 diag = Vec3(1, 1, 1).normalized();
  b.x = c.x + q * (Vec3(0.01, 0.01, 0.01) + diag * (r - 0.0005));
  ASSERT_EQ(t.pair(id, TypeId{0})->fn(c, b, p), 1);
  EXPECT_NEAR(p[0].g.overlap, 0.0005, 1e-15);
  EXPECT_LT((p[0].g.normal - q * diag).norm(), 1e-12);
  b.x = c.x + q * (Vec3(0.01, 0.01, 0.01) + diag * (r + 0.0005));
  EXPECT_EQ(t.pair(id, TypeId{0})->fn(c, b, p), 0);
}

ElementDef cube(const Vec3d& x, double half, const std::string& mat) {
  ElementDef e = grain(x, 0, mat);
  e.shape = "polyhedron";
  e.shapeParams = flatten(boxCorners(Vec3(half, half, half)));
  return e;
}

double axisZ(const ElementState& g, int k) {
  const Quat q(g.orientation[0], g.orientation[1], g.orientation[2], g.orientation[3]);
  return (q.normalized() * Vec3::Unit(k)).z();
}

// A cube dropped turned onto a plane comes to rest on a face, on four points, and then stays
// exactly still: no rocking from corner to corner.
TEST(SimPolytope, BoxComesToRestFaceDownWithoutJitter) {
  for (const std::string wall : {"plane", "box"}) {
    auto s = makeSimulation(3);
    s->addMaterial("glass", material(1e7, 0.5, 0.5));
    if (wall == "plane") {
      s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
    } else {
      WallDef w;
      w.shape = WallShape::Box;
      w.point = {0, 0, -0.05};
      w.halfExtents = {0.2, 0.2, 0.05};
      w.material = "glass";
      s->addWall(w);
    }
    s->addGravity({0, 0, -9.81});
    ElementDef e = cube({0, 0, 0.03}, 0.01, "glass");
    e.orientation = {0.98, 0.1, 0.15, 0.05};
    const ElementId id = s->addElement(e);
    s->runTime(1.0);
    const ElementState a = s->element(id);
    EXPECT_EQ(s->contactCount(), 4u) << wall;
    EXPECT_NEAR(a.position[2], 0.01, 5e-5) << wall;
    double up = 0;
    for (int k = 0; k < 3; ++k) up = std::max(up, std::abs(axisZ(a, k)));
    EXPECT_GT(up, 1 - 1e-9) << wall;
    s->runTime(0.5);
    const ElementState z = s->element(id);
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(z.position[d], a.position[d], 1e-12) << wall;
      EXPECT_LT(std::abs(z.angularVelocity[d]), 1e-9) << wall;
    }
  }
}

// A cube on a slope (gravity tilted by theta): below tan(theta) = mu it stays; above, it slides
// at g (sin theta - mu cos theta), face down, without rolling.
TEST(SimPolytope, CubeOnAnInclineSticksOrSlidesByCoulomb) {
  const double mu = 0.4, g0 = 9.81;
  for (const double theta : {0.25, 0.55}) {
    const testing::InclineRun r = testing::runIncline(cube({0, 0, 0.01}, 0.01, "glass"), theta, mu, 0.2, 0.3);
    if (std::tan(theta) < mu) {
      EXPECT_LT(std::abs(r.moved), 1e-6) << theta;
    } else {
      const double want = g0 * (std::sin(theta) - mu * std::cos(theta));
      EXPECT_NEAR(r.acceleration, want, 0.01 * want) << theta;
    }
    // Face down: tilted only by the corners' unequal overlaps under the friction's moment.
    EXPECT_GT(std::abs(axisZ(r.end, 2)), 1 - 1e-6) << theta;
  }
}

// A block three times as tall as wide on a slope with friction enough not to slide: it stands
// below the tipping angle atan(1/3) = 18.4 degrees and falls over above it.
TEST(SimPolytope, TallBlockTipsAtItsGeometricAngle) {
  const double g0 = 9.81, deg = std::numbers::pi / 180;
  for (const double theta : {17.0 * deg, 19.5 * deg}) {
    auto s = makeSimulation(3);
    s->addMaterial("glass", material(1e8, 0.3, 0.9));
    s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
    s->addGravity({g0 * std::sin(theta), 0, -g0 * std::cos(theta)});
    ElementDef e = grain({0, 0, 0.015}, 0, "glass");
    e.shape = "polyhedron";
    e.shapeParams = flatten(boxCorners(Vec3(0.005, 0.005, 0.015)));
    const ElementId id = s->addElement(e);
    s->runTime(1.5);
    const ElementState z = s->element(id);
    if (std::tan(theta) < 1.0 / 3) {
      EXPECT_GT(std::abs(axisZ(z, 2)), 1 - 1e-6) << theta;  // standing
    } else {
      EXPECT_LT(std::abs(axisZ(z, 2)), 0.01) << theta;  // lying
    }
  }
}

// 2D: a square dropped turned onto a segment wall rests on its side on two points, and a
// polygon pair's contact agrees with the brute-force least overlap.
TEST(SimPolytope, PolygonsRestOnASideAndMeetByTheLeastOverlap) {
  auto s = makeSimulation(2);
  s->addMaterial("glass", material(1e7, 0.5, 0.5));
  s->addWall(plane({0, 0, 0}, {0, 1, 0}, "glass"));
  s->addGravity({0, -9.81, 0});
  ElementDef e = grain({0, 0.03, 0}, 0, "glass");
  e.shape = "polygon";
  e.shapeParams = {-0.01, -0.01, 0.01, -0.01, 0.01, 0.01, -0.01, 0.01};
  e.orientation = {0.4};
  const ElementId id = s->addElement(e);
  s->runTime(2.0);
  EXPECT_EQ(s->contactCount(), 2u);
  const ElementState a = s->element(id);
  EXPECT_LT(a.position[1], 0.01);  // its half side less the overlap, which is under 5 %
  EXPECT_GT(a.position[1], 0.0095);
  EXPECT_LT(std::abs(std::remainder(a.orientation[0], std::numbers::pi / 2)), 1e-6);

  const ShapeTable<2>& t = ShapeTable<2>::get();
  const TypeId id2 = *t.id("polygon");
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> ang(0, 2 * std::numbers::pi), frac(-0.02, 0.03);
  int touching = 0;
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<double> pa, pb;
    for (std::vector<double>* p : {&pa, &pb}) {
      const int n = 3 + static_cast<int>(rng() % 6);
      std::vector<Real> th(n);
      for (Real& x : th) x = ang(rng);
      std::sort(th.begin(), th.end());
      for (Real x : th) p->insert(p->end(), {0.01 * std::cos(x), 0.006 * std::sin(x)});
    }
    Geometry<2> ga, gb;
    try {
      ga = t.makeGeometry("polygon", pa), gb = t.makeGeometry("polygon", pb);
    } catch (const Error&) {
      continue;  // nearly repeated angles
    }
    const auto& A = *static_cast<const Polytope<2>*>(ga.data.get());
    const auto& B = *static_cast<const Polytope<2>*>(gb.data.get());
    const Rotation2 qa(ang(rng)), qb(ang(rng));
    const Vec2 u(std::cos(ang(rng)), std::sin(ang(rng)));
    const auto world = [](const Polytope<2>& P, const Rotation2& q, const Vec2& x) {
      std::vector<Vec2> c;
      for (const Vec2& v : P.vertices) c.push_back(x + rotate(q, v));
      return c;
    };
    const auto over = [&](const std::vector<Vec2>& ca, const std::vector<Vec2>& cb, const Vec2& n) {
      Real hi = -1e300, lo = 1e300;
      for (const Vec2& c : ca) hi = std::max(hi, n.dot(c));
      for (const Vec2& c : cb) lo = std::min(lo, n.dot(c));
      return hi - lo;
    };
    const std::vector<Vec2> ca = world(A, qa, Vec2::Zero());
    const Vec2 xb = u * (over(ca, world(B, qb, Vec2::Zero()), u) - frac(rng) * 0.006);
    const std::vector<Vec2> cb = world(B, qb, xb);
    Real least = 1e300;
    for (int k = 0; k < 20000; ++k) {
      const Real x = 2 * std::numbers::pi * k / 20000;
      least = std::min(least, over(ca, cb, Vec2(std::cos(x), std::sin(x))));
    }
    ContactPoint<2> p[kMaxContactPoints];
    const int n = t.pair(id2, id2)->fn({Vec2::Zero(), qa, ga.boundRadius, &ga}, {xb, qb, gb.boundRadius, &gb}, p);
    if (least < -1e-9) {
      EXPECT_EQ(n, 0) << trial;
      continue;
    }
    if (least < 1e-9) continue;
    ASSERT_GT(n, 0) << trial;
    ASSERT_LE(n, 2) << trial;
    ++touching;
    EXPECT_LT(over(ca, cb, p[0].g.normal), least * 1.03 + 1e-12) << trial;
    for (int k = 0; k < n; ++k) EXPECT_LE(p[k].g.overlap, over(ca, cb, p[0].g.normal) * (1 + 1e-9));
  }
  EXPECT_GT(touching, 30);
}

}  // namespace sim_polytope_test
}  // namespace demlab::sim
