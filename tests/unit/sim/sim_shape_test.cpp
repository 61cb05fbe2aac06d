// Shape types registered from the test code alone (no edit to src/): a "toyball" that is a
// sphere behind the shape table's generic path, and a "toybox" cuboid with vertex contacts on
// planes. The toyball must reproduce the built-in sphere's physics through the other path; the
// toybox must rest face down on a plane without jitter.
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/thread_pool.hpp"
#include "physics/narrow_phase.hpp"
#include "sim/shape.hpp"
#include "sim/shapes/level_set.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_shape_test {

using testing::codeOf;
using testing::grain;
using testing::material;
using testing::plane;

class ToyBall final : public ShapeType<3> {
 public:
  std::string_view name() const override { return "toyball"; }
  std::string_view parameters() const override { return "r: radius (m)"; }
  void check(std::span<const double> p) const override {
    if (p.size() != 1 || !(p[0] > 0)) throw Error("bad toyball", {"VALUE", "SHAPE"});
  }
  Real boundingRadius(std::span<const double> p) const override { return p[0]; }
  MassProperties<3> massProperties(std::span<const double> p) const override {
    MassProperties<3> m;
    m.volume = 4.0 / 3.0 * std::numbers::pi * p[0] * p[0] * p[0];
    m.inertia = Mat3::Identity() * 0.4 * m.volume * p[0] * p[0];
    return m;
  }
};

// A cuboid of half extents p[0..2], or, with a fourth parameter t != 0, the same cuboid described
// in a body frame turned by t about (1, 1, 1): its inertia tensor there is not diagonal.
class ToyBox final : public ShapeType<3> {
 public:
  explicit ToyBox(std::string name) : name_(std::move(name)) {}
  std::string_view name() const override { return name_; }
  std::string_view parameters() const override { return "a b c ?t?: half extents, tilt"; }
  void check(std::span<const double> p) const override {
    if ((p.size() != 3 && p.size() != 4) || !(p[0] > 0 && p[1] > 0 && p[2] > 0)) {
      throw Error("bad toybox", {"VALUE", "SHAPE"});
    }
  }
  Real boundingRadius(std::span<const double> p) const override {
    return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
  }
  MassProperties<3> massProperties(std::span<const double> p) const override {
    MassProperties<3> m;
    const Real a2 = p[0] * p[0], b2 = p[1] * p[1], c2 = p[2] * p[2];
    m.volume = 8 * p[0] * p[1] * p[2];
    const Mat3 diag = Vec3(b2 + c2, a2 + c2, a2 + b2).asDiagonal();
    const Mat3 r = tilt(p);
    m.inertia = r * (m.volume / 3 * diag) * r.transpose();
    return m;
  }
  static Mat3 tilt(std::span<const double> p) {
    return p.size() == 4 ? AngleAxis(p[3], Vec3(1, 1, 1).normalized()).toRotationMatrix()
                         : Mat3::Identity();
  }

 private:
  std::string name_;
};

// Toyball pairs: the sphere geometry of physics' narrow phase.
int toyballPair(const ElementRef<3>& a, const ElementRef<3>& b, ContactPoint<3>* out) {
  const Real ra = a.g->params.empty() ? a.r : a.g->params[0];
  const Real rb = b.g->params.empty() ? b.r : b.g->params[0];
  const auto g = physics::intersect<3>(physics::SphereShape<3>{a.x, ra},
                                       physics::SphereShape<3>{b.x, rb});
  if (!g) return 0;
  out[0] = {*g, ra * rb / (ra + rb)};
  return 1;
}

int toyballPlane(const ElementRef<3>& a, const void* wall, ContactPoint<3>* out) {
  const auto g = physics::intersect<3>(physics::SphereShape<3>{a.x, a.g->params[0]},
                                       *static_cast<const physics::PlaneShape<3>*>(wall));
  if (!g) return 0;
  out[0] = {*g, a.g->params[0]};
  return 1;
}

