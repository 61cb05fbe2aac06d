// The shapes of grains and walls, as plain data the narrow phase reads (narrow_phase.hpp), and
// the axis-aligned bounds each wall shape gives the broad phase (CGrid).
//
// Grains are spheres (3D) or discs (2D). Walls are few and large: an infinite plane (a line in
// 2D), a finite flat wall (a segment in 2D, a rectangle in 3D; either may have a hole in its
// middle: a slot, an orifice), an oriented solid box, and a
// drum (grains inside a circle in 2D, inside a cylinder in 3D). Every wall is rigid, has
// infinite mass, and is B in a grain-wall contact (the normal points from the grain to it).
//
// Bounds: a closed box; an unbounded direction gets +-infinity. Infinite planes are unbounded,
// so boundsWithin(plane, domain) clips them to the scene's domain for the broad phase. A drum's
// bounds are its whole box: every grain in the drum is a candidate, and the narrow phase
// rejects a grain well inside it with one dot product and compare.
#pragma once

#include <array>
#include <limits>
#include <memory>

#include "core/math.hpp"
#include "physics/triangle_mesh.hpp"
#include "search/box.hpp"

namespace demlab::physics {

template <int D>
using Bounds = search::Box<D, Real>;

template <int D>
struct SphereShape {
  VecD<D> centre;
  Real radius;  // > 0
};

// Infinite plane through point with unit normal; grains live on the + side. The wall is
// one-sided: a grain whose centre is below the plane is still pushed back out along +normal.
template <int D>
struct PlaneShape {
  VecD<D> point;
  VecD<D> normal;  // unit
};

// A finite flat wall of zero thickness, touched from both sides: the points
// centre + sum_i s_i axes[i] with |s_i| <= halfExtents[i]. axes are unit and orthogonal to
// each other; D-1 of them (one in 2D: a segment; two in 3D: a rectangle).
// It may have a hole centred at centre, hole > 0 (an orifice plate, a slot): 3D the points with
// |sum_i s_i axes[i]| < hole are not part of it (a circular hole of radius hole), 2D those with
// |s_0| < hole (a gap of width 2 hole). hole < every half extent, so the hole lies inside.
template <int D>
struct FlatWallShape {
  VecD<D> centre;
  std::array<VecD<D>, D - 1> axes;
  std::array<Real, D - 1> halfExtents;  // >= 0
  Real hole = 0;                        // >= 0; 0: none
};
using SegmentShape = FlatWallShape<2>;
using RectangleShape = FlatWallShape<3>;

// A solid box wall: the points centre + axes * s with |s_k| <= halfExtents[k]. axes is a
// rotation matrix whose columns are the box's axes in world coordinates.
template <int D>
struct BoxShape {
  VecD<D> centre;
  MatD<D> axes;         // orthonormal, columns = box axes
  VecD<D> halfExtents;  // > 0
};

// A drum: grains live INSIDE a circle (2D: centre, radius) or a cylinder (3D: axis through
// centre, unit axis, radius, and the mantle spans |(x - centre).axis| <= halfLength; its end
// caps, if wanted, are separate walls). A grain whose centre lies beyond the ends does not
// touch the mantle. axis and halfLength are ignored in 2D.
template <int D>
struct DrumShape {
  VecD<D> centre;
  VecD<D> axis = VecD<D>::Unit(D - 1);  // unit (3D only)
  Real radius;
  Real halfLength = std::numeric_limits<Real>::infinity();  // 3D only

  // Returns x - centre without its part along the axis (3D): the outward radial vector.
  VecD<D> radial(const VecD<D>& x) const {
    VecD<D> r = x - centre;
    if constexpr (D == 3) r -= r.dot(axis) * axis;
    return r;
  }
  // Returns true when a body within distance reach of x may meet the mantle: between the ends
  // (3D) and reaching beyond the radius.
  bool mayReach(const VecD<D>& x, Real reach) const {
    if constexpr (D == 3) {
      if (std::abs((x - centre).dot(axis)) > halfLength) return false;
    }
    return radial(x).norm() + reach > radius;
  }
};

// A triangle-mesh wall (3D only): the mesh (physics/triangle_mesh.hpp) in its own frame, placed
// by a rotation and an offset, world = rotation * local + offset. Two-sided, as a finite wall:
// a grain is pushed away from the nearest point of the surface.
template <int D>
struct MeshShape {
  std::shared_ptr<const TriangleMesh> mesh;
  Mat3 rotation = Mat3::Identity();
  Vec3 offset = Vec3::Zero();
};

// Each returns the closed axis-aligned box around the shape (+-infinity where unbounded);
// changes nothing.
template <int D>
Bounds<D> bounds(const SphereShape<D>& s);
template <int D>
Bounds<D> bounds(const PlaneShape<D>& p);  // the half-space behind the plane: its whole box
template <int D>
Bounds<D> bounds(const FlatWallShape<D>& w);
template <int D>
Bounds<D> bounds(const BoxShape<D>& b);
template <int D>
Bounds<D> bounds(const DrumShape<D>& d);
template <int D>
Bounds<D> bounds(const MeshShape<D>& m);

// Returns the bounds of the part of the plane's back half-space {x : (x - point).normal <= 0}
// that lies in the domain box (exact: the box of the clipped polytope); an empty intersection
// gives a box with lo > hi on some axis. Changes nothing.
template <int D>
Bounds<D> boundsWithin(const PlaneShape<D>& p, const Bounds<D>& domain);

}  // namespace demlab::physics
