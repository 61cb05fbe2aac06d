// The polygon (2D) and polyhedron (3D) shape types: parameters the corners, x y [z] each
// (sim/shapes/polytope.hpp has the structure and the contact).
//
// Rows: against itself, the ball and the superquadric (and the clump, whose members meet it as
// balls: sim/shapes/clump.cpp), and every wall kind. A plane or a drum holds a convex body inside it
// exactly when it holds every corner, so those rows take the corners below the plane or beyond
// the drum's radius, each a contact point keyed by its corner. Solid boxes and finite walls are
// polytopes themselves and go through the pair routine; a finite wall with a hole drops the
// points over the hole (its rim's edge is not a contact feature: a corner or face resting across
// the rim is held by the points beside the hole). The Hertz radius is the volume-equivalent
// sphere's, as for superquadrics, taken at each point of a face contact.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "physics/narrow_phase.hpp"
#include "physics/triangle_mesh.hpp"
#include "physics/shapes.hpp"
#include "sim/obj_manager.hpp"
#include "sim/shape.hpp"
#include "sim/shapes/convex_contact.hpp"
#include "sim/shapes/point_rows.hpp"
#include "sim/shapes/polytope.hpp"

namespace demlab::sim {

namespace {

template <int D>
constexpr const char* typeName() {
  return D == 3 ? "polyhedron" : "polygon";
}

template <int D>
class PolytopeType final : public ShapeType<D> {
 public:
  std::string_view name() const override { return typeName<D>(); }
  std::string_view parameters() const override {
    return D == 3 ? "x y z ...: the corners (4 to 64), about any point (m); the shape is their "
                    "convex hull, and every point must be one of its corners"
                  : "x y ...: the corners (3 to 64), about any point (m); the shape is their "
                    "convex hull, and every point must be one of its corners";
  }
  void check(std::span<const double> p) const override { buildPolytope<D>(p, typeName<D>()); }
  Real boundingRadius(std::span<const double> p) const override {
    Real r = 0;
    for (size_t k = 0; k + D <= p.size(); k += D) {
      Real s = 0;
      for (int d = 0; d < D; ++d) s += p[k + d] * p[k + d];
      r = std::max(r, std::sqrt(s));
    }
    return r * (1 + 1e-12);
  }
  MassProperties<D> massProperties(std::span<const double> p) const override {
    return polytopeMassProperties(buildPolytope<D>(p, typeName<D>()));
  }
  std::optional<std::vector<double>> scaled(std::span<const double> p, Real f) const override {
    std::vector<double> out(p.begin(), p.end());
    for (double& x : out) x *= f;
    return out;
  }
  std::optional<std::vector<double>> translated(std::span<const double> p,
                                                const VecD<D>& offset) const override {
    std::vector<double> out(p.begin(), p.end());
    for (size_t k = 0; k < out.size(); ++k) out[k] += offset[static_cast<int>(k % D)];
    return out;
  }
  std::shared_ptr<const void> derive(std::span<const double> p) const override {
    return std::make_shared<const Polytope<D>>(buildPolytope<D>(p, typeName<D>()));
  }
  // 3D: each face fanned from its first corner; 2D: the polygon fanned from the centroid.
  std::vector<Vec3> renderTriangles(std::span<const double> p) const override {
    const Polytope<D> poly = buildPolytope<D>(p, typeName<D>());
    std::vector<Vec3> out;
    const auto at = [&](uint32_t k) {
      Vec3 v = Vec3::Zero();
      v.template head<D>() = poly.vertices[k];
      return v;
    };
    for (const auto& f : poly.faces) {
      if constexpr (D == 2) {
        out.push_back(Vec3::Zero());
        out.push_back(at(f.loop[0]));
        out.push_back(at(f.loop[1]));
      } else {
        for (size_t k = 1; k + 1 < f.loop.size(); ++k) {
          out.push_back(at(f.loop[0]));
          out.push_back(at(f.loop[k]));
          out.push_back(at(f.loop[k + 1]));
        }
      }
    }
    return out;
  }
};

template <int D>
const Polytope<D>& polytopeOf(const ElementRef<D>& e) {
  return *static_cast<const Polytope<D>*>(e.g->data.get());
}

template <int D>
Real hertzRadius(const ElementRef<D>& e) {
  return volumeEquivalentRadius(*e.g);
}

// An element's corners and face normals in the world (scratch per thread and slot).
template <int D>
struct Placed {
  std::vector<VecD<D>> corners, normals;
  void place(const ElementRef<D>& e) {
    const Polytope<D>& p = polytopeOf(e);
    const MatD<D> rot = rotationMatrix(e.q);
    corners.resize(p.vertices.size());
    normals.resize(p.faces.size());
    for (size_t k = 0; k < p.vertices.size(); ++k) corners[k] = e.x + rot * p.vertices[k];
    for (size_t k = 0; k < p.faces.size(); ++k) normals[k] = rot * p.faces[k].normal;
  }
};

// Sets every point's Hertz radius to r.
template <int D>
int withRadius(int n, Real r, ContactPoint<D>* out) {
  for (int k = 0; k < n; ++k) out[k].effRadius = r;
  return n;
}

template <int D>
int pairRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!((b.x - a.x).norm() < a.r + b.r)) return 0;
  thread_local Placed<D> pa, pb;
  pa.place(a);
  pb.place(b);
  const int n = polytopeContact<D>(polytopeOf(a), pa.corners, pa.normals, polytopeOf(b), pb.corners,
                                   pb.normals, out);
  const Real ra = hertzRadius(a), rb = hertzRadius(b);
  return withRadius(n, ra * rb / (ra + rb), out);
}

