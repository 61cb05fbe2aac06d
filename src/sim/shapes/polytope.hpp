// Convex polytopes: the polygon (2D) and the polyhedron (3D), and the contact between them.
//
// A polytope is given by its corners (the shape's parameters, x y [z] per corner, about any
// point: the table moves them about the centroid). Its structure, found once per Geometry by a
// convex hull (sim/shapes/polytope_hull.cpp) and shared by every element of that shape, is the
// faces (3D: planar polygons, corners counterclockwise seen from outside; 2D: the edges, as
// faces of two corners), their outward unit normals, and in 3D the edges with their two faces.
//
// Contact is by separating axes (the faces' normals, and in 3D the edges' cross products), and
// where the least overlap is along a face normal, by clipping the other body's most opposed face
// against that reference face (Sutherland-Hodgman), as Box2D does for polygons and Gregorius
// (GDC 2013) for polyhedra: a box face down on another yields its four corners, each with its
// own depth, so a resting box feels a stable manifold and does not rock from corner to corner.
// The penalty measure is the depth of each manifold point (not the overlap volume): it is what
// the contact laws of demlab take for every other shape, it costs no volume clipping, and a
// face contact's points share the load by their depths. Walls are polytopes too: a solid box,
// and a finite wall as a flat one (two faces of opposite normals).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/math.hpp"
#include "sim/shape.hpp"
#include "sim/shapes/convex_contact.hpp"

namespace demlab::sim {

// The structure of a convex polytope in some frame (the body frame of a shape, or the world for
// a wall).
template <int D>
struct Polytope {
  struct Face {
    VecD<D> normal;               // outward, unit
    Real offset = 0;              // normal . x = offset on the face
    std::vector<uint32_t> loop;   // corners (indices into vertices), counterclockwise from outside
  };
  struct Edge {
    uint32_t a = 0, b = 0;  // corners
  };
  std::vector<VecD<D>> vertices;
  std::vector<Face> faces;
  std::vector<Edge> edges;  // 3D only
};

// The most corners a polygon or polyhedron may have.
inline constexpr size_t kMaxPolytopeCorners = 64;

// Returns the polytope whose corners are the points of params (x y [z] each), checked: between
// D + 1 and kMaxPolytopeCorners points, finite, within the validity policy's sizes, pairwise
// distinct, each a corner of their convex hull (none inside it or on one of its faces or
// edges), and not all on one line or plane. Throws demlab::Error {VALUE SHAPE} naming the
// fault, with `what` ("polygon", "polyhedron") in the message. Changes nothing.
template <int D>
Polytope<D> buildPolytope(std::span<const double> params, const char* what);

// Returns the volume (2D: area), centroid and inertia tensor per unit density of p (about the
// centroid; 2D: only (2, 2) set).
template <int D>
MassProperties<D> polytopeMassProperties(const Polytope<D>& p);

// Writes to p the polytope of a solid box wall, or of a finite wall as a flat box of two faces
// of opposite normals (in 2D a segment with two sides), in the world frame; p's arrays are
// reused, so a wall row built each step allocates nothing after its first.
template <int D>
void boxPolytope(const VecD<D>& centre, const MatD<D>& axes, const VecD<D>& halfExtents,
                 Polytope<D>& p);
template <int D>
void flatPolytope(const VecD<D>& centre, std::span<const VecD<D>> axes,
                  std::span<const Real> halfExtents, Polytope<D>& p);

// Writes the contact points of polytopes a and b, whose corners in the world are wa and wb
// (same order as their vertices) and their faces' world normals na and nb, to out and returns
// their count (at most kMaxContactPoints; 0: apart). Normals point from a to b; each point's
// effRadius is left to the caller; features are stable while the same faces touch. Changes
// nothing else.
template <int D>
int polytopeContact(const Polytope<D>& a, std::span<const VecD<D>> wa, std::span<const VecD<D>> na,
                    const Polytope<D>& b, std::span<const VecD<D>> wb, std::span<const VecD<D>> nb,
                    ContactPoint<D>* out);

// Writes the contact of polytope a (world corners wa, face normals na) with the smooth convex
// body g (a superquadric; reach: the radius of a ball about its centre that holds it) to out[0]
// and returns 1, or 0 when they are apart. The normal is the one of least overlap among a's face
// normals, g's normals where a's corners and the points of a's edges deepest in g's gauge lie,
// and the centre line; out's effRadius and feature are left to the caller. Changes nothing else.
template <int D>
int polytopeGaugeContact(const Polytope<D>& a, std::span<const VecD<D>> wa,
                         std::span<const VecD<D>> na, const PlacedGauge<D>& g, Real reach,
                         ContactPoint<D>* out);

// Returns true and writes the contact of a ball (centre, radius) with the polytope element e,
// the normal from the ball to e and the pair's Hertz radius (a clump's member meets a polytope
// this way: sim/shapes/clump.cpp). Changes nothing else.
template <int D>
bool ballPolytopeContact(const VecD<D>& centre, Real radius, const ElementRef<D>& e,
                         ContactPoint<D>& out);

}  // namespace demlab::sim
