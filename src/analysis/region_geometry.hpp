// How much of a segment or a ball lies inside a region (a box or a sphere, sim::Region): the
// weights with which the analysis queries count contacts and element volumes.
#pragma once

#include "sim/packing.hpp"

namespace demlab::analysis {

using sim::Region;
using sim::Vec3d;

// Returns true if point p lies in region (boundary included) over the first d axes.
bool holdsPoint(const Region& region, const Vec3d& p, int d);

// Returns the fraction (0 to 1) of the segment p -> q lying inside region over the first d
// axes; for a zero-length segment, 1 if p is inside and 0 otherwise. Changes nothing.
double segmentFractionInside(const Region& region, const Vec3d& p, const Vec3d& q, int d);

// Returns the area of the disc of radius r centred at the origin that lies in the rectangle
// [x0, x1] x [y0, y1] (exact, closed form). Changes nothing.
double discRectangleArea(double r, double x0, double x1, double y0, double y1);

// Returns the volume (3D) or area (2D) of the ball of radius r at c that lies inside region.
// Exact in 2D and for a sphere region (lens formulas); a 3D box integrates the exact
// disc-rectangle area over the ball's slices by adaptive Simpson quadrature, split at the
// slices where the area's derivative jumps, to 1e-12 of the ball's volume. Changes nothing.
double ballVolumeInside(const Region& region, const Vec3d& c, double r, int d);

}  // namespace demlab::analysis
