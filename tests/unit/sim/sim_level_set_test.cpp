// The level-set shape type: grids built from a closed mesh and from an implicit function against
// the exact signed distance, mass properties against closed forms, contacts against the exact
// shapes (a box's corners under a plane, the polyhedron routine for two boxes, two spheres'
// centre distance) on random poses, and a cube on an incline against Coulomb's law.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "sim/shape.hpp"
#include "sim/shapes/level_set.hpp"
#include "sim/shapes/polytope.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_level_set_test {

using testing::grain;
using testing::material;
using testing::plane;
using testing::randomQuat;

// The 12 triangles of a box of half extents e about the origin.
std::vector<std::array<double, 9>> boxTriangles(const Vec3& e) {
  const auto corner = [&](int k) {
    return Vec3(k & 1 ? e.x() : -e.x(), k & 2 ? e.y() : -e.y(), k & 4 ? e.z() : -e.z());
  };
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<std::array<double, 9>> out;
  for (const auto& q : quads) {
    for (const auto& t : {std::array<int, 3>{q[0], q[1], q[2]}, std::array<int, 3>{q[0], q[2], q[3]}}) {
      std::array<double, 9> tri{};
      for (int k = 0; k < 3; ++k) {
        for (int d = 0; d < 3; ++d) tri[3 * k + d] = corner(t[k])[d];
      }
      out.push_back(tri);
    }
  }
  return out;
}

// The exact signed distance to the box of half extents e.
Real boxDistance(const Vec3& e, const Vec3& p) {
  const Vec3 q = p.cwiseAbs() - e;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

struct Body {
  Geometry<3> g;
  Vec3 x = Vec3::Zero();
  Quat q = Quat::Identity();
  ElementRef<3> ref() const { return {x, q, g.boundRadius, &g}; }
};

const LevelSet<3>& levelSetOf(const Geometry<3>& g) {
  return *static_cast<const LevelSet<3>*>(g.data.get());
}

TEST(SimLevelSet, BoxFromAMeshHasTheBoxsDistanceAndMassProperties) {
  const Vec3 e(0.01, 0.015, 0.02);
  const Real h = 0.001;
  const std::vector<double> p = levelSetFromMesh(boxTriangles(e), h);
  const Geometry<3> g = ShapeTable<3>::get().makeGeometry("levelset", p);
  const LevelSet<3>& ls = levelSetOf(g);
  // The body was already about its centroid: the field is the box's own.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<Real> u(-1, 1);
  Real worst = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 x = (e + Vec3::Constant(2 * h)).cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
    const Real exact = boxDistance(e, x);
    if (std::abs(exact) > 2 * h) continue;
    Real v;
    Vec3 grad;
    ASSERT_TRUE(ls.sample(x, v, grad));
    worst = std::max(worst, std::abs(v - exact));
  }
  // Exact where the distance is linear over a cell (near the faces); off by a fraction of a
  // cell only in the cells that hold an edge or a corner.
  EXPECT_LT(worst, 0.3 * h);
  const Real volume = 8 * e.prod();
  EXPECT_NEAR(g.volume, volume, 0.01 * volume);
  const Vec3 wantUnsorted = volume / 3 * Vec3(e.y() * e.y() + e.z() * e.z(), e.x() * e.x() + e.z() * e.z(),
                                      e.x() * e.x() + e.y() * e.y());
  Vec3 got = g.principalMoments, want = wantUnsorted;
  std::sort(got.data(), got.data() + 3);
  std::sort(want.data(), want.data() + 3);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(got[d], want[d], 0.02 * want[d]) << d;
  // An open mesh is refused.
  std::vector<std::array<double, 9>> open = boxTriangles(e);
  open.pop_back();
  EXPECT_EQ(testing::codeOf([&] { levelSetFromMesh(open, h); }),
            (std::vector<std::string>{"VALUE", "MESH"}));
}

// The grid of spacing h over the cube of side 2.6 r about the origin, and f at its nodes.
constexpr std::array<int, 3> kSphereGrid{27, 27, 27};
template <class F>
std::vector<double> sampleSphereGrid(Real h, F f) {
  std::vector<double> values;
  for (int k = 0; k < kSphereGrid[2]; ++k)
    for (int j = 0; j < kSphereGrid[1]; ++j)
      for (int i = 0; i < kSphereGrid[0]; ++i) values.push_back(f(Vec3(Vec3::Constant(-13 * h) + h * Vec3(i, j, k))));
  return values;
}

