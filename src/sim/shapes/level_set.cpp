// The level-set shape type (sim/shapes/level_set.hpp) and its rows.
//
// Contact is node against field, in both directions (Kawamoto et al. 2016): each surface node of
// one body where the other's field is negative is a contact point, its depth -phi and its
// normal the field's gradient there, keyed by the node. A pair's force is the sum over its
// nodes in contact, each through the scene's law, so it grows continuously as nodes enter and
// the work of the forces is conservative; the cost, stated in doc/design.md, is that the
// contact's stiffness grows with the number of nodes touching (a face contact is stiffer than
// a corner's, as a polytope's four corners are), so a scene of flat faces pressed together
// needs a smaller step than the automatic one. Beyond kMaxContactPoints nodes the deepest are
// kept.
//
// Rows: against itself, the ball (the ball's centre in the field, the field extended beyond the
// grid by the distance to it: one point), the polytope (its nodes in the polytope, the
// polytope's corners in its field), the superquadric (its nodes in the gauge, points of the
// superquadric's surface in its field), the clump (its members as balls), and the plane, drum,
// box, finite and mesh walls (its nodes beyond them). The Hertz radius is the volume-equivalent
// sphere's, as for the other shapes without curvature of their own.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "physics/narrow_phase.hpp"
#include "physics/shapes.hpp"
#include "physics/triangle_mesh.hpp"
#include "sim/shape.hpp"
#include "sim/shapes/level_set.hpp"
#include "sim/shapes/convex_contact.hpp"
#include "sim/shapes/level_set_internal.hpp"
#include "sim/shapes/point_rows.hpp"
#include "sim/shapes/polytope.hpp"