// A polytope against a superquadric (sim/shapes/polytope.hpp, polytopeGaugeContact): one point.
template <int D>
int gaugeRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!((b.x - a.x).norm() < a.r + b.r)) return 0;
  thread_local Placed<D> pa;
  pa.place(a);
  if (polytopeGaugeContact<D>(polytopeOf(a), pa.corners, pa.normals, placedGauge(b), b.r, out) == 0) return 0;
  const Real ra = hertzRadius(a), rb = hertzRadius(b);
  out[0].effRadius = ra * rb / (ra + rb);
  out[0].feature = 0;
  return 1;
}

// A polytope against a ball: the ball's routine with the normal turned to point from a to b.
template <int D>
int ballRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!ballPolytopeContact(b.x, b.r, a, out[0])) return 0;
  out[0].g.normal = -out[0].g.normal;
  return 1;
}

// The corners beyond a surface: depth(x) > 0 is how far corner x lies beyond it, normal(x) the
// direction from the element into the wall there.
template <int D, class Depth, class Normal>
int cornerRow(const ElementRef<D>& a, Depth depth, Normal normal, ContactPoint<D>* out) {
  thread_local Placed<D> pa;
  pa.place(a);
  thread_local std::vector<ContactPoint<D>> all;
  all.clear();
  for (size_t k = 0; k < pa.corners.size(); ++k) {
    const VecD<D>& x = pa.corners[k];
    const Real d = depth(x);
    if (!(d > 0)) continue;
    const VecD<D> n = normal(x);
    ContactPoint<D> p;
    p.g = {n, d, VecD<D>(x - 0.5 * d * n)};
    p.effRadius = hertzRadius(a);
    p.feature = static_cast<uint32_t>(k);
    all.push_back(p);
  }
  return keepDeepestPoints<D>(all, out);
}

// The corners beyond a plane or a drum (sim/shapes/point_rows.hpp).
struct Corners {
  template <int D, class Depth, class Normal>
  static int run(const ElementRef<D>& a, Depth depth, Normal normal, ContactPoint<D>* out) {
    return cornerRow<D>(a, depth, normal, out);
  }
};

// The element against a wall's polytope w (in the world: its corners and normals as given).
template <int D>
int polytopeWall(const ElementRef<D>& a, const Polytope<D>& w, ContactPoint<D>* out) {
  thread_local Placed<D> pa;
  thread_local std::vector<VecD<D>> wn;
  pa.place(a);
  wn.resize(w.faces.size());
  for (size_t k = 0; k < w.faces.size(); ++k) wn[k] = w.faces[k].normal;
  const int n = polytopeContact<D>(polytopeOf(a), pa.corners, pa.normals, w, w.vertices, wn, out);
  return withRadius(n, hertzRadius(a), out);
}

