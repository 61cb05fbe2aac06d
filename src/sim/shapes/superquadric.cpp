// The superquadric shape type (3D, parameters a b c n1 n2) and the superellipse (2D, a b n):
// sim/shapes/superquadric.hpp has the geometry, sim/shapes/convex_contact.hpp the contact.
//
// Rows: superquadric against superquadric and against the ball (a ball is the superquadric
// (r, r, r, 2, 2)), and against every wall kind: planes and drums by the support point, finite
// and box walls by the wall's point deepest in the superquadric. Each contact is one point. The Hertz
// radius of a superquadric is its volume-equivalent sphere's (the area-equivalent disc's in
// 2D), so that an ellipsoid of equal half axes is the sphere in every respect; the pair's is
// R_a R_b / (R_a + R_b).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/validity.hpp"
#include "physics/narrow_phase.hpp"
#include "physics/shapes.hpp"
#include "sim/obj_manager.hpp"
#include "sim/shape.hpp"
#include "physics/triangle_mesh.hpp"
#include "sim/shapes/convex_contact.hpp"
#include "sim/shapes/polytope.hpp"
#include "sim/shapes/radial_mesh.hpp"
#include "sim/shapes/superquadric.hpp"

namespace demlab::sim {

namespace {

constexpr Real kMinExponent = 2, kMaxExponent = 20;

template <int D>
Superquadric<D> fromParams(std::span<const double> p) {
  Superquadric<D> s;
  s.a = p[0];
  s.b = p[1];
  if constexpr (D == 3) {
    s.c = p[2];
    s.n1 = p[3];
    s.n2 = p[4];
  } else {
    s.n1 = s.n2 = p[2];
  }
  return s;
}

template <int D>
class SuperquadricType final : public ShapeType<D> {
 public:
  std::string_view name() const override { return D == 3 ? "superquadric" : "superellipse"; }
  std::string_view parameters() const override {
    return D == 3 ? "a b c n1 n2: half axes along x, y, z (m); blockiness from the xy plane to "
                    "z and within the xy plane (2: ellipsoid; up to 20: a rounded box)"
                  : "a b n: half axes along x, y (m); blockiness (2: ellipse; up to 20: a "
                    "rounded rectangle)";
  }
  void check(std::span<const double> p) const override {
    const size_t want = D == 3 ? 5 : 3;
    if (p.size() != want) {
      throw Error("bad shape parameters: a " + std::string(name()) + " takes " +
                      std::to_string(want) + " (" + std::string(parameters()) + "), got " +
                      std::to_string(p.size()),
                  {"VALUE", "SHAPE"});
    }
    for (int k = 0; k < D; ++k) {
      if (!validity::inRange(p[k], validity::kMinRadius, validity::kMaxRadius)) {
        throw Error("bad shape parameters: half axis " + std::to_string(k + 1) + " of the " +
                        std::string(name()) + " must be between 1e-12 and 1e9 m",
                    {"VALUE", "SHAPE"});
      }
    }
    for (size_t k = D; k < p.size(); ++k) {
      if (!validity::inRange(p[k], kMinExponent, kMaxExponent)) {
        throw Error("bad shape parameters: the " + std::string(name()) +
                        "'s exponents must be between 2 and 20 (convex and smooth)",
                    {"VALUE", "SHAPE"});
      }
    }
    const Real lo = *std::min_element(p.begin(), p.begin() + D);
    const Real hi = *std::max_element(p.begin(), p.begin() + D);
    if (hi > 1e6 * lo) {
      throw Error("bad shape parameters: the " + std::string(name()) +
                      "'s half axes differ by more than 1e6",
                  {"VALUE", "SHAPE"});
    }
  }

  std::optional<std::vector<double>> scaled(std::span<const double> p, Real f) const override {
    std::vector<double> out(p.begin(), p.end());
    for (int k = 0; k < D; ++k) out[k] *= f;
    return out;
  }

