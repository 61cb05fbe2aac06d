// Single calls of the contact laws against their formulas: LIGGGHTS's Hertz-Mindlin constants,
// the linear law's stiffness, the Coulomb cap and the sliding loss, the history's frame
// (rotated or projected into the tangent plane), the cut-off of attraction, and the law table.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

#include "core/error.hpp"
#include "physics/contact.hpp"
#include "physics/law_hertz_mindlin.hpp"
#include "physics/law_linear.hpp"
#include "physics/pair_params.hpp"

namespace demlab::physics {
namespace physics_law_test {

PairParams pair(LawKind law, Real e = 0.5, Real mu = 0.5,
                CoulombCriterion coulomb = CoulombCriterion::Total,
                HertzDamping damping = HertzDamping::Calibrated) {
  MaterialDef m;
  m.density = 2500;
  m.young = 5e6;
  m.poisson = 0.3;
  m.restitution = e;
  m.friction = mu;
  PairParams p = mixPair(law, m, m, damping);
  p.coulomb = coulomb;
  return p;
}

TEST(PhysicsLaw, HertzMatchesLiggghtsFormulas) {
  const PairParams p =
      pair(LawKind::HertzMindlin, 0.5, 0.5, CoulombCriterion::Spring, HertzDamping::Liggghts);
  const Real ystar = 5e6 / (2 * (1 - 0.09)), gstar = 5e6 / (4 * 1.7 * 1.3);
  const Real delta = 3e-6, rstar = 5e-4, mstar = 5e-6, vn = -0.3, dt = 1e-6;
  const Vec3 n(0, 0, 1), vt(0.2, -0.1, 0);
  const Real lnE = std::log(0.5),
             beta = lnE / std::sqrt(lnE * lnE + std::numbers::pi * std::numbers::pi);
  // LIGGGHTS normal_model_hertz.h, written out independently.
  const Real sn = 2 * ystar * std::sqrt(rstar * delta), st = 8 * gstar * std::sqrt(rstar * delta);
  const Real kn = 4.0 / 3.0 * ystar * std::sqrt(rstar * delta), kt = st;
  const Real gn = -2 * std::sqrt(5.0 / 6.0) * beta * std::sqrt(sn * mstar);
  const Real gt = -2 * std::sqrt(5.0 / 6.0) * beta * std::sqrt(st * mstar);
  const Real fn = kn * delta - gn * vn;
  TangentialHistory<3> h;
  const ContactForce<3> f =
      hertzMindlinContact<3>(p, ContactGeometry<3>{n, delta, Vec3::Zero()},
                             ContactKinematics<3>{vn * n + vt, mstar, rstar}, &h, dt);
  EXPECT_NEAR(f.force.dot(n), fn, 1e-12 * fn);
  // First step of the history: shear = vt dt, sticking (kt |shear| < mu Fn), Ft = -kt s - gt vt.
  ASSERT_LT(kt * (vt * dt).norm(), 0.5 * fn);
  const Vec3 ft = -kt * vt * dt - gt * vt;
  EXPECT_NEAR((f.force - f.force.dot(n) * n - ft).norm(), 0, 1e-12 * ft.norm());
  EXPECT_NEAR((h.spring - vt * dt).norm(), 0, 1e-20);
  EXPECT_NEAR(f.elasticEnergy, 0.4 * kn * delta * delta + 0.5 * kt * (vt * dt).squaredNorm(),
              1e-12 * f.elasticEnergy);
  EXPECT_NEAR(f.dampingLoss, -(fn - kn * delta) * vn * dt + gt * vt.squaredNorm() * dt,
              1e-12 * f.dampingLoss);
}

TEST(PhysicsLaw, LinearStiffnessFromYoungAndExplicit) {
  const PairParams p = pair(LawKind::Linear, 1.0, 0.0);
  const Real rstar = 7e-4, delta = 1e-6;
  const Vec3 n(1, 0, 0);
  const ContactForce<3> f =
      linearContact<3>(p, ContactGeometry<3>{n, delta, Vec3::Zero()},
                       ContactKinematics<3>{Vec3::Zero(), 1e-5, rstar}, nullptr, 1e-6);
  const Real kn = 5e6 / (2 * (1 - 0.09)) * rstar;  // E* R*
  EXPECT_NEAR(f.force.x(), kn * delta, 1e-12 * kn * delta);
  EXPECT_NEAR(f.elasticEnergy, 0.5 * kn * delta * delta, 1e-12 * kn * delta * delta);
  MaterialDef m;
  m.density = 2500;
  m.young = 5e6;
  m.poisson = 0.3;
  m.restitution = 1;
  m.friction = 0;
  m.normalStiffness = 1234;
  const PairParams q = mixPair(LawKind::Linear, m, m);
  const ContactForce<2> g =
      linearContact<2>(q, ContactGeometry<2>{Vec2(0, 1), delta, Vec2::Zero()},
                       ContactKinematics<2>{Vec2::Zero(), 1e-5, rstar}, nullptr, 1e-6);
  EXPECT_NEAR(g.force.y(), 1234 * delta, 1e-15);
}

// Holds an overlap and slides B over A at constant tangential speed; after the spring reaches
// the Coulomb limit the force is mu Fn and each step dissipates mu Fn |vt| dt. With the Total
// criterion |Ft| <= mu Fn at every step and no step loses energy it did not have; with Spring
// (LIGGGHTS) the first steps stick, with the dashpot's force on top of the spring's.
template <int D, class Law>
void coulombCap(Law law, const PairParams& p) {
  const Real delta = 2e-6, rstar = 5e-4, mstar = 5e-6, dt = 1e-7;
  VecD<D> n = VecD<D>::Zero();
  n[D - 1] = 1;
  VecD<D> vt = VecD<D>::Zero();
  vt[0] = 0.05;
  TangentialHistory<D> h;
  ContactForce<D> f{};
  const ContactGeometry<D> g{n, delta, VecD<D>::Zero()};
  const ContactKinematics<D> k{vt, mstar, rstar};
  f = law(p, g, k, &h, dt);
  const Real fn = f.force.dot(n);
  auto tangential = [&] { return (f.force - f.force.dot(n) * n).norm(); };
  if (p.coulomb == CoulombCriterion::Spring) {
    // Sticking: the tangential force -kt s - ct vt, no friction loss, above mu Fn here.
    EXPECT_EQ(f.frictionLoss, 0);
    EXPECT_GT(tangential(), p.friction * fn);
  }
  const Real limitLoss = p.friction * fn * vt.norm() * dt;
  int steps = 0;
  while (std::abs(f.frictionLoss - limitLoss) > 1e-9 * limitLoss && steps < 100000) {
    if (p.coulomb == CoulombCriterion::Total) {
      EXPECT_LE(tangential(), p.friction * fn * (1 + 1e-12)) << "step " << steps;
      EXPECT_GE(f.frictionLoss, 0) << "step " << steps;
    }
    f = law(p, g, k, &h, dt), ++steps;
  }
  ASSERT_LT(steps, 100000);
  for (int i = 0; i < 10; ++i) f = law(p, g, k, &h, dt);
  const VecD<D> ft = f.force - f.force.dot(n) * n;
  EXPECT_NEAR(ft.norm(), p.friction * fn, 1e-12 * fn);
  EXPECT_LT(ft.dot(vt), 0);  // opposes the sliding
  EXPECT_NEAR(f.frictionLoss, p.friction * fn * vt.norm() * dt, 1e-9 * f.frictionLoss);
  EXPECT_EQ(f.dampingLoss, 0);  // vn = 0, and the tangential dashpot is off while sliding
  // The stored spring is at the limit: energy (mu Fn)^2 / (2 kt) on top of the normal spring.
  EXPECT_NEAR(h.spring.norm() * ft.norm(),
              2 * (f.elasticEnergy - 0.5 * fn * delta * (p.law == LawKind::HertzMindlin ? 0.8 : 1)),
              1e-9 * h.spring.norm() * ft.norm());
}

TEST(PhysicsLaw, CoulombCapAndSlidingLoss) {
  for (CoulombCriterion c : {CoulombCriterion::Total, CoulombCriterion::Spring}) {
    SCOPED_TRACE(std::string(coulombCriterionName(c)));
    coulombCap<3>(&linearContact<3>, pair(LawKind::Linear, 0.5, 0.5, c));
    coulombCap<2>(&linearContact<2>, pair(LawKind::Linear, 0.5, 0.5, c));
    coulombCap<3>(&hertzMindlinContact<3>, pair(LawKind::HertzMindlin, 0.5, 0.5, c));
    coulombCap<2>(&hertzMindlinContact<2>, pair(LawKind::HertzMindlin, 0.9, 0.3, c));
  }
}

// Random contact states (springs of any length and direction, tangential velocities of any
// size, approaching and separating): with the Total criterion the tangential force never
// exceeds mu Fn and only a spring turning back books a negative loss; with Spring the first
// can fail.
TEST(PhysicsLaw, TotalCriterionHoldsCoulombEverywhere) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Real> u(-1, 1), pos(0, 1);
  int springExceeded = 0;
  for (LawKind law : {LawKind::Linear, LawKind::HertzMindlin}) {
    for (CoulombCriterion c : {CoulombCriterion::Total, CoulombCriterion::Spring}) {
      const PairParams p = pair(law, 0.3, 0.4, c);
      for (int trial = 0; trial < 4000; ++trial) {
        const Vec3 n = Vec3(u(rng), u(rng), u(rng)).normalized();
        const Real delta = 1e-6 + 1e-5 * pos(rng), rstar = 5e-4, mstar = 5e-6, dt = 1e-6;
        Vec3 v(u(rng), u(rng), u(rng));
        v *= std::pow(10.0, 2 * u(rng));  // 0.01 to 100 m/s
        TangentialHistory<3> h;
        const Vec3 s0(u(rng), u(rng), u(rng));
        h.spring = (s0 - s0.dot(n) * n) * 1e-6 * pos(rng);
        const Vec3 h0 = h.spring;
        const ContactForce<3> f =
            law == LawKind::Linear
                ? linearContact<3>(p, ContactGeometry<3>{n, delta, Vec3::Zero()},
                                   ContactKinematics<3>{v, mstar, rstar}, &h, dt)
                : hertzMindlinContact<3>(p, ContactGeometry<3>{n, delta, Vec3::Zero()},
                                         ContactKinematics<3>{v, mstar, rstar}, &h, dt);
        const Real fn = f.force.dot(n), ft = (f.force - fn * n).norm();
        if (c == CoulombCriterion::Total) {
          ASSERT_LE(ft, p.friction * fn * (1 + 1e-12) + 1e-300) << "trial " << trial;
          // A loss below 0 (the trapezoid identity's share, tangential.hpp) only where the
          // spring turns back within the step (these springs have no step yet: u = vt dt).
          const Vec3 reach = h0 + (v - v.dot(n) * n) * dt;
          if (f.frictionLoss < -1e-12 * f.elasticEnergy) {
            ASSERT_LT(h0.dot(reach), 0) << "trial " << trial;
          }
        } else if (ft > p.friction * fn * (1 + 1e-9)) {
          ++springExceeded;
        }
      }
    }
  }
  EXPECT_GT(springExceeded, 100) << "the states never make the dashpot exceed the limit";
}

// Turns the normal by `angle` per step about an axis, with no relative velocity: the stored
// spring must stay in the tangent plane; the linear law keeps its length (Rotate), Hertz-Mindlin
// drops the normal component (Project) and books that energy as friction loss.
TEST(PhysicsLaw, HistoryFollowsTheTangentPlane) {
  for (Real angle : {1e-4, 2e-3, 0.3}) {
    for (LawKind kind : {LawKind::Linear, LawKind::HertzMindlin}) {
      const PairParams p = pair(kind, 1.0, 100.0);  // high mu: never slides
      const ContactLawFn<3> law = contactLawFor<3>(kind);
      const Vec3 axis = Vec3(1, 2, 0.5).normalized();
      Vec3 n = axis.cross(Vec3(0, 0, 1)).normalized();
      TangentialHistory<3> h;
      h.spring = 1e-7 * (axis + 0.3 * axis.cross(n)).normalized();  // in the plane, not along axis
      Real len = h.spring.norm();
      const Quat turn(AngleAxis(angle, axis));
      for (int i = 0; i < 50; ++i) {
        n = turn * n;
        const Vec3 before = h.spring;
        const ContactForce<3> f = law(p, ContactGeometry<3>{n, 1e-6, Vec3::Zero()},
                                      ContactKinematics<3>{Vec3::Zero(), 1e-5, 5e-4}, &h, 1e-7);
        EXPECT_LT(std::abs(h.spring.dot(n)), 1e-12 * h.spring.norm()) << angle;
        if (kind == LawKind::Linear) {
          EXPECT_NEAR(h.spring.norm(), len, 1e-12 * len) << angle;
          // The spring turns with the frame: its component along the turning axis stays, to
          // the O(angle^2) by which dropping the normal part and restoring the length differs
          // from the exact rotation (which would need the previous normal).
          EXPECT_NEAR(h.spring.dot(axis), before.dot(axis), angle * angle * len) << angle;
          const Real kt = p.shearRatio * (p.knFixed + p.knPerRadius * 5e-4);
          EXPECT_NEAR(f.frictionLoss, 0, 1e-12 * kt * len * len) << angle;  // rounding
        } else {
          const Real sn = before.dot(n);
          EXPECT_NEAR(h.spring.norm(), std::sqrt(before.squaredNorm() - sn * sn), 1e-12 * len);
          const Real kt = p.hertzKt * std::sqrt(5e-4 * 1e-6);
          EXPECT_NEAR(f.frictionLoss, 0.5 * kt * sn * sn, 1e-9 * kt * len * len + 1e-30);
          len = h.spring.norm();
        }
      }
    }
  }
}

// A contact's first step under synchronized velocities (no drift velocity yet) adds to its
// spring only the part of the step's tangential displacement made while touching: the overlap
// over what the step's approach added. Later steps, plain Verlet's contacts, and a contact
// already touching at the step's start add the whole step's.
TEST(PhysicsLaw, NewContactSpringStartsAtTheTouch) {
  const Real dt = 1e-6, vn = -0.5, vt = 0.2;
  const Vec3 n(0, 0, 1);
  for (LawKind kind : {LawKind::Linear, LawKind::HertzMindlin}) {
    const PairParams p = pair(kind, 0.5, 100.0);  // high mu: sticks
    const ContactLawFn<3> law = contactLawFor<3>(kind);
    const ContactKinematics<3> sync{Vec3(vt, 0, vn), 1e-5, 5e-4, 0.0};
    for (Real share : {0.1, 0.3, 0.9}) {
      SCOPED_TRACE(share);
      const Real overlap = share * -vn * dt;  // touching for `share` of the step
      TangentialHistory<3> h;
      law(p, ContactGeometry<3>{n, overlap, Vec3::Zero()}, sync, &h, dt);
      EXPECT_NEAR(h.spring.x(), share * vt * dt, 1e-12 * vt * dt);
      EXPECT_EQ(h.spring.y(), 0);
      // The next step: the whole step's displacement (the drift now known, equal to vS).
      const Real before = h.spring.x();
      law(p, ContactGeometry<3>{n, overlap - vn * dt, Vec3::Zero()}, sync, &h, dt);
      EXPECT_NEAR(h.spring.x() - before, vt * dt, 1e-12 * vt * dt);
      // Plain Verlet's contacts carry no first-step mark: the whole step.
      TangentialHistory<3> v;
      ContactKinematics<3> verlet = sync;
      verlet.velocityLag = 0.5;
      law(p, ContactGeometry<3>{n, overlap, Vec3::Zero()}, verlet, &v, dt);
      EXPECT_NEAR(v.spring.x(), vt * dt, 1e-12 * vt * dt);
    }
    // Touching at the step's start already (a new slot for an old contact): the whole step.
    TangentialHistory<3> h;
    law(p, ContactGeometry<3>{n, 2 * -vn * dt, Vec3::Zero()}, sync, &h, dt);
    EXPECT_NEAR(h.spring.x(), vt * dt, 1e-12 * vt * dt);
  }
  EXPECT_EQ(touchingFraction(1.0, -4.0, 1.0), 0.25);
  EXPECT_EQ(touchingFraction(1.0, 2.0, 1.0), 1.0);  // parting: not a touch
  EXPECT_EQ(touchingFraction(1.0, -1.0, 1.0), 1.0);  // touching at the start (overlap 0)
}

TEST(PhysicsLaw, HistoryInTwoDimensionsKeepsItsSide) {
  const PairParams p = pair(LawKind::Linear, 1.0, 100.0);
  TangentialHistory<2> h;
  Real phi = 0.4;
  h.spring = 3e-8 * perp(Vec2(std::cos(phi), std::sin(phi)));
  for (int i = 0; i < 200; ++i) {
    phi += 0.01;
    const Vec2 n(std::cos(phi), std::sin(phi));
    linearContact<2>(p, ContactGeometry<2>{n, 1e-6, Vec2::Zero()},
                     ContactKinematics<2>{Vec2::Zero(), 1e-5, 5e-4}, &h, 1e-7);
    EXPECT_NEAR(h.spring.dot(perp(n)), 3e-8, 1e-20);  // rotated with the normal, same length
  }
}

TEST(PhysicsLaw, NoAttractionAndNoHistoryMeansNormalOnly) {
  for (LawKind kind : {LawKind::Linear, LawKind::HertzMindlin}) {
    const PairParams p = pair(kind, 0.3, 0.5);
    const Vec3 n(0, 1, 0);
    // Parting fast with a small overlap: spring < damper, the force is cut off at 0.
    const ContactKinematics<3> k{Vec3(0.3, 5.0, 0), 1e-5, 5e-4, 0.5};
    TangentialHistory<3> h;
    h.spring = Vec3(1e-9, 0, 0);
    const ContactForce<3> f =
        evaluateContact<3>(p, ContactGeometry<3>{n, 1e-9, Vec3::Zero()}, k, &h, 1e-7);
    EXPECT_EQ(f.force.dot(n), 0);
    EXPECT_EQ(f.force.norm(), 0);  // Coulomb limit mu * 0
    // The spring's energy leaves through the damper: loss = spring force * vn * dt.
    const Real springForce = kind == LawKind::Linear ? p.knPerRadius * 5e-4 * 1e-9
                                                     : p.hertzKn * std::sqrt(5e-4 * 1e-9) * 1e-9;
    EXPECT_NEAR(f.dampingLoss, springForce * 5.0 * 1e-7, 1e-9 * springForce * 5e-7);
    // No history: purely normal force even with tangential motion.
    const ContactKinematics<3> slow{Vec3(0.3, -0.1, 0), 1e-5, 5e-4};
    const ContactForce<3> g =
        evaluateContact<3>(p, ContactGeometry<3>{n, 1e-6, Vec3::Zero()}, slow, nullptr, 1e-7);
    EXPECT_GT(g.force.y(), 0);
    EXPECT_EQ(g.force.x(), 0);
    EXPECT_EQ(g.force.z(), 0);
    // A frictionless pair with a history clears the spring and adds no tangential force.
    const PairParams q = pair(kind, 0.3, 0.0);
    h.spring = Vec3(1e-9, 0, 0);
    const ContactForce<3> z =
        evaluateContact<3>(q, ContactGeometry<3>{n, 1e-6, Vec3::Zero()}, slow, &h, 1e-7);
    EXPECT_EQ(z.force.x(), 0);
    EXPECT_EQ(h.spring.norm(), 0);
  }
}

TEST(PhysicsLaw, LawTableMatchesSwitch) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (LawKind kind : {LawKind::Linear, LawKind::HertzMindlin}) {
    const PairParams p = pair(kind);
    for (int i = 0; i < 100; ++i) {
      const Vec3 n = Vec3(u(rng), u(rng), u(rng)).normalized();
      const ContactGeometry<3> g{n, 1e-6 * (1.5 + u(rng)), Vec3::Zero()};
      const ContactKinematics<3> k{Vec3(u(rng), u(rng), u(rng)), 1e-5, 5e-4};
      TangentialHistory<3> h1, h2;
      h1.spring = h2.spring = 1e-8 * Vec3(u(rng), u(rng), u(rng));
      const ContactForce<3> a = contactLawFor<3>(kind)(p, g, k, &h1, 1e-7);
      const ContactForce<3> b = evaluateContact<3>(p, g, k, &h2, 1e-7);
      // The bytes of the figures before the flag (past it: padding).
      const size_t figures = static_cast<size_t>(reinterpret_cast<const char*>(&a.cutOff) -
                                                 reinterpret_cast<const char*>(&a));
      EXPECT_EQ(std::memcmp(&a, &b, figures), 0);
      EXPECT_EQ(a.cutOff, b.cutOff);
      EXPECT_EQ(h1.spring, h2.spring);
    }
  }
  try {
    contactLawFor<2>(static_cast<LawKind>(99));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "LOOKUP", "LAW"}));
  }
}

}  // namespace physics_law_test
}  // namespace demlab::physics
