// The level set: MIMES's discrete function representation (DFR, seed section 1.1.2) in its modern
// form, level-set DEM (Kawamoto, Ando, Viggiani, Andrade, JMPS 2016): a body of any shape, convex
// or not, given by its signed distance function phi (negative inside) sampled on a regular grid
// in its body frame and interpolated multilinearly between the nodes, and by nodes on its surface.
//
// The shape's parameters are the grid itself (spacing, node counts, first node's position, then
// phi at every node, x fastest), so a checkpoint carries the shape exactly and every shape
// command works on it unchanged (scaling scales every number; moving moves the first node). The
// grids are built from a closed triangle mesh (an STL file) or from sampled values of an
// implicit function (sim/shapes/level_set_distance.cpp); either way phi is the exact distance
// to a triangulated surface, so its gradient is a unit normal and its value a depth.
//
// Derived once per Geometry: the surface of the zero level set by marching simplices (each grid
// cell split into Kuhn simplices: six tetrahedra in 3D, two triangles in 2D; their faces match
// across cells, so the surface is closed), from which the mass properties come (as a polytope's,
// from its faces) and which snapshots draw; and the surface nodes, one where each grid line
// crosses the surface. Contact is node against field: a node of one body inside another (phi < 0
// there) is a contact point of depth -phi and normal along the field's gradient.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "core/math.hpp"
#include "sim/shape.hpp"
#include "sim/shapes/polytope.hpp"

namespace demlab::sim {

// The bounds on a grid: nodes per axis, and in all (each node is a double in the parameters).
inline constexpr int kLevelSetMinNodes = 3;
inline constexpr int kLevelSetMaxNodesPerAxis = 400;
inline constexpr size_t kLevelSetMaxNodes = size_t{1} << 21;

template <int D>
struct LevelSet {
  Real h = 0;                   // node spacing (m)
  std::array<int, D> n{};       // nodes per axis
  VecD<D> origin;               // the first node's position in the body frame
  std::vector<Real> phi;        // x fastest, then y (then z)
  Polytope<D> surface;          // the zero level set: triangles (3D) or segments (2D), outward
  std::vector<VecD<D>> nodes;   // surface nodes (body frame), in grid order

  // Returns true and sets value and gradient (body frame) at x when x lies in the grid's box;
  // false outside it (the body holds no point there). Changes nothing.
  bool sample(const VecD<D>& x, Real& value, VecD<D>& gradient) const;
};

// Returns the level set of params (h, n per axis, first node's position, phi per node), checked:
// h positive and within the validity policy, node counts whole numbers in [kLevelSetMinNodes,
// kLevelSetMaxNodesPerAxis] and at most kLevelSetMaxNodes in all, as many values as nodes, all
// finite and within the grid's diagonal, every node of the grid's border outside (phi > 0, so
// the body is closed) and some node inside. Throws demlab::Error {VALUE SHAPE} naming the
// fault. Changes nothing.
template <int D>
LevelSet<D> buildLevelSet(std::span<const double> params);

// Returns the level-set parameters of the body enclosed by a closed triangle mesh (three
// corners per triangle, any orientation), with spacing h and a border of two nodes beyond the
// mesh's bounds. The mesh must be closed (every edge shared by exactly two triangles, corners
// merged where they coincide); the sign comes from ray parity, the distance is exact within
// two nodes of the surface and propagated from the nearest triangles beyond (Bridson's
// sweeping). Throws {VALUE MESH} for an open mesh, {VALUE SPACING} for a bad h or a grid
// beyond the bounds. Polls for Ctrl-C. Changes nothing.
std::vector<double> levelSetFromMesh(std::span<const std::array<double, 9>> triangles, Real h);

// Returns the level-set parameters of the body where the sampled function values (one per node
// of the grid of n nodes per axis from origin, x fastest) are negative, re-distanced: phi is the
// exact distance to the surface of the values' zero level set (marching simplices), with the
// values' sign. Throws {VALUE SHAPE} as buildLevelSet for values that do not describe a closed
// body inside the grid, {VALUE SPACING}. Polls for Ctrl-C. Changes nothing.
template <int D>
std::vector<double> levelSetFromValues(Real h, const std::array<int, D>& n, const VecD<D>& origin,
                                       std::span<const double> values);

// Returns true and writes the contact of a ball (centre, radius) with the level-set element e,
// the normal from the ball to e and the pair's Hertz radius (a clump's member meets a level set
// this way). Changes nothing else.
template <int D>
bool ballLevelSetContact(const VecD<D>& centre, Real radius, const ElementRef<D>& e,
                         ContactPoint<D>& out);

}  // namespace demlab::sim