  // The largest distance 1/phi(u) over unit directions u: a 16 x 16 grid over the first octant
  // (the shape is symmetric in every axis; its distance has one peak there, at an axis or at the
  // corner) refined about its best point by pattern search, widened by 1e-9 for what the
  // refinement leaves.
  Real boundingRadius(std::span<const double> p) const override {
    const Superquadric<D> s = fromParams<D>(p);
    const auto dirOf = [](Real t, Real u) {
      VecD<D> d;
      if constexpr (D == 3) {
        d = Vec3(std::cos(t) * std::sin(u), std::sin(t) * std::sin(u), std::cos(u));
      } else {
        (void)u;
        d = Vec2(std::cos(t), std::sin(t));
      }
      return d;
    };
    const Real q = std::numbers::pi / 2;
    const int n = D == 3 ? 16 : 256;
    Real best = 0, bt = 0, bu = 0;
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= (D == 3 ? n : 0); ++j) {
        const Real t = q * i / n, u = q * j / n;
        const Real r = 1 / s.gauge(dirOf(t, u));
        if (r > best) best = r, bt = t, bu = u;
      }
    }
    for (Real h = q / n; h > 1e-12; h *= 0.5) {
      bool moved = true;
      while (moved) {
        moved = false;
        for (int k = 0; k < 4; ++k) {
          const Real t = std::clamp(bt + (k == 0 ? h : k == 1 ? -h : 0), Real{0}, q);
          const Real u = std::clamp(bu + (k == 2 ? h : k == 3 ? -h : 0), Real{0}, q);
          const Real r = 1 / s.gauge(dirOf(t, u));
          if (r > best) best = r, bt = t, bu = u, moved = true;
        }
      }
    }
    return best * (1 + 1e-9);
  }

  // Closed forms through Euler's beta function (Jaklic, Leonardis and Solina, Segmentation and
  // Recovery of Superquadrics, 2000, for 3D; the Dirichlet integral for 2D).
  MassProperties<D> massProperties(std::span<const double> p) const override {
    MassProperties<D> m;
    if constexpr (D == 3) {
      const Real a = p[0], b = p[1], c = p[2], e1 = 2 / p[3], e2 = 2 / p[4];
      const auto B = [](Real x, Real y) { return std::beta(x, y); };
      m.volume = 2 * a * b * c * e1 * e2 * B(e1 / 2 + 1, e1) * B(e2 / 2, e2 / 2);
      const Real k = 0.5 * a * b * c * e1 * e2;
      const Real t1 = B(1.5 * e2, 0.5 * e2) * B(0.5 * e1, 2 * e1 + 1);
      const Real t2 = 4 * B(0.5 * e2, 0.5 * e2 + 1) * B(1.5 * e1, e1 + 1);
      m.inertia = Mat3::Zero();
      m.inertia(0, 0) = k * (b * b * t1 + c * c * t2);
      m.inertia(1, 1) = k * (a * a * t1 + c * c * t2);
      m.inertia(2, 2) = k * (a * a + b * b) * t1;
    } else {
      const Real a = p[0], b = p[1], n = p[2];
      // J(p, q) = integral of u^(p-1) v^(q-1) over u^n + v^n <= 1, u, v >= 0.
      const auto J = [n](Real pp, Real qq) {
        return std::exp(std::lgamma(pp / n) + std::lgamma(qq / n) - std::lgamma((pp + qq) / n + 1)) /
               (n * n);
      };
      m.volume = 4 * a * b * J(1, 1);
      m.inertia = Mat3::Zero();
      m.inertia(2, 2) = 4 * a * b * (a * a * J(3, 1) + b * b * J(1, 3));
    }
    return m;
  }

