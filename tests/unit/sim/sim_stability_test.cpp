// The stability suite (issue 6): short scenes at the edges of what an explicit DEM step
// handles, each asserting its outcome: bounded energy and correct physics with the automatic
// step, or the documented error. Stiffness 1e3 .. 1e12 N/m, size ratio 1:1000 with friction,
// mass ratio 1e6, a 100 m/s impact on a thin wall, deep initial overlaps, bad parameters, and
// each watchdog check firing. Each case prints one row of the stability table of
// doc/verification.md ("stability | case | dt | outcome").
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>

#include "physics/critical_step.hpp"
#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_stability_test {

using testing::codeOf;
using testing::grain;
using testing::material;
using testing::plane;
using testing::setWatchdog;
using testing::watchdogOf;

constexpr double kG = 9.81;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void row(const std::string& name, double dt, const std::string& outcome) {
  std::printf("stability | %s | %.3g | %s\n", name.c_str(), dt, outcome.c_str());
}

// Returns the watchdog's check that stopped f's run, or "" (and fails) if none did.
template <class F>
std::string tripOf(F&& f, WatchdogTrip* out = nullptr) {
  try {
    f();
  } catch (const RunStopped& e) {
    EXPECT_EQ(e.code().at(0), "DEMLAB");
    EXPECT_EQ(e.code().at(1), "WATCHDOG");
    if (out) *out = e.trip();
    return e.trip().check;
  }
  ADD_FAILURE() << "the watchdog did not stop the run";
  return "";
}

MaterialDef linearMaterial(double kn, double restitution, double friction, double density) {
  MaterialDef m = material(1e9, restitution, friction, density);
  m.normalStiffness = kn;
  return m;
}

// The contacts' critical step (sim/contact_stiffness.hpp) of two equal elastic Hertz spheres
// pressed 2 % of a radius together: after the first force pass's neighbour search the critical
// step is 2 / omega of the pair's fastest mode at that overlap, the normal one
// (omega^2 = 2 kn / m, kn = 2 E* sqrt(R* delta)) or the tangential-rotational one
// (omega^2 = kt (2/m + 2 l^2 / I), kt = 8 G* sqrt(R* delta), l = r - delta/2, I = 2/5 m r^2);
// the automatic step is 0.2 of the least of the static estimate and 2.5 times it.
TEST(Stability, TheContactsStepIsThePairsFastestModeAtItsOverlap) {
  auto s = makeSimulation(3);
  s->addMaterial("m", material(5e6, 1.0, 0.5));
  s->setContactLaw(LawKind::HertzMindlin);
  const double r = 1e-3, delta = 0.02 * r;
  const ElementId a = s->addElement(grain({-r + delta / 2, 0, 0}, r, "m"));
  s->addElement(grain({r - delta / 2, 0, 0}, r, "m"));
  const double staticStep = s->criticalTimeStep();
  EXPECT_DOUBLE_EQ(s->timeStep(), 0.2 * staticStep);  // no search yet
  s->runSteps(1);
  const double nu = 0.3, e = 5e6, g = e / (2 * (1 + nu));
  const double eStar = e / (2 * (1 - nu * nu)), gStar = g / (2 * (2 - nu));
  const double m = s->element(a).mass, inertia = 0.4 * m * r * r, l = r - delta / 2;
  const double root = std::sqrt(r / 2 * delta);
  const double wn2 = 2 * eStar * root * 2 / m;
  const double wt2 = 8 * gStar * root * (2 / m + 2 * l * l / inertia);
  const double expected = 2 / std::sqrt(std::max(wn2, wt2));
  ASSERT_LT(expected, staticStep);  // the overlap makes the contacts the limit
  EXPECT_NEAR(s->criticalTimeStep() / expected, 1, 1e-12);
  EXPECT_NEAR(s->timeStep() / (0.2 * std::min(staticStep, 2.5 * expected)), 1, 1e-12);
}

