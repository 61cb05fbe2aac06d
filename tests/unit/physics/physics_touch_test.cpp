// The touch correction's formulas (physics/touch.hpp) against hand-worked answers.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/touch.hpp"

namespace demlab::physics {
namespace physics_touch_test {

PairParams linear(Real kn, Real zeta) {
  PairParams p;
  p.law = LawKind::Linear;
  p.knFixed = kn;
  p.dampingRatio = zeta;
  return p;
}

TEST(PhysicsTouch, HurwitzZeta) {
  for (double a : {0.05, 0.3, 0.5, 1.0}) {
    EXPECT_NEAR(hurwitzZeta(0, a), 0.5 - a, 1e-13) << a;
    EXPECT_NEAR(hurwitzZeta(-1, a), -(a * a - a + 1.0 / 6) / 2, 1e-13) << a;
  }
  // mpmath.zeta(-1.5), zeta(-1.5, 0.3), zeta(-0.25, 0.7).
  EXPECT_NEAR(hurwitzZeta(-1.5, 1), -0.025485201889833, 1e-13);
  EXPECT_NEAR(hurwitzZeta(-1.5, 0.3), -0.00818556048583598, 1e-13);
  EXPECT_NEAR(hurwitzZeta(-0.25, 0.7), -0.0812018699984099, 1e-13);
}

// The event powers by square roots agree with pow to an ulp or two, over the arguments the
// zeta sums and the weights take (0 < x <= 11).
TEST(PhysicsTouch, EventPowerIsPow) {
  for (double p : {1.5, 0.25, 0.5, 1.25}) {
    for (double x = 1e-6; x <= 11; x *= 1.37) {
      const double want = std::pow(x, p);
      EXPECT_NEAR(eventPower(x, p), want, 4e-16 * want) << p << " " << x;
    }
  }
}

TEST(PhysicsTouch, ZeroFraction) {
  EXPECT_DOUBLE_EQ(zeroFraction(-1, 3), 0.75);  // rising: the last 3/4 of the step
  EXPECT_DOUBLE_EQ(zeroFraction(3, -1), 0.75);  // falling: the first 3/4
  EXPECT_DOUBLE_EQ(zeroFraction(1, 3), 1);      // no zero inside: clamped
  EXPECT_DOUBLE_EQ(zeroFraction(0, 0), 1);
}

// An elastic linear contact touching at 0.3 of the step (overlap -3 then 7 um, 1 m/s): the
// kick gave F dt/2, the contact acted for 0.7 dt, so the impulse changes by F (0.35 - 0.5) dt,
// plus the kink's end term dt^2 kn |vn| / 12; the release mirrors it.
TEST(PhysicsTouch, ElasticLinearTouchAndRelease) {
  const Real kn = 1e4, dt = 1e-5, m = 0.01, R = 0.005;
  const PairParams p = linear(kn, 0);
  const TouchCorrection t = touchCorrection(p, m, R, dt, 0, {false, -3e-6, -1}, {true, 7e-6, -1});
  const Real F = kn * 7e-6;
  EXPECT_NEAR(t.impulse, F * (0.35 - 0.5) * dt + dt * dt * kn / 12, 1e-18);
  EXPECT_TRUE(t.atEnd);
  EXPECT_EQ(t.loss, 0);
  const TouchCorrection r = touchCorrection(p, m, R, dt, 0, {true, 7e-6, 1}, {false, -3e-6, 1});
  EXPECT_NEAR(r.impulse, F * (0.35 - 0.5) * dt + dt * dt * kn / 12, 1e-18);
  EXPECT_FALSE(r.atEnd);
  // Touching at both ends: nothing to correct; apart at both: nothing.
  EXPECT_FALSE(touchCorrection(p, m, R, dt, 0, {true, 1e-6, -1}, {true, 2e-6, -1}).any());
  EXPECT_FALSE(touchCorrection(p, m, R, dt, 0, {false, -1e-6, 1}, {false, -2e-6, 1}).any());
}

// A damped linear touch: the damper's force c |vn| is a jump (power 0): it acted for T, the
// kick gave it dt/2; the ledger's damping loss gets the same share of its power c vn^2.
TEST(PhysicsTouch, DampedLinearTouchBooksTheDamperShare) {
  const Real kn = 1e4, dt = 1e-5, m = 0.01, R = 0.005, zeta = 0.2;
  const PairParams p = linear(kn, zeta);
  const Real c = 2 * zeta * std::sqrt(m * kn);
  const TouchCorrection t = touchCorrection(p, m, R, dt, 0, {false, -8e-6, -1}, {true, 2e-6, -1});
  const Real T = 0.2 * dt;
  EXPECT_NEAR(t.impulse, kn * 2e-6 * (T / 2 - dt / 2) + c * (T - dt / 2) + dt * dt * kn / 12,
              1e-18);
  EXPECT_NEAR(t.loss, c * (T - dt / 2), 1e-18);
}

// A damped force reaching its cut-off while the grains still overlap: the gap kn delta - c vn
// falls from 2 to -2 (in units of kn um) across the step, so the force acted for half of it,
// and its slope at the cut-off is F0 / (dt / 2).
TEST(PhysicsTouch, DampedCutOffRelease) {
  const Real kn = 1e4, dt = 1e-5, m = 0.01, R = 0.005, zeta = 0.2;
  const PairParams p = linear(kn, zeta);
  const Real c = 2 * zeta * std::sqrt(m * kn);
  // vn chosen so that kn delta - c vn = kn (2 um) at t0 and -kn (2 um) at t1.
  const Real vn = kn * 4e-6 / c;
  const TouchCorrection r = touchCorrection(p, m, R, dt, 0, {true, 6e-6, vn}, {true, 2e-6, vn});
  const Real F0 = kn * 2e-6;
  EXPECT_NEAR(r.impulse, F0 * (0.5 * dt / 2 - dt / 2) + dt * dt * (F0 / (0.5 * dt)) / 12, 1e-18);
  EXPECT_EQ(r.loss, 0);
}

// Hertz: the spring (power 3/2) and the damper (power 1/4) at a touch half-way through the step:
// -F dt zeta(-p, 1/2) / (1/2)^p each, zeta(s, 1/2) = (2^s - 1) zeta(s).
TEST(PhysicsTouch, HertzTouchPowers) {
  PairParams p;
  p.law = LawKind::HertzMindlin;
  p.hertzKn = 1e8;
  p.hertzGammaN = 50;
  const Real dt = 1e-6, m = 0.01, R = 0.005, d1 = 1e-7, vn = -0.2;
  const TouchCorrection t = touchCorrection(p, m, R, dt, 0, {false, -1e-7, vn}, {true, d1, vn});
  const NormalTerms n = normalTerms(p, d1, vn, m, R);
  const Real z15 = (std::pow(2.0, -1.5) - 1) * -0.025485201889833;  // zeta(-1.5, 1/2)
  const Real z025 = hurwitzZeta(-0.25, 0.5);
  EXPECT_NEAR(z025, (std::pow(2.0, -0.25) - 1) * hurwitzZeta(-0.25, 1), 1e-13);
  EXPECT_NEAR(t.impulse,
              -dt * (n.spring * z15 / std::pow(0.5, 1.5) + n.damper * z025 / std::pow(0.5, 0.25)),
              1e-12 * std::abs(t.impulse));
}

}  // namespace physics_touch_test
}  // namespace demlab::physics
