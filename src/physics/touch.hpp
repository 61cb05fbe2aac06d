// The sub-step treatment of contact onset and release (doc/design.md, "Touch and release"):
// the per-contact formulas, apart from the sim module that applies them (sim/touch.hpp), so
// the tests can check them against closed forms.
//
// Velocity Verlet's kicks are the trapezoidal rule on the force: over a step [t0, t1] the
// velocity receives dt/2 (F(t0) + F(t1)). A contact's normal force is not smooth where it
// begins or ends: the spring rises from zero with a kink, the damper of a damped law jumps to
// c |vn| at the touch, and a damped force that is cut off at zero (contact.hpp) ends with a
// kink while the grains still overlap. A kink inside a step leaves an O(dt^2) impulse error per
// event, a jump O(dt), so the energy of an elastic gas wanders by O(dt^2) per collision and the
// restitution of damped impacts converges at first order (doc/verification.md, findings 3, 7).
//
// The correction makes the sum of the kicks over a contact's life the integral of its force.
// Near an event a force term is F(t) = A |t - te|^p (te the event, p its power: the linear
// spring p = 1, the Hertz spring 3/2, the linear damper 0 (the jump), the Hertz damper 1/4,
// gamma_n ~ a^(1/2) ~ delta^(1/4)). The kicks weigh the grid points t_k by dt, and the
// generalised Euler-Maclaurin formula for a power singularity at an offset theta dt from the
// grid (Navot 1961) gives their sum minus the integral as A dt^(p+1) zeta(-p, theta) plus the
// smooth terms the scheme's own O(dt^2) already holds, zeta the Hurwitz zeta function. So the
// step next to the event gets the impulse -F dt zeta(-p, theta) / theta^p, F the term's value
// at the grid point nearest the event, theta dt its distance from it (eventImpulse). For p = 0
// that is F (theta dt - dt/2): the force over the part of the step it acted, less the kick's
// dt/2; for p = 1, F (theta dt/2 - dt/2) + F dt / (12 theta): the partial step's F T / 2 and
// the trapezoid's end term dt^2 F' / 12 of the kink (without it, an elastic gas's energy still
// wanders by dt^2 kn vn^2 / 12 per collision where many collide at once: in a binary impact
// the touch's and the release's end terms cancel). For p = 3/2 the error of a Hertz touch is
// spread over the following steps (the force's curvature is singular), which the zeta
// function sums; a correction of the partial step alone would be five times too large.
//  - touch (no overlap at t0, overlap at t1): theta = delta1 / (delta1 - delta0) from the
//    signed overlaps; the spring and the damper terms at t1 each get their impulse. The
//    damper's power, booked by the laws as P(t1) dt per step, gets the same correction in the
//    ledger's damping loss (power p of the damper).
//  - release (force positive at t0, zero at t1: the overlap ended, or the damped force reached
//    its cut-off): theta from the zero of a gap between the two ends, the impulse from F(t0).
//    The gap is the unclamped force kn delta - cn vn for the linear law (p = 1, extended to
//    delta < 0 as it stands), delta for the elastic Hertz law (p = 3/2), and F / delta^(1/4) =
//    K delta^(5/4) - G vn for the damped Hertz law (p = 1). The damper's power is continuous
//    at a cut-off (kn delta = cn vn there, and the clamped law books the spring's unworked
//    energy at the same rate), so the ledger needs nothing.
//  - re-engagement (touching at both ends, the damped force cut off at t0 and positive at
//    t1): as release, mirrored, from the force at t1.
// What is left per event is O(dt^3). The positions are not corrected: the drift of the event
// step moves by dt^2/2 a(t0), whose error is O(dt^3) since the force is O(dt) at an event. The
// tangential force is not corrected (the spring's first increment stays vt dt): the frictional
// cases keep the order they had (doc/design.md says why).
#pragma once

#include <algorithm>
#include <cmath>

#include "physics/pair_params.hpp"