// Two equal grains (r = 1 mm, 2500 kg/m^3) meet head on at 0.2 m/s, linear law with the given
// normal stiffness, restitution 0.5, the automatic step.
TEST(Stability, StiffnessFrom1e3To1e12WithAutoStep) {
  for (double kn : {1e3, 1e6, 1e9, 1e12}) {
    SCOPED_TRACE(kn);
    auto s = makeSimulation(3);
    s->addMaterial("m", linearMaterial(kn, 0.5, 0, 2500));
    s->setContactLaw(LawKind::Linear);
    const double r = 1e-3, v = 0.1;
    // Start two and a half steps of travel apart, so the stiffest case needs no long approach
    // and the touch falls mid-step (the error of a damped touch depends on its phase in the
    // step, doc/verification.md finding 3).
    const ElementId a = s->addElement(grain({-r, 0, 0}, r, "m", {v, 0, 0}));
    const ElementId b = s->addElement(grain({r, 0, 0}, r, "m", {-v, 0, 0}));
    const double dt = s->timeStep();
    const double m = s->element(a).mass, omega = std::sqrt(kn / (m / 2));
    const double tc = std::numbers::pi / omega;  // about; damping lengthens it a little
    // The accuracy target: the contact's force lasts 20 steps, below 0.2 of the critical step.
    const double force = physics::linearForceDuration(physics::linearDampingRatio(0.5)) / omega;
    EXPECT_NEAR(dt / (force / kDefaultStepsPerContact), 1, 1e-12);
    EXPECT_LT(dt, 0.2 * s->criticalTimeStep());
    s->setElementPosition(a, {-r - 2.5 * v * dt, 0, 0});
    s->setElementPosition(b, {r + 2.5 * v * dt, 0, 0});
    s->runSteps(static_cast<uint64_t>(3 * tc / dt) + 10);
    const double e = (s->element(b).velocity[0] - s->element(a).velocity[0]) / (2 * v);
    EXPECT_EQ(s->contactCount(), 0u);
    // 20 steps per contact (0.2 of the critical step gave 10 and 4 % low): within 1 %.
    EXPECT_NEAR(e, 0.5, 0.005);
    EXPECT_LT(s->energy().residual, 0.01);
    char buf[64];
    std::snprintf(buf, sizeof buf, "bounded (residual %.2g), restitution %.3f (0.5)",
                  s->energy().residual, e);
    row("head-on, linear, kn = 1e" + std::to_string(static_cast<int>(std::lround(std::log10(kn)))) +
            " N/m",
        dt, buf);
  }
}

// A grain of r = 1 mm lies on a sphere of R = 1 m (size ratio 1:1000), 20 degrees from its
// top, friction 0.5 (> tan 20 deg): it must roll down without slipping (no rolling resistance
// is modelled), its angle from the top growing as (5/7) g sin(theta) t^2 / (2 (R + r)), not
// as the sliding g sin(theta) t^2 / (2 (R + r)). The big grain rests on a floor. Both start at
// their static Hertz overlaps.
TEST(Stability, SizeRatio1000WithFrictionRollsWithoutSlip) {
  auto s = makeSimulation(3);
  s->addMaterial("m", material(1e9, 0.5, 0.5));
  s->addWall(plane({0, 0, 0}, {0, 0, 1}, "m"));
  const double R = 1, r = 1e-3, theta = 20 * std::numbers::pi / 180;
  const MaterialDef mat = s->material("m");
  const double ystar = mat.young / (2 * (1 - mat.poisson * mat.poisson));
  auto hertzOverlap = [&](double force, double rstar) {
    return std::pow(3 * force / (4 * ystar * std::sqrt(rstar)), 2.0 / 3.0);
  };
  const double M = 4.0 / 3.0 * std::numbers::pi * R * R * R * mat.density;
  const double m = 4.0 / 3.0 * std::numbers::pi * r * r * r * mat.density;
  const double zBig = R - hertzOverlap((M + m) * kG, R);
  const double d = R + r - hertzOverlap(m * kG * std::cos(theta), R * r / (R + r));
  const ElementId big = s->addElement(grain({0, 0, zBig}, R, "m"));
  const ElementId small =
      s->addElement(grain({d * std::sin(theta), 0, zBig + d * std::cos(theta)}, r, "m"));
  s->addGravity({0, 0, -kG});
  const double dt = s->timeStep();
  s->runSteps(20000);
  const ElementState a = s->element(big), b = s->element(small);
  const Vec3d n{b.position[0] - a.position[0], 0, b.position[2] - a.position[2]};
  const double dist = std::hypot(n[0], n[2]);
  const double angle = std::atan2(n[0], n[2]);
  const double t = s->time();
  const double rolling = 5.0 / 7.0 * kG * std::sin(theta) * t * t / (2 * (R + r));
  EXPECT_NEAR(angle - theta, rolling, 0.03 * rolling);
  // No slip at the contact: the small grain's surface moves with the big one's.
  // Contact point velocity of the small grain: v + w x (-r n/|n|) (in the x-z plane, w along y).
  const double nx = n[0] / dist, nz = n[2] / dist;
  const double wy = b.angularVelocity[1], Wy = a.angularVelocity[1];
  // w x p for w = (0, wy, 0), p = (px, 0, pz): (wy pz, 0, -wy px).
  const double cx = b.velocity[0] + wy * (-r * nz) - (a.velocity[0] + Wy * (R * nz));
  const double cz = b.velocity[2] - wy * (-r * nx) - (a.velocity[2] - Wy * (R * nx));
  const double slip = std::hypot(cx, cz), speed = std::hypot(b.velocity[0], b.velocity[2]);
  EXPECT_LT(slip, 0.01 * speed);
  EXPECT_LT(s->energy().residual, 0.05);
  char buf[128];
  std::snprintf(buf, sizeof buf,
                "bounded, rolls without slip: angle gained %.4g rad (rolling %.4g, sliding %.4g)",
                angle - theta, rolling, rolling * 7 / 5);
  row("size ratio 1:1000, friction 0.5, 20 deg off the top", dt, buf);
}