TEST(SimLevelSet, AnImplicitFunctionIsRedistancedToItsZeroSet) {
  // |x|^2 - r^2: negative inside the sphere, but not a distance.
  const Real r = 0.01, h = 0.001;
  const std::array<int, 3> n = kSphereGrid;
  const Vec3 origin = Vec3::Constant(-13 * h);
  const std::vector<double> values = sampleSphereGrid(h, [&](const Vec3& x) { return x.squaredNorm() - r * r; });
  const std::vector<double> p = levelSetFromValues<3>(h, n, origin, values);
  const Geometry<3> g = ShapeTable<3>::get().makeGeometry("levelset", p);
  const LevelSet<3>& ls = levelSetOf(g);
  Real worst = 0;
  std::mt19937_64 rng(5);
  for (int k = 0; k < 2000; ++k) {
    const Vec3 x = testing::randomUnit(rng) * (r + std::uniform_real_distribution<Real>(-2 * h, 2 * h)(rng));
    Real v;
    Vec3 grad;
    ASSERT_TRUE(ls.sample(x, v, grad));
    worst = std::max(worst, std::abs(v - (x.norm() - r)));
  }
  EXPECT_LT(worst, 0.08 * h);
  const Real volume = 4.0 / 3 * std::numbers::pi * r * r * r;
  EXPECT_NEAR(g.volume, volume, 0.01 * volume);
  EXPECT_NEAR(g.principalMoments.minCoeff(), 0.4 * volume * r * r, 0.02 * 0.4 * volume * r * r);
  // Values that do not close a body inside the grid are refused.
  std::vector<double> leaky = values;
  leaky[0] = -1;
  EXPECT_EQ(testing::codeOf([&] { levelSetFromValues<3>(h, n, origin, leaky); }),
            (std::vector<std::string>{"VALUE", "SHAPE"}));
}

// A box level set against a plane, on random poses: the deepest contact is the box's deepest
// corner's depth (up to the nodes' distance from the corners), and none when the exact box
// is clear of the plane by a node spacing.
TEST(SimLevelSet, ContactsAgreeWithTheExactShapes) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const Vec3 e(0.01, 0.006, 0.008);
  const Real h = 0.001;
  Body a, b;
  a.g = t.makeGeometry("levelset", levelSetFromMesh(boxTriangles(e), h));
  b.g = a.g;
  std::vector<double> corners;
  for (int k = 0; k < 8; ++k) {
    for (int d = 0; d < 3; ++d) corners.push_back(k >> d & 1 ? e[d] : -e[d]);
  }
  Body pa, pb;
  pa.g = t.makeGeometry("polyhedron", corners);
  pb.g = pa.g;
  const physics::PlaneShape<3> floor{Vec3::Zero(), Vec3::UnitZ()};
  const auto* planeRow = t.wall(t.id("levelset").value(), WallShape::Plane);
  ContactPoint<3> pts[kMaxContactPoints];
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<Real> u(-1, 1);
  int touching = 0, pairs = 0;
  for (int trial = 0; trial < 300; ++trial) {
    a.q = randomQuat(rng);
    a.x = Vec3(0, 0, 0.005 + 0.01 * u(rng));
    Real lowest = 1e300;
    for (int k = 0; k < 8; ++k) {
      lowest = std::min(lowest, (a.x + a.q * Vec3(corners[3 * k], corners[3 * k + 1], corners[3 * k + 2])).z());
    }
    const int m = planeRow->fn(a.ref(), &floor, pts);
    Real deepest = 0;
    for (int k = 0; k < m; ++k) {
      deepest = std::max(deepest, pts[k].g.overlap);
      EXPECT_LT((pts[k].g.normal + Vec3::UnitZ()).norm(), 1e-12);
    }
    if (lowest > h) {
      EXPECT_EQ(m, 0) << trial;
    }
    if (lowest < -h) {
      ++touching;
      EXPECT_GT(m, 0) << trial;
      EXPECT_NEAR(deepest, -lowest, 1.5 * h) << trial;
    }
    // Two boxes: the level sets' deepest point against the polyhedra's deepest manifold point.
    b.q = randomQuat(rng);
    b.x = a.x + Vec3(u(rng), u(rng), u(rng)).normalized() * (0.018 + 0.006 * u(rng));
    pa.x = a.x, pa.q = a.q, pb.x = b.x, pb.q = b.q;
    ContactPoint<3> ref[kMaxContactPoints];
    const int nr = t.pair(pa.g.shape, pb.g.shape)->fn(pa.ref(), pb.ref(), ref);
    Real want = 0;
    for (int k = 0; k < nr; ++k) want = std::max(want, ref[k].g.overlap);
    const int nl = t.pair(a.g.shape, b.g.shape)->fn(a.ref(), b.ref(), pts);
    Real got = 0;
    Vec3 sum = Vec3::Zero();
    for (int k = 0; k < nl; ++k) got = std::max(got, pts[k].g.overlap), sum += pts[k].g.normal;
    // Shallow overlaps (under a quarter of the thinnest side): deeper, the field's depth (to
    // the other body's nearest face) and the separating axis's part ways.
    if (want > 1.5 * h && want < 0.003) {
      ++pairs;
      EXPECT_GT(nl, 0) << trial;
      EXPECT_NEAR(got, want, 1.5 * h) << trial;
      // The normals point from a to b.
      EXPECT_GT(sum.dot(b.x - a.x), 0) << trial;
    }
    if (nr == 0) {
      EXPECT_LT(got, 2 * h) << trial;
    }
  }
  EXPECT_GT(touching, 60);
  EXPECT_GT(pairs, 30);
}

