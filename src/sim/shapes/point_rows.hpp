// The plane and drum rows of the shapes that meet those walls by points of their own: a
// polytope by its corners (exact for a convex body), a level set by its surface nodes. The
// shape's Points type says how: Points::run<D>(a, depth, normal, out) writes a contact point
// for each of a's points x with depth(x) > 0 (how far x lies beyond the wall's surface), of
// normal normal(x) (from a into the wall), and returns their count.
#pragma once

#include "physics/shapes.hpp"
#include "sim/shape.hpp"

namespace demlab::sim {

template <int D, class Points>
int planeByPoints(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& pl = *static_cast<const physics::PlaneShape<D>*>(wall);
  if ((a.x - pl.point).dot(pl.normal) >= a.r) return 0;
  return Points::template run<D>(
      a, [&](const VecD<D>& x) { return -(x - pl.point).dot(pl.normal); },
      [&](const VecD<D>&) { return VecD<D>(-pl.normal); }, out);
}

template <int D, class Points>
int drumByPoints(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& dr = *static_cast<const physics::DrumShape<D>*>(wall);
  if (!dr.mayReach(a.x, a.r)) return 0;
  return Points::template run<D>(
      a, [&](const VecD<D>& x) { return dr.radial(x).norm() - dr.radius; },
      [&](const VecD<D>& x) { return VecD<D>(dr.radial(x).normalized()); }, out);
}

}  // namespace demlab::sim