// A heavy grain (1e6 kg/m^3) rests on a light one (1 kg/m^3) on a floor, Hertz: the mass ratio
// is 1e6. The automatic step must follow the light grain squeezed between the two (its own
// Rayleigh step), and the floor must carry both weights.
TEST(Stability, MassRatio1e6StackIsStatic) {
  auto s = makeSimulation(3);
  s->addMaterial("light", material(1e9, 0.5, 0.3, 1));
  s->addMaterial("heavy", material(1e9, 0.5, 0.3, 1e6));
  s->addWall(plane({0, 0, 0}, {0, 0, 1}, "light"));
  const double r = 1e-3;
  const MaterialDef mat = s->material("light");
  const double ystar = mat.young / (2 * (1 - mat.poisson * mat.poisson));
  auto hertzOverlap = [&](double force, double rstar) {
    return std::pow(3 * force / (4 * ystar * std::sqrt(rstar)), 2.0 / 3.0);
  };
  const double vol = 4.0 / 3.0 * std::numbers::pi * r * r * r;
  const double m = vol * 1, M = vol * 1e6;
  const double z1 = r - hertzOverlap((M + m) * kG, r);
  const double z2 = z1 + 2 * r - hertzOverlap(M * kG, r / 2);
  const ElementId lo = s->addElement(grain({0, 0, z1}, r, "light"));
  const ElementId hi = s->addElement(grain({0, 0, z2}, r, "heavy"));
  s->addGravity({0, 0, -kG});
  // The light grain's own Rayleigh step bounds the estimate (the pair's slower material
  // would allow a step 1000 times too large).
  EXPECT_LE(s->criticalTimeStep(), physics::rayleighTimeStep(mat, r));
  const double dt = s->timeStep();
  s->runSteps(20000);
  const double floorForce = s->wall(s->wallIds()[0]).force[2];
  EXPECT_NEAR(-floorForce, (M + m) * kG, 0.02 * (M + m) * kG);
  EXPECT_NEAR(s->element(hi).position[2], z2, 0.01 * r);
  EXPECT_NEAR(s->element(lo).position[2], z1, 0.01 * r);
  EXPECT_LT(s->energy().residual, 0.05);
  char buf[96];
  std::snprintf(buf, sizeof buf, "bounded, static: floor force / weights = %.4f",
                -floorForce / ((M + m) * kG));
  row("mass ratio 1e6 (stack on a floor, Hertz)", dt, buf);
}