// A toybox's corners below a plane, each a contact point (normal from the box into the plane),
// the point midway through the overlap, the smallest half extent as the curvature radius.
int toyboxPlane(const ElementRef<3>& a, const void* wall, ContactPoint<3>* out) {
  const auto& pl = *static_cast<const physics::PlaneShape<3>*>(wall);
  const std::vector<double>& p = a.g->params;
  const Mat3 body = a.q.toRotationMatrix() * ToyBox::tilt(p);
  int n = 0;
  for (int c = 0; c < 8 && n < kMaxContactPoints; ++c) {
    const Vec3 local((c & 1 ? 1 : -1) * p[0], (c & 2 ? 1 : -1) * p[1], (c & 4 ? 1 : -1) * p[2]);
    const Vec3 v = a.x + body * local;
    const Real d = (v - pl.point).dot(pl.normal);
    if (d >= 0) continue;
    out[n].g.normal = -pl.normal;
    out[n].g.overlap = -d;
    out[n].g.point = v - 0.5 * d * pl.normal;
    out[n].effRadius = std::min({p[0], p[1], p[2]});
    out[n].feature = static_cast<uint32_t>(c);
    ++n;
  }
  return n;
}

// A toybox's corners inside a ball b (a toy's routine: edges and faces are left out).
int toyboxBall(const ElementRef<3>& a, const ElementRef<3>& b, ContactPoint<3>* out) {
  const std::vector<double>& p = a.g->params;
  const Real rb = b.g->params.empty() ? b.r : b.g->params[0];
  const Mat3 body = a.q.toRotationMatrix() * ToyBox::tilt(p);
  int n = 0;
  for (int c = 0; c < 8 && n < kMaxContactPoints; ++c) {
    const Vec3 local((c & 1 ? 1 : -1) * p[0], (c & 2 ? 1 : -1) * p[1], (c & 4 ? 1 : -1) * p[2]);
    const Vec3 v = a.x + body * local, d = b.x - v;
    const Real dist = d.norm();
    if (!(dist < rb) || dist == 0) continue;
    out[n].g.normal = d / dist;
    out[n].g.overlap = rb - dist;
    out[n].g.point = v + 0.5 * out[n].g.overlap * out[n].g.normal;
    out[n].effRadius = rb;
    out[n].feature = static_cast<uint32_t>(c);
    ++n;
  }
  return n;
}

// Registers the toy types once for the whole test program.
void registerToys() {
  static const bool once = [] {
    ShapeTable<3>& t = ShapeTable<3>::get();
    t.add(std::make_unique<ToyBall>());
    t.add(std::make_unique<ToyBox>("toybox"));
    t.add(std::make_unique<ToyBox>("toybox-lonely"));
    t.addPair("toyball", "toyball", {toyballPair, false});
    t.addPair("sphere", "toyball", {toyballPair, false});
    t.addWall("toyball", WallShape::Plane, {toyballPlane, false});
    t.addWall("toybox", WallShape::Plane, {toyboxPlane, false});
    t.addPair("toybox", "toyball", {toyboxBall, false});
    return true;
  }();
  (void)once;
}

ElementDef toy(const Vec3d& x, double r, const Vec3d& v = {}) {
  ElementDef g = grain(x, 0, "glass", v);
  g.shape = "toyball";
  g.shapeParams = {r};
  return g;
}

class SimShape : public ::testing::Test {
 protected:
  void SetUp() override { registerToys(); }
};

// Returns the x velocities of two elements after a head-on impact of a on b.
std::pair<double, double> impact(const ElementDef& a, const ElementDef& b, double e) {
  auto s = makeSimulation(3);
  s->setOption("touch", "on", false);  // (it covers balls' contacts, not shapes')
  s->addMaterial("glass", material(1e7, e, 0));
  const ElementId ia = s->addElement(a), ib = s->addElement(b);
  s->setTimeStep(2e-5);  // one step for every variant (a shape's automatic step is smaller)
  RunOptions o;
  o.steps = 4000;
  s->run(o);
  return {s->element(ia).velocity[0], s->element(ib).velocity[0]};
}