  // The surface through the gauge: the direction u maps to u / phi(u).
  std::vector<Vec3> renderTriangles(std::span<const double> p) const override {
    const Superquadric<D> s = fromParams<D>(p);
    std::vector<Vec3> out;
    const Real pi = std::numbers::pi;
    if constexpr (D == 2) {
      const int n = 72;
      for (int i = 0; i < n; ++i) {
        const Vec2 d0(std::cos(2 * pi * i / n), std::sin(2 * pi * i / n));
        const Vec2 d1(std::cos(2 * pi * (i + 1) / n), std::sin(2 * pi * (i + 1) / n));
        const Vec2 p0 = d0 / s.gauge(d0), p1 = d1 / s.gauge(d1);
        out.push_back(Vec3::Zero());
        out.emplace_back(p0.x(), p0.y(), 0);
        out.emplace_back(p1.x(), p1.y(), 0);
      }
    } else {
      appendRadialMesh(out, 16, 32, [&](const Vec3& d) { return Vec3(d / s.gauge(d)); });
    }
    return out;
  }
};

// Returns element e as a placed gauge body (a ball as the superquadric (r, r, r, 2, 2)).
template <int D>
PlacedGauge<D> placed(const ElementRef<D>& e) {
  PlacedGauge<D> g;
  if (e.g->params.empty()) {
    g.shape.a = g.shape.b = g.shape.c = e.r;
  } else {
    g.shape = fromParams<D>(e.g->params);
  }
  g.centre = e.x;
  g.rot = rotationMatrix(e.q);
  return g;
}

// Returns the Hertz radius of element e: the ball's radius, or the equal-volume ball's.
template <int D>
Real hertzRadius(const ElementRef<D>& e) {
  return e.g->params.empty() ? e.r : volumeEquivalentRadius(*e.g);
}

// Returns the radius of curvature of g's surface near x (world): 3D the Gaussian one,
// 1 / sqrt(K), 2D the curve's. K is the curvature of the level set of g's gauge through x,
// -det([[H, grad], [grad^T, 0]]) / |grad|^4 (|grad|^3 in 2D) from the squared gauge's gradient
// and Hessian; the level set phi = s is the surface scaled by s about the centre, so the
// surface's radius is the level set's over s. Flat parts (a blocky face: K -> 0) take at most
// the largest radius an ellipsoid of the same half axes has, a_max^2 / a_min. Changes nothing.
template <int D>
Real surfaceRadius(const PlacedGauge<D>& g, const VecD<D>& x) {
  VecD<D> grad;
  MatD<D> h;
  const Real psi = g.squaredGauge(x, grad, h);
  Eigen::Matrix<Real, D + 1, D + 1> bordered = Eigen::Matrix<Real, D + 1, D + 1>::Zero();
  bordered.template topLeftCorner<D, D>() = h;
  bordered.template topRightCorner<D, 1>() = grad;
  bordered.template bottomLeftCorner<1, D>() = grad.transpose();
  const Real len = grad.norm(), k = -bordered.determinant();
  const Real lo = D == 3 ? std::min({g.shape.a, g.shape.b, g.shape.c}) : std::min(g.shape.a, g.shape.b);
  const Real hi = D == 3 ? std::max({g.shape.a, g.shape.b, g.shape.c}) : std::max(g.shape.a, g.shape.b);
  const Real cap = hi * hi / lo;
  if (!(psi > 0 && len > 0 && k > 0)) return cap;
  const Real levelRadius = D == 3 ? len * len / std::sqrt(k) : len * len * len / k;
  return std::min(cap, levelRadius / std::sqrt(psi));
}

template <int D>
int pairRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!((b.x - a.x).norm() < a.r + b.r)) return 0;  // bounding balls apart
  const PlacedGauge<D> ga = placed(a), gb = placed(b);
  ConvexContact<D> c;
  if (!convexContact(ga, gb, a.r + b.r, c)) return 0;
  const Real ra = hertzRadius(a), rb = hertzRadius(b);
  out[0].g = {c.normal, c.overlap, c.point};
  out[0].effRadius = ra * rb / (ra + rb);
  out[0].localRadius = 0;
  if (a.localCurvature) {
    const Real la = surfaceRadius(ga, c.point), lb = surfaceRadius(gb, c.point);
    out[0].localRadius = la * lb / (la + lb);
  }
  out[0].feature = 0;
  return 1;
}