// A grain (r = 1 mm, glass-like E = 7e10 Pa) hits a thin (zero-thickness) plate at 100 m/s.
WallDef plate() {
  WallDef w;
  w.shape = WallShape::Finite;
  w.material = "m";
  w.normal = {1, 0, 0};
  w.axis = {0, 1, 0};
  w.halfExtents = {0.05, 0.05, 0};
  return w;
}

TEST(Stability, Impact100MetresPerSecondOnAThinWall) {
  const double r = 1e-3, v = 100;
  {
    // Automatic step: the skin tracks the grain, the contact resolves, the grain rebounds.
    auto s = makeSimulation(3);
    s->addMaterial("m", material(7e10, 0.5, 0.3));
    s->addWall(plate());
    const ElementId g = s->addElement(grain({-r - 1e-4, 0, 0}, r, "m", {v, 0, 0}));
    s->runTime(8e-6);
    const double dt = s->timeStep();
    const ElementState b = s->element(g);
    EXPECT_LT(b.position[0], -r);        // still on its side: no tunnelling
    EXPECT_LT(b.velocity[0], -0.4 * v);  // rebounded (Hertz, e = 0.5 gives about 0.55)
    EXPECT_GT(b.velocity[0], -0.7 * v);
    EXPECT_LT(s->energy().residual, 0.02);
    char buf[64];
    std::snprintf(buf, sizeof buf, "bounded, rebounds at %.3g m/s, no tunnelling", -b.velocity[0]);
    row("100 m/s on a thin plate, dt auto", dt, buf);
  }
  {
    // A fixed step of 30 us: 3 mm per step, 1.5 times the grain's diameter. Reported before
    // the first step; nothing moved.
    auto s = makeSimulation(3);
    s->addMaterial("m", material(7e10, 0.5, 0.3));
    s->addWall(plate());
    const ElementId g = s->addElement(grain({-r - 1e-4, 0, 0}, r, "m", {v, 0, 0}));
    s->setTimeStep(3e-5);
    const uint64_t digest0 = s->stateDigest();
    WatchdogTrip t;
    EXPECT_EQ(tripOf([&] { s->runSteps(10); }, &t), "SPEED");
    EXPECT_TRUE(t.atStart);
    EXPECT_EQ(t.step, 0u);
    ASSERT_EQ(t.grains.size(), 1u);
    EXPECT_EQ(t.grains[0], g);
    EXPECT_EQ(s->stepCount(), 0u);
    EXPECT_EQ(s->element(g).position[0], -r - 1e-4);
    (void)digest0;
    row("100 m/s on a thin plate, dt = 3e-5 s (1.5 diameters per step)", 3e-5,
        "WATCHDOG SPEED before the first step");
    // With the watchdog off the grain passes through the plate: the failure it prevents.
    WatchdogOptions off;
    off.enabled = false;
    setWatchdog(*s, off);
    s->runSteps(2);
    EXPECT_GT(s->element(g).position[0], r);
  }
}

// Two grains placed overlapping by 0.6 of a radius, and a grain 0.6 of a radius into a floor:
// deeper than the watchdog's `placed` limit (0.5).
TEST(Stability, DeepInitialOverlapsAreReportedOrRelaxed) {
  const double r = 1e-3;
  auto build = [&] {
    auto s = makeSimulation(3);
    s->addMaterial("m", material(1e8, 0.5, 0.3));
    s->addWall(plane({0, 0, 0}, {0, 0, 1}, "m"));
    s->addElement(grain({0, 0, 0.01}, r, "m"));
    s->addElement(grain({1.4 * r, 0, 0.01}, r, "m"));
    s->addElement(grain({0.01, 0, 0.4 * r}, r, "m"));
    return s;
  };
  auto s = build();
  const double dt = s->timeStep();
  const std::vector<ElementId> ids = s->elementIds();
  std::vector<Vec3d> x0;
  for (ElementId id : ids) x0.push_back(s->element(id).position);
  WatchdogTrip t;
  EXPECT_EQ(tripOf([&] { s->runSteps(100); }, &t), "OVERLAP");
  EXPECT_TRUE(t.atStart);
  EXPECT_EQ(s->stepCount(), 0u);
  std::vector<Vec3d> x1;
  for (ElementId id : ids) x1.push_back(s->element(id).position);
  EXPECT_EQ(x1, x0);
  EXPECT_NE(t.cause.find("placed overlapping"), std::string::npos);
  EXPECT_NE(t.fix.find("sim relax"), std::string::npos);
  row("deep initial overlaps (0.6 r), no relaxation", dt, "WATCHDOG OVERLAP before the first step");
  // Reported again by the next run: the scene has still not made its first step.
  EXPECT_EQ(tripOf([&] { s->runSteps(100); }), "OVERLAP");

  // Relaxed on request: the overlaps go below 1 % of the radius and the run is quiet.
  const RelaxReport rr = s->relax(0.01, 1000);
  EXPECT_NEAR(rr.before, 0.6, 1e-9);
  EXPECT_LE(rr.after, 0.01);
  EXPECT_EQ(rr.moved, 3u);
  s->runSteps(2000);
  const EnergyLedger e = s->energy();
  EXPECT_LT(e.residual, 0.01);
  for (const ContactInfo& c : s->contacts()) EXPECT_LT(c.overlap, 0.02 * r);
  char buf[96];
  std::snprintf(buf, sizeof buf, "sim relax: %llu passes, 0.6 -> %.3g r; then bounded",
                static_cast<unsigned long long>(rr.iterations), rr.after);
  row("deep initial overlaps (0.6 r), relaxed", dt, buf);
}