TEST_F(SimShape, ToyballReproducesTheSpherePath) {
  for (double e : {0.3, 0.9}) {
    const auto ref = impact(grain({0, 0, 0}, 0.01, "glass", {0.5, 0, 0}),
                            grain({0.025, 0, 0}, 0.012, "glass"), e);
    const auto viaTable = impact(toy({0, 0, 0}, 0.01, {0.5, 0, 0}), toy({0.025, 0, 0}, 0.012), e);
    const auto mixed = impact(grain({0, 0, 0}, 0.01, "glass", {0.5, 0, 0}),
                              toy({0.025, 0, 0}, 0.012), e);
    ASSERT_GT(ref.second, 0.1);  // they met
    EXPECT_NEAR(viaTable.first, ref.first, 1e-9);
    EXPECT_NEAR(viaTable.second, ref.second, 1e-9);
    EXPECT_NEAR(mixed.first, ref.first, 1e-9);
    EXPECT_NEAR(mixed.second, ref.second, 1e-9);
  }
}

TEST_F(SimShape, GeometryIsSharedAndMassFollowsTheShape) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0));
  const ElementId a = s->addElement(toy({0, 0, 0}, 0.01));
  s->addElement(toy({1, 0, 0}, 0.01));
  const ElementState g = s->element(a);
  EXPECT_EQ(g.shape, "toyball");
  EXPECT_DOUBLE_EQ(g.radius, 0.01);
  EXPECT_NEAR(g.mass, 2500 * 4.0 / 3.0 * std::numbers::pi * 1e-6, 1e-15);
  EXPECT_NEAR(g.inertia, 0.4 * g.mass * 1e-4, 1e-18);
  // Both share one Geometry beside the ball's.
  const auto& m = dynamic_cast<const SimulationManager<3>&>(*s);
  EXPECT_EQ(m.scene().geometries.size(), 2u);
  EXPECT_EQ(m.scene().elements.a.geometry, (std::vector<uint32_t>{1, 1}));
}

TEST_F(SimShape, BadShapesChangeNothing) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0));
  s->addElement(toy({0, 0, 0}, 0.01));
  const uint64_t digest = s->stateDigest();
  using Code = std::vector<std::string>;
  ElementDef g = toy({0.1, 0, 0}, -1);
  EXPECT_EQ(codeOf([&] { s->addElement(g); }), (Code{"VALUE", "SHAPE"}));
  g = toy({0.1, 0, 0}, 0.01);
  g.radius = 0.01;  // a toyball's size is in its parameters
  EXPECT_EQ(codeOf([&] { s->addElement(g); }), (Code{"VALUE", "RADIUS"}));
  g.radius = 0;
  g.shape = "nosuch";
  EXPECT_EQ(codeOf([&] { s->addElement(g); }), (Code{"VALUE", "SHAPE"}));
  EXPECT_EQ(s->stateDigest(), digest);
  // No routine for toybox-lonely against anything: the run refuses before a step.
  ElementDef b = grain({0.5, 0, 0}, 0, "glass");
  b.shape = "toybox-lonely";
  b.shapeParams = {0.01, 0.01, 0.01};
  s->addElement(b);
  const uint64_t before = s->stateDigest();
  RunOptions o;
  o.steps = 3;
  EXPECT_EQ(codeOf([&] { s->run(o); }), (Code{"LOOKUP", "INTERACTION"}));
  EXPECT_EQ(s->stateDigest(), before);
}

TEST_F(SimShape, ToyballRestsOnAPlaneAsASphereDoes) {
  double height[2];
  for (int k = 0; k < 2; ++k) {
    auto s = makeSimulation(3);
    s->addMaterial("glass", material(1e7, 0.3, 0.5));
    s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
    s->addGravity({0, 0, -9.81});
    const ElementId id = s->addElement(k == 0 ? grain({0, 0, 0.0101}, 0.01, "glass")
                                          : toy({0, 0, 0.0101}, 0.01));
    s->setTimeStep(2e-5);
    RunOptions o;
    o.steps = 20000;
    s->run(o);
    height[k] = s->element(id).position[2];
    EXPECT_LT(std::abs(s->element(id).velocity[2]), 1e-6);
  }
  EXPECT_LT(height[0], 0.01);
  EXPECT_NEAR(height[1], height[0], 1e-12);
}