// A ball against a sphere's level set: the overlap of the two spheres, whether the ball's centre
// lies in the grid or beyond it.
TEST(SimLevelSet, ABallMeetsASphereAsTheSphereItIs) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const Real r = 0.01, h = 0.001;
  Body s;
  s.g = t.makeGeometry("levelset", levelSetFromValues<3>(h, kSphereGrid, Vec3::Constant(-13 * h),
                                                         sampleSphereGrid(h, [&](const Vec3& x) { return x.norm() - r; })));
  Geometry<3> ballGeom = t.makeGeometry("sphere", {});
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 200; ++trial) {
    s.q = randomQuat(rng);
    const Real rb = trial % 2 ? 0.002 : 0.02;
    const Real gap = std::uniform_real_distribution<Real>(-0.5 * rb, 0.1 * rb)(rng);
    const Vec3 dir = testing::randomUnit(rng);
    const ElementRef<3> ball{s.x + dir * (r + rb + gap), Quat::Identity(), rb, &ballGeom};
    ContactPoint<3> p[kMaxContactPoints];
    const int m = t.pair(s.g.shape, ballGeom.shape)->fn(s.ref(), ball, p);
    if (gap > 0.05 * h) {
      EXPECT_EQ(m, 0) << trial;
    } else if (gap < -0.05 * h) {
      ASSERT_EQ(m, 1) << trial;
      EXPECT_NEAR(p[0].g.overlap, -gap, 0.1 * h) << trial;
      // The multilinear field's gradient turns by up to about h / r across a cell.
      EXPECT_LT((p[0].g.normal - dir).norm(), 0.08) << trial;
    }
  }
}

