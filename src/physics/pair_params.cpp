// mixPair: the one place where two materials become the constants of a contact law.
#include "physics/pair_params.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <numbers>

namespace demlab::physics {

std::string_view lawName(LawKind law) {
  switch (law) {
    case LawKind::Linear:
      return "linear";
    case LawKind::HertzMindlin:
      return "hertz_mindlin";
  }
  return "unknown";
}

std::string_view coulombCriterionName(CoulombCriterion c) {
  switch (c) {
    case CoulombCriterion::Total:
      return "total";
    case CoulombCriterion::Spring:
      return "spring";
  }
  return "unknown";
}

std::string_view hertzDampingName(HertzDamping d) {
  switch (d) {
    case HertzDamping::Calibrated:
      return "calibrated";
    case HertzDamping::Liggghts:
      return "liggghts";
  }
  return "unknown";
}

namespace {

// Returns 2 x y / (x + y), the harmonic mean, with a value of 0 meaning "not given": then the
// other value (or 0 if neither is given). Symmetric and exact for x == y.
Real mixStiffness(Real x, Real y) {
  if (x == 0) return y;
  if (y == 0) return x;
  return 2 * x * y / (x + y);
}

// Returns sqrt(rho/G) / (0.1631 nu + 0.8766) for one material (the Rayleigh step per radius / pi).
Real rayleighSlowness(const MaterialDef& m) {
  const Real g = m.young / (2 * (1 + m.poisson));
  return std::sqrt(m.density / g) / (0.1631 * m.poisson + 0.8766);
}

}  // namespace

Real linearForceDuration(Real zeta) {
  if (zeta < 1) {
    const Real s = std::sqrt((1 - zeta) * (1 + zeta));  // omega_d / omega_n, accurate near 1
    return 2 * std::atan2(s, zeta) / s;
  }
  if (zeta == 1) return 2;
  const Real w = std::sqrt((zeta - 1) * (zeta + 1));
  return 2 * std::log(zeta + w) / w;
}

Real linearRestitution(Real zeta) {
  const Real t = linearForceDuration(zeta);
  if (zeta <= 1) return std::exp(-zeta * t);
  const Real w = std::sqrt((zeta - 1) * (zeta + 1));
  return std::exp(-zeta * t) * std::abs(std::cosh(w * t) - zeta / w * std::sinh(w * t));
}

Real linearDampingRatio(Real e) {
  if (e >= 1) return 0;
  // linearRestitution falls monotonically from 1 to 0: bracket, then bisect to rounding.
  // Beyond zeta = 1e100 (e ~ 2.5e-201) cosh and sinh overflow; no physical e is that small.
  Real lo = 0, hi = 1;
  while (hi < 1e100 && linearRestitution(hi) > e) lo = hi, hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-16 * hi; ++i) {
    const Real mid = 0.5 * (lo + hi);
    (linearRestitution(mid) > e ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

namespace {

// The state of the dimensionless Hertz impact (pair_params.hpp): overlap x, velocity v = x'.
struct HertzState {
  Real x, v;
};

// Returns the normal force x^(3/2) + c x^(1/4) v, not cut off (x below 0, met only inside a
// step, counts as 0). Changes nothing.
Real hertzForce(const HertzState& s, Real c) {
  const Real x = std::max<Real>(s.x, 0);
  const Real q = std::sqrt(std::sqrt(x));
  return x * q * q + c * q * s.v;
}

// Returns the state one classical RK4 step of length h after s. Changes nothing.
HertzState hertzStep(const HertzState& s, Real c, Real h) {
  const auto at = [&](Real dx, Real dv) { return HertzState{s.x + dx, s.v + dv}; };
  const Real k1x = s.v, k1v = -hertzForce(s, c);
  const HertzState s2 = at(0.5 * h * k1x, 0.5 * h * k1v);
  const Real k2x = s2.v, k2v = -hertzForce(s2, c);
  const HertzState s3 = at(0.5 * h * k2x, 0.5 * h * k2v);
  const Real k3x = s3.v, k3v = -hertzForce(s3, c);
  const HertzState s4 = at(h * k3x, h * k3v);
  const Real k4x = s4.v, k4v = -hertzForce(s4, c);
  return {s.x + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x),
          s.v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)};
}

}  // namespace

Real hertzRestitution(Real c) {
  if (c <= 0) return 1;
  // Series start: x^(1/4) makes the solution a series in t^(1/4) at t = 0, which RK4 would
  // integrate at first order; to t0 the series below is exact to ~1e-16.
  const Real t0 = 1e-8;
  const Real t14 = std::sqrt(std::sqrt(t0)), t54 = t0 * t14, t52 = t0 * t0 * std::sqrt(t0);
  HertzState s{t0 - 16.0 / 45 * c * t0 * t54 - 4.0 / 35 * t52 * t0,
               1 - 0.8 * c * t54 - 0.4 * t52 + 16.0 / 45 * c * c * t52};
  // Adaptive RK4 by step doubling: a step is kept when its two halves and the whole step agree
  // to tol (the kept, halved result is then ~tol/15 off); the step then grows or shrinks.
  const Real tol = 1e-13;
  Real h = 1e-6;
  for (int n = 0; n < 10000000; ++n) {
    const HertzState whole = hertzStep(s, c, h);
    const HertzState half = hertzStep(hertzStep(s, c, 0.5 * h), c, 0.5 * h);
    const Real err = std::max(std::abs(whole.x - half.x), std::abs(whole.v - half.v));
    if (err > tol && h > 1e-14) {
      h *= std::max(0.2, 0.9 * std::pow(tol / err, 0.2));
      continue;
    }
    if (hertzForce(half, c) <= 0) {
      // The force vanishes within this step: bisect the step's length (RK4 steps from s, each
      // as accurate as the step) for the moment it does.
      Real lo = 0, hi = h;
      for (int i = 0; i < 100 && hi - lo > 1e-15 * hi; ++i) {
        const Real mid = 0.5 * (lo + hi);
        (hertzForce(hertzStep(s, c, mid), c) > 0 ? lo : hi) = mid;
      }
      return -hertzStep(s, c, 0.5 * (lo + hi)).v;
    }
    s = half;
    h *= err > 0 ? std::min(4.0, 0.9 * std::pow(tol / err, 0.2)) : 4.0;
  }
  return -s.v;  // not reached for c <= 1e4
}

Real hertzDampingFactor(Real e) {
  if (e >= 1) return 0;
  // Each solve costs some thousand RK4 steps per bisection step; a scene has a few distinct
  // e, mixed at every run start, so the answers are remembered.
  static std::mutex mutex;
  static std::map<Real, Real> solved;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = solved.find(e);
    if (it != solved.end()) return it->second;
  }
  // hertzRestitution falls monotonically from 1: bracket, then bisect (to 1e-12 in c, far
  // below the integration's own error in e).
  Real lo = 0, hi = 1;
  while (hi < 1e4 && hertzRestitution(hi) > e) lo = hi, hi *= 2;
  hi = std::min<Real>(hi, 1e4);
  for (int i = 0; i < 100 && hi - lo > 1e-12 * hi; ++i) {
    const Real mid = 0.5 * (lo + hi);
    (hertzRestitution(mid) > e ? lo : hi) = mid;
  }
  const Real c = 0.5 * (lo + hi);
  const std::lock_guard<std::mutex> lock(mutex);
  if (solved.size() < 4096) solved.emplace(e, c);
  return c;
}