namespace demlab::sim {

namespace {

constexpr uint32_t kOtherBody = 0x80000000u;  // feature bit: the point is the other body's node

template <int D>
class LevelSetType final : public ShapeType<D> {
 public:
  std::string_view name() const override { return "levelset"; }
  std::string_view parameters() const override {
    return "h nx ny [nz] x0 y0 [z0] phi...: the signed distance (m, negative inside) on a grid "
           "of spacing h from the node (x0, y0 [, z0]), x fastest; `element levelset` builds it "
           "from an STL file or sampled function values";
  }
  void check(std::span<const double> p) const override { buildLevelSet<D>(p); }
  // Every point where the interpolated field is negative lies in a cell with a negative corner,
  // within a cell's diagonal of that corner.
  Real boundingRadius(std::span<const double> p) const override {
    const LevelSet<D> ls = buildLevelSet<D>(p);
    Real r = 0;
    for (size_t i = 0; i < ls.phi.size(); ++i) {
      if (!(ls.phi[i] < 0)) continue;
      const std::array<int, D> ix = nodeIndex<D>(i, ls.n);
      VecD<D> x;
      for (int d = 0; d < D; ++d) x[d] = ls.origin[d] + ls.h * ix[d];
      r = std::max(r, x.norm());
    }
    return r + ls.h * std::sqrt(Real{D});
  }
  MassProperties<D> massProperties(std::span<const double> p) const override {
    return polytopeMassProperties(buildLevelSet<D>(p).surface);
  }
  std::optional<std::vector<double>> scaled(std::span<const double> p, Real f) const override {
    std::vector<double> out(p.begin(), p.end());
    out[0] *= f;
    for (size_t k = 1 + D; k < out.size(); ++k) out[k] *= f;
    return out;
  }
  std::optional<std::vector<double>> translated(std::span<const double> p,
                                                const VecD<D>& offset) const override {
    std::vector<double> out(p.begin(), p.end());
    for (int d = 0; d < D; ++d) out[1 + D + d] += offset[d];
    return out;
  }
  std::shared_ptr<const void> derive(std::span<const double> p) const override {
    return std::make_shared<const LevelSet<D>>(buildLevelSet<D>(p));
  }
  // 3D: the surface's triangles. 2D: the inside of each cell's two triangles, fanned.
  std::vector<Vec3> renderTriangles(std::span<const double> p) const override {
    const LevelSet<D> ls = buildLevelSet<D>(p);
    std::vector<Vec3> out;
    const auto lift = [](const VecD<D>& v) {
      Vec3 w = Vec3::Zero();
      w.template head<D>() = v;
      return w;
    };
    if constexpr (D == 3) {
      for (const auto& f : ls.surface.faces) {
        for (uint32_t v : f.loop) out.push_back(lift(ls.surface.vertices[v]));
      }
    } else {
      const auto node = [&](int i, int j) {
        return Vec2(ls.origin.x() + ls.h * i, ls.origin.y() + ls.h * j);
      };
      const auto value = [&](int i, int j) { return ls.phi[static_cast<size_t>(j) * ls.n[0] + i]; };
      for (int j = 0; j + 1 < ls.n[1]; ++j) {
        for (int i = 0; i + 1 < ls.n[0]; ++i) {
          const int tri[2][3][2] = {{{0, 0}, {1, 0}, {1, 1}}, {{0, 0}, {1, 1}, {0, 1}}};
          for (const auto& t : tri) {
            // The triangle clipped to phi < 0 (linear along its edges): at most four corners.
            Vec2 poly[4];
            int m = 0;
            for (int k = 0; k < 3; ++k) {
              const int* a = t[k];
              const int* b = t[(k + 1) % 3];
              const Real va = value(i + a[0], j + a[1]), vb = value(i + b[0], j + b[1]);
              const Vec2 pa = node(i + a[0], j + a[1]), pb = node(i + b[0], j + b[1]);
              if (va < 0) poly[m++] = pa;
              if ((va < 0) != (vb < 0)) poly[m++] = pa + va / (va - vb) * (pb - pa);
            }
            for (int k = 1; k + 1 < m; ++k) {
              out.push_back(lift(poly[0]));
              out.push_back(lift(poly[k]));
              out.push_back(lift(poly[k + 1]));
            }
          }
        }
      }
    }
    return out;
  }
};

template <int D>
const LevelSet<D>& levelSetOf(const ElementRef<D>& e) {
  return *static_cast<const LevelSet<D>*>(e.g->data.get());
}

template <int D>
Real pairRadius(const ElementRef<D>& a, const ElementRef<D>& b) {
  const Real ra = volumeEquivalentRadius(*a.g), rb = volumeEquivalentRadius(*b.g);
  return ra * rb / (ra + rb);
}

// Calls visit(k, x) for each surface node k of level-set element e, x its world position,
// within reach of centre (nodes farther cannot touch what lies there).
template <int D, class Visit>
void forNodesNear(const ElementRef<D>& e, const VecD<D>& centre, Real reach, Visit visit) {
  const LevelSet<D>& ls = levelSetOf(e);
  const VecD<D> c = rotateInverse(e.q, VecD<D>(centre - e.x));
  const Real reach2 = reach * reach;
  for (size_t k = 0; k < ls.nodes.size(); ++k) {
    if ((ls.nodes[k] - c).squaredNorm() > reach2) continue;
    visit(static_cast<uint32_t>(k), VecD<D>(e.x + rotate(e.q, ls.nodes[k])));
  }
}

// Calls visit(k, x) for every surface node k of level-set element e (all lie within its
// bounding radius: the wall rows need no filter).
template <int D, class Visit>
void forEachNode(const ElementRef<D>& e, Visit visit) {
  const LevelSet<D>& ls = levelSetOf(e);
  for (size_t k = 0; k < ls.nodes.size(); ++k) {
    visit(static_cast<uint32_t>(k), VecD<D>(e.x + rotate(e.q, ls.nodes[k])));
  }
}

// Returns true and the depth and world outward normal of point x inside level-set element e.
template <int D>
bool insideField(const ElementRef<D>& e, const VecD<D>& x, Real& depth, VecD<D>& normal) {
  const LevelSet<D>& ls = levelSetOf(e);
  Real v;
  VecD<D> g;
  if (!ls.sample(rotateInverse(e.q, VecD<D>(x - e.x)), v, g) || !(v < 0)) return false;
  const Real len = g.norm();
  if (!(len > 0)) return false;
  depth = -v;
  normal = rotate(e.q, VecD<D>(g / len));
  return true;
}

// A point of depth d at x with normal n (from a to b): x is a's node inside b when ofA, else
// b's node inside a; the point is halfway between x and the surface it is under.
template <int D>
ContactPoint<D> point(const VecD<D>& x, const VecD<D>& n, Real d, bool ofA, Real radius,
                      uint32_t feature) {
  ContactPoint<D> p;
  p.g = {n, d, VecD<D>(x + (ofA ? -0.5 : 0.5) * d * n)};
  p.effRadius = radius;
  p.feature = feature;
  return p;
}

template <int D>
int pairRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!((b.x - a.x).norm() < a.r + b.r)) return 0;
  thread_local std::vector<ContactPoint<D>> all;
  all.clear();
  const Real radius = pairRadius(a, b);
  Real depth;
  VecD<D> n;
  forNodesNear(a, b.x, b.r, [&](uint32_t k, const VecD<D>& x) {
    if (insideField(b, x, depth, n)) all.push_back(point<D>(x, VecD<D>(-n), depth, true, radius, k));
  });
  forNodesNear(b, a.x, a.r, [&](uint32_t k, const VecD<D>& x) {
    if (insideField(a, x, depth, n)) all.push_back(point<D>(x, n, depth, false, radius, k | kOtherBody));
  });
  return keepDeepestPoints<D>(all, out);
}

}  // namespace