// Zero, negative and NaN parameters are rejected and change nothing.
TEST(Stability, BadParametersAreRejected) {
  auto s = makeSimulation(3);
  s->addMaterial("m", material(1e8, 0.5, 0.3));
  s->addElement(grain({0, 0, 0.01}, 1e-3, "m"));
  const uint64_t digest = s->stateDigest();
  using Code = std::vector<std::string>;
  for (double bad : {0.0, -1.0, kNaN}) {
    SCOPED_TRACE(bad);
    MaterialDef m = material(1e8, 0.5, 0.3);
    m.density = bad;
    EXPECT_EQ(codeOf([&] { s->addMaterial("x", m); }), (Code{"VALUE", "DENSITY"}));
    m = material(bad, 0.5, 0.3);
    EXPECT_EQ(codeOf([&] { s->addMaterial("x", m); }), (Code{"VALUE", "YOUNG"}));
    EXPECT_EQ(codeOf([&] { s->addElement(grain({0, 0, 0}, bad, "m")); }), (Code{"VALUE", "RADIUS"}));
    EXPECT_EQ(codeOf([&] { s->setTimeStep(bad); }), (Code{"VALUE", "TIMESTEP"}));
    EXPECT_EQ(codeOf([&] { s->setAutoTimeStep(bad); }), (Code{"VALUE", "FRACTION"}));
    EXPECT_EQ(codeOf([&] { s->relax(bad, 10); }), (Code{"VALUE", "FRACTION"}));
  }
  for (double bad : {-1.0, kNaN}) {
    MaterialDef m = material(1e8, bad, 0.3);
    EXPECT_EQ(codeOf([&] { s->addMaterial("x", m); }), (Code{"VALUE", "RESTITUTION"}));
    m = material(1e8, 0.5, bad);
    EXPECT_EQ(codeOf([&] { s->addMaterial("x", m); }), (Code{"VALUE", "FRICTION"}));
    m = material(1e8, 0.5, 0.3);
    m.normalStiffness = bad;
    EXPECT_EQ(codeOf([&] { s->addMaterial("x", m); }), (Code{"VALUE", "NORMALSTIFFNESS"}));
    WatchdogOptions o;
    o.overlap = bad;
    EXPECT_EQ(codeOf([&] { setWatchdog(*s, o); }), (Code{"VALUE", "OVERLAP"}));
    o = {};
    o.energy = bad;
    EXPECT_EQ(codeOf([&] { setWatchdog(*s, o); }), (Code{"VALUE", "ENERGY"}));
  }
  MaterialDef m = material(1e8, 0.5, 0.3);
  m.poisson = kNaN;
  EXPECT_EQ(codeOf([&] { s->addMaterial("x", m); }), (Code{"VALUE", "POISSON"}));
  EXPECT_EQ(codeOf([&] {
              s->addElement(grain({kNaN, 0, 0}, 1e-3, "m"));
            }),
            (Code{"VALUE", "POSITION"}));
  EXPECT_EQ(codeOf([&] {
              s->addElement(grain({0, 0, 0}, 1e-3, "m", {0, kNaN, 0}));
            }),
            (Code{"VALUE", "VELOCITY"}));
  EXPECT_EQ(codeOf([&] { s->addGravity({0, 0, kNaN}); }), (Code{"VALUE", "GRAVITY"}));
  EXPECT_EQ(codeOf([&] { s->relax(0.01, 0); }), (Code{"VALUE", "ITERATIONS"}));
  WatchdogOptions o;
  o.overlap = std::numeric_limits<double>::infinity();
  EXPECT_EQ(codeOf([&] { setWatchdog(*s, o); }), (Code{"VALUE", "OVERLAP"}));
  o = {};
  o.energy = std::numeric_limits<double>::infinity();
  EXPECT_EQ(codeOf([&] { setWatchdog(*s, o); }), (Code{"VALUE", "ENERGY"}));
  o = {};
  o.placed = -1;
  EXPECT_EQ(codeOf([&] { setWatchdog(*s, o); }), (Code{"VALUE", "PLACED"}));
  EXPECT_EQ(s->stateDigest(), digest);
  row("zero, negative and NaN parameters", 0, "rejected (DEMLAB VALUE ...), nothing changed");
}

