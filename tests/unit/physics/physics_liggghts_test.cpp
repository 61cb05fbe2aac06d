// demlab's Hertz-Mindlin against LIGGGHTS 3.8.0 itself: two collisions (sphere-sphere and
// sphere-wall, oblique, spinning, with sticking and sliding) run in LIGGGHTS with
// `pair_style gran model hertz tangential history limitForce on` and its nve/sphere
// integrator, replayed here with demlab's law and narrow phase in the same integration
// scheme. The states LIGGGHTS dumped at step 150 (in contact) and 700 (after it) are embedded
// below; tests/unit/physics/liggghts/ holds the inputs and how to regenerate them.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "physics/law_hertz_mindlin.hpp"
#include "physics/narrow_phase.hpp"

namespace demlab::physics {
namespace physics_liggghts_test {

// x, v, omega, f of one atom, as LIGGGHTS dumped it.
using State = std::array<Real, 12>;

struct Body {
  Real r, mass, inertia;
  Vec3 x, v, w, f = Vec3::Zero(), t = Vec3::Zero();
};

Body body(Real r, Vec3 x, Vec3 v, Vec3 w) {
  const Real mass = 4.0 / 3.0 * std::numbers::pi * r * r * r * 2500;
  return Body{r, mass, 0.4 * mass * r * r, x, v, w};
}

PairParams liggghtsMaterial() {
  MaterialDef m;
  m.density = 2500;
  m.young = 5e6;
  m.poisson = 0.3;
  m.restitution = 0.5;
  m.friction = 0.5;
  // LIGGGHTS's damping and Coulomb test.
  PairParams p = mixPair(LawKind::HertzMindlin, m, m, HertzDamping::Liggghts);
  p.coulomb = CoulombCriterion::Spring;
  return p;
}

// LIGGGHTS's fix nve/sphere, first half: kick, drift, spin kick (I = 0.4 m r^2).
void initialIntegrate(Body& b, Real dt) {
  b.v += 0.5 * dt * b.f / b.mass;
  b.x += dt * b.v;
  b.w += 0.5 * dt * b.t / b.inertia;
  b.f.setZero();
  b.t.setZero();
}

void finalIntegrate(Body& b, Real dt) {
  b.v += 0.5 * dt * b.f / b.mass;
  b.w += 0.5 * dt * b.t / b.inertia;
}

void expectState(const Body& b, const State& want, int step) {
  const Vec3 parts[4] = {b.x, b.v, b.w, b.f};
  for (int q = 0; q < 4; ++q) {
    const Vec3 w(want[3 * q], want[3 * q + 1], want[3 * q + 2]);
    const Real scale = std::max(w.norm(), 1e-300);
    EXPECT_LT((parts[q] - w).norm(), 1e-12 * scale) << "step " << step << " quantity " << q;
  }
}

TEST(PhysicsLiggghts, SphereSphereOblique) {
  const PairParams p = liggghtsMaterial();
  Body a = body(0.001, Vec3(0, 0, 0), Vec3(0.5, 0.2, 0), Vec3(0, 0, 100));
  Body b = body(0.0011, Vec3(0.002, 0.00055, 0.0004), Vec3(-0.5, -0.3, 0.1), Vec3(50, -30, 20));
  const Real dt = 1e-6;
  TangentialHistory<3> h;
  int contactSteps = 0;
  for (int step = 1; step <= 700; ++step) {
    initialIntegrate(a, dt);
    initialIntegrate(b, dt);
    if (auto g = intersect(SphereShape<3>{a.x, a.r}, SphereShape<3>{b.x, b.r})) {
      ++contactSteps;
      const Vec3 armA = g->point - a.x, armB = g->point - b.x;
      const ContactKinematics<3> k{b.v + b.w.cross(armB) - a.v - a.w.cross(armA),
                                   a.mass * b.mass / (a.mass + b.mass), a.r * b.r / (a.r + b.r),
                                   0.5};
      const ContactForce<3> c = hertzMindlinContact<3>(p, *g, k, &h, dt);
      if (c.force.squaredNorm() == 0) --contactSteps;  // parting, force cut off
      b.f += c.force;
      a.f -= c.force;
      b.t += armB.cross(c.force);
      a.t -= armA.cross(c.force);
    } else {
      h = TangentialHistory<3>{};  // the contact opened: LIGGGHTS zeroes the shear
    }
    finalIntegrate(a, dt);
    finalIntegrate(b, dt);
    if (step == 150) {
      expectState(a,
                  {3.9073490784452233e-05, 1.2877267448814758e-05, -1.9481274496394357e-06,
                   -0.11174620182968066, -0.050729986681252122, -0.063760465942068092,
                   83.267463010253849, -152.74588642618454, -101.98948650701659,
                   -0.051834327976121475, -0.011838825433540515, -0.012547224439533714},
                  step);
      expectState(b,
                  {0.001951992118118368, 0.0005178645623975846, 0.00041646365698695675,
                   -0.040386024170036623, -0.11162284997651943, 0.14790418177465675,
                   106.99566245206294, -134.55399842305718, -118.25695841255548,
                   0.051834327976121475, 0.011838825433540515, 0.012547224439533714},
                  step);
    }
  }
  EXPECT_EQ(contactSteps, 258 - 12 + 1);  // the steps LIGGGHTS dumped a nonzero force
  expectState(a,
              {-0.00015786819617501403, -3.3679568465643414e-05, -7.9747104707181125e-05,
               -0.37472555887511821, -0.085997276268128475, -0.14748076490517875,
               50.865889394527841, -94.977227826232138, -24.784128990172082, 0, 0, 0},
              700);
  expectState(b,
              {0.0020315688926935103, 0.00047048803040243981, 0.00052991518009556384,
               0.15719425910978188, -0.085126013322217087, 0.21080448152154674, 84.800878009990953,
               -94.983313928328954, -65.371370050896545, 0, 0, 0},
              700);
}

TEST(PhysicsLiggghts, SphereWallObliqueWithSliding) {
  const PairParams p = liggghtsMaterial();
  Body a = body(0.001, Vec3(0, 0, 0.00102), Vec3(0.8, -0.3, -0.6), Vec3(20, -40, 300));
  const PlaneShape<3> wall{Vec3::Zero(), Vec3::UnitZ()};
  const Real dt = 1e-6;
  TangentialHistory<3> h;
  int contactSteps = 0, slidingSteps = 0;
  for (int step = 1; step <= 700; ++step) {
    initialIntegrate(a, dt);
    if (auto g = intersect(SphereShape<3>{a.x, a.r}, wall)) {
      ++contactSteps;
      const Vec3 arm = g->point - a.x;
      const ContactKinematics<3> k{-(a.v + a.w.cross(arm)), a.mass, a.r, 0.5};
      const ContactForce<3> c = hertzMindlinContact<3>(p, *g, k, &h, dt);
      if (c.frictionLoss > 1e-3 * c.elasticEnergy) ++slidingSteps;
      if (c.force.squaredNorm() == 0) --contactSteps;  // parting, force cut off
      a.f -= c.force;
      a.t -= arm.cross(c.force);
    } else {
      h = TangentialHistory<3>{};
    }
    finalIntegrate(a, dt);
    if (step == 150) {
      expectState(a,
                  {0.00010702706944627446, -4.0671375794600473e-05, 0.00094909560646129737,
                   0.56977390872686595, -0.22313513285877642, -0.19657584811203455,
                   209.25425991355212, 526.85966115112603, 300, -0.024177707910898259,
                   0.0080878383907553308, 0.050989202373039257},
                  step);
    }
  }
  EXPECT_EQ(contactSteps, 337 - 34 + 1);
  EXPECT_GT(slidingSteps, 50);  // the Coulomb cap was exercised
  expectState(a,
              {0.00039273319944543649, -0.00015407796116845358, 0.0010974439472842196,
               0.52792233019856682, -0.20901937998045561, 0.33004851612160824, 243.29115360966455,
               627.77037603158999, 300, 0, 0, 0},
              700);
}

}  // namespace physics_liggghts_test
}  // namespace demlab::physics