TEST_F(SimShape, BoxRestsFaceDownWithoutJitter) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.3, 0.5));
  const WallId floor = s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
  s->addGravity({0, 0, -9.81});
  ElementDef b = grain({0, 0, 0.0102}, 0, "glass");
  b.shape = "toybox";
  b.shapeParams = {0.02, 0.015, 0.01};
  const ElementId id = s->addElement(b);
  RunOptions o;
  o.steps = 30000;
  s->run(o);
  const ElementState g = s->element(id);
  // Settled face down: still, level (orientation the identity), the floor carrying m g.
  EXPECT_LT(std::hypot(g.velocity[0], g.velocity[1], g.velocity[2]), 1e-6);
  EXPECT_LT(std::hypot(g.angularVelocity[0], g.angularVelocity[1], g.angularVelocity[2]), 1e-6);
  EXPECT_NEAR(std::abs(g.orientation[0]), 1, 1e-12);
  EXPECT_LT(g.position[2], 0.01);
  EXPECT_GT(g.position[2], 0.0099);
  EXPECT_NEAR(s->wall(floor).force[2], -g.mass * 9.81, 1e-6 * g.mass * 9.81);
  EXPECT_EQ(s->contactCount(), 4u);
  // The contacts as queried are its corners, each carrying a quarter of the weight.
  for (const ContactInfo& c : s->contacts()) {
    EXPECT_NEAR(std::abs(c.point[0]), 0.02, 1e-9);
    EXPECT_NEAR(std::abs(c.point[1]), 0.015, 1e-9);
    EXPECT_GT(c.overlap, 0);
    EXPECT_LT(c.overlap, 1e-4);
    EXPECT_NEAR(c.normal[2], -1, 1e-12);
    EXPECT_NEAR(c.force[2], -0.25 * g.mass * 9.81, 1e-6 * g.mass * 9.81);
  }
  // And it stays so: another stretch moves it by no more than rounding; relaxing, a ball
  // model, leaves it where it is.
  const ElementState before = s->element(id);
  s->run(o);
  EXPECT_NEAR(s->element(id).position[2], before.position[2], 1e-12);
  const double z = s->element(id).position[2];
  s->relax(0.01, 10);
  EXPECT_EQ(s->element(id).position[2], z);
}

// A tilted, spinning box dropped on a plane with damping and friction: the ledger's residual is
// the discretisation error of the shape path, and it converges with the step.
TEST_F(SimShape, DroppedTiltedBoxLandsAndTheLedgerConverges) {
  double residual[2];
  for (int k = 0; k < 2; ++k) {
    auto s = makeSimulation(3);
    s->addMaterial("glass", material(1e7, 0.5, 0.4));
    s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
    s->addGravity({0, 0, -9.81});
    ElementDef b = grain({0, 0, 0.05}, 0, "glass", {0.05, 0, -0.2});
    b.shape = "toybox";
    b.shapeParams = {0.02, 0.015, 0.01};
    const Quat q(AngleAxis(0.4, Vec3(1, 2, 0.5).normalized()));
    b.orientation = {q.w(), q.x(), q.y(), q.z()};
    b.angularVelocity = {1, -2, 3};
    const ElementId id = s->addElement(b);
    // The fraction alone sets the step (no accuracy target), so the two runs are 4x apart.
    s->setAutoTimeStep(k == 0 ? 0.2 : 0.05, 0);
    RunOptions o;
    o.steps = k == 0 ? 20000 : 80000;
    s->run(o);
    const ElementState g = s->element(id);
    EXPECT_GT(g.position[2], 0.009);  // on the floor, not through it
    EXPECT_LT(g.position[2], 0.03);
    const EnergyLedger e = s->energy();
    EXPECT_GT(e.dampingLoss, 0.01);
    EXPECT_GT(e.frictionLoss, 0.001);
    residual[k] = std::abs(e.residual);
  }
  // Second order: 0.048 and 3.1e-3, 4x apart in dt. (With the springs lengthened by the
  // synchronized velocity, first order, it was 0.045 and 1.1e-3: their error cancelled part of
  // the dampers'; physics/tangential.hpp.)
  EXPECT_LT(residual[1], 4e-3) << residual[0];
  EXPECT_GT(residual[0] / residual[1], 10);
}