// A superquadric against a level set, through shapePairPoints (the row is registered level set
// first): a sphere as a superquadric meets a sphere's level set as the two spheres overlap; a
// blocky superquadric meets an ellipsoid's level set as the superquadric row meets the
// ellipsoid itself, for shallow overlaps; apart, no point.
TEST(SimLevelSet, SuperquadricsMeetLevelSetsAsTheShapesTheyAre) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const Real r = 0.01, h = 0.001;
  Body s, e;
  s.g = t.makeGeometry("levelset", levelSetFromValues<3>(h, kSphereGrid, Vec3::Constant(-13 * h),
                                                         sampleSphereGrid(h, [&](const Vec3& x) { return x.norm() - r; })));
  // The ellipsoid 1.2 : 1 : 0.8 cm, sampled as its gauge less one (re-distanced).
  const Vec3 axes(0.012, 0.01, 0.008);
  e.g = t.makeGeometry("levelset", levelSetFromValues<3>(h, kSphereGrid, Vec3::Constant(-13 * h),
                                                         sampleSphereGrid(h, [&](const Vec3& x) { return x.cwiseQuotient(axes).norm() - 1; })));
  Body sq, ell, blocky;
  sq.g = t.makeGeometry("superquadric", std::vector<double>{0.004, 0.004, 0.004, 2, 2});
  ell.g = t.makeGeometry("superquadric", std::vector<double>{axes.x(), axes.y(), axes.z(), 2, 2});
  blocky.g = t.makeGeometry("superquadric", std::vector<double>{0.006, 0.004, 0.005, 6, 4});
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<Real> u(-1, 1);
  ContactPoint<3> got[kMaxContactPoints], want[kMaxContactPoints];
  const auto deepest = [](const ContactPoint<3>* p, int n) {
    int at = -1;
    for (int k = 0; k < n; ++k) {
      if (at < 0 || p[k].g.overlap > p[at].g.overlap) at = k;
    }
    return at;
  };
  int spheres = 0, shapes = 0;
  for (int trial = 0; trial < 200; ++trial) {
    s.q = randomQuat(rng);
    sq.q = randomQuat(rng);
    const Real gap = 0.002 * u(rng);
    const Vec3 dir = testing::randomUnit(rng);
    sq.x = s.x + dir * (r + 0.004 + gap);
    const int m = shapePairPoints<3>(sq.ref(), s.ref(), got);
    if (gap > 0.15 * h) {
      EXPECT_EQ(m, 0) << trial;
    }
    if (gap < -0.15 * h) {
      ++spheres;
      const int k = deepest(got, m);
      ASSERT_GE(k, 0) << trial;
      EXPECT_NEAR(got[k].g.overlap, -gap, 0.1 * h) << trial;
      // From the superquadric to the level set; the deepest node lies up to half a cell's
      // diagonal off the centre line (0.7 h), where the 4 mm sphere's normal is turned by up to
      // 0.7 h / r = 0.18.
      EXPECT_LT((got[k].g.normal + dir).norm(), 0.25) << trial;
    }
    // The blocky superquadric against the ellipsoid's level set and against the ellipsoid.
    e.q = ell.q = randomQuat(rng);
    blocky.q = randomQuat(rng);
    blocky.x = e.x + testing::randomUnit(rng) * (0.014 + 0.004 * u(rng));
    ell.x = e.x;
    const int nr = shapePairPoints<3>(blocky.ref(), ell.ref(), want);
    const int nl = shapePairPoints<3>(blocky.ref(), e.ref(), got);
    const Real w = nr > 0 ? want[deepest(want, nr)].g.overlap : 0;
    const Real g = nl > 0 ? got[deepest(got, nl)].g.overlap : 0;
    if (w > 1.5 * h && w < 0.003) {
      ++shapes;
      EXPECT_NEAR(g, w, 1.5 * h) << trial;
      EXPECT_GT(got[deepest(got, nl)].g.normal.dot(e.x - blocky.x), 0) << trial;
    }
    if (nr == 0) {
      EXPECT_LT(g, 1.5 * h) << trial;
    }
  }
  EXPECT_GT(spheres, 50);
  EXPECT_GT(shapes, 20);
}

ElementDef levelSetCube(const Vec3d& x, double half, double h, const std::string& mat) {
  ElementDef e = grain(x, 0, mat);
  e.shape = "levelset";
  e.shapeParams = levelSetFromMesh(boxTriangles(Vec3::Constant(half)), h);
  return e;
}

// A cube on a slope (gravity tilted by theta): below tan(theta) = mu it stays; above, it slides
// at g (sin theta - mu cos theta) without rolling. Its face holds 8 x 8 nodes, each a spring,
// so the step is an eighth of the automatic one (the contact is about 64 times as stiff).
TEST(SimLevelSet, CubeOnAnInclineSticksOrSlidesByCoulomb) {
  const double mu = 0.4, g0 = 9.81;
  for (const double theta : {0.25, 0.55}) {
    const testing::InclineRun r =
        testing::runIncline(levelSetCube({0, 0, 0.0101}, 0.01, 0.0025, "glass"), theta, mu, 0.1, 0.2, 8);
    if (std::tan(theta) < mu) {
      EXPECT_LT(std::abs(r.moved), 1e-6) << theta;
    } else {
      const double want = g0 * (std::sin(theta) - mu * std::cos(theta));
      EXPECT_NEAR(r.acceleration, want, 0.02 * want) << theta;
    }
    const ElementState& z = r.end;
    const Quat q(z.orientation[0], z.orientation[1], z.orientation[2], z.orientation[3]);
    EXPECT_GT(std::abs((q.normalized() * Vec3::UnitZ()).z()), 1 - 1e-4) << theta;
  }
}

}  // namespace sim_level_set_test
}  // namespace demlab::sim
