// The convex hull and mass properties of polygons and polyhedra (sim/shapes/polytope.hpp).
//
// A shape has at most 64 corners and its hull is found once per Geometry, so the hull is the
// plainest correct one: in 2D Andrew's monotone chain; in 3D every plane through three corners
// that has all the others on one side is a face plane (the corners on it, as a 64-bit mask,
// tell the faces apart), and each face's corners are the 2D hull of the points on its plane.
// Tolerances are relative to the shape's size, so a box of 1 um and one of 1 km hull alike.
#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <string>

#include "core/error.hpp"
#include "core/validity.hpp"
#include "sim/shapes/polytope.hpp"

namespace demlab::sim {

namespace {

[[noreturn]] void fail(const char* what, const std::string& why) {
  throw Error(std::string("bad shape parameters: the ") + what + " " + why, {"VALUE", "SHAPE"});
}

// Returns the indices of the corners of the 2D convex hull of pts, counterclockwise, starting
// at the lowest-leftmost point; points on the hull's edges or inside it are left out.
// tolArea: a cross product at most this is a straight line.
std::vector<uint32_t> hull2(const std::vector<Vec2>& pts, Real tolArea) {
  std::vector<uint32_t> idx(pts.size());
  for (uint32_t k = 0; k < idx.size(); ++k) idx[k] = k;
  std::sort(idx.begin(), idx.end(), [&](uint32_t a, uint32_t b) {
    return pts[a].x() != pts[b].x() ? pts[a].x() < pts[b].x() : pts[a].y() < pts[b].y();
  });
  const auto turn = [&](uint32_t o, uint32_t a, uint32_t b) {
    return cross(Vec2(pts[a] - pts[o]), Vec2(pts[b] - pts[o]));
  };
  std::vector<uint32_t> h;
  for (int pass = 0; pass < 2; ++pass) {
    const size_t base = h.size();
    for (size_t s = 0; s < idx.size(); ++s) {
      const uint32_t p = pass == 0 ? idx[s] : idx[idx.size() - 1 - s];
      while (h.size() >= base + 2 && turn(h[h.size() - 2], h.back(), p) <= tolArea) h.pop_back();
      h.push_back(p);
    }
    h.pop_back();  // the last point of each chain starts the other
  }
  return h;
}

// Returns the largest distance of a point from their mean: the scale of the tolerances.
template <int D>
Real spread(const std::vector<VecD<D>>& v) {
  VecD<D> mean = VecD<D>::Zero();
  for (const VecD<D>& p : v) mean += p;
  mean /= static_cast<Real>(v.size());
  Real s = 0;
  for (const VecD<D>& p : v) s = std::max(s, (p - mean).norm());
  return s;
}

template <int D>
std::vector<VecD<D>> readCorners(std::span<const double> params, const char* what) {
  if (params.size() % D != 0) {
    fail(what, "takes " + std::to_string(D) + " coordinates a corner (" + std::string(D == 3 ? "x y z" : "x y") +
                   " ...), got " + std::to_string(params.size()) + " numbers");
  }
  const size_t n = params.size() / D;
  if (n < D + 1 || n > kMaxPolytopeCorners) {
    fail(what, "takes " + std::to_string(D + 1) + " to " + std::to_string(kMaxPolytopeCorners) +
                   " corners, got " + std::to_string(n));
  }
  std::vector<VecD<D>> v(n);
  for (size_t k = 0; k < n; ++k) {
    for (int d = 0; d < D; ++d) {
      const double x = params[k * D + d];
      if (!(std::abs(x) <= validity::kMaxRadius)) {
        fail(what, "has corner " + std::to_string(k + 1) + " beyond 1e9 m (or not finite)");
      }
      v[k][d] = x;
    }
  }
  return v;
}

}  // namespace

template <int D>
Polytope<D> buildPolytope(std::span<const double> params, const char* what) {
  Polytope<D> p;
  p.vertices = readCorners<D>(params, what);
  const std::vector<VecD<D>>& v = p.vertices;
  const size_t n = v.size();
  const Real scale = spread<D>(v);
  if (!(scale >= validity::kMinRadius)) fail(what, "is smaller than 1e-12 m");
  const Real tol = 1e-9 * scale;
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) {
      if ((v[i] - v[j]).norm() <= tol) {
        fail(what, "has corners " + std::to_string(i + 1) + " and " + std::to_string(j + 1) +
                       " at the same point");
      }
    }
  }
  std::vector<bool> corner(n, false);
  if constexpr (D == 2) {
    const std::vector<uint32_t> h = hull2(v, tol * scale);
    if (h.size() < 3) fail(what, "has all its corners on one line");
    for (size_t k = 0; k < h.size(); ++k) {
      const uint32_t a = h[k], b = h[(k + 1) % h.size()];
      const Vec2 e = (v[b] - v[a]).normalized();
      typename Polytope<2>::Face f;
      f.normal = Vec2(e.y(), -e.x());
      f.offset = f.normal.dot(v[a]);
      f.loop = {a, b};
      p.faces.push_back(f);
      corner[a] = true;
    }
  } else {
    // The face planes, told apart by the set of corners on them.
    std::map<uint64_t, std::pair<Vec3, Real>> planes;
    for (size_t i = 0; i < n; ++i) {
      for (size_t j = i + 1; j < n; ++j) {
        for (size_t k = j + 1; k < n; ++k) {
          Vec3 nrm = (v[j] - v[i]).cross(v[k] - v[i]);
          if (!(nrm.norm() > 1e-6 * scale * scale)) continue;  // (nearly) on one line
          nrm.normalize();
          int above = 0, below = 0;
          uint64_t on = 0;
          for (size_t m = 0; m < n; ++m) {
            const Real s = nrm.dot(v[m] - v[i]);
            if (s > tol) ++above;
            else if (s < -tol) ++below;
            else on |= uint64_t{1} << m;
          }
          if (above > 0 && below > 0) continue;
          if (above == 0 && below == 0) fail(what, "has all its corners on one plane");
          if (above > 0) nrm = -nrm;
          planes.emplace(on, std::make_pair(nrm, nrm.dot(v[i])));
        }
      }
    }
    // A tolerance-wide plane through an edge may catch fewer corners than the true face: keep
    // only the sets that no other set contains.
    std::map<std::pair<uint32_t, uint32_t>, int> edgeFaces;
    for (const auto& [mask, plane] : planes) {
      bool inside = false;
      for (const auto& other : planes) {
        if (other.first != mask && (other.first & mask) == mask) inside = true;
      }
      if (inside) continue;
      typename Polytope<3>::Face f;
      f.normal = plane.first;
      f.offset = plane.second;
      // The corners of the face: the 2D hull of its points in the plane's (u, w) basis, which
      // with the outward normal is right-handed, so the hull's order is counterclockwise seen
      // from outside.
      const Vec3 u = f.normal.unitOrthogonal(), w = f.normal.cross(u);
      std::vector<uint32_t> ids;
      std::vector<Vec2> flat;
      for (uint32_t m = 0; m < n; ++m) {
        if (mask >> m & 1) ids.push_back(m), flat.emplace_back(u.dot(v[m]), w.dot(v[m]));
      }
      for (uint32_t k : hull2(flat, tol * scale)) f.loop.push_back(ids[k]);
      if (f.loop.size() < 3) fail(what, "is degenerate (corners nearly on one plane)");
      for (size_t k = 0; k < f.loop.size(); ++k) {
        const uint32_t a = f.loop[k], b = f.loop[(k + 1) % f.loop.size()];
        corner[a] = true;
        edgeFaces[{std::min(a, b), std::max(a, b)}] += 1;
      }
      p.faces.push_back(std::move(f));
    }
    for (const auto& [e, count] : edgeFaces) {
      if (count != 2) fail(what, "is degenerate (corners nearly on one plane)");
      p.edges.push_back({e.first, e.second});
    }
  }
  for (size_t k = 0; k < n; ++k) {
    if (!corner[k]) {
      fail(what, "has point " + std::to_string(k + 1) +
                     " inside its convex hull or on a side of it: give the corners only");
    }
  }
  if (D == 3 && n + p.faces.size() != p.edges.size() + 2) {  // Euler's formula
    fail(what, "is degenerate (corners nearly on one plane)");
  }
  return p;
}