TEST_F(SimShape, CheckpointContinuesBitForBit) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0.4));
  s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
  s->addGravity({0, 0, -9.81});
  ElementDef b = grain({0, 0, 0.03}, 0, "glass", {0.05, 0, 0});
  b.shape = "toybox";
  b.shapeParams = {0.02, 0.015, 0.01};
  b.angularVelocity = {1, -2, 3};
  s->addElement(b);
  s->addElement(toy({0.06, 0, 0.02}, 0.01));
  RunOptions o;
  o.steps = 3000;
  s->run(o);
  std::stringstream ck;
  s->save(ck);
  auto t = makeSimulation(3);
  t->load(ck);
  EXPECT_EQ(t->stateDigest(), s->stateDigest());
  s->run(o);
  t->run(o);
  EXPECT_EQ(t->stateDigest(), s->stateDigest());
}

// A bed of balls large enough for the threaded passes (several element blocks), with toy balls
// among them (the shape pass, serial), gives the same bits on 1 to 4 threads.
TEST_F(SimShape, MixedBedGivesTheSameBitsOnAnyThreadCount) {
  auto build = [] {
    auto s = makeSimulation(3);
    s->addMaterial("glass", material(1e7, 0.5, 0.4));
    s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
    s->addGravity({0, 0, -9.81});
    const double r = 0.002;
    uint32_t seed = 7;
    auto jitter = [&] {
      seed = seed * 1664525u + 1013904223u;
      return (static_cast<double>(seed >> 8) / 16777216.0 - 0.5) * 0.1;
    };
    for (int i = 0; i < 12; ++i) {
      for (int j = 0; j < 12; ++j) {
        for (int k = 0; k < 9; ++k) {
          const Vec3d x{(2 * i + 1) * r, (2 * j + 1) * r, (2 * k + 1) * r};
          if (k == 8 && (i + j) % 5 == 0) {
            ElementDef b = grain({x[0], x[1], x[2] + 0.01}, 0, "glass", {jitter(), jitter(), -0.1});
            b.shape = "toyball";
            b.shapeParams = {0.0015 + 0.0001 * ((i + j) % 3)};
            s->addElement(b);
          } else {
            s->addElement(grain(x, r, "glass", {jitter(), jitter(), jitter() - 0.1}));
          }
        }
      }
    }
    return s;
  };
  const unsigned before = ThreadPool::global().threads();
  std::vector<uint64_t> digests;
  for (unsigned t : {1u, 2u, 3u, 4u}) {
    ThreadPool::global().setThreads(t);
    auto s = build();
    RunOptions o;
    o.steps = 150;
    s->run(o);
    EXPECT_GT(s->contactCount(), 1000u);
    digests.push_back(s->stateDigest());
  }
  ThreadPool::global().setThreads(before);
  for (uint64_t d : digests) EXPECT_EQ(d, digests[0]);
}

// ---- 2D: a square of half side p[0], corners on planes --------------------------------------

class ToySquare final : public ShapeType<2> {
 public:
  std::string_view name() const override { return "toysquare"; }
  std::string_view parameters() const override { return "a: half side (m)"; }
  void check(std::span<const double> p) const override {
    if (p.size() != 1 || !(p[0] > 0)) throw Error("bad toysquare", {"VALUE", "SHAPE"});
  }
  Real boundingRadius(std::span<const double> p) const override { return p[0] * std::sqrt(2.0); }
  MassProperties<2> massProperties(std::span<const double> p) const override {
    MassProperties<2> m;
    m.volume = 4 * p[0] * p[0];
    m.inertia(2, 2) = m.volume * 2.0 / 3.0 * p[0] * p[0];
    return m;
  }
};