// Writes c as the row's one contact point (a against a wall: the wall is flat, so the pair's
// local radius is a's).
template <int D>
int convexPoint(const ElementRef<D>& a, const ConvexContact<D>& c, ContactPoint<D>* out) {
  out[0].g = {c.normal, c.overlap, c.point};
  out[0].effRadius = hertzRadius(a);
  out[0].localRadius = a.localCurvature ? surfaceRadius(placed(a), c.point) : 0;
  out[0].feature = 0;
  return 1;
}

// Writes the contact with a surface whose outward normal (towards the element) is n at the
// deepest point p, depth = how far p lies behind it.
template <int D>
int wallPoint(const ElementRef<D>& a, const VecD<D>& p, const VecD<D>& n, Real depth,
              ContactPoint<D>* out) {
  if (!(depth > 0)) return 0;
  return convexPoint(a, ConvexContact<D>{VecD<D>(-n), VecD<D>(p + 0.5 * depth * n), depth}, out);
}

template <int D>
int planeRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& pl = *static_cast<const physics::PlaneShape<D>*>(wall);
  if ((a.x - pl.point).dot(pl.normal) >= a.r) return 0;
  const VecD<D> p = placed(a).support(-pl.normal);
  return wallPoint(a, p, pl.normal, -(p - pl.point).dot(pl.normal), out);
}

// Inside a drum, the deepest point is the one farthest from the axis: the support point along
// the outward radial direction, found by fixed-point iteration on that direction (exact for a
// ball; for an element small against the drum, the iteration contracts by about its size over
// the drum's radius each time).
template <int D>
int drumRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& dr = *static_cast<const physics::DrumShape<D>*>(wall);
  if (!dr.mayReach(a.x, a.r)) return 0;
  VecD<D> r = dr.radial(a.x);
  if (!(r.norm() > 0)) return 0;
  const PlacedGauge<D> g = placed(a);
  VecD<D> u = r / r.norm(), p = g.support(u);
  for (int it = 0; it < 50; ++it) {
    r = dr.radial(p);
    if (!(r.norm() > 0)) return 0;
    const VecD<D> u1 = r / r.norm();
    const bool done = (u1 - u).norm() <= 1e-14;
    u = u1;
    p = g.support(u);
    if (done) break;
  }
  return wallPoint(a, p, VecD<D>(-u), dr.radial(p).norm() - dr.radius, out);
}

// A finite wall (a rectangle or a segment, touched from both sides, perhaps with a hole): its
// point deepest in the element's gauge (convex_contact.hpp); over the hole, the rim's deepest
// point instead (the holed wall is not convex, but a convex function's least value on it lies on
// the rim when the whole wall's lies in the hole).
template <int D>
int finiteRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& w = *static_cast<const physics::FlatWallShape<D>*>(wall);
  if (!physics::intersect<D>(physics::SphereShape<D>{a.x, a.r}, w)) return 0;
  const PlacedGauge<D> g = placed(a);
  Eigen::Matrix<Real, D, D - 1> axes;
  Eigen::Matrix<Real, D - 1, 1> half;
  for (int k = 0; k < D - 1; ++k) axes.col(k) = w.axes[k], half[k] = w.halfExtents[k];
  const Eigen::Matrix<Real, D - 1, 1> s = minimiseOverBox<D, D - 1>(g, w.centre, axes, half, a.r);
  VecD<D> y = w.centre + axes * s;
  if (w.hole > 0 && s.norm() < w.hole) {
    if constexpr (D == 2) {
      const Vec2 lo = w.centre - w.hole * w.axes[0], hi = w.centre + w.hole * w.axes[0];
      y = g.gauge(lo) <= g.gauge(hi) ? lo : hi;
    } else {
      const auto rim = [&](Real t) {
        return Vec3(w.centre + w.hole * (std::cos(t) * w.axes[0] + std::sin(t) * w.axes[1]));
      };
      const int n = 64;
      const Real step = 2 * std::numbers::pi / n;
      Real best = 0, fbest = g.gauge(rim(0));
      for (int k = 1; k < n; ++k) {
        const Real f = g.gauge(rim(k * step));
        if (f < fbest) fbest = f, best = k * step;
      }
      // Golden-section search about the best sample.
      Real lo = best - step, hi = best + step;
      const Real r = (std::sqrt(5.0) - 1) / 2;
      for (int it = 0; it < 80 && hi - lo > 1e-13; ++it) {
        const Real x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo);
        if (g.gauge(rim(x1)) < g.gauge(rim(x2))) {
          hi = x2;
        } else {
          lo = x1;
        }
      }
      y = rim(0.5 * (lo + hi));
    }
  }
  ConvexContact<D> c;
  if (!contactAtWallPoint(g, y, c)) return 0;
  return convexPoint(a, c, out);
}

