// criticalTimeStep is the real stability limit: two equal grains pressed together by opposite
// constant forces oscillate about a static overlap and never part; velocity Verlet with the
// damper seeing the half-step velocity has the characteristic polynomial
// l^2 - (2 - h^2 - 2 zeta h) l + (1 - 2 zeta h), h = omega dt, stable exactly for
// h < 2(sqrt(1 + zeta^2) - zeta); with the damper seeing the synchronized estimate
// v(t+dt/2) + a(t) dt/2 (the default integrator) the limit is the same with 2 zeta
// (dampedStepFactor). Just below the step the oscillation decays, just above it grows until
// the grains part.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/contact.hpp"
#include "physics/critical_step.hpp"
#include "physics/narrow_phase.hpp"

namespace demlab::physics {
namespace physics_time_step_test {

// Returns the largest |overlap - static overlap| over the last 200 of `steps` steps over the
// starting offset, or +inf once the grains part. The pair starts 10 % of the static
// overlap off its equilibrium, well inside the range where the force is never cut off.
Real pressedPair(const PairParams& p, Real mass, Real r, Real dt, int steps, bool synchronized) {
  const ContactLawFn<2> law = contactLawFor<2>(p.law);
  const Real kn = p.knFixed + p.knPerRadius * r / 2;
  const Real f0 = kn * 1e-5;  // static overlap 1e-5
  Vec2 xa(0, 0), xb(2 * r - 1.1e-5, 0), va = Vec2::Zero(), vb = Vec2::Zero();
  // The contact force on B, from the start (a first kick without it would itself shake the
  // pair by more than the static overlap).
  Vec2 f = law(p, *intersect(SphereShape<2>{xa, r}, SphereShape<2>{xb, r}),
               ContactKinematics<2>{Vec2::Zero(), mass / 2, r / 2, synchronized ? 0.0 : 0.5},
               nullptr, dt)
               .force;
  Real last = 0;
  for (int n = 0; n < steps; ++n) {
    const Vec2 ha = va + 0.5 * dt * (Vec2(f0, 0) - f) / mass;
    const Vec2 hb = vb + 0.5 * dt * (Vec2(-f0, 0) + f) / mass;
    xa += dt * ha;
    xb += dt * hb;
    const auto g = intersect(SphereShape<2>{xa, r}, SphereShape<2>{xb, r});
    if (!g) return std::numeric_limits<Real>::infinity();
    // Synchronized: the half-step velocities plus half a step of the last accelerations.
    const Vec2 v = synchronized ? Vec2(hb - ha + dt * (f - Vec2(f0, 0)) / mass) : Vec2(hb - ha);
    f = law(p, *g, ContactKinematics<2>{v, mass / 2, r / 2, synchronized ? 0.0 : 0.5}, nullptr, dt)
            .force;
    va = ha + 0.5 * dt * (Vec2(f0, 0) - f) / mass;
    vb = hb + 0.5 * dt * (Vec2(-f0, 0) + f) / mass;
    const Real offset = std::abs(g->overlap - 1e-5);
    if (n >= steps - 200) last = std::max(last, offset);
  }
  return last / 1e-6;
}

TEST(PhysicsTimeStep, CriticalStepIsTheStabilityLimit) {
  for (Real e : {1.0, 0.5, 0.1}) {
    MaterialDef m;
    m.density = 2500;
    m.young = 5e6;
    m.poisson = 0.3;
    m.restitution = e;
    m.friction = 0;
    const PairParams p = mixPair(LawKind::Linear, m, m);
    const Real mass = 1e-5, r = 1e-3;
    for (bool synchronized : {false, true}) {
      const Real dc = criticalTimeStep(p, mass, r, synchronized);
      const Real below = pressedPair(p, mass, r, 0.98 * dc, 3000, synchronized);
      const Real above = pressedPair(p, mass, r, 1.02 * dc, 3000, synchronized);
      EXPECT_LE(below, 1.01) << e << synchronized;  // bounded (decaying when damped)
      // Growing, until parting or the cut-off stops it: the alternating mode's damper force
      // 2 c A/dt exceeds the spring's kn delta0 once A > delta0 omega dt / (4 zeta), which for
      // the overdamped e = 0.1 is 1.3 times the starting offset. With synchronized velocities
      // that pair's cut-off holds the mode at 0.6 of the offset: a lasting oscillation where
      // just below the limit it decays to 1e-12.
      EXPECT_GT(above, synchronized && e < 0.2 ? 0.5 : 1.2) << e << synchronized;
      std::printf("critical step e=%.1f %s: amplitude ratio %.3g at 0.98 dt_c, %.3g at 1.02 dt_c\n",
                  e, synchronized ? "synchronized" : "verlet", below, above);
    }
  }
}

TEST(PhysicsTimeStep, FrictionAddsTheRotationalMode) {
  MaterialDef m;
  m.density = 2500;
  m.young = 5e6;
  m.poisson = 0.3;
  m.restitution = 0.5;
  m.friction = 0;
  const Real frictionless = criticalTimeStep(mixPair(LawKind::Linear, m, m), 1e-5, 1e-3, false);
  m.friction = 0.5;
  const Real frictional = criticalTimeStep(mixPair(LawKind::Linear, m, m), 1e-5, 1e-3, false);
  // 7 kt/m against 2 kn/m with kt/kn = 2(1 - nu)/(2 - nu): ratio sqrt(2 / (7 * 0.8235)).
  EXPECT_NEAR(frictional / frictionless, std::sqrt(2 / (7 * 1.4 / 1.7)), 1e-12);
}

}  // namespace physics_time_step_test
}  // namespace demlab::physics