int toysquarePlane(const ElementRef<2>& a, const void* wall, ContactPoint<2>* out) {
  const auto& pl = *static_cast<const physics::PlaneShape<2>*>(wall);
  const Real h = a.g->params[0];
  int n = 0;
  for (int c = 0; c < 4; ++c) {
    const Vec2 v = a.x + rotate(a.q, Vec2((c & 1 ? 1 : -1) * h, (c & 2 ? 1 : -1) * h));
    const Real d = (v - pl.point).dot(pl.normal);
    if (d >= 0) continue;
    out[n] = {{-pl.normal, -d, v - 0.5 * d * pl.normal}, h, static_cast<uint32_t>(c)};
    ++n;
  }
  return n;
}

TEST(SimShape2D, SquareSettlesFlatOnItsCorners) {
  static const bool once = [] {
    ShapeTable<2>::get().add(std::make_unique<ToySquare>());
    ShapeTable<2>::get().addWall("toysquare", WallShape::Plane, {toysquarePlane, false});
    return true;
  }();
  (void)once;
  auto s = makeSimulation(2);
  s->addMaterial("glass", material(1e7, 0.4, 0.5));
  const WallId floor = s->addWall(plane({0, 0, 0}, {0, 1, 0}, "glass"));
  s->addGravity({0, -9.81, 0});
  ElementDef b = grain({0, 0.0102, 0}, 0, "glass", {0, 0, 0});
  b.shape = "toysquare";
  b.shapeParams = {0.01};
  b.orientation = {0.05};  // a corner lands first
  const ElementId id = s->addElement(b);
  const ElementState g0 = s->element(id);
  EXPECT_NEAR(g0.mass, 2500 * 4e-4, 1e-12);
  EXPECT_NEAR(g0.inertia, g0.mass * 2.0 / 3.0 * 1e-4, 1e-15);
  RunOptions o;
  o.steps = 40000;
  s->run(o);
  const ElementState g = s->element(id);
  EXPECT_NEAR(g.orientation[0], 0, 1e-6);  // it tipped onto its face
  EXPECT_LT(std::hypot(g.velocity[0], g.velocity[1]), 1e-6);
  EXPECT_NEAR(s->wall(floor).force[1], -g.mass * 9.81, 1e-6 * g.mass * 9.81);
  EXPECT_EQ(s->contactCount(), 2u);
}

// ---- rigid-body rotation (sim/rigid_body.hpp) ----------------------------------------------

// Returns a free toybox (half extents 0.03 0.02 0.01: moments in the ratio 5 : 10 : 13 about
// x, y, z) spinning at w (world frame), with params' optional tilt and orientation q.
std::unique_ptr<Simulation> spinningBox(const Vec3d& w, std::vector<double> params = {0.03, 0.02, 0.01},
                                        const Quat& q = Quat::Identity()) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0));
  ElementDef b = grain({0, 0, 0}, 0, "glass");
  b.shape = "toybox";
  b.shapeParams = std::move(params);
  b.angularVelocity = w;
  b.orientation = {q.w(), q.x(), q.y(), q.z()};
  s->addElement(b);
  s->setTimeStep(1e-4);
  return s;
}

Quat orientationOf(const ElementState& g) {
  return Quat(g.orientation[0], g.orientation[1], g.orientation[2], g.orientation[3]);
}
Vec3 spinOf(const ElementState& g) {
  return Vec3(g.angularVelocity[0], g.angularVelocity[1], g.angularVelocity[2]);
}

// Returns the world angular momentum of element g whose principal frame is turned by principal
// from its body frame (a toybox's: none).
Vec3 momentumOf(const ElementState& g, const Quat& principal = Quat::Identity()) {
  const Mat3 r = (orientationOf(g) * principal).toRotationMatrix();
  const Vec3 I(g.principalInertia[0], g.principalInertia[1], g.principalInertia[2]);
  return r * I.asDiagonal() * r.transpose() * spinOf(g);
}