// Returns true and writes the contact of a ball (centre, radius) with level-set element e (the
// normal from the ball to e). A centre in the grid reads the field there; a centre beyond it
// (a ball larger than the grid's border) is projected onto the surface: from the surface point
// nearest the grid's point nearest the centre, steps of at most a node spacing along the surface towards
// the centre, each projected back onto it, until the step vanishes (the nearest surface point of a convex
// patch). Changes nothing else.
template <int D>
bool ballLevelSetContact(const VecD<D>& centre, Real radius, const ElementRef<D>& e,
                         ContactPoint<D>& out) {
  if (!((e.x - centre).norm() < radius + e.r)) return false;
  const LevelSet<D>& ls = levelSetOf(e);
  const VecD<D> c = rotateInverse(e.q, VecD<D>(centre - e.x));
  const auto clampToGrid = [&](VecD<D> p) {
    for (int d = 0; d < D; ++d) p[d] = std::clamp(p[d], ls.origin[d], ls.origin[d] + ls.h * (ls.n[d] - 1));
    return p;
  };
  Real v, dist;
  VecD<D> g, nLocal;
  if (ls.sample(c, v, g)) {
    const Real len = g.norm();
    if (!(v < radius) || !(len > 0)) return false;
    dist = v;
    nLocal = g / len;
  } else {
    // The surface point nearest p: p - phi grad phi.
    const auto project = [&](const VecD<D>& p, VecD<D>& y, VecD<D>& n) {
      Real pv;
      VecD<D> pg;
      if (!ls.sample(clampToGrid(p), pv, pg) || !(pg.norm() > 0)) return false;
      n = pg / pg.norm();
      y = clampToGrid(p) - pv * n;
      return true;
    };
    VecD<D> y, n;
    if (!project(c, y, n)) return false;
    for (int it = 0; it < 64; ++it) {
      VecD<D> t = c - y;
      t -= t.dot(n) * n;
      const Real len = t.norm();
      if (!(len > 1e-6 * ls.h)) break;
      if (len > ls.h) t *= ls.h / len;  // short steps: the surface curves away
      if (!project(VecD<D>(y + t), y, n)) return false;
    }
    dist = (c - y).norm();
    if (!(dist < radius) || !(dist > 0)) return false;
    nLocal = (c - y) / dist;
  }
  const Real depth = radius - dist;
  const VecD<D> nWorld = rotate(e.q, nLocal);  // e's outward normal, towards the ball
  const VecD<D> at = centre - (radius - 0.5 * depth) * nWorld;
  out.g = {VecD<D>(-nWorld), depth, at};
  const Real rb = volumeEquivalentRadius(*e.g);
  out.effRadius = radius * rb / (radius + rb);
  out.feature = 0;
  return true;
}