// 2D: the shoelace sums over the edges' triangles with the origin. 3D: the faces fanned into
// triangles, each with the origin a tetrahedron whose second moments are det(A) A C A^T with
// C the canonical tetrahedron's ([2 1 1; 1 2 1; 1 1 2] / 120).
template <int D>
MassProperties<D> polytopeMassProperties(const Polytope<D>& p) {
  MassProperties<D> m;
  const std::vector<VecD<D>>& v = p.vertices;
  if constexpr (D == 2) {
    Real area = 0, jz = 0;
    Vec2 first = Vec2::Zero();
    for (const auto& f : p.faces) {
      const Vec2 a = v[f.loop[0]], b = v[f.loop[1]];
      const Real c = cross(a, b);
      area += c / 2;
      first += c / 6 * (a + b);
      jz += c / 12 * (a.squaredNorm() + a.dot(b) + b.squaredNorm());
    }
    m.volume = area;
    m.centroid = first / area;
    m.inertia = Mat3::Zero();
    m.inertia(2, 2) = jz - area * m.centroid.squaredNorm();
  } else {
    Real vol = 0;
    Vec3 first = Vec3::Zero();
    Mat3 second = Mat3::Zero();
    Mat3 canon;
    canon << 2, 1, 1, 1, 2, 1, 1, 1, 2;
    canon /= 120;
    for (const auto& f : p.faces) {
      for (size_t k = 1; k + 1 < f.loop.size(); ++k) {
        Mat3 a;
        a.col(0) = v[f.loop[0]], a.col(1) = v[f.loop[k]], a.col(2) = v[f.loop[k + 1]];
        const Real det = a.determinant();
        vol += det / 6;
        first += det / 24 * (a.col(0) + a.col(1) + a.col(2));
        second += det * a * canon * a.transpose();
      }
    }
    m.volume = vol;
    m.centroid = first / vol;
    const Mat3 c = second - vol * m.centroid * m.centroid.transpose();
    m.inertia = c.trace() * Mat3::Identity() - c;
  }
  return m;
}

