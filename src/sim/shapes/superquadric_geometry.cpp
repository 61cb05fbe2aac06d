// The superquadric's gauge, its derivatives and its support point (superquadric.hpp).
#include <cmath>

#include "sim/shapes/superquadric.hpp"

namespace demlab::sim {

namespace {

// |x/a|^p and its first two derivatives in x.
struct PowTerm {
  Real v, d1, d2;
};

// Returns t^p for t > 0: by multiplication for the whole exponents most shapes use (pow is
// most of a contact's cost otherwise).
Real power(Real t, Real p) {
  int whole = static_cast<int>(p);
  if (whole == p && whole >= 0) {
    // By squaring (std::pow(double, int) calls pow itself).
    Real out = 1;
    for (Real base = t; whole > 0; whole >>= 1, base *= base) {
      if (whole & 1) out *= base;
    }
    return out;
  }
  if (p == 0.5) return std::sqrt(t);
  return std::pow(t, p);
}

PowTerm powTerm(Real x, Real a, Real p) {
  const Real t = std::abs(x) / a;
  if (t == 0) return {0, 0, p == 2 ? 2 / (a * a) : 0};
  const Real tp2 = power(t, p - 2);
  const Real sign = x < 0 ? -1 : 1;
  return {tp2 * t * t, sign * p * tp2 * t / a, p * (p - 1) * tp2 / (a * a)};
}

// F, its gradient and Hessian at x (the inside-outside function of superquadric.hpp).
template <int D>
Real insideOutside(const Superquadric<D>& s, const VecD<D>& x, VecD<D>& g, MatD<D>& h) {
  h.setZero();
  if constexpr (D == 2) {
    const PowTerm gx = powTerm(x[0], s.a, s.n1), gy = powTerm(x[1], s.b, s.n1);
    g = Vec2(gx.d1, gy.d1);
    h(0, 0) = gx.d2;
    h(1, 1) = gy.d2;
    return gx.v + gy.v;
  } else {
    const PowTerm gx = powTerm(x[0], s.a, s.n2), gy = powTerm(x[1], s.b, s.n2),
                  gz = powTerm(x[2], s.c, s.n1);
    const Real hsum = gx.v + gy.v, e = s.n1 / s.n2;
    Real p = hsum, k1 = 1, k2 = 0;  // P = hsum^e; dP = k1 dh; d2P = k1 d2h + k2 dh dh^T
    if (e != 1) {
      if (hsum > 1e-250) {
        p = power(hsum, e);
        k1 = e * p / hsum;
        k2 = e * (e - 1) * p / (hsum * hsum);
      } else {
        p = 0, k1 = 0, k2 = 0;  // on the z axis: the xy part's derivatives vanish (n1, n2 > 2)
      }
    }
    g = Vec3(k1 * gx.d1, k1 * gy.d1, gz.d1);
    h(0, 0) = k1 * gx.d2 + k2 * gx.d1 * gx.d1;
    h(1, 1) = k1 * gy.d2 + k2 * gy.d1 * gy.d1;
    h(0, 1) = h(1, 0) = k2 * gx.d1 * gy.d1;
    h(2, 2) = gz.d2;
    return p + gz.v;
  }
}

// Returns sign(p) |p / s|^(m - 1): the Hoelder point's coordinate.
Real holder(Real p, Real s, Real m) {
  if (p == 0 || s == 0) return 0;
  return std::copysign(power(std::abs(p) / s, m - 1), p);
}

// Returns (|p|^m + |q|^m)^(1/m), scaled against overflow.
Real dualNorm(Real p, Real q, Real m) {
  const Real big = std::max(std::abs(p), std::abs(q));
  if (big == 0) return 0;
  return big * power(power(std::abs(p) / big, m) + power(std::abs(q) / big, m), 1 / m);
}

}  // namespace

template <int D>
Real Superquadric<D>::level(const VecD<D>& x) const {
  const auto term = [](Real v, Real a, Real p) { return power(std::abs(v) / a, p); };
  if constexpr (D == 2) {
    return term(x[0], a, n1) + term(x[1], b, n1);
  } else {
    const Real hsum = term(x[0], a, n2) + term(x[1], b, n2);
    return (n1 == n2 ? hsum : power(hsum, n1 / n2)) + term(x[2], c, n1);
  }
}

template <int D>
Real Superquadric<D>::gauge(const VecD<D>& x) const {
  VecD<D> g;
  MatD<D> h;
  const Real f = insideOutside(*this, x, g, h);
  return f > 0 ? power(f, 1 / n1) : 0;
}

template <int D>
VecD<D> Superquadric<D>::gaugeGradient(const VecD<D>& x) const {
  Real phi;
  return gaugeAndGradient(x, phi);
}

template <int D>
VecD<D> Superquadric<D>::gaugeAndGradient(const VecD<D>& x, Real& phi) const {
  VecD<D> g;
  MatD<D> h;
  const Real f = insideOutside(*this, x, g, h);
  if (!(f > 0)) {
    phi = 0;
    return VecD<D>::Zero();
  }
  phi = power(f, 1 / n1);
  return (phi / (n1 * f)) * g;
}

template <int D>
Real Superquadric<D>::squaredGauge(const VecD<D>& x, VecD<D>& grad, MatD<D>& hess) const {
  VecD<D> g;
  MatD<D> h;
  const Real f = insideOutside(*this, x, g, h);
  if (!(f > 0)) {
    grad.setZero();
    hess = h;
    return 0;
  }
  const Real m = 2 / n1, psi = power(f, m);
  const Real c1 = m * psi / f, c2 = m * (m - 1) * psi / (f * f);
  grad = c1 * g;
  hess = c1 * h + c2 * g * g.transpose();
  return psi;
}

template <int D>
VecD<D> Superquadric<D>::support(const VecD<D>& dir) const {
  const VecD<D> d = dir / dir.norm();
  if constexpr (D == 2) {
    const Real p = a * d[0], q = b * d[1], m = n1 / (n1 - 1);
    const Real s = dualNorm(p, q, m);
    return Vec2(a * holder(p, s, m), b * holder(q, s, m));
  } else {
    // The xy part at unit "radius" rho = 1, then the split between rho and z.
    const Real p = a * d[0], q = b * d[1], r = c * d[2];
    const Real m2 = n2 / (n2 - 1), m1 = n1 / (n1 - 1);
    const Real s = dualNorm(p, q, m2), t = dualNorm(s, r, m1);
    const Real rho = holder(s, t, m1);
    return Vec3(a * rho * holder(p, s, m2), b * rho * holder(q, s, m2), c * holder(r, t, m1));
  }
}

template struct Superquadric<2>;
template struct Superquadric<3>;

}  // namespace demlab::sim
