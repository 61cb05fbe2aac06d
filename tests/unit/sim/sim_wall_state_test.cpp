// WallState's geometry (centre, normal, axes, half extents, radius, half length): as defined,
// and after a prescribed rotation, against the rotation applied by hand.
#include <cmath>

#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_wall_state_test {

using testing::material;

void expectNear(const Vec3d& a, const Vec3d& b, double tol = 1e-12) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], tol) << "component " << k;
}

// Returns v turned by angle about z.
Vec3d turnZ(const Vec3d& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]};
}

TEST(SimWallState, GeometryIn2DFollowsTheRotation) {
  auto s = makeSimulation(2);
  s->addMaterial("steel", material(2e11, 0.5, 0.3, 7800));
  const double w = 2.0;  // rad/s
  WallDef seg;
  seg.shape = WallShape::Finite;
  seg.point = {0.1, 0.2, 0};
  seg.normal = {0, 1, 0};
  seg.halfExtents = {0.05, 0, 0};
  seg.material = "steel";
  seg.motion = WallMotion{};
  seg.motion->angularVelocity = {0, 0, w};
  const WallId fin = s->addWall(seg);
  WallDef box;
  box.shape = WallShape::Box;
  box.point = {-0.3, 0, 0};
  box.halfExtents = {0.02, 0.01, 0};
  box.rotation = {0, 0, 0.5};
  box.material = "steel";
  const WallId bx = s->addWall(box);
  WallDef drum;
  drum.shape = WallShape::Drum;
  drum.point = {0, 0, 0};
  drum.radius = 0.4;
  drum.material = "steel";
  const WallId dr = s->addWall(drum);
  WallDef pl;
  pl.shape = WallShape::Plane;
  pl.point = {0, -1, 0};
  pl.normal = {0, 1, 0};
  pl.material = "steel";
  const WallId pn = s->addWall(pl);
  s->addElement(testing::grain({0, 0, 0}, 0.01, "steel"));
  s->setTimeStep(1e-3);

  WallState f = s->wall(fin);
  expectNear(f.centre, {0.1, 0.2, 0});
  expectNear(f.normal, {0, 1, 0});
  EXPECT_NEAR(std::abs(f.axes[0][0]), 1, 1e-12);  // the segment lies along x
  EXPECT_EQ(f.halfExtents[0], 0.05);
  const Vec3d axis0 = f.axes[0];
  s->runSteps(250);  // t = 0.25 s: turned by 0.5 rad about its centre
  f = s->wall(fin);
  const double a = w * s->time();
  expectNear(f.centre, {0.1, 0.2, 0});
  expectNear(f.normal, turnZ({0, 1, 0}, a));
  expectNear(f.axes[0], turnZ(axis0, a));

  const WallState b = s->wall(bx);
  expectNear(b.centre, {-0.3, 0, 0});
  expectNear(b.axes[0], turnZ({1, 0, 0}, 0.5));
  expectNear(b.axes[1], turnZ({0, 1, 0}, 0.5));
  expectNear(b.halfExtents, {0.02, 0.01, 0});
  const WallState d = s->wall(dr);
  expectNear(d.centre, {0, 0, 0});
  EXPECT_EQ(d.radius, 0.4);
  const WallState p = s->wall(pn);
  expectNear(p.centre, {0, -1, 0});
  expectNear(p.normal, {0, 1, 0});
}

TEST(SimWallState, GeometryIn3D) {
  auto s = makeSimulation(3);
  s->addMaterial("steel", material(2e11, 0.5, 0.3, 7800));
  WallDef rect;
  rect.shape = WallShape::Finite;
  rect.point = {0, 0, 1};
  rect.normal = {0, 0, 1};
  rect.axis = {1, 0, 0};
  rect.halfExtents = {0.3, 0.2, 0};
  rect.material = "steel";
  const WallState r = s->wall(s->addWall(rect));
  expectNear(r.centre, {0, 0, 1});
  expectNear(r.normal, {0, 0, 1});
  expectNear(r.axes[0], {1, 0, 0});
  expectNear(r.axes[1], {0, 1, 0});  // normal x axis
  EXPECT_EQ(r.halfExtents[0], 0.3);
  EXPECT_EQ(r.halfExtents[1], 0.2);
  WallDef drum;
  drum.shape = WallShape::Drum;
  drum.point = {1, 2, 3};
  drum.axis = {0, 1, 0};
  drum.radius = 0.5;
  drum.halfLength = 0.25;
  drum.material = "steel";
  const WallState d = s->wall(s->addWall(drum));
  expectNear(d.centre, {1, 2, 3});
  expectNear(d.axes[0], {0, 1, 0});
  EXPECT_EQ(d.radius, 0.5);
  EXPECT_EQ(d.halfLength, 0.25);
}

}  // namespace sim_wall_state_test
}  // namespace demlab::sim