// A solid box wall: its point deepest in the element's gauge. An element whose centre has
// entered the box is pushed out through the nearest face, as a ball is.
template <int D>
int boxRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& w = *static_cast<const physics::BoxShape<D>*>(wall);
  const auto ball = physics::intersect<D>(physics::SphereShape<D>{a.x, a.r}, w);
  if (!ball) return 0;
  const PlacedGauge<D> g = placed(a);
  const VecD<D> local = w.axes.transpose() * (a.x - w.centre);
  ConvexContact<D> c;
  if ((local.cwiseAbs() - w.halfExtents).maxCoeff() > 0) {
    const VecD<D> s = minimiseOverBox<D, D>(g, w.centre, w.axes, w.halfExtents, a.r);
    if (!contactAtWallPoint(g, VecD<D>(w.centre + w.axes * s), c)) return 0;
    return convexPoint(a, c, out);
  }
  // The centre inside: the ball's normal (into the nearest face) and that face's plane.
  const VecD<D> n = ball->normal;
  int face = 0;
  for (int k = 1; k < D; ++k) {
    if (w.halfExtents[k] - std::abs(local[k]) < w.halfExtents[face] - std::abs(local[face])) face = k;
  }
  const VecD<D> onFace = a.x + (w.halfExtents[face] - std::abs(local[face])) * VecD<D>(-n);
  const VecD<D> p = g.support(n);
  c.normal = n;
  c.overlap = n.dot(p - onFace);
  c.point = p - 0.5 * c.overlap * n;
  return convexPoint(a, c, out);
}

