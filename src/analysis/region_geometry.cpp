#include "analysis/region_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace demlab::analysis {

namespace {

constexpr double kPi = std::numbers::pi;

// Returns the squared distance of p from the region's centre over d axes (sphere regions).
double centreDistance2(const Region& region, const Vec3d& p, int d) {
  double s = 0;
  for (int k = 0; k < d; ++k) s += (p[k] - region.centre[k]) * (p[k] - region.centre[k]);
  return s;
}

// Returns the integral of sqrt(r^2 - t^2) from 0 to x (|x| <= r).
double halfChordIntegral(double r, double x) {
  x = std::clamp(x, -r, r);
  return 0.5 * (x * std::sqrt(std::max(0.0, r * r - x * x)) + r * r * std::asin(x / r));
}

// Returns the area of the disc of radius r at the origin in the quadrant {x <= X, y <= Y}:
// the integral over x of the part of the chord [-s(x), s(x)] below Y.
double discQuadrantArea(double r, double X, double Y) {
  if (X <= -r || Y <= -r) return 0;
  X = std::min(X, r);
  auto S = [r](double x) { return halfChordIntegral(r, x); };
  if (Y >= r) return 2 * (S(X) - S(-r));
  const double a = std::sqrt(r * r - Y * Y);  // the chord at height Y spans [-a, a]
  double area = 0;
  double top = std::min(X, a);
  if (top > -a) area += Y * (top + a) + S(top) - S(-a);  // chords cut by y = Y
  if (Y > 0) {                                           // whole chords beyond |x| = a
    double left = std::min(X, -a);
    if (left > -r) area += 2 * (S(left) - S(-r));
    if (X > a) area += 2 * (S(X) - S(a));
  }
  return area;
}

// Returns the integral of f over [a, b] by adaptive Simpson to absolute tolerance tol.
template <class F>
double adaptiveSimpson(const F& f, double a, double b, double fa, double fm, double fb,
                       double whole, double tol, int depth) {
  double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
  double flm = f(lm), frm = f(rm);
  double left = (m - a) / 6 * (fa + 4 * flm + fm), right = (b - m) / 6 * (fm + 4 * frm + fb);
  double diff = left + right - whole;
  if (depth <= 0 || std::abs(diff) <= 15 * tol) return left + right + diff / 15;
  return adaptiveSimpson(f, a, m, fa, flm, fm, left, tol / 2, depth - 1) +
         adaptiveSimpson(f, m, b, fm, frm, fb, right, tol / 2, depth - 1);
}

// Returns the volume of the ball (radius r, centre c) inside an axis-aligned box, by slices.
double ballBoxVolume(const Region& box, const Vec3d& c, double r) {
  const double x0 = box.lo[0] - c[0], x1 = box.hi[0] - c[0];
  const double y0 = box.lo[1] - c[1], y1 = box.hi[1] - c[1];
  const double z0 = std::max(box.lo[2] - c[2], -r), z1 = std::min(box.hi[2] - c[2], r);
  if (!(z1 > z0)) return 0;
  auto slice = [&](double z) {
    double rho = std::sqrt(std::max(0.0, r * r - z * z));
    return rho > 0 ? discRectangleArea(rho, x0, x1, y0, y1) : 0.0;
  };
  // The slice area is smooth between the heights where its circle meets an edge line or a
  // corner of the rectangle; the quadrature starts a piece at each of them.
  std::vector<double> cuts{z0, z1};
  const double edges2[] = {x0 * x0, x1 * x1, y0 * y0, y1 * y1, x0 * x0 + y0 * y0,
                           x0 * x0 + y1 * y1, x1 * x1 + y0 * y0, x1 * x1 + y1 * y1};
  for (double dd : edges2) {
    if (dd >= r * r) continue;
    double z = std::sqrt(r * r - dd);
    for (double s : {z, -z})
      if (s > z0 && s < z1) cuts.push_back(s);
  }
  std::sort(cuts.begin(), cuts.end());
  const double tol = 1e-12 * 4.0 / 3.0 * kPi * r * r * r;
  double v = 0;
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    double a = cuts[k], b = cuts[k + 1];
    if (!(b > a)) continue;
    double fa = slice(a), fb = slice(b), fm = slice(0.5 * (a + b));
    double whole = (b - a) / 6 * (fa + 4 * fm + fb);
    v += adaptiveSimpson(slice, a, b, fa, fm, fb, whole, tol / double(cuts.size()), 40);
  }
  return v;
}