Real liggghtsBeta(Real e) {
  const Real lnE = std::log(e);
  return lnE / std::sqrt(lnE * lnE + std::numbers::pi * std::numbers::pi);
}

PairParams mixPair(LawKind law, const MaterialDef& a, const MaterialDef& b, HertzDamping damping) {
  a.check();
  b.check();
  PairParams p;
  p.law = law;
  p.friction = mixFriction(a, b);
  p.restitution = mixRestitution(a, b);
  // The two sums are written in a fixed order of (a, b) terms; both are commutative additions
  // of two terms, so the mix is bit-for-bit symmetric.
  p.youngEff = 1 / ((1 - a.poisson * a.poisson) / a.young + (1 - b.poisson * b.poisson) / b.young);
  p.shearEff = 1 / (2 * (2 - a.poisson) * (1 + a.poisson) / a.young +
                    2 * (2 - b.poisson) * (1 + b.poisson) / b.young);
  p.dampingRatio = linearDampingRatio(p.restitution);

  // Linear law.
  const Real kn = mixStiffness(a.normalStiffness, b.normalStiffness);
  const Real kt = mixStiffness(a.shearStiffness, b.shearStiffness);
  const Real mindlin = 4 * p.shearEff / p.youngEff;
  if (kn > 0) {
    p.knFixed = kn;
    p.shearRatio = kt > 0 ? kt / kn : mindlin;
  } else {
    p.knPerRadius = p.youngEff;
    p.shearRatio = mindlin;
  }

  // Hertz-Mindlin (LIGGGHTS normal_model_hertz.h). The tangential damper takes the normal
  // one's beta, calibrated or not, as LIGGGHTS's does.
  const Real beta = damping == HertzDamping::Liggghts
                        ? liggghtsBeta(p.restitution)
                        : -hertzDampingFactor(p.restitution) / std::sqrt(5.0);  // <= 0
  const Real sqrtFiveSixths = std::sqrt(5.0 / 6.0);
  p.hertzKn = 4.0 / 3.0 * p.youngEff;
  p.hertzKt = 8 * p.shearEff;
  p.hertzGammaN = -2 * sqrtFiveSixths * beta * std::sqrt(2 * p.youngEff);
  p.hertzGammaT = -2 * sqrtFiveSixths * beta * std::sqrt(8 * p.shearEff);

  p.rayleighSlowness = std::max(rayleighSlowness(a), rayleighSlowness(b));
  return p;
}

}  // namespace demlab::physics