TEST_F(SimShape, InertiaTensorIsDiagonalisedWhateverTheBodyFrame) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  const Geometry<3> plain = t.makeGeometry("toybox", std::vector<double>{0.03, 0.02, 0.01});
  const Geometry<3> tilted = t.makeGeometry("toybox", std::vector<double>{0.03, 0.02, 0.01, 0.7});
  const Real v = 8 * 0.03 * 0.02 * 0.01;
  const Vec3 expect = v / 3 * Vec3(0.0005, 0.001, 0.0013);
  for (const Geometry<3>* g : {&plain, &tilted}) {
    EXPECT_FALSE(g->isotropic);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(g->principalMoments[k], expect[k], 1e-15);
  }
  // The tilted frame's principal axes are the box's axes turned by the tilt.
  const Mat3 axes = tilted.principal.toRotationMatrix();
  const Mat3 r = ToyBox::tilt(std::vector<double>{0, 0, 0, 0.7});
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(axes.col(k).dot(r.col(k))), 1, 1e-12);
  // A cube is isotropic: the ball's integrator serves it.
  EXPECT_TRUE(t.makeGeometry("toybox", std::vector<double>{0.01, 0.01, 0.01}).isotropic);
}

TEST_F(SimShape, FreePrecessionConservesEnergyAndMomentum) {
  auto s = spinningBox({0.3, 0.2, 4});
  const ElementId id = s->elementIds()[0];
  const Vec3 l0 = momentumOf(s->element(id));

  const double e0 = s->energy().kineticRotational;
  double worstE = 0, worstL = 0;
  RunOptions o;
  o.steps = 1000;
  for (int k = 0; k < 20; ++k) {
    s->run(o);
    worstE = std::max(worstE, std::abs(s->energy().kineticRotational / e0 - 1));
    worstL = std::max(worstL, (momentumOf(s->element(id)) - l0).norm() / l0.norm());
  }
  // The body precesses: the spin's direction moves in the world.
  EXPECT_GT((spinOf(s->element(id)).normalized() - Vec3(0.3, 0.2, 4).normalized()).norm(), 1e-3);
  EXPECT_LT(worstE, 1e-5);
  EXPECT_LT(worstL, 1e-11);
}

// Every shape type's asymmetric body tumbling free keeps its angular momentum and energy: the
// superquadric, the polyhedron, the level set and the clump each hand their own inertia tensor
// and principal frame (not the body frame) to the same rotor.
TEST_F(SimShape, EveryShapeTumblingFreeKeepsItsAngularMomentum) {
  const ShapeTable<3>& t = ShapeTable<3>::get();
  // A wedge-like level set: the box 30 x 20 x 10 mm less the half-space x + z > 0.02.
  std::vector<double> wedge;
  const Real h = 0.002;
  for (int k = 0; k < 13; ++k)
    for (int j = 0; j < 17; ++j)
      for (int i = 0; i < 23; ++i) {
        const Vec3 x = Vec3(-0.022, -0.016, -0.012) + h * Vec3(i, j, k);
        const Vec3 q = x.cwiseAbs() - Vec3(0.015, 0.01, 0.005);
        const Real box = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
        wedge.push_back(std::max(box, (x.x() + x.z() - 0.01) / std::sqrt(2.0)));
      }
  const std::vector<std::pair<std::string, std::vector<double>>> shapes = {
      {"superquadric", {0.02, 0.013, 0.008, 3, 2.5}},
      {"polyhedron", {0, 0, 0, 0.03, 0, 0, 0, 0.02, 0, 0, 0, 0.012, 0.02, 0.015, 0.01}},
      {"levelset", levelSetFromValues<3>(h, {23, 17, 13}, Vec3(-0.022, -0.016, -0.012), wedge)},
      {"clump", {0, 0, 0, 0.01, 0.015, 0, 0, 0.006, 0, 0.012, 0.004, 0.005}}};
  for (const auto& [shape, params] : shapes) {
    auto s = makeSimulation(3);
    s->addMaterial("glass", material(1e7, 0.5, 0));
    ElementDef b = grain({0, 0, 0}, 0, "glass");
    b.shape = shape;
    b.shapeParams = params;
    b.angularVelocity = {0.3, 0.2, 4};
    b.orientation = {0.9, 0.2, -0.3, 0.1};
    const ElementId id = s->addElement(b);
    s->setTimeStep(1e-4);
    const ElementState g0 = s->element(id);
    const Geometry<3> geom = t.makeGeometry(shape, g0.shapeParams);
    ASSERT_FALSE(geom.isotropic) << shape;
    const auto momentum = [&](const ElementState& g) { return momentumOf(g, geom.principal); };
    const Vec3 l0 = momentum(g0);
    const double e0 = s->energy().kineticRotational;
    double worstE = 0, worstL = 0;
    RunOptions o;
    o.steps = 1000;
    for (int k = 0; k < 10; ++k) {
      s->run(o);
      worstE = std::max(worstE, std::abs(s->energy().kineticRotational / e0 - 1));
      worstL = std::max(worstL, (momentum(s->element(id)) - l0).norm() / l0.norm());
    }
    EXPECT_GT((spinOf(s->element(id)).normalized() - Vec3(0.3, 0.2, 4).normalized()).norm(), 1e-3) << shape;
    EXPECT_LT(worstE, 1e-5) << shape;
    EXPECT_LT(worstL, 1e-11) << shape;
  }
}

