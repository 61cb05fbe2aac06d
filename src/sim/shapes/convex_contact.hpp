// Contact of smooth convex bodies given by a gauge (sim/shapes/superquadric.hpp), after the
// midway-point method of Podlozhnyuk, Pirker and Kloss (Comp. Part. Mech. 4, 2017).
//
// The midway point X of bodies A and B minimises max(phi_A, phi_B): the point where the two
// bodies, scaled by the same factor s about their centres, first touch. There phi_A = phi_B = s
// and the gradients are opposite; s < 1 means the bodies overlap. The contact normal is phi_A's
// gradient at X; the line through X along it meets A's surface at p_A and B's at p_B, and the
// overlap is (p_A - p_B) . n, the point their middle. For two spheres this is the centre line,
// the radii sum less the distance and the middle of the overlap: the ball's own geometry.
//
// X is found by Newton's method on the optimality conditions (grad psi_A + mu grad psi_B = 0,
// psi_A = psi_B, psi = phi^2) from the point where the centre line's scaled bodies meet. If it
// fails to converge (or converges to mu <= 0), the safeguard is Perram and Wertheim's form of the
// same point: the root in lambda of psi_A(X(lambda)) - psi_B(X(lambda)), where X(lambda)
// minimises lambda psi_A + (1 - lambda) psi_B (a convex minimisation, by damped Newton steps),
// bracketed on [0, 1] and found by the Illinois method. Both are deterministic.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "core/math.hpp"
#include "sim/shapes/superquadric.hpp"

namespace demlab::sim {

// Returns the rotation's matrix (body frame to world).
inline Mat3 rotationMatrix(const Quat& q) { return q.toRotationMatrix(); }
inline Mat2 rotationMatrix(const Rotation2& r) {
  const Real c = std::cos(r.angle), s = std::sin(r.angle);
  Mat2 m;
  m << c, -s, s, c;
  return m;
}

// A gauge body placed in the world: centre, rotation (body to world) and its shape. aligned:
// the rotation is the identity and the centre the origin (a pair's first body, in whose frame
// the pair is solved), so its evaluations skip the transforms.
template <int D>
struct PlacedGauge {
  Superquadric<D> shape;
  VecD<D> centre;
  MatD<D> rot;
  bool aligned = false;