// A fixed step well above the critical estimate: the watchdog stops the run at the step where
// the contacts blow up, with each check in turn (the others off).
std::unique_ptr<Simulation> unstableScene(double factor) {
  auto s = makeSimulation(3);
  s->addMaterial("m", linearMaterial(1e6, 0.9, 0, 2500));
  s->setContactLaw(LawKind::Linear);
  const double r = 1e-3;
  s->addWall(plane({0, 0, 0}, {0, 0, 1}, "m"));
  for (int k = 0; k < 4; ++k) s->addElement(grain({0, 0, r + 2 * r * k}, r, "m"));
  s->addGravity({0, 0, -kG});
  s->setTimeStep(factor * s->criticalTimeStep());
  return s;
}

TEST(Stability, WatchdogStopsABlowUp) {
  const double factor = 3;
  {
    auto s = unstableScene(factor);
    WatchdogTrip t;
    const std::string check = tripOf([&] { s->runSteps(100000); }, &t);
    EXPECT_TRUE(check == "OVERLAP" || check == "ENERGY" || check == "SPEED") << check;
    EXPECT_EQ(t.step, s->stepCount());
    EXPECT_LT(s->stepCount(), 100000u);
    EXPECT_FALSE(t.atStart);
    EXPECT_NE(t.cause.find("time step is too large"), std::string::npos) << t.cause;
    EXPECT_NE(t.fix.find("sim timestep auto"), std::string::npos) << t.fix;
    for (double x : s->positions()) EXPECT_TRUE(std::isfinite(x));
    row("4 grains on a floor, linear, dt = 3 x critical", s->timeStep(),
        "WATCHDOG " + check + " at step " + std::to_string(t.step));
  }
  // Each check alone.
  for (const char* only : {"OVERLAP", "ENERGY"}) {
    SCOPED_TRACE(only);
    auto s = unstableScene(factor);
    WatchdogOptions o;
    o.speed = false;
    o.overlap = std::string(only) == "OVERLAP" ? 0.2 : 0;
    o.energy = std::string(only) == "ENERGY" ? 0.5 : 0;
    setWatchdog(*s, o);
    EXPECT_EQ(tripOf([&] { s->runSteps(100000); }), only);
  }
  // With the watchdog off the same scene flies apart: the grains leave with energy the
  // integration made, many times what they had.
  auto s = unstableScene(factor);
  WatchdogOptions off;
  off.enabled = false;
  setWatchdog(*s, off);
  s->runSteps(20000);
  EXPECT_GT(s->energy().residual, 0.5);
}