template <int D>
int boxRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& w = *static_cast<const physics::BoxShape<D>*>(wall);
  if (!physics::intersect<D>(physics::SphereShape<D>{a.x, a.r}, w)) return 0;
  thread_local Polytope<D> box;
  boxPolytope<D>(w.centre, w.axes, w.halfExtents, box);
  return polytopeWall(a, box, out);
}

template <int D>
int finiteRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& w = *static_cast<const physics::FlatWallShape<D>*>(wall);
  if (!physics::intersect<D>(physics::SphereShape<D>{a.x, a.r}, w)) return 0;
  thread_local Polytope<D> flat;
  flatPolytope<D>(w.centre, w.axes, w.halfExtents, flat);
  const int n = polytopeWall(a, flat, out);
  if (!(w.hole > 0)) return n;
  int kept = 0;
  for (int k = 0; k < n; ++k) {
    VecD<D> in = out[k].g.point - w.centre;
    Real s2 = 0;
    for (int d = 0; d < D - 1; ++d) s2 += std::pow(in.dot(w.axes[d]), 2);
    if (std::sqrt(s2) >= w.hole) out[kept++] = out[k];
  }
  return kept;
}

// A polyhedron against a mesh wall, as its corners against a plane and the mesh's ridges
// against its faces: each corner beyond a triangle near it (on the far side of the triangle's
// plane from the element's centre, over the triangle) is a point, the deepest such triangle's,
// keyed by the corner, so its spring follows it from triangle to triangle; and each edge where
// the mesh bends away from the element (or its border) that passes through the element gives
// its deepest point, pushed out through the element's nearest face. Edges and corners inside a
// flat or hollow part of the mesh are not contact features, so a box face down on a floor of
// many triangles rests on its four corners, as on a plane.
template <int D>
int meshRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  if constexpr (D != 3) {
    return 0;
  } else {
    const auto& m = *static_cast<const physics::MeshShape<D>*>(wall);
    const physics::TriangleMesh& mesh = *m.mesh;
    const Polytope<3>& poly = polytopeOf(a);
    thread_local std::vector<uint32_t> near;
    thread_local std::vector<ContactPoint<D>> all;
    thread_local std::vector<Vec3> corners, normals;
    thread_local std::vector<Real> offsets;
    // The element in the mesh's frame.
    const Mat3 rt = m.rotation.transpose();
    const Vec3 c = rt * (a.x - m.offset);
    const Mat3 rot = rt * rotationMatrix(a.q);
    corners.resize(poly.vertices.size());
    for (size_t k = 0; k < corners.size(); ++k) corners[k] = c + rot * poly.vertices[k];
    normals.resize(poly.faces.size());
    offsets.resize(poly.faces.size());
    for (size_t f = 0; f < poly.faces.size(); ++f) {
      normals[f] = rot * poly.faces[f].normal;
      offsets[f] = normals[f].dot(corners[poly.faces[f].loop[0]]);
    }
    mesh.near(c, a.r, near);
    all.clear();
    const Real r = hertzRadius(a);
    const auto emit = [&](const Vec3& point, const Vec3& normal, Real depth, uint32_t feature) {
      ContactPoint<D> p;
      p.g = {Vec3(m.rotation * normal), depth, Vec3(m.rotation * point + m.offset)};
      p.effRadius = r;
      p.feature = feature;
      all.push_back(p);
    };
    // The side of triangle t the element's centre is on (its unit normal towards it).
    const auto towards = [&](uint32_t t) {
      const Vec3& n = mesh.normals[t];
      return n.dot(c - mesh.vertices[mesh.triangles[t][0]]) >= 0 ? n : Vec3(-n);
    };
    thread_local physics::FacingTriangles facing;
    facing.prepare(mesh, near, c);
    for (size_t k = 0; k < corners.size(); ++k) {
      const Vec3& x = corners[k];
      Vec3 normal = Vec3::Zero();
      const Real deepest = facing.depthBehind(mesh, x, a.r, normal);
      if (deepest > 0) emit(Vec3(x - 0.5 * deepest * normal), normal, deepest, static_cast<uint32_t>(k));
    }
    // The ridges: edges of the near triangles with one triangle, or whose two triangles bend
    // away from the element.
    thread_local std::vector<std::array<uint32_t, 4>> edges;  // corners a < b, triangle, slot
    edges.clear();
    for (uint32_t t : near) {
      const auto& v = mesh.triangles[t];
      for (int e = 0; e < 3; ++e) {
        edges.push_back({std::min(v[e], v[(e + 1) % 3]), std::max(v[e], v[(e + 1) % 3]), t, v[(e + 2) % 3]});
      }
    }
    std::sort(edges.begin(), edges.end());
    for (size_t i = 0; i < edges.size();) {
      size_t j = i + 1;
      while (j < edges.size() && edges[j][0] == edges[i][0] && edges[j][1] == edges[i][1]) ++j;
      bool ridge = j - i == 1;
      if (j - i == 2) {
        const uint32_t t1 = edges[i][2];
        const Vec3 other = mesh.vertices[edges[i + 1][3]];
        ridge = towards(t1).dot(other - mesh.vertices[edges[i][0]]) < -1e-9 * a.r;
      }
      if (ridge) {
        // The edge's part inside the element (clipped by its face planes), and there the point
        // deepest below the nearest face (a concave function along the edge: golden section).
        const Vec3 p = mesh.vertices[edges[i][0]], d = mesh.vertices[edges[i][1]] - p;
        Real lo = 0, hi = 1;
        for (size_t f = 0; f < normals.size() && lo <= hi; ++f) {
          const Real s0 = normals[f].dot(p) - offsets[f], s1 = normals[f].dot(d);
          if (s1 == 0) {
            if (s0 > 0) hi = -1;
          } else if (s1 > 0) {
            hi = std::min(hi, -s0 / s1);
          } else {
            lo = std::max(lo, -s0 / s1);
          }
        }
        if (lo < hi) {
          const auto depthAt = [&](Real t, size_t* face) {
            Real least = std::numeric_limits<Real>::infinity();
            for (size_t f = 0; f < normals.size(); ++f) {
              const Real h = offsets[f] - normals[f].dot(p + t * d);
              if (h < least) least = h, *face = f;
            }
            return least;
          };
          size_t face = 0;
          Real x0 = lo, x1 = hi;
          const Real g = (std::sqrt(5.0) - 1) / 2;
          for (int it = 0; it < 60 && x1 - x0 > 1e-12; ++it) {
            const Real u = x1 - g * (x1 - x0), w = x0 + g * (x1 - x0);
            if (depthAt(u, &face) > depthAt(w, &face)) {
              x1 = w;
            } else {
              x0 = u;
            }
          }
          const Real t = 0.5 * (x0 + x1);
          const Real depth = depthAt(t, &face);
          if (depth > 0) {
            const Vec3 at = p + t * d;
            emit(Vec3(at + 0.5 * depth * normals[face]), normals[face], depth,
                 0x10000u + ((edges[i][0] * 2654435761u) ^ edges[i][1]) % 0xfff0000u);
          }
        }
      }
      i = j;
    }
    return keepDeepestPoints<D>(all, out);
  }
}

}  // namespace

template <int D>
void registerPolytope(ShapeTable<D>& t) {
  t.add(std::make_unique<PolytopeType<D>>());
  const std::string_view n = typeName<D>();
  t.addPair(n, n, {pairRow<D>, false});
  t.addPair(n, D == 3 ? "sphere" : "disc", {ballRow<D>, false});
  t.addPair(n, D == 3 ? "superquadric" : "superellipse", {gaugeRow<D>, false});
  t.addWall(n, WallShape::Plane, {planeByPoints<D, Corners>, false});
  t.addWall(n, WallShape::Drum, {drumByPoints<D, Corners>, false});
  t.addWall(n, WallShape::Finite, {finiteRow<D>, false});
  t.addWall(n, WallShape::Box, {boxRow<D>, false});
  if (D == 3) t.addWall(n, WallShape::Mesh, {meshRow<D>, false});
}

template void registerPolytope<2>(ShapeTable<2>&);
template void registerPolytope<3>(ShapeTable<3>&);

}  // namespace demlab::sim