  VecD<D> toBody(const VecD<D>& x) const { return aligned ? x : VecD<D>(rot.transpose() * (x - centre)); }
  VecD<D> toWorld(const VecD<D>& v) const { return aligned ? v : VecD<D>(rot * v); }
  Real gauge(const VecD<D>& x) const { return shape.gauge(toBody(x)); }
  Real level(const VecD<D>& x) const { return shape.level(toBody(x)); }
  VecD<D> gaugeGradient(const VecD<D>& x) const { return toWorld(shape.gaugeGradient(toBody(x))); }
  VecD<D> gaugeAndGradient(const VecD<D>& x, Real& phi) const {
    return toWorld(shape.gaugeAndGradient(toBody(x), phi));
  }
  Real squaredGauge(const VecD<D>& x, VecD<D>& g, MatD<D>& h) const {
    if (aligned) return shape.squaredGauge(x, g, h);
    VecD<D> gb;
    MatD<D> hb;
    const Real v = shape.squaredGauge(toBody(x), gb, hb);
    g = rot * gb;
    h = rot * hb * rot.transpose();
    return v;
  }
  // The world point of the surface farthest along d.
  VecD<D> support(const VecD<D>& d) const {
    return aligned ? shape.support(d) : VecD<D>(centre + rot * shape.support(rot.transpose() * d));
  }
};

// Returns element e, a superquadric (or a ball, as the superquadric (r, r, r, 2, 2)), as a
// placed gauge body (sim/shapes/superquadric.cpp).
template <int D>
PlacedGauge<D> placedGauge(const ElementRef<D>& e);

// The result of the midway-point search.
template <int D>
struct MidwayPoint {
  VecD<D> x;       // the midway point
  Real scale = 0;  // phi_A = phi_B there; < 1: overlapping
  bool found = false;
};

namespace convex_detail {

// Newton's method on the optimality conditions from x0. Returns found = false unless it
// converges with mu > 0.
template <int D>
MidwayPoint<D> newtonMidway(const PlacedGauge<D>& A, const PlacedGauge<D>& B, VecD<D> x,
                            Real length) {
  using Mat = Eigen::Matrix<Real, D + 1, D + 1>;
  using Vec = Eigen::Matrix<Real, D + 1, 1>;
  VecD<D> ga, gb;
  MatD<D> ha, hb;
  Real pa = A.squaredGauge(x, ga, ha), pb = B.squaredGauge(x, gb, hb);
  Real mu = gb.squaredNorm() > 0 ? -ga.dot(gb) / gb.squaredNorm() : 1;
  const auto residual = [&](Real a, Real b, const VecD<D>& g1, const VecD<D>& g2, Real m) {
    Vec r;
    r.template head<D>() = (g1 + m * g2) * length;
    r[D] = a - b;
    return r;
  };
  Vec r = residual(pa, pb, ga, gb, mu);
  for (int it = 0; it < 30; ++it) {
    Mat J;
    J.template topLeftCorner<D, D>() = (ha + mu * hb) * length;
    J.template topRightCorner<D, 1>() = gb * length;
    J.template bottomLeftCorner<1, D>() = (ga - gb).transpose();
    J(D, D) = 0;
    const Vec step = J.partialPivLu().solve(-r);
    if (!step.allFinite()) return {};
    // Backtracking on the residual's norm.
    Real t = 1;
    bool accepted = false;
    for (int k = 0; k < 20; ++k, t *= 0.5) {
      const VecD<D> x1 = x + t * step.template head<D>();
      const Real mu1 = mu + t * step[D];
      VecD<D> ga1, gb1;
      MatD<D> ha1, hb1;
      const Real pa1 = A.squaredGauge(x1, ga1, ha1), pb1 = B.squaredGauge(x1, gb1, hb1);
      const Vec r1 = residual(pa1, pb1, ga1, gb1, mu1);
      if (r1.allFinite() && r1.norm() < (1 - 1e-4 * t) * r.norm()) {
        x = x1, mu = mu1, pa = pa1, pb = pb1, ga = ga1, gb = gb1, ha = ha1, hb = hb1, r = r1;
        accepted = true;
        break;
      }
    }
    const Real moved = t * step.template head<D>().norm();
    if (!accepted || moved <= 1e-14 * length || r.norm() <= 1e-15) {
      if (r.norm() <= 1e-10 && mu > 0) return {x, std::sqrt(std::max(pa, pb)), true};
      return {};
    }
  }
  return {};
}

// Returns the minimiser of lambda psi_A + (1 - lambda) psi_B, by damped Newton steps from x.
template <int D>
VecD<D> minimiseBlend(const PlacedGauge<D>& A, const PlacedGauge<D>& B, Real lambda, VecD<D> x,
                      Real length) {
  VecD<D> ga, gb;
  MatD<D> ha, hb;
  const auto value = [&](const VecD<D>& y) {
    return lambda * A.squaredGauge(y, ga, ha) + (1 - lambda) * B.squaredGauge(y, gb, hb);
  };
  Real f = value(x);
  for (int it = 0; it < 60; ++it) {
    const VecD<D> g = lambda * ga + (1 - lambda) * gb;
    MatD<D> h = lambda * ha + (1 - lambda) * hb;
    // A small Levenberg shift keeps the step a descent direction where the Hessian is flat.
    h += (1e-12 * h.trace() + 1e-300) * MatD<D>::Identity();
    VecD<D> step = -h.ldlt().solve(g);
    if (!step.allFinite() || step.dot(g) >= 0) step = -g * (length * length);
    Real t = 1;
    bool accepted = false;
    for (int k = 0; k < 40; ++k, t *= 0.5) {
      const VecD<D> y = x + t * step;
      const Real fy = value(y);
      if (fy <= f + 1e-4 * t * step.dot(g)) {
        x = y, f = fy, accepted = true;
        break;
      }
    }
    if (!accepted) value(x);  // restore the derivatives at x
    if (!accepted || t * step.norm() <= 1e-15 * length) break;
  }
  return x;
}

// The Perram-Wertheim safeguard: the root of psi_A - psi_B along lambda, by the Illinois method.
template <int D>
MidwayPoint<D> blendMidway(const PlacedGauge<D>& A, const PlacedGauge<D>& B, Real length) {
  VecD<D> g;
  MatD<D> h;
  Real lo = 0, hi = 1;
  Real flo = A.squaredGauge(B.centre, g, h), fhi = -B.squaredGauge(A.centre, g, h);
  VecD<D> x = 0.5 * (A.centre + B.centre);
  Real psi = 0;
  int side = 0;
  for (int it = 0; it < 200; ++it) {
    Real lambda = (lo * fhi - hi * flo) / (fhi - flo);
    if (!(lambda > lo && lambda < hi)) lambda = 0.5 * (lo + hi);
    x = minimiseBlend(A, B, lambda, x, length);
    const Real pa = A.squaredGauge(x, g, h), pb = B.squaredGauge(x, g, h);
    const Real f = pa - pb;
    psi = std::max(pa, pb);
    if (std::abs(f) <= 1e-14 * std::max(psi, Real{1e-300}) || hi - lo <= 1e-15) break;
    if (f > 0) {
      lo = lambda, flo = f;
      if (side == 1) fhi *= 0.5;
      side = 1;
    } else {
      hi = lambda, fhi = f;
      if (side == -1) flo *= 0.5;
      side = -1;
    }
  }
  return {x, std::sqrt(psi), std::isfinite(psi)};
}

// Returns t >= 0 with body.gauge(x + t d) = 1, for x inside (gauge < 1) and unit d; Newton's
// method on a convex function, monotone after its first step.
template <int D>
Real exitDistance(const PlacedGauge<D>& body, const VecD<D>& x, const VecD<D>& d, Real length) {
  Real t = 0;
  for (int it = 0; it < 100; ++it) {
    Real phi;
    const Real slope = body.gaugeAndGradient(x + t * d, phi).dot(d), f = phi - 1;
    if (!(slope > 0)) break;
    const Real step = f / slope;
    t = std::max(Real{0}, t - step);
    if (std::abs(step) <= 1e-15 * length) break;
  }
  return t;
}

}  // namespace convex_detail

// Returns the midway point of A and B (superquadric.hpp's gauges placed in the world).
template <int D>
MidwayPoint<D> midwayPoint(const PlacedGauge<D>& A, const PlacedGauge<D>& B, Real length) {
  // The start: where the centre line's scaled bodies meet.
  const VecD<D> d = B.centre - A.centre;
  const Real fa = A.shape.gauge(A.rot.transpose() * d), fb = B.shape.gauge(B.rot.transpose() * -d);
  const VecD<D> x0 = A.centre + (fb / (fa + fb)) * d;
  MidwayPoint<D> m = convex_detail::newtonMidway(A, B, x0, length);
  if (!m.found) m = convex_detail::blendMidway(A, B, length);
  return m;
}

// The contact of two placed gauge bodies, if they overlap: normal from A to B, overlap, point.
template <int D>
struct ConvexContact {
  VecD<D> normal, point;
  Real overlap = 0;
};

// convexContact's solver, in whatever frame A and B are given.
template <int D>
bool solveConvexContact(const PlacedGauge<D>& A, const PlacedGauge<D>& B, Real length,
                        ConvexContact<D>& out) {
  const VecD<D> d = B.centre - A.centre;
  const Real dist = d.norm();
  if (dist == 0) return false;  // concentric: no normal to choose (the pair is refused earlier)
  // Separated along the centre line: the supports do not reach each other.
  const VecD<D> u = d / dist;
  if (u.dot(A.support(u)) - u.dot(B.support(-u)) <= 0) return false;
  const MidwayPoint<D> m = midwayPoint(A, B, length);
  if (!m.found || !(m.scale < 1)) return false;
  VecD<D> n = A.gaugeGradient(m.x);
  const Real nn = n.norm();
  if (!(nn > 0)) return false;
  n /= nn;
  const Real ta = convex_detail::exitDistance(A, m.x, n, length);
  const Real tb = convex_detail::exitDistance(B, m.x, VecD<D>(-n), length);
  out.normal = n;
  out.overlap = ta + tb;
  out.point = m.x + 0.5 * (ta - tb) * n;
  return out.overlap > 0;
}

// Returns true and writes the contact if A and B overlap. length: a size of the pair (the sum
// of their bounding radii), the solvers' scale. Changes nothing else.
template <int D>
bool convexContact(const PlacedGauge<D>& Aworld, const PlacedGauge<D>& Bworld, Real length,
                   ConvexContact<D>& out) {
  // Solved in A's body frame (A's evaluations then need no transform), the result turned back.
  const PlacedGauge<D> A{Aworld.shape, VecD<D>::Zero(), MatD<D>::Identity(), true};
  const PlacedGauge<D> B{Bworld.shape, Aworld.toBody(Bworld.centre),
                         Aworld.aligned ? Bworld.rot : MatD<D>(Aworld.rot.transpose() * Bworld.rot)};
  if (!solveConvexContact(A, B, length, out)) return false;
  out.normal = Aworld.toWorld(out.normal);
  out.point = Aworld.aligned ? out.point : VecD<D>(Aworld.centre + Aworld.rot * out.point);
  return true;
}

// Returns the parameters s in [-half, half]^K minimising psi_B(origin + axes s): the point of a
// box (K = D: a solid box wall), a rectangle or a segment (K = D - 1: a finite wall) deepest in
// B in the gauge's sense, by projected Newton steps (psi is convex, so the minimum is unique
// for a strictly convex B). Starts from the projection of B's centre.
template <int D, int K>
Eigen::Matrix<Real, K, 1> minimiseOverBox(const PlacedGauge<D>& B, const VecD<D>& origin,
                                          const Eigen::Matrix<Real, D, K>& axes,
                                          const Eigen::Matrix<Real, K, 1>& half, Real length) {
  using VecK = Eigen::Matrix<Real, K, 1>;
  using MatK = Eigen::Matrix<Real, K, K>;
  const auto clampBox = [&](VecK v) {
    for (int k = 0; k < K; ++k) v[k] = std::clamp(v[k], -half[k], half[k]);
    return v;
  };
  VecK s = clampBox(axes.transpose() * (B.centre - origin));
  VecD<D> gy;
  MatD<D> hy;
  Real f = B.squaredGauge(origin + axes * s, gy, hy);
  for (int it = 0; it < 60; ++it) {
    const VecK g = axes.transpose() * gy;
    MatK h = axes.transpose() * hy * axes;
    // Variables held at a bound the gradient pushes against stay there this step.
    bool held[K];
    for (int k = 0; k < K; ++k) {
      held[k] = (s[k] <= -half[k] && g[k] > 0) || (s[k] >= half[k] && g[k] < 0);
      if (held[k]) {
        h.row(k).setZero();
        h.col(k).setZero();
        h(k, k) = 1;
      }
    }
    VecK gf = g;
    for (int k = 0; k < K; ++k) gf[k] = held[k] ? 0 : g[k];
    if (gf.norm() * length <= 1e-15) break;
    h += (1e-12 * h.trace() + 1e-300) * MatK::Identity();
    VecK d = -h.ldlt().solve(gf);
    if (!d.allFinite() || d.dot(gf) >= 0) d = -gf * (length * length);
    Real t = 1;
    bool accepted = false;
    for (int k = 0; k < 50; ++k, t *= 0.5) {
      const VecK s1 = clampBox(s + t * d);
      VecD<D> g1;
      MatD<D> h1;
      const Real f1 = B.squaredGauge(origin + axes * s1, g1, h1);
      if (f1 <= f + 1e-4 * g.dot(s1 - s)) {
        const Real moved = (s1 - s).norm();
        s = s1, f = f1, gy = g1, hy = h1, accepted = true;
        if (moved <= 1e-15 * length) it = 1 << 20;  // converged
        break;
      }
    }
    if (!accepted) break;
  }
  return s;
}

// The contact of B with the wall point y, the deepest in B's gauge of a convex wall (found by
// minimiseOverBox or on a hole's rim): the normal is the gauge's gradient there (from B to the
// wall), the depth how far B's support along it passes y. For a ball it is the closest point's
// contact. Returns false if y lies outside B or at its centre (no direction to push).
template <int D>
bool contactAtWallPoint(const PlacedGauge<D>& B, const VecD<D>& y, ConvexContact<D>& out) {
  if (!(B.gauge(y) < 1)) return false;
  VecD<D> n = B.gaugeGradient(y);
  const Real nn = n.norm();
  if (!(nn > 0)) return false;
  n /= nn;
  const VecD<D> p = B.support(n);
  out.normal = n;
  out.overlap = n.dot(p - y);
  out.point = p - 0.5 * out.overlap * n;
  return out.overlap > 0;
}

}  // namespace demlab::sim