// Sets face f of p: its normal, the loop of corners and the offset from its first corner.
template <int D, size_t N>
void setFace(Polytope<D>& p, size_t f, const VecD<D>& normal, const std::array<uint32_t, N>& loop) {
  auto& face = p.faces[f];
  face.normal = normal;
  face.loop.assign(loop.begin(), loop.end());
  face.offset = normal.dot(p.vertices[loop[0]]);
}

template <int D>
void boxPolytope(const VecD<D>& centre, const MatD<D>& axes, const VecD<D>& half, Polytope<D>& p) {
  const int corners = 1 << D;
  p.vertices.resize(corners);
  for (int c = 0; c < corners; ++c) {
    VecD<D> x = centre;
    for (int d = 0; d < D; ++d) x += ((c >> d & 1) ? 1 : -1) * half[d] * axes.col(d);
    p.vertices[c] = x;
  }
  if constexpr (D == 2) {
    const uint32_t loop[4] = {0, 1, 3, 2};  // counterclockwise for a right-handed frame
    p.faces.resize(4);
    for (int k = 0; k < 4; ++k) {
      const uint32_t a = loop[k], b = loop[(k + 1) % 4];
      const Vec2 e = (p.vertices[b] - p.vertices[a]).normalized();
      setFace<2, 2>(p, k, Vec2(e.y(), -e.x()), {a, b});
    }
  } else {
    // Per axis d, the face at +half (corners with bit d set) and at -half; each loop is put
    // counterclockwise about its outward normal.
    p.faces.resize(6);
    for (int d = 0; d < 3; ++d) {
      for (int s = 0; s < 2; ++s) {
        const int d1 = (d + 1) % 3, d2 = (d + 2) % 3;
        const uint32_t base = s ? (1u << d) : 0u;
        std::array<uint32_t, 4> loop = {base, base | (1u << d1), base | (1u << d1) | (1u << d2),
                                        base | (1u << d2)};
        const Vec3 n = (s ? 1 : -1) * axes.col(d);
        const Vec3 turn = (p.vertices[loop[1]] - p.vertices[loop[0]])
                              .cross(p.vertices[loop[2]] - p.vertices[loop[1]]);
        if (turn.dot(n) < 0) std::reverse(loop.begin(), loop.end());
        setFace<3, 4>(p, 2 * d + s, n, loop);
      }
    }
    p.edges.clear();
    for (uint32_t a = 0; a < 8; ++a) {
      for (int d = 0; d < 3; ++d) {
        if (!(a >> d & 1)) p.edges.push_back({a, a | (1u << d)});
      }
    }
  }
}

template <int D>
void flatPolytope(const VecD<D>& centre, std::span<const VecD<D>> axes, std::span<const Real> half,
                  Polytope<D>& p) {
  p.faces.resize(2);
  if constexpr (D == 2) {
    p.vertices = {Vec2(centre - half[0] * axes[0]), Vec2(centre + half[0] * axes[0])};
    const Vec2 n(-axes[0].y(), axes[0].x());
    setFace<2, 2>(p, 0, Vec2(-n), {0, 1});
    setFace<2, 2>(p, 1, n, {1, 0});
  } else {
    const Vec3 n = axes[0].cross(axes[1]);
    p.vertices.resize(4);
    int k = 0;
    for (int c : {0, 1, 3, 2}) {
      p.vertices[k++] = centre + ((c & 1) ? 1 : -1) * half[0] * axes[0] + ((c & 2) ? 1 : -1) * half[1] * axes[1];
    }
    // Corners 0, 1, 2, 3 go counterclockwise about n.
    setFace<3, 4>(p, 0, n, {0, 1, 2, 3});
    setFace<3, 4>(p, 1, Vec3(-n), {3, 2, 1, 0});
    p.edges.clear();
    for (uint32_t e = 0; e < 4; ++e) p.edges.push_back({std::min(e, (e + 1) % 4), std::max(e, (e + 1) % 4)});
  }
}

template Polytope<2> buildPolytope<2>(std::span<const double>, const char*);
template Polytope<3> buildPolytope<3>(std::span<const double>, const char*);
template MassProperties<2> polytopeMassProperties<2>(const Polytope<2>&);
template MassProperties<3> polytopeMassProperties<3>(const Polytope<3>&);
template void boxPolytope<2>(const Vec2&, const Mat2&, const Vec2&, Polytope<2>&);
template void boxPolytope<3>(const Vec3&, const Mat3&, const Vec3&, Polytope<3>&);
template void flatPolytope<2>(const Vec2&, std::span<const Vec2>, std::span<const Real>, Polytope<2>&);
template void flatPolytope<3>(const Vec3&, std::span<const Vec3>, std::span<const Real>, Polytope<3>&);

}  // namespace demlab::sim
