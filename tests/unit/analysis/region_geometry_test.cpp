// The exact and quadrature volumes of balls cut by regions against closed forms and a brute
// force sum, and the clipping of segments.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "analysis/region_geometry.hpp"

namespace demlab::analysis {
namespace region_geometry_test {

constexpr double kPi = std::numbers::pi;

Region box(Vec3d lo, Vec3d hi) {
  Region r;
  r.lo = lo, r.hi = hi;
  return r;
}

Region sphere(Vec3d c, double radius) {
  Region r;
  r.kind = Region::Sphere;
  r.centre = c, r.radius = radius;
  return r;
}

TEST(RegionGeometry, DiscRectangleAreaOfHalvesAndQuarters) {
  const double r = 0.7, full = kPi * r * r;
  EXPECT_NEAR(discRectangleArea(r, -1, 1, -1, 1), full, 1e-14);
  EXPECT_NEAR(discRectangleArea(r, 0, 1, -1, 1), full / 2, 1e-14);
  EXPECT_NEAR(discRectangleArea(r, -1, 0, -1, 0), full / 4, 1e-14);
  // A segment beyond x = h: r^2 acos(h/r) - h sqrt(r^2 - h^2).
  const double h = 0.3;
  EXPECT_NEAR(discRectangleArea(r, h, 5, -5, 5), r * r * std::acos(h / r) - h * std::sqrt(r * r - h * h),
              1e-14);
}

TEST(RegionGeometry, BallCutByBoxPlanesAndCorners) {
  const double r = 1e-3, whole = 4.0 / 3.0 * kPi * r * r * r;
  const Vec3d c{0, 0, 0};
  EXPECT_NEAR(ballVolumeInside(box({-1, -1, 0}, {1, 1, 1}), c, r, 3) / whole, 0.5, 1e-10);
  EXPECT_NEAR(ballVolumeInside(box({0, 0, 0}, {1, 1, 1}), c, r, 3) / whole, 0.125, 1e-10);
  // A cap of height a = r - h beyond z = h: pi a^2 (3r - a) / 3.
  const double h = 0.4e-3, a = r - h;
  EXPECT_NEAR(ballVolumeInside(box({-1, -1, h}, {1, 1, 1}), c, r, 3) / (kPi * a * a * (3 * r - a) / 3),
              1, 1e-10);
}

TEST(RegionGeometry, BallCutByABoxCornerMatchesABruteForceSum) {
  // Three cuts through the ball, none through its centre: a midpoint sum over 160^3 cells.
  const double r = 1;
  const Region b = box({-0.3, 0.2, -2}, {2, 2, 0.5});
  const int n = 160;
  double h = 2 * r / n, sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        Vec3d p{-r + (i + 0.5) * h, -r + (j + 0.5) * h, -r + (k + 0.5) * h};
        if (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= r * r && holdsPoint(b, p, 3)) sum += h * h * h;
      }
  EXPECT_NEAR(ballVolumeInside(b, {0, 0, 0}, r, 3), sum, 2e-3 * sum);
}

TEST(RegionGeometry, LensesOfSphereRegions) {
  const double r = 1;
  // Equal balls a distance d apart: pi (4r + d)(2r - d)^2 / 12.
  const double d = 0.8;
  EXPECT_NEAR(ballVolumeInside(sphere({d, 0, 0}, r), {0, 0, 0}, r, 3),
              kPi * (4 * r + d) * (2 * r - d) * (2 * r - d) / 12, 1e-13);
  // Equal discs a radius apart: r^2 (2 pi / 3 - sqrt(3) / 2).
  EXPECT_NEAR(ballVolumeInside(sphere({r, 0, 0}, r), {0, 0, 0}, r, 2),
              r * r * (2 * kPi / 3 - std::sqrt(3.0) / 2), 1e-13);
  EXPECT_EQ(ballVolumeInside(sphere({3, 0, 0}, r), {0, 0, 0}, r, 3), 0);
}

TEST(RegionGeometry, SegmentFractions) {
  const Region b = box({0, 0, 0}, {1, 1, 1});
  EXPECT_NEAR(segmentFractionInside(b, {-1, 0.5, 0.5}, {1, 0.5, 0.5}, 3), 0.5, 1e-15);
  EXPECT_NEAR(segmentFractionInside(b, {0.2, 0.5, 0.5}, {0.8, 0.5, 0.5}, 3), 1, 1e-15);
  EXPECT_EQ(segmentFractionInside(b, {2, 0.5, 0.5}, {3, 0.5, 0.5}, 3), 0);
  const Region s = sphere({0, 0, 0}, 1);
  EXPECT_NEAR(segmentFractionInside(s, {0, 0, 0}, {2, 0, 0}, 3), 0.5, 1e-15);
  EXPECT_NEAR(segmentFractionInside(s, {-2, 0, 0}, {2, 0, 0}, 2), 0.5, 1e-15);
}

}  // namespace region_geometry_test
}  // namespace demlab::analysis
