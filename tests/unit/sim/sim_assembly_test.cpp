// The assembly shape type (sim/shapes/assembly.cpp): a rigid body of members of the other
// types. Its mass properties against the closed forms of the solids its members make up, its
// contacts against the members' own rows (a one-member assembly is its member; two assemblies
// of balls are two clumps), its parameters built from names (members given off their centroid
// stay where they were given; overlapping members refused), and its physics against analytic
// answers (a brick of two cubes slides down a slope at g (sin - mu cos), sticks below).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "sim/shape.hpp"
#include "sim/shapes/assembly.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_assembly_test {

using testing::codeOf;
using testing::randomQuat;

// The corners of a box of half extents h about c, as a polyhedron's (3D) or polygon's (2D)
// parameters.
template <int D>
std::vector<double> boxCorners(const VecD<D>& h, const VecD<D>& c = VecD<D>::Zero()) {
  std::vector<double> out;
  for (int k = 0; k < (1 << D); ++k) {
    // 2D corners in order round the square (the polygon needs no order, the hull finds it).
    for (int i = 0; i < D; ++i) out.push_back(c[i] + ((k >> i) & 1 ? h[i] : -h[i]));
  }
  return out;
}

template <int D>
AssemblyMemberDef boxMember(const VecD<D>& h, const VecD<D>& at) {
  AssemblyMemberDef m;
  m.shape = D == 3 ? "polyhedron" : "polygon";
  m.params = boxCorners<D>(h);
  m.position.assign(at.data(), at.data() + D);
  return m;
}

// Expects the principal moments of g (per unit density) to be a box's of full sides s.
void expectBoxInertia(const Geometry<3>& g, const Vec3& s, double tol) {
  const double v = s.prod();
  std::vector<double> want = {v * (s.y() * s.y() + s.z() * s.z()) / 12,
                              v * (s.x() * s.x() + s.z() * s.z()) / 12,
                              v * (s.x() * s.x() + s.y() * s.y()) / 12};
  std::vector<double> got(g.principalMoments.data(), g.principalMoments.data() + 3);
  std::sort(want.begin(), want.end());
  std::sort(got.begin(), got.end());
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], tol * want[2]) << i;
  EXPECT_NEAR(g.volume, v, tol * v);
}

TEST(SimAssembly, MassPropertiesAreTheSolidTheMembersMakeUp) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  // Two cubes of side 2 cm side by side along x: a 4 x 2 x 2 cm brick, its centre between them.
  const Vec3 h(0.01, 0.01, 0.01);
  const auto two = assemblyParams<3>({boxMember<3>(h, Vec3(0.05, 0.2, 0)),
                                      boxMember<3>(h, Vec3(0.07, 0.2, 0))});
  expectBoxInertia(t.makeGeometry("assembly", two), Vec3(0.04, 0.02, 0.02), 1e-12);
  // A brick of 1 x 2 x 3 cm turned a quarter about z is a 2 x 1 x 3 cm one: with a 1 x 1 x 3 cm
  // one beside it along x, a 3 x 1 x 3 cm block.
  AssemblyMemberDef turned = boxMember<3>(Vec3(0.005, 0.01, 0.015), Vec3(0, 0, 0));
  turned.orientation = {std::cos(M_PI / 4), 0, 0, std::sin(M_PI / 4)};
  const auto block = assemblyParams<3>({turned, boxMember<3>(Vec3(0.005, 0.005, 0.015),
                                                             Vec3(0.015, 0, 0))});
  expectBoxInertia(t.makeGeometry("assembly", block), Vec3(0.03, 0.01, 0.03), 1e-12);
  // A sphere on a cube's top face: the sum by the parallel-axis theorem.
  AssemblyMemberDef ball;
  ball.shape = "sphere";
  ball.radius = 0.01;
  ball.position = {0, 0, 0.02};
  const Geometry<3> g = t.makeGeometry("assembly", assemblyParams<3>({boxMember<3>(h, Vec3::Zero()), ball}));
  const double vc = 8e-6, vs = 4.0 / 3 * M_PI * 1e-6, z = vs * 0.02 / (vc + vs);
  const double izz = vc * 8e-4 / 12 + 0.4 * vs * 1e-4;
  const double ixx = izz + vc * z * z + vs * (0.02 - z) * (0.02 - z);
  EXPECT_NEAR(g.volume, vc + vs, 1e-18);
  std::vector<double> got(g.principalMoments.data(), g.principalMoments.data() + 3);
  std::sort(got.begin(), got.end());
  EXPECT_NEAR(got[0], izz, 1e-12 * ixx);
  EXPECT_NEAR(got[1], ixx, 1e-12 * ixx);
  EXPECT_NEAR(got[2], ixx, 1e-12 * ixx);
  // 2D: two squares of side 2 cm make a 4 x 2 cm rectangle.
  const auto rect = assemblyParams<2>({boxMember<2>(Vec2(0.01, 0.01), Vec2(0, 0)),
                                       boxMember<2>(Vec2(0.01, 0.01), Vec2(0.02, 0))});
  const Geometry<2> g2 = ShapeTable<2>::get().makeGeometry("assembly", rect);
  EXPECT_NEAR(g2.volume, 8e-4, 1e-16);
  EXPECT_NEAR(g2.principalMoments[2], 8e-4 * (16e-4 + 4e-4) / 12, 1e-12 * 1e-7);
}

