// Restitution means what it says: the linear law's inverted Schwager-Poeschel relation and
// Hertz-Mindlin's calibrated damping (pair_params.hpp) against independent integrations of the
// dimensionless laws, and the rebound of head-on impacts through the real law functions (two
// grains and grain on wall) for e = 0.05 ... 0.95, with the normal force never attractive.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>

#include "physics/contact.hpp"
#include "physics/narrow_phase.hpp"
#include "physics/pair_params.hpp"

namespace demlab::physics {
namespace physics_restitution_test {

// Returns -x' when the force f(x, x') first vanishes after the turning point of
// x'' = -f(x, x'), x(0) = x0, x'(0) = v0, integrated in the variable s with t = s^p (p = 1:
// plain time; p = 4 makes Hertz's x^(1/4) smooth at t = 0) by fixed RK4 steps ds, the
// crossing found by bisecting the last step. Changes nothing.
template <class F>
double reboundOf(F force, double ds, int p) {
  struct S {
    double x, v;
  };
  const auto rate = [&](const S& y, double s, double& dx, double& dv) {
    const double dtds = p == 1 ? 1 : p * std::pow(s, p - 1);
    dx = dtds * y.v;
    dv = -dtds * force(std::max(y.x, 0.0), y.v);
  };
  const auto step = [&](const S& y, double s, double h) {
    double ax, av, bx, bv, cx, cv, dx, dv;
    rate(y, s, ax, av);
    rate({y.x + 0.5 * h * ax, y.v + 0.5 * h * av}, s + 0.5 * h, bx, bv);
    rate({y.x + 0.5 * h * bx, y.v + 0.5 * h * bv}, s + 0.5 * h, cx, cv);
    rate({y.x + h * cx, y.v + h * cv}, s + h, dx, dv);
    return S{y.x + h / 6 * (ax + 2 * bx + 2 * cx + dx), y.v + h / 6 * (av + 2 * bv + 2 * cv + dv)};
  };
  S y{0, 1};
  double s = 0;
  for (int n = 0; n < 100000000; ++n) {
    const S next = step(y, s, ds);
    if (next.v < 0 && force(std::max(next.x, 0.0), next.v) <= 0) {
      double lo = 0, hi = ds;
      for (int i = 0; i < 80; ++i) {
        const double mid = 0.5 * (lo + hi);
        const S m = step(y, s, mid);
        (force(std::max(m.x, 0.0), m.v) > 0 ? lo : hi) = mid;
      }
      return -step(y, s, 0.5 * (lo + hi)).v;
    }
    y = next;
    s += ds;
  }
  ADD_FAILURE() << "no rebound";
  return 0;
}

// The cut-off linear oscillator x'' = -x - 2 zeta x' (units of 1/omega_n and v0), integrated
// numerically, against the closed form linearRestitution inverts (Schwager and Poeschel).
TEST(PhysicsRestitution, LinearClosedFormMatchesIntegration) {
  for (double zeta : {0.01, 0.1, 0.3, 0.5, 0.9, 1.0, 1.2, 2.0, 5.0}) {
    const double e =
        reboundOf([&](double x, double v) { return x + 2 * zeta * v; }, 1e-4, 1);
    EXPECT_NEAR(linearRestitution(zeta), e, 1e-10 * (1 + zeta)) << zeta;
  }
  for (double e = 0.05; e < 0.96; e += 0.05) {
    EXPECT_NEAR(linearRestitution(linearDampingRatio(e)), e, 1e-14) << e;
  }
}

// hertzRestitution (adaptive RK4 with a series start) against fixed RK4 steps in s = t^(1/4),
// in which the solution is smooth from the touch on: two different integrations agree to 1e-9.
TEST(PhysicsRestitution, HertzCalibrationMatchesIntegration) {
  for (double c : {0.02, 0.1, 0.3, 0.6, 1.0, 2.0, 4.35}) {
    const double e = reboundOf(
        [&](double x, double v) { return x * std::sqrt(x) + c * std::sqrt(std::sqrt(x)) * v; },
        2e-4, 4);
    EXPECT_NEAR(hertzRestitution(c), e, 1e-9) << c;
  }
  EXPECT_EQ(hertzRestitution(0), 1);
  EXPECT_EQ(hertzDampingFactor(1), 0);
  // Monotone, and the inverse reproduces e.
  double lastC = INFINITY;
  for (double e = 0.05; e < 0.96; e += 0.05) {
    const double c = hertzDampingFactor(e);
    EXPECT_NEAR(hertzRestitution(c), e, 1e-11) << e;
    EXPECT_LT(hertzRestitution(c * 1.001), e);
    EXPECT_LT(c, lastC);
    lastC = c;
  }
  // Tiny e: e falls as 1.25 / c^2, so e = 1e-6 is still reached.
  EXPECT_NEAR(hertzRestitution(hertzDampingFactor(1e-6)), 1e-6, 1e-12);
}

MaterialDef material(double e) {
  MaterialDef m;
  m.density = 2500;
  m.young = 5e6;
  m.poisson = 0.3;
  m.restitution = e;
  m.friction = 0;
  return m;
}

struct Rebound {
  double e;        // -(normal relative velocity after) / (before)
  double minimum;  // the least normal force seen (N): >= 0
};

// Returns the rebound of a head-on impact at closing speed v: two equal grains (radius 1 mm,
// mass 1.05e-5 kg) or one grain on a plane wall, integrated by velocity Verlet with dt =
// tc / divisor (tc the elastic Hertz contact time, or pi / omega_n for the linear law), the
// law called through contactLawFor with the half-step velocity (velocityLag 0.5). Changes
// nothing.
Rebound impact(const PairParams& p, bool wall, double v, double divisor = 1000) {
  const ContactLawFn<3> law = contactLawFor<3>(p.law);
  const double r = 1e-3, m = 1.05e-5;
  const double mstar = wall ? m : 0.5 * m, rstar = wall ? r : 0.5 * r;
  const double tc =
      p.law == LawKind::Linear
          ? std::numbers::pi / std::sqrt(p.knPerRadius * rstar / mstar)
          : 2.868 * std::pow(mstar * mstar / (rstar * p.youngEff * p.youngEff * v), 0.2);
  const double dt = tc / divisor;
  // A moves up along z towards B (the other grain, or the wall above it).
  Vec3 xa(0, 0, 0), va(0, 0, wall ? v : 0.5 * v), xb(0, 0, wall ? r : 2 * r),
      vb(0, 0, wall ? 0 : -0.5 * v);
  const PlaneShape<3> plane{Vec3(0, 0, r), Vec3(0, 0, -1)};
  Vec3 f = Vec3::Zero();  // on B; A gets -f
  const double ma = m, mb = wall ? INFINITY : m;
  Rebound out{0, INFINITY};
  bool started = false;
  for (int n = 0; n < 10 * static_cast<int>(divisor) + 100; ++n) {
    const Vec3 ha = va - 0.5 * dt * f / ma, hb = vb + 0.5 * dt * f / mb;
    xa += dt * ha;
    xb += dt * hb;
    std::optional<ContactGeometry<3>> g;
    if (wall) {
      g = intersect(SphereShape<3>{xa, r}, plane);  // normal from A (the grain) to the wall
    } else {
      g = intersect(SphereShape<3>{xa, r}, SphereShape<3>{xb, r});
    }
    Vec3 fNew = Vec3::Zero();
    if (g) {
      started = true;
      const ContactKinematics<3> k{hb - ha, mstar, rstar, 0.5};
      fNew = law(p, *g, k, nullptr, dt).force;
      out.minimum = std::min(out.minimum, fNew.dot(g->normal));
    } else if (started) {
      out.e = (hb - ha).z() / v;  // no force in this step: ha, hb are the velocities after
      return out;
    }
    va = ha - 0.5 * dt * fNew / ma;
    vb = hb + 0.5 * dt * fNew / mb;
    f = fNew;
  }
  ADD_FAILURE() << "no separation";
  return out;
}

// Returns the pair of one material with restitution e under `law` and `damping`.
PairParams pairOf(LawKind law, double e, HertzDamping damping = HertzDamping::Calibrated) {
  return mixPair(law, material(e), material(e), damping);
}

// e_out = e_in to 1e-3 at dt = tc/1000 for both laws, two grains and grain on wall (velocity
// Verlet's error in e is first order in dt here: ~1e-4 at this step, 6e-4 at tc/200), and
// the normal force is never negative. Printed: the LIGGGHTS damping's rebound for comparison.
TEST(PhysicsRestitution, HeadOnReboundIsTheAskedRestitution) {
  for (double e = 0.05; e < 0.96; e += 0.05) {
    for (bool wall : {false, true}) {
      for (LawKind law : {LawKind::Linear, LawKind::HertzMindlin}) {
        SCOPED_TRACE(::testing::Message() << lawName(law) << " e=" << e << " wall=" << wall);
        const Rebound r = impact(pairOf(law, e), wall, 1.0);
        EXPECT_NEAR(r.e, e, 1e-3);
        EXPECT_GE(r.minimum, 0);
      }
    }
    const double old = impact(pairOf(LawKind::HertzMindlin, e, HertzDamping::Liggghts), false, 1).e;
    std::printf("e %.2f: hertz liggghts damping rebounds with %.4f (cut-off ODE %.4f)\n", e, old,
                hertzRestitution(-std::sqrt(5.0) * liggghtsBeta(e)));
    // The integrated impact follows the dimensionless law (pair_params.hpp) to the same 1e-3.
    EXPECT_NEAR(old, hertzRestitution(-std::sqrt(5.0) * liggghtsBeta(e)), 1e-3);
  }
}

TEST(PhysicsRestitution, ElasticReboundIsOne) {
  for (bool wall : {false, true}) {
    for (LawKind law : {LawKind::Linear, LawKind::HertzMindlin}) {
      for (HertzDamping d : {HertzDamping::Calibrated, HertzDamping::Liggghts}) {
        const PairParams p = pairOf(law, 1, d);
        EXPECT_EQ(p.hertzGammaN, 0);
        EXPECT_NEAR(impact(p, wall, 1.0).e, 1, 1e-5) << lawName(law) << wall;
      }
    }
  }
}

// The damping form makes Hertz's restitution independent of the impact speed, calibrated or
// not: 1e-3 to 10 m/s (each run at tc(v)/1000) rebound alike.
TEST(PhysicsRestitution, HertzReboundIndependentOfSpeed) {
  for (double e : {0.1, 0.5, 0.9}) {
    for (HertzDamping d : {HertzDamping::Calibrated, HertzDamping::Liggghts}) {
      const PairParams p = pairOf(LawKind::HertzMindlin, e, d);
      const double ref = impact(p, false, 1.0).e;
      for (double v : {1e-3, 1e-2, 1e-1, 10.0}) {
        EXPECT_NEAR(impact(p, false, v).e, ref, 2e-5) << e << " " << v;
      }
    }
  }
}

// The choice: LIGGGHTS's beta when asked for, and the Calibrated pair differs from it only in
// the dampers.
TEST(PhysicsRestitution, DampingChoiceChangesOnlyTheDampers) {
  const PairParams cal = pairOf(LawKind::HertzMindlin, 0.3);
  const PairParams lig = pairOf(LawKind::HertzMindlin, 0.3, HertzDamping::Liggghts);
  const double ystar = cal.youngEff;
  EXPECT_NEAR(lig.hertzGammaN, -2 * std::sqrt(5.0 / 6.0) * liggghtsBeta(0.3) * std::sqrt(2 * ystar),
              1e-14 * lig.hertzGammaN);
  EXPECT_NEAR(cal.hertzGammaN,
              2 * std::sqrt(5.0 / 6.0) * hertzDampingFactor(0.3) / std::sqrt(5.0) *
                  std::sqrt(2 * ystar),
              1e-14 * cal.hertzGammaN);
  EXPECT_GT(cal.hertzGammaN, lig.hertzGammaN);
  EXPECT_NEAR(cal.hertzGammaT / cal.hertzGammaN, lig.hertzGammaT / lig.hertzGammaN, 1e-14);
  EXPECT_EQ(cal.hertzKn, lig.hertzKn);
  EXPECT_EQ(cal.dampingRatio, lig.dampingRatio);
  EXPECT_EQ(hertzDampingName(HertzDamping::Calibrated), "calibrated");
  EXPECT_EQ(hertzDampingName(HertzDamping::Liggghts), "liggghts");
}

}  // namespace physics_restitution_test
}  // namespace demlab::physics