namespace demlab::physics {

// The normal force of one contact split into its spring and damper terms: the force is
// max(0, spring + damper), and near zero overlap spring ~ delta^springPower, damper ~
// delta^damperPower. Linear: kn delta and -cn vn; Hertz-Mindlin: (4/3) E* a delta and
// -hertzGammaN sqrt(a m*) vn, a = sqrt(R* delta).
struct NormalTerms {
  Real spring = 0, damper = 0;
  Real springPower = 1, damperPower = 0;
  Real force() const { return std::max<Real>(0, spring + damper); }
};

// Returns the normal terms at overlap delta > 0 and normal velocity vn (B minus A along the
// normal, < 0 approaching) for the pair p and the contact's effective mass and radius, exactly
// as law_linear.hpp and law_hertz_mindlin.hpp form them. Changes nothing.
inline NormalTerms normalTerms(const PairParams& p, Real delta, Real vn, Real effMass,
                               Real effRadius) {
  NormalTerms t;
  if (p.law == LawKind::Linear) {
    const Real kn = p.knFixed + p.knPerRadius * effRadius;
    const Real beta = 2 * p.dampingRatio * std::sqrt(effMass / kn);
    t.spring = kn * delta;
    t.damper = -beta * kn * vn;
  } else {
    const Real a = std::sqrt(effRadius * delta);
    t.spring = p.hertzKn * a * delta;
    t.damper = -p.hertzGammaN * std::sqrt(a * effMass) * vn;
    t.springPower = 1.5;
    t.damperPower = 0.25;
  }
  return t;
}

// A gap of the release and re-engagement rule: value (> 0 while the force acts, linear in time
// near its zero) and the power p of the force in it.
struct ReleaseGap {
  Real value = 0, power = 1;
};

// Returns the gap at signed overlap delta (< 0: apart) and normal velocity vn (as normalTerms).
// Changes nothing.
inline ReleaseGap releaseGap(const PairParams& p, Real delta, Real vn, Real effMass,
                             Real effRadius) {
  if (p.law == LawKind::Linear) {
    const Real kn = p.knFixed + p.knPerRadius * effRadius;
    const Real beta = 2 * p.dampingRatio * std::sqrt(effMass / kn);
    return {kn * delta - beta * kn * vn, 1};
  }
  if (p.hertzGammaN == 0) return {delta, 1.5};
  // F = delta^(1/4) (hertzKn sqrt(R*) delta^(5/4) - hertzGammaN sqrt(m*) R*^(1/4) vn).
  const Real d = std::max<Real>(0, delta);
  const Real r4 = std::sqrt(std::sqrt(effRadius));
  return {p.hertzKn * r4 * r4 * d * std::sqrt(std::sqrt(d)) -
              p.hertzGammaN * std::sqrt(effMass) * r4 * vn,
          1};
}

// One end of a step for one contact: whether it touches, its signed overlap (> 0 touching) and
// the normal velocity the law sees there, along that end's normal.
struct ContactEnd {
  bool touch = false;
  Real overlap = 0, vn = 0;
};

// Returns true if the damped normal force at end e (touching) is cut off at zero, by the law's
// own comparison squared (no square root; the same as normalTerms(...).force() == 0 but for
// rounding at the boundary, where the correction is continuous). Changes nothing.
inline bool cutOff(const PairParams& p, const ContactEnd& e, Real effMass, Real effRadius) {
  if (!(e.vn > 0)) return false;  // approaching: the damper pushes too
  if (p.law == LawKind::Linear) {
    // kn delta <= beta kn vn, beta = 2 zeta sqrt(m*/kn): kn delta^2 <= 4 zeta^2 m* vn^2.
    const Real kn = p.knFixed + p.knPerRadius * effRadius;
    return kn * e.overlap * e.overlap <=
           4 * p.dampingRatio * p.dampingRatio * effMass * e.vn * e.vn;
  }
  // hertzKn a delta <= gammaN sqrt(a m*) vn, a = sqrt(R* delta): hertzKn^4 R* delta^5 <=
  // gammaN^4 m*^2 vn^4.
  const Real d2 = e.overlap * e.overlap, k2 = p.hertzKn * p.hertzKn;
  const Real g2 = p.hertzGammaN * p.hertzGammaN, mv2 = effMass * e.vn * e.vn;
  return k2 * k2 * effRadius * d2 * d2 * e.overlap <= g2 * g2 * mv2 * mv2;
}

// What the correction does to one contact over one step: an impulse on B along the normal of
// the end named by atEnd (A receives its opposite), and the damping loss to add to the ledger.
struct TouchCorrection {
  Real impulse = 0;
  bool atEnd = true;  // along the normal at t1 (touch, re-engagement); else at t0 (release)
  Real loss = 0;
  bool any() const { return impulse != 0 || loss != 0; }
};

// Returns the fraction of the step from the zero of a quantity linear in time to the step's
// end (rising: before <= 0 < after) or from its start to the zero (falling: before > 0 >=
// after), clamped to [0, 1] (estimated ends that do not bracket a zero give 1 or 0). Changes
// nothing.
inline Real zeroFraction(Real before, Real after) {
  const Real span = before - after;
  if (span == 0) return 1;
  const Real f = after > before ? after / (after - before) : before / span;
  return std::clamp<Real>(f, 0, 1);
}

// Returns x^p for x > 0: the event powers of the Hertz law (p = 3/2 for the spring, 1/4 for
// the damper, 1/2) from square roots, which are correctly rounded and several times cheaper
// than pow; std::pow for any other p. Changes nothing.
inline Real eventPower(Real x, Real p) {
  if (p == 1.5) return x * std::sqrt(x);
  if (p == 0.25) return std::sqrt(std::sqrt(x));
  if (p == 0.5) return std::sqrt(x);
  return std::pow(x, p);
}

// Returns the Hurwitz zeta function zeta(s, a) = sum_{k >= 0} (k + a)^-s (continued
// analytically) for s <= 0 and 0 < a <= 1, by Euler-Maclaurin summation from k = 10 with five
// Bernoulli terms (error below 1e-12 for s >= -2). Changes nothing.
inline Real hurwitzZeta(Real s, Real a) {
  // The linear law's powers in closed form: zeta(0, a) = 1/2 - a, zeta(-1, a) = -B2(a) / 2.
  if (s == 0) return 0.5 - a;
  if (s == -1) return -0.5 * (a * a - a + 1.0 / 6);
  constexpr int kTerms = 10;
  Real sum = 0;
  for (int k = 0; k < kTerms; ++k) sum += eventPower(k + a, -s);
  const Real x = kTerms + a;
  const Real xp = eventPower(x, -s);  // x^-s; x^(1-s) = x xp and x^(-s-1) = xp / x
  sum += x * xp / (s - 1) + 0.5 * xp;
  constexpr Real kBernoulli[] = {1.0 / 6, -1.0 / 30, 1.0 / 42, -1.0 / 30, 5.0 / 66};
  Real factorial = 1, rising = s, power = xp / x;
  for (int j = 1; j <= 5; ++j) {
    factorial *= (2 * j - 1) * (2 * j);
    sum += kBernoulli[j - 1] / factorial * rising * power;
    rising *= (s + 2 * j - 1) * (s + 2 * j);
    power /= x * x;
  }
  return sum;
}

// Returns zeta(-p, theta) / theta^p, the weight of eventImpulse (theta > 0). Changes nothing.
inline Real eventWeight(Real p, Real theta) {
  return p == 0 ? hurwitzZeta(0, theta) : hurwitzZeta(-p, theta) / eventPower(theta, p);
}

// Returns the impulse to add for a force term ~ (time since the event)^p that is worth F at the
// grid point nearest the event, a fraction theta (0 < theta <= 1) of a step dt away from it:
// -F dt zeta(-p, theta) / theta^p (see the file's comment). p = 0: F (theta dt - dt/2), the
// partial step; p = 1: F (theta dt/2 - dt/2) + F dt / (12 theta), the partial step and the
// kink's end term. Changes nothing.
inline Real eventImpulse(Real F, Real p, Real theta, Real dt) {
  if (!(theta > 0) || F == 0) return 0;
  return -F * dt * eventWeight(p, theta);
}

// Returns the correction for one contact over one step of length dt > 0 from its two ends (as
// above), the pair's parameters, its effective mass and radius, and the lag of the law's
// velocities (ContactKinematics::velocityLag: 0.5 plain Verlet, 0 synchronized), which the
// damping loss is charged at as the laws do. Changes nothing.
inline TouchCorrection touchCorrection(const PairParams& p, Real effMass, Real effRadius, Real dt,
                                       Real lag, const ContactEnd& e0, const ContactEnd& e1) {
  TouchCorrection c;
  if (!e0.touch && !e1.touch) return c;
  if (!e0.touch) {
    // Touch within the step: the spring and the damper terms, each with its power.
    const NormalTerms t = normalTerms(p, e1.overlap, e1.vn, effMass, effRadius);
    const Real fn = t.force();
    if (fn == 0) return c;
    const Real theta = zeroFraction(e0.overlap, e1.overlap);
    if (!(theta > 0)) return c;
    const Real wd = t.damper != 0 ? eventWeight(t.damperPower, theta) : 0;
    c.impulse = -dt * (t.spring * eventWeight(t.springPower, theta) + t.damper * wd);
    // The damper's power at t1, charged at the force time (contact.hpp, velocityLag), ~ the
    // damper's coefficient, so of the damper's power in time: the damper's weight.
    const Real vForce = e1.vn + lag * dt * fn / effMass;
    c.loss = -dt * (t.spring - fn) * vForce * wd;
    return c;
  }
  const NormalTerms t0 = normalTerms(p, e0.overlap, e0.vn, effMass, effRadius);
  const ReleaseGap g0 = releaseGap(p, e0.overlap, e0.vn, effMass, effRadius);
  const ReleaseGap g1 = releaseGap(p, e1.overlap, e1.vn, effMass, effRadius);
  if (t0.force() > 0 && g0.value > 0 && g1.value <= 0) {
    // Release within the step.
    c.impulse = eventImpulse(t0.force(), g0.power, zeroFraction(g0.value, g1.value), dt);
    c.atEnd = false;
    return c;
  }
  if (e1.touch && t0.force() == 0 && g0.value <= 0 && g1.value > 0) {
    // Re-engagement of a force cut off at t0.
    const Real f1 = normalTerms(p, e1.overlap, e1.vn, effMass, effRadius).force();
    c.impulse = eventImpulse(f1, g1.power, zeroFraction(g0.value, g1.value), dt);
  }
  return c;
}

}  // namespace demlab::physics