namespace {

template <int D>
int ballRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!ballLevelSetContact(b.x, b.r, a, out[0])) return 0;
  out[0].g.normal = -out[0].g.normal;
  return 1;
}

// A level set against a polytope: its nodes inside the polytope (depth below the nearest face
// plane) and the polytope's corners inside its field.
template <int D>
int polytopeRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!((b.x - a.x).norm() < a.r + b.r)) return 0;
  const Polytope<D>& poly = *static_cast<const Polytope<D>*>(b.g->data.get());
  thread_local std::vector<ContactPoint<D>> all;
  all.clear();
  const Real radius = pairRadius(a, b);
  forNodesNear(a, b.x, b.r, [&](uint32_t k, const VecD<D>& x) {
    const VecD<D> y = rotateInverse(b.q, VecD<D>(x - b.x));
    Real least = std::numeric_limits<Real>::infinity();
    size_t face = 0;
    for (size_t f = 0; f < poly.faces.size(); ++f) {
      const Real s = poly.faces[f].offset - poly.faces[f].normal.dot(y);
      if (s < least) least = s, face = f;
    }
    if (least > 0) {
      const VecD<D> n = rotate(b.q, poly.faces[face].normal);
      all.push_back(point<D>(x, VecD<D>(-n), least, true, radius, k));
    }
  });
  Real depth;
  VecD<D> n;
  for (size_t k = 0; k < poly.vertices.size(); ++k) {
    const VecD<D> x = b.x + rotate(b.q, poly.vertices[k]);
    if (insideField(a, x, depth, n)) {
      all.push_back(point<D>(x, n, depth, false, radius, static_cast<uint32_t>(k) | kOtherBody));
    }
  }
  return keepDeepestPoints<D>(all, out);
}

// A level set against a superquadric (superellipse in 2D): its nodes inside the superquadric,
// each at the depth (1 - phi) / |grad phi| below its surface (first order in the gauge phi,
// exact for a sphere) along the gradient, and points of the superquadric's surface inside its
// field, as the polytope's corners are. The surface points are the radial projections u / phi(u)
// of directions u spread evenly (a Fibonacci sphere; a fan in 2D), as many as put them about a
// node spacing apart, taken only where the ray from the centre along u can reach the level
// set's bounding sphere.
template <int D>
int gaugeRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!((b.x - a.x).norm() < a.r + b.r)) return 0;
  const PlacedGauge<D> g = placedGauge(b);
  const LevelSet<D>& ls = levelSetOf(a);
  thread_local std::vector<ContactPoint<D>> all;
  all.clear();
  const Real radius = pairRadius(a, b);
  forNodesNear(a, b.x, b.r, [&](uint32_t k, const VecD<D>& x) {
    Real phi;
    const VecD<D> grad = g.gaugeAndGradient(x, phi);
    const Real len = grad.norm();
    if (!(phi < 1) || !(len > 0)) return;
    all.push_back(point<D>(x, VecD<D>(-grad / len), (1 - phi) / len, true, radius, k));
  });
  const Real inner = D == 3 ? std::min({g.shape.a, g.shape.b, g.shape.c})
                            : std::min(g.shape.a, g.shape.b);
  const Real pi = std::numbers::pi;
  const Real spacing = ls.h;  // the field's own resolution
  const int count = D == 3 ? static_cast<int>(std::min(4096.0, std::ceil(4 * pi * b.r * b.r / (spacing * spacing))))
                           : static_cast<int>(std::min(1024.0, std::ceil(2 * pi * b.r / spacing)));
  const Real golden = pi * (3 - std::sqrt(Real{5}));
  Real depth;
  VecD<D> n;
  for (int i = 0; i < count; ++i) {
    VecD<D> u;
    if constexpr (D == 3) {
      const Real z = 1 - 2 * (i + 0.5) / count, rho = std::sqrt(std::max(Real{0}, 1 - z * z));
      u = Vec3(rho * std::cos(golden * i), rho * std::sin(golden * i), z);
    } else {
      const Real t = 2 * pi * (i + 0.5) / count;
      u = Vec2(std::cos(t), std::sin(t));
    }
    const VecD<D> w = g.rot * u;
    const Real t = std::clamp((a.x - b.x).dot(w), inner, b.r);
    if ((b.x + t * w - a.x).squaredNorm() > a.r * a.r) continue;
    const VecD<D> x = b.x + g.rot * VecD<D>(u / g.shape.gauge(u));
    if (insideField(a, x, depth, n)) {
      all.push_back(point<D>(x, n, depth, false, radius, static_cast<uint32_t>(i) | kOtherBody));
    }
  }
  return keepDeepestPoints<D>(all, out);
}