TEST(SimAssembly, MembersGivenOffTheirCentroidStayWhereGiven) {
  // A polygon given about (1 cm, 1 cm) at position (2 cm, 0), turned by 0.3 rad: its corners in
  // the assembly's frame are the given ones turned and moved, whatever point it was given about.
  AssemblyMemberDef off = boxMember<2>(Vec2(0.01, 0.005), Vec2(0.02, 0));
  off.params = boxCorners<2>(Vec2(0.01, 0.005), Vec2(0.01, 0.01));
  off.orientation = {0.3};
  const auto p = assemblyParams<2>({off});
  ASSERT_EQ(p.size(), 13u);                       // type, count, x, y, angle, 8 corners
  EXPECT_NEAR(p[2], 0.02 + std::cos(0.3) * 0.01 - std::sin(0.3) * 0.01, 1e-15);
  EXPECT_NEAR(p[3], std::sin(0.3) * 0.01 + std::cos(0.3) * 0.01, 1e-15);
  for (size_t k = 5; k < p.size(); k += 2) {
    EXPECT_NEAR(std::abs(p[k]), 0.01, 1e-15);
    EXPECT_NEAR(std::abs(p[k + 1]), 0.005, 1e-15);
  }
}

TEST(SimAssembly, BadMembersAreRefusedNamingTheMember) {
  const Vec3 h(0.01, 0.01, 0.01);
  using Members = std::vector<AssemblyMemberDef>;
  const auto refused = [](const Members& m) {
    return codeOf([&] { assemblyParams<3>(m); });
  };
  const std::vector<std::string> shape = {"VALUE", "SHAPE"};
  // Overlapping (by 1 mm), an unknown type, a nested assembly, a ball without a radius, a
  // polyhedron with a radius, a position of two numbers, a zero quaternion, bad corners.
  EXPECT_EQ(refused({boxMember<3>(h, Vec3::Zero()), boxMember<3>(h, Vec3(0.019, 0, 0))}), shape);
  AssemblyMemberDef m = boxMember<3>(h, Vec3::Zero());
  m.shape = "cube";
  EXPECT_EQ(refused({m}), shape);
  m.shape = "assembly";
  EXPECT_EQ(refused({m}), shape);
  m.shape = "sphere";
  m.params.clear();
  EXPECT_EQ(refused({m}), shape);
  m = boxMember<3>(h, Vec3::Zero());
  m.radius = 0.01;
  EXPECT_EQ(refused({m}), shape);
  m = boxMember<3>(h, Vec3::Zero());
  m.position = {0, 0};
  EXPECT_EQ(refused({m}), shape);
  m = boxMember<3>(h, Vec3::Zero());
  m.orientation = {0, 0, 0, 0};
  EXPECT_EQ(refused({m}), shape);
  m = boxMember<3>(h, Vec3::Zero());
  m.params.resize(6);
  EXPECT_EQ(refused({m}), shape);
  // Touching members (a shared face) are accepted.
  EXPECT_NO_THROW(assemblyParams<3>({boxMember<3>(h, Vec3::Zero()), boxMember<3>(h, Vec3(0.02, 0, 0))}));
  // Raw parameter lists: cut short, a type id out of range, a count beyond the list.
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const auto good = assemblyParams<3>({boxMember<3>(h, Vec3::Zero())});
  for (auto edit : std::vector<std::function<void(std::vector<double>&)>>{
           [](std::vector<double>& p) { p.resize(5); },
           [](std::vector<double>& p) { p[0] = 99; },
           [](std::vector<double>& p) { p[0] = 0.5; },
           [](std::vector<double>& p) { p[1] = 1e9; },
           [](std::vector<double>& p) { p[5] = 2; }}) {
    std::vector<double> p = good;
    edit(p);
    EXPECT_EQ(codeOf([&] { t.makeGeometry("assembly", p); }), shape);
  }
}

// Expects the contact points a and b (n each) to be the same set, in any order, to tol.
template <int D>
void expectSamePoints(const ContactPoint<D>* a, int na, const ContactPoint<D>* b, int nb, double tol) {
  ASSERT_EQ(na, nb);
  for (int i = 0; i < na; ++i) {
    double best = 1e300;
    int at = -1;
    for (int j = 0; j < nb; ++j) {
      const double d = (a[i].g.point - b[j].g.point).norm();
      if (d < best) best = d, at = j;
    }
    ASSERT_GE(at, 0);
    EXPECT_LT(best, tol);
    EXPECT_NEAR(a[i].g.overlap, b[at].g.overlap, tol);
    EXPECT_LT((a[i].g.normal - b[at].g.normal).norm(), 1e3 * tol);
    EXPECT_NEAR(a[i].effRadius, b[at].effRadius, tol);
  }
}