// A superquadric against a mesh wall: each triangle near it as a flat polytope
// (polytopeGaugeContact), a point each; points two triangles give alike kept once, and points
// on triangles' rims dropped when a triangle touches with its face (on a flat mesh the body
// rests on the faces under it, not on the rims of those beside). A ridge with no face touching
// keeps its rim point.
template <int D>
int meshRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  if constexpr (D != 3) {
    return 0;
  } else {
    const auto& m = *static_cast<const physics::MeshShape<D>*>(wall);
    const physics::TriangleMesh& mesh = *m.mesh;
    thread_local std::vector<uint32_t> near;
    thread_local std::vector<ContactPoint<D>> all;
    thread_local Polytope<3> tri;
    mesh.near(Vec3(m.rotation.transpose() * (a.x - m.offset)), a.r, near);
    all.clear();
    if (tri.faces.empty()) {
      tri.vertices.resize(3);
      tri.faces = {{Vec3::Zero(), 0, {0, 1, 2}}, {Vec3::Zero(), 0, {2, 1, 0}}};
      tri.edges = {{0, 1}, {1, 2}, {0, 2}};
    }
    const PlacedGauge<D> g = placed(a);
    std::array<Vec3, 2> normals;
    for (uint32_t t : near) {
      for (int k = 0; k < 3; ++k) tri.vertices[k] = m.rotation * mesh.vertices[mesh.triangles[t][k]] + m.offset;
      normals[0] = m.rotation * mesh.normals[t];
      normals[1] = -normals[0];
      ContactPoint<D> p;
      if (polytopeGaugeContact<3>(tri, tri.vertices, normals, g, a.r, &p) == 0) continue;
      p.g.normal = -p.g.normal;  // from the element to the wall
      p.effRadius = hertzRadius(a);
      p.feature = std::abs(p.g.normal.dot(normals[0])) >= 1 - 1e-9 ? 1 : 0;  // on a face
      bool merged = false;
      for (ContactPoint<D>& q : all) {
        if ((q.g.point - p.g.point).norm() <= 1e-9 * a.r) {
          if (p.g.overlap > q.g.overlap) q = p;
          merged = true;
          break;
        }
      }
      if (!merged) all.push_back(p);
    }
    // A triangle's rim meets the body beside the face it rests on (within its contact patch):
    // where some triangle touches with its face, the rims' tilted points are dropped.
    if (std::any_of(all.begin(), all.end(), [](const ContactPoint<D>& x) { return x.feature == 1; })) {
      std::erase_if(all, [](const ContactPoint<D>& x) { return x.feature == 0; });
    }
    // Deepest first, a point's feature its rank (as a ball's on a mesh).
    std::sort(all.begin(), all.end(), [](const ContactPoint<D>& x, const ContactPoint<D>& y) {
      return x.g.overlap > y.g.overlap;
    });
    for (size_t k = 0; k < all.size(); ++k) all[k].feature = static_cast<uint32_t>(k);
    return keepDeepestPoints<D>(all, out);
  }
}

}  // namespace

template <int D>
PlacedGauge<D> placedGauge(const ElementRef<D>& e) {
  return placed(e);
}

template PlacedGauge<2> placedGauge<2>(const ElementRef<2>&);
template PlacedGauge<3> placedGauge<3>(const ElementRef<3>&);

template <int D>
bool ballSuperquadricContact(const VecD<D>& centre, Real radius, const ElementRef<D>& sq,
                             ContactPoint<D>& out) {
  if (!((sq.x - centre).norm() < radius + sq.r)) return false;
  PlacedGauge<D> ball;
  ball.shape.a = ball.shape.b = ball.shape.c = radius;
  ball.centre = centre;
  ball.rot = MatD<D>::Identity();
  ConvexContact<D> c;
  if (!convexContact(ball, placed(sq), radius + sq.r, c)) return false;
  const Real rb = hertzRadius(sq);
  out.g = {c.normal, c.overlap, c.point};
  out.effRadius = radius * rb / (radius + rb);
  out.localRadius = 0;
  if (sq.localCurvature) {
    const Real local = surfaceRadius(placed(sq), c.point);
    out.localRadius = radius * local / (radius + local);
  }
  out.feature = 0;
  return true;
}

template bool ballSuperquadricContact<2>(const Vec2&, Real, const ElementRef<2>&, ContactPoint<2>&);
template bool ballSuperquadricContact<3>(const Vec3&, Real, const ElementRef<3>&, ContactPoint<3>&);

template <int D>
void registerSuperquadric(ShapeTable<D>& t) {
  t.add(std::make_unique<SuperquadricType<D>>());
  const std::string_view n = D == 3 ? "superquadric" : "superellipse";
  const std::string_view ball = D == 3 ? "sphere" : "disc";
  t.addPair(n, n, {pairRow<D>, false});
  t.addPair(n, ball, {pairRow<D>, false});
  t.addWall(n, WallShape::Plane, {planeRow<D>, false});
  t.addWall(n, WallShape::Drum, {drumRow<D>, false});
  t.addWall(n, WallShape::Finite, {finiteRow<D>, false});
  t.addWall(n, WallShape::Box, {boxRow<D>, false});
  if (D == 3) t.addWall(n, WallShape::Mesh, {meshRow<D>, false});
}

template void registerSuperquadric<2>(ShapeTable<2>&);
template void registerSuperquadric<3>(ShapeTable<3>&);

}  // namespace demlab::sim