// The nodes beyond a wall's surface: depth(x) > 0 how far node x lies beyond it, normal(x) the
// direction from the element into the wall there.
template <int D, class Depth, class Normal>
int nodeRow(const ElementRef<D>& a, Depth depth, Normal normal, ContactPoint<D>* out) {
  thread_local std::vector<ContactPoint<D>> all;
  all.clear();
  const Real radius = volumeEquivalentRadius(*a.g);
  forEachNode(a, [&](uint32_t k, const VecD<D>& x) {
    const Real d = depth(x);
    if (d > 0) all.push_back(point<D>(x, normal(x), d, true, radius, k));
  });
  return keepDeepestPoints<D>(all, out);
}

// The nodes beyond a plane or a drum (sim/shapes/point_rows.hpp).
struct Nodes {
  template <int D, class Depth, class Normal>
  static int run(const ElementRef<D>& a, Depth depth, Normal normal, ContactPoint<D>* out) {
    return nodeRow<D>(a, depth, normal, out);
  }
};

// A solid box: its nodes inside the box (depth to the nearest face) and the box's corners in
// its field.
template <int D>
int boxRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& w = *static_cast<const physics::BoxShape<D>*>(wall);
  if (!physics::intersect<D>(physics::SphereShape<D>{a.x, a.r}, w)) return 0;
  thread_local std::vector<ContactPoint<D>> all;
  all.clear();
  const Real radius = volumeEquivalentRadius(*a.g);
  forEachNode(a, [&](uint32_t k, const VecD<D>& x) {
    const VecD<D> y = w.axes.transpose() * (x - w.centre);
    Real least = std::numeric_limits<Real>::infinity();
    VecD<D> n = VecD<D>::Zero();
    for (int d = 0; d < D; ++d) {
      const Real s = w.halfExtents[d] - std::abs(y[d]);
      if (s < least) least = s, n = Real(y[d] >= 0 ? 1 : -1) * w.axes.col(d);
    }
    if (least > 0) all.push_back(point<D>(x, VecD<D>(-n), least, true, radius, k));
  });
  Real depth;
  VecD<D> n;
  for (int c = 0; c < (1 << D); ++c) {
    VecD<D> x = w.centre;
    for (int d = 0; d < D; ++d) x += Real((c >> d & 1) ? 1 : -1) * w.halfExtents[d] * w.axes.col(d);
    if (insideField(a, x, depth, n)) all.push_back(point<D>(x, n, depth, false, radius, c | kOtherBody));
  }
  return keepDeepestPoints<D>(all, out);
}

