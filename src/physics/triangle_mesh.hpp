// A triangle mesh for walls (a hopper, a chute, a mixer's blade): its corners merged where the
// file repeats them, so triangles that meet share corner numbers (which is how a contact at a
// shared edge or corner is told to be one contact, not two), and a uniform grid over its
// triangles for finding those near a point.
//
// The mesh is immutable once built and shared by a wall's geometry at creation and now (the
// wall's motion moves a pose, not the corners), by every copy of a scene and by checkpoints.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <span>
#include <vector>

#include "core/math.hpp"

namespace demlab::physics {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<Vec3> normals;  // unit, from the corners' order (right-handed)
  std::string source;         // the file it came from, for queries
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // the corners' bounds

  // Returns the mesh of the given triangles (three corners each), corners at exactly the same
  // point merged, triangles of no area (to 1e-12 of the mesh's size) dropped. Throws
  // demlab::Error {VALUE MESH} when no triangle is left, or a coordinate is beyond
  // validity::kMaxCoordinate. Changes nothing.
  static TriangleMesh build(const std::vector<std::array<double, 9>>& triangles, std::string source);

  // Appends to out (cleared first) the triangles whose bounds come within reach of point p, in
  // increasing order, each once. Changes out only.
  void near(const Vec3& p, Real reach, std::vector<uint32_t>& out) const;

  // Returns the bytes the mesh holds on the heap (for the memory report).
  size_t heapBytes() const;

  // The grid: cells of side cell from lo, dims[k] along each axis; cellStart has one more entry
  // than there are cells, cellTriangles the triangles of each cell, in order.
  Real cell = 1;
  std::array<int, 3> dims{1, 1, 1};
  std::vector<uint32_t> cellStart, cellTriangles;
};

// The triangles near an element, each with its unit normal turned towards the element's
// centre: prepared once per element and step, then asked about each of its points (a
// polyhedron's corners, a level set's nodes). All in the mesh's frame.
struct FacingTriangles {
  std::vector<uint32_t> ids;
  std::vector<Vec3> normals, corners;  // per triangle: towards the centre; its first corner

  // Prepares the triangles near (of mesh) for an element centred at centre. Changes this only.
  void prepare(const TriangleMesh& mesh, std::span<const uint32_t> near, const Vec3& centre);
  // Returns the depth (> 0) of point x behind the deepest triangle that it lies over (its foot
  // on the triangle's plane inside the triangle) and behind (beyond the plane from the centre),
  // no deeper than reach, and in normal that triangle's normal pointing away from the centre;
  // 0 when x is behind none. Changes normal only.
  Real depthBehind(const TriangleMesh& mesh, const Vec3& x, Real reach, Vec3& normal) const;
};

// Where the point of a triangle nearest to p lies: inside (Face), on an edge (Edge, edge k from
// corner k to corner k + 1) or at a corner (Vertex, corner k).
struct TrianglePoint {
  enum Kind { Face, Edge, Vertex } kind = Face;
  int k = 0;
  Vec3 point = Vec3::Zero();
};

// Returns the point of triangle (a, b, c) nearest to p and which feature it lies on (Ericson,
// Real-Time Collision Detection, 5.1.5). Changes nothing.
TrianglePoint nearestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace demlab::physics