TEST_F(SimShape, IntermediateAxisIsUnstableTheOthersAreNot) {
  // Body-frame spin about each axis with a small perturbation, for 6 s (the intermediate
  // axis's growth rate is 2.4 /s: the perturbation grows 10^6 times and the spin flips).
  for (int axis = 0; axis < 3; ++axis) {
    Vec3d w{1e-3, 1e-3, 1e-3};
    w[axis] = 5;
    auto s = spinningBox(w);
    const ElementId id = s->elementIds()[0];
    double least = 5;
    RunOptions o;
    o.steps = 100;
    for (int k = 0; k < 600; ++k) {
      s->run(o);
      const ElementState g = s->element(id);
      const Vec3 body = orientationOf(g).conjugate() * spinOf(g);
      least = std::min(least, body[axis]);
    }
    if (axis == 1) {
      EXPECT_LT(least, -4.5) << "the intermediate axis must flip";
    } else {
      EXPECT_GT(least, 4.9) << "axis " << axis << " must be stable";
    }
  }
}

TEST_F(SimShape, BlockedRotationsOfARigidBodyKeepTheirSpin) {
  // Spin about z only, x and y blocked: the gyroscopic term must not give it any.
  const Quat q(AngleAxis(0.5, Vec3(1, 1, 0).normalized()));
  auto s = spinningBox({0, 0, 3}, {0.03, 0.02, 0.01}, q);
  const ElementId id = s->elementIds()[0];
  s->setElementBlocked(id, dof::Rx | dof::Ry);
  RunOptions o;
  o.steps = 2000;
  s->run(o);
  const Vec3 w = spinOf(s->element(id));
  EXPECT_EQ(w.x(), 0);
  EXPECT_EQ(w.y(), 0);
  EXPECT_GT(std::abs(w.z()), 0.1);
}

TEST_F(SimShape, NonDiagonalInertiaTurnsAsTheDiagonalBody) {
  // The same body described twice: in its principal frame, and in a frame turned by the tilt
  // (non-diagonal tensor) with the orientation turned back. Their motions must agree.
  const Quat tilt(ToyBox::tilt(std::vector<double>{0, 0, 0, 0.7}));
  const Quat q0(AngleAxis(0.3, Vec3(0, 1, 0)));
  auto a = spinningBox({0.5, 2, 3}, {0.03, 0.02, 0.01, 0.7}, q0);
  auto b = spinningBox({0.5, 2, 3}, {0.03, 0.02, 0.01}, q0 * tilt);
  RunOptions o;
  o.steps = 5000;
  a->run(o);
  b->run(o);
  const ElementState ga = a->element(a->elementIds()[0]), gb = b->element(b->elementIds()[0]);
  EXPECT_LT((spinOf(ga) - spinOf(gb)).norm(), 1e-9);
  EXPECT_LT(orientationOf(ga).angularDistance(orientationOf(gb) * tilt.conjugate()), 1e-9);
}

}  // namespace sim_shape_test
}  // namespace demlab::sim
