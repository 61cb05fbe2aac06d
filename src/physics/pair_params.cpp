// mixPair: the one place where two materials become the constants of a contact law.
#include "physics/pair_params.hpp"

#include <algorithm>
#include <cmath>
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

PairParams mixPair(LawKind law, const MaterialDef& a, const MaterialDef& b) {
  a.check();
  b.check();
  PairParams p;
  p.law = law;
  p.friction = std::min(a.friction, b.friction);
  // sqrt(e e) rounds to e exactly for the common one-material pair (sqrt is correctly rounded).
  p.restitution = std::sqrt(a.restitution * b.restitution);
  // The two sums are written in a fixed order of (a, b) terms; both are commutative additions
  // of two terms, so the mix is bit-for-bit symmetric.
  p.youngEff = 1 / ((1 - a.poisson * a.poisson) / a.young + (1 - b.poisson * b.poisson) / b.young);
  p.shearEff = 1 / (2 * (2 - a.poisson) * (1 + a.poisson) / a.young +
                    2 * (2 - b.poisson) * (1 + b.poisson) / b.young);
  const Real lnE = std::log(p.restitution);
  const Real root = std::sqrt(lnE * lnE + std::numbers::pi * std::numbers::pi);
  const Real beta = lnE / root;  // <= 0; LIGGGHTS's betaeff
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

  // Hertz-Mindlin (LIGGGHTS normal_model_hertz.h).
  const Real sqrtFiveSixths = std::sqrt(5.0 / 6.0);
  p.hertzKn = 4.0 / 3.0 * p.youngEff;
  p.hertzKt = 8 * p.shearEff;
  p.hertzGammaN = -2 * sqrtFiveSixths * beta * std::sqrt(2 * p.youngEff);
  p.hertzGammaT = -2 * sqrtFiveSixths * beta * std::sqrt(8 * p.shearEff);

  p.rayleighSlowness = std::max(rayleighSlowness(a), rayleighSlowness(b));
  return p;
}

}  // namespace demlab::physics