// A finite wall (no thickness): the nodes on the far side of its plane from the element's
// centre, over the wall (not over its hole), within the element's reach.
template <int D>
int finiteRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& w = *static_cast<const physics::FlatWallShape<D>*>(wall);
  if (!physics::intersect<D>(physics::SphereShape<D>{a.x, a.r}, w)) return 0;
  VecD<D> normal;
  if constexpr (D == 3) {
    normal = w.axes[0].cross(w.axes[1]).normalized();
  } else {
    normal = Vec2(-w.axes[0].y(), w.axes[0].x());
  }
  if ((a.x - w.centre).dot(normal) < 0) normal = -normal;  // towards the element
  const auto over = [&](const VecD<D>& x) {
    const VecD<D> in = x - w.centre;
    Real s2 = 0;
    for (int d = 0; d < D - 1; ++d) {
      const Real s = in.dot(w.axes[d]);
      if (std::abs(s) > w.halfExtents[d]) return false;
      s2 += s * s;
    }
    return !(w.hole > 0) || std::sqrt(s2) >= w.hole;
  };
  return nodeRow<D>(
      a,
      [&](const VecD<D>& x) {
        const Real h = (x - w.centre).dot(normal);
        return h < 0 && -h <= a.r && over(x) ? -h : Real{0};
      },
      [&](const VecD<D>&) { return VecD<D>(-normal); }, out);
}

// A mesh wall: the nodes behind the triangles they lie over (as a polytope's corners: a flat
// floor of many triangles bears a level set as a plane does). A sharp ridge of the mesh pressing
// into the body between two nodes is felt only when it reaches a node: resolved to the nodes'
// spacing.
template <int D>
int meshRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  if constexpr (D != 3) {
    return 0;
  } else {
    const auto& m = *static_cast<const physics::MeshShape<D>*>(wall);
    const physics::TriangleMesh& mesh = *m.mesh;
    thread_local std::vector<uint32_t> near;
    thread_local std::vector<ContactPoint<D>> all;
    const Mat3 rt = m.rotation.transpose();
    const Vec3 c = rt * (a.x - m.offset);  // the element's centre in the mesh's frame
    mesh.near(c, a.r, near);
    all.clear();
    if (near.empty()) return 0;
    const Real radius = volumeEquivalentRadius(*a.g);
    thread_local physics::FacingTriangles facing;
    facing.prepare(mesh, near, c);
    forEachNode(a, [&](uint32_t k, const Vec3& x) {
      Vec3 normal;
      const Real d = facing.depthBehind(mesh, Vec3(rt * (x - m.offset)), a.r, normal);
      if (d > 0) all.push_back(point<D>(x, Vec3(m.rotation * normal), d, true, radius, k));
    });
    return keepDeepestPoints<D>(all, out);
  }
}

}  // namespace

template <int D>
void registerLevelSet(ShapeTable<D>& t) {
  t.add(std::make_unique<LevelSetType<D>>());
  t.addPair("levelset", "levelset", {pairRow<D>, false});
  t.addPair("levelset", D == 3 ? "sphere" : "disc", {ballRow<D>, false});
  t.addPair("levelset", D == 3 ? "polyhedron" : "polygon", {polytopeRow<D>, false});
  t.addPair("levelset", D == 3 ? "superquadric" : "superellipse", {gaugeRow<D>, false});
  t.addWall("levelset", WallShape::Plane, {planeByPoints<D, Nodes>, false});
  t.addWall("levelset", WallShape::Drum, {drumByPoints<D, Nodes>, false});
  t.addWall("levelset", WallShape::Box, {boxRow<D>, false});
  t.addWall("levelset", WallShape::Finite, {finiteRow<D>, false});
  if (D == 3) t.addWall("levelset", WallShape::Mesh, {meshRow<D>, false});
}

template void registerLevelSet<2>(ShapeTable<2>&);
template void registerLevelSet<3>(ShapeTable<3>&);
template bool ballLevelSetContact<2>(const Vec2&, Real, const ElementRef<2>&, ContactPoint<2>&);
template bool ballLevelSetContact<3>(const Vec3&, Real, const ElementRef<3>&, ContactPoint<3>&);

}  // namespace demlab::sim