TEST(SimAssembly, OneMemberIsItsMemberAndBallsAreAClump) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-0.015, 0.015);
  const Vec3 h(0.01, 0.006, 0.004);
  const Geometry<3> poly = t.makeGeometry("polyhedron", boxCorners<3>(h));
  const Geometry<3> one = t.makeGeometry("assembly", assemblyParams<3>({boxMember<3>(h, Vec3::Zero())}));
  const Geometry<3> ball = t.makeGeometry("sphere", std::vector<double>{});
  // Two balls as an assembly and as a clump.
  AssemblyMemberDef b1, b2;
  b1.shape = b2.shape = "sphere";
  b1.radius = 0.006, b2.radius = 0.004;
  b1.position = {-0.005, 0, 0}, b2.position = {0.008, 0, 0};
  const Geometry<3> balls = t.makeGeometry("assembly", assemblyParams<3>({b1, b2}));
  const std::vector<double> clumpParams = {-0.005, 0, 0, 0.006, 0.008, 0, 0, 0.004};
  const Geometry<3> clump = t.makeGeometry("clump", clumpParams);
  int touching = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Vec3 x(u(rng), u(rng), u(rng));
    const Quat q = randomQuat(rng), qb = randomQuat(rng);
    ContactPoint<3> got[kMaxContactPoints], want[kMaxContactPoints];
    // Against a ball of radius 5 mm at x.
    const ElementRef<3> B{x, qb, 0.005, &ball};
    int n = shapePairPoints<3>({Vec3::Zero(), q, one.boundRadius, &one}, B, got);
    int m = shapePairPoints<3>({Vec3::Zero(), q, poly.boundRadius, &poly}, B, want);
    expectSamePoints(got, n, want, m, 1e-15);
    touching += n > 0;
    // The assembly of balls against the polyhedron, as the clump.
    const ElementRef<3> P{x, qb, poly.boundRadius, &poly};
    n = shapePairPoints<3>({Vec3::Zero(), q, balls.boundRadius, &balls}, P, got);
    m = shapePairPoints<3>({Vec3::Zero(), q, clump.boundRadius, &clump}, P, want);
    expectSamePoints(got, n, want, m, 1e-15);
    // Two assemblies of balls, as two clumps (the second one's normals negated: B first).
    n = shapePairPoints<3>({Vec3::Zero(), q, balls.boundRadius, &balls}, {x, qb, balls.boundRadius, &balls}, got);
    m = shapePairPoints<3>({Vec3::Zero(), q, clump.boundRadius, &clump}, {x, qb, clump.boundRadius, &clump}, want);
    expectSamePoints(got, n, want, m, 1e-15);
    touching += n > 0;
    // Against a plane through x.
    const physics::PlaneShape<3> plane{x, randomQuat(rng) * Vec3::UnitZ()};
    n = shapeWallPoints<3>({Vec3::Zero(), q, one.boundRadius, &one}, WallShape::Plane, &plane, got);
    m = shapeWallPoints<3>({Vec3::Zero(), q, poly.boundRadius, &poly}, WallShape::Plane, &plane, want);
    expectSamePoints(got, n, want, m, 1e-15);
  }
  EXPECT_GT(touching, 200);
}

TEST(SimAssembly, BrickOfTwoCubesSlidesAtTheCoulombRateAndSticksBelow) {
  // Two cubes of 2 cm side by side along the slope: 8 corners on the floor, the load shared.
  ElementDef e;
  e.shape = "assembly";
  e.shapeParams = assemblyParams<3>({boxMember<3>(Vec3(0.01, 0.01, 0.01), Vec3(0, 0, 0)),
                                     boxMember<3>(Vec3(0.01, 0.01, 0.01), Vec3(0.02, 0, 0))});
  e.position = {0, 0, 0.0101};
  const double mu = 0.4, g0 = 9.81;
  const double slides = std::atan(mu) + 0.15, sticks = std::atan(mu) - 0.1;
  const testing::InclineRun fast = testing::runIncline(e, slides, mu, 0.2, 0.3, 4);
  const double want = g0 * (std::sin(slides) - mu * std::cos(slides));
  EXPECT_NEAR(fast.acceleration, want, 0.02 * want);
  const testing::InclineRun still = testing::runIncline(e, sticks, mu, 0.2, 0.3, 4);
  EXPECT_LT(std::abs(still.moved), 1e-5);
  // Face down throughout: its z axis stays up.
  for (const auto* r : {&fast, &still}) {
    const Quat q(r->end.orientation[0], r->end.orientation[1], r->end.orientation[2],
                 r->end.orientation[3]);
    EXPECT_GT((q * Vec3::UnitZ()).z(), 1 - 1e-6);
  }
}

}  // namespace sim_assembly_test
}  // namespace demlab::sim