// Returns the area of the intersection of two discs (radii r, R, centres a distance d apart).
double lensArea(double r, double R, double d) {
  if (d >= r + R) return 0;
  if (d <= std::abs(R - r)) return kPi * std::min(r, R) * std::min(r, R);
  double a = std::acos(std::clamp((d * d + r * r - R * R) / (2 * d * r), -1.0, 1.0));
  double b = std::acos(std::clamp((d * d + R * R - r * r) / (2 * d * R), -1.0, 1.0));
  double k = std::sqrt(std::max(0.0, (-d + r + R) * (d + r - R) * (d - r + R) * (d + r + R)));
  return r * r * a + R * R * b - 0.5 * k;
}

// Returns the volume of the intersection of two balls (radii r, R, centres d apart).
double lensVolume(double r, double R, double d) {
  if (d >= r + R) return 0;
  if (d <= std::abs(R - r)) return 4.0 / 3.0 * kPi * std::pow(std::min(r, R), 3);
  return kPi * (R + r - d) * (R + r - d) *
         (d * d + 2 * d * r - 3 * r * r + 2 * d * R + 6 * r * R - 3 * R * R) / (12 * d);
}

}  // namespace

bool holdsPoint(const Region& region, const Vec3d& p, int d) {
  if (region.kind == Region::Box) {
    for (int k = 0; k < d; ++k)
      if (p[k] < region.lo[k] || p[k] > region.hi[k]) return false;
    return true;
  }
  return centreDistance2(region, p, d) <= region.radius * region.radius;
}

double segmentFractionInside(const Region& region, const Vec3d& p, const Vec3d& q, int d) {
  Vec3d e{};
  double len2 = 0;
  for (int k = 0; k < d; ++k) e[k] = q[k] - p[k], len2 += e[k] * e[k];
  if (len2 == 0) return holdsPoint(region, p, d) ? 1.0 : 0.0;
  double t0 = 0, t1 = 1;  // the part of the segment p + t e, t in [0, 1], inside
  if (region.kind == Region::Box) {
    for (int k = 0; k < d; ++k) {
      if (e[k] == 0) {
        if (p[k] < region.lo[k] || p[k] > region.hi[k]) return 0;
        continue;
      }
      double a = (region.lo[k] - p[k]) / e[k], b = (region.hi[k] - p[k]) / e[k];
      t0 = std::max(t0, std::min(a, b));
      t1 = std::min(t1, std::max(a, b));
    }
  } else {
    // |p - c + t e|^2 = R^2: t^2 len2 + 2 t (p - c).e + |p - c|^2 - R^2 = 0.
    double b = 0;
    for (int k = 0; k < d; ++k) b += (p[k] - region.centre[k]) * e[k];
    double c = centreDistance2(region, p, d) - region.radius * region.radius;
    double disc = b * b - len2 * c;
    if (disc <= 0) return 0;
    double s = std::sqrt(disc);
    t0 = std::max(t0, (-b - s) / len2);
    t1 = std::min(t1, (-b + s) / len2);
  }
  return std::max(0.0, t1 - t0);
}

double discRectangleArea(double r, double x0, double x1, double y0, double y1) {
  if (!(x1 > x0) || !(y1 > y0) || !(r > 0)) return 0;
  return discQuadrantArea(r, x1, y1) - discQuadrantArea(r, x0, y1) -
         discQuadrantArea(r, x1, y0) + discQuadrantArea(r, x0, y0);
}

double ballVolumeInside(const Region& region, const Vec3d& c, double r, int d) {
  const double whole = d == 2 ? kPi * r * r : 4.0 / 3.0 * kPi * r * r * r;
  if (region.holds(c, r, d)) return whole;
  if (region.kind == Region::Sphere) {
    double dist = std::sqrt(centreDistance2(region, c, d));
    return d == 2 ? lensArea(r, region.radius, dist) : lensVolume(r, region.radius, dist);
  }
  for (int k = 0; k < d; ++k)
    if (c[k] + r <= region.lo[k] || c[k] - r >= region.hi[k]) return 0;
  if (d == 2)
    return discRectangleArea(r, region.lo[0] - c[0], region.hi[0] - c[0], region.lo[1] - c[1],
                             region.hi[1] - c[1]);
  return ballBoxVolume(region, c, r);
}

}  // namespace demlab::analysis