// Two 2D grains, the second at speed v, with a load on it whose function turns NaN after
// step 10 of the automatic step. Returns the simulation, the loaded grain and the step.
struct NanLoadScene {
  std::unique_ptr<Simulation> s;
  ElementId g;
  double dt;
};
NanLoadScene nanLoadScene(double v) {
  auto s = makeSimulation(2);
  s->addMaterial("m", material(1e8, 0.5, 0.3));
  s->addElement(grain({0, 0, 0}, 1e-3, "m"));
  const ElementId g = s->addElement(grain({0.01, 0, 0}, 1e-3, "m", {v, 0, 0}));
  const double dt = s->timeStep();
  LoadDef l;
  l.grain = g;
  l.forceFn[0] = [dt](double t) { return t > 10.5 * dt ? kNaN : 0.0; };
  s->addLoad(l);
  return {std::move(s), g, dt};
}

// A load whose function turns NaN: the watchdog names the grain at that step.
TEST(Stability, WatchdogCatchesANonFiniteLoad) {
  auto [s, g, dt] = nanLoadScene(0);
  WatchdogTrip t;
  EXPECT_EQ(tripOf([&] { s->runSteps(100); }, &t), "NAN");
  EXPECT_EQ(t.step, 11u);
  EXPECT_EQ(s->stepCount(), 11u);
  ASSERT_EQ(t.grains.size(), 1u);
  EXPECT_EQ(t.grains[0], g);
  // The automatic step is in force: the fix names the loads, not the setting already in use.
  EXPECT_NE(t.fix.find("check the loads"), std::string::npos) << t.fix;
  EXPECT_EQ(t.fix.find("use sim timestep auto"), std::string::npos) << t.fix;
  row("a load turning NaN at step 11 (2D)", dt, "WATCHDOG NAN at step 11, naming the element");
}

// The same with the watchdog off: the automatic step's motion bound ignores the non-finite
// speed (a zero step would make the run endless), and the run's own finiteness check ends it.
TEST(Stability, NonFiniteStateLeavesTheAutomaticStepAlone) {
  auto [s, g, dt] = nanLoadScene(0.1);
  WatchdogOptions off;
  off.enabled = false;
  setWatchdog(*s, off);
  EXPECT_THROW(s->runSteps(5000), Error);
  EXPECT_LE(s->stepCount(), 1100u);
  const double after = s->timeStep();
  EXPECT_GT(after, 0);
  EXPECT_TRUE(std::isfinite(after));
}

// The same scene runs bit-identically with the watchdog on and off, and the watchdog's options
// are part of the scene (checkpoint, clone), written only when they differ from the defaults.
TEST(Stability, WatchdogChangesNothingAndIsSaved) {
  auto build = [] {
    auto s = makeSimulation(3);
    s->addMaterial("m", material(1e8, 0.5, 0.5));
    s->addWall(plane({0, 0, 0}, {0, 0, 1}, "m"));
    s->addElements(testing::latticeGrains(3, 27, 1e-3, 0.01, 0.05, "m", 7));
    s->addGravity({0, 0, -kG});
    return s;
  };
  auto on = build(), off = build();
  EXPECT_EQ(on->stateDigest(), off->stateDigest());
  WatchdogOptions o;
  o.enabled = false;
  setWatchdog(*off, o);
  EXPECT_NE(on->stateDigest(), off->stateDigest());
  on->runSteps(500);
  off->runSteps(300);
  setWatchdog(*off, WatchdogOptions{});  // back on mid-run: the trajectory does not notice
  off->runSteps(200);
  EXPECT_EQ(on->positions(), off->positions());
  EXPECT_EQ(on->velocities(), off->velocities());
  EXPECT_EQ(on->stateDigest(), off->stateDigest());
  const auto mods = on->listModules();
  EXPECT_NE(std::find(mods.begin(), mods.end(), "watchdog"), mods.end());

  std::ostringstream plain;
  on->save(plain);
  EXPECT_EQ(plain.str().find("WDOG"), std::string::npos);
  o = {};
  o.overlap = 0.3;
  o.speed = false;
  setWatchdog(*on, o);
  std::ostringstream saved;
  on->save(saved);
  auto back = makeSimulation(3);
  std::istringstream in(saved.str());
  back->load(in);
  EXPECT_EQ(watchdogOf(*back), o);
  EXPECT_EQ(back->stateDigest(), on->stateDigest());
  EXPECT_EQ(watchdogOf(*on->clone()), o);
}

}  // namespace sim_stability_test
}  // namespace demlab::sim
