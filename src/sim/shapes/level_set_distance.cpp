// Building level sets (sim/shapes/level_set.hpp): the signed distance to a triangulated surface
// on a grid, from a closed triangle mesh or from sampled values of an implicit function.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "core/validity.hpp"
#include "physics/triangle_mesh.hpp"
#include "sim/shapes/level_set.hpp"
#include "sim/shapes/level_set_internal.hpp"

namespace demlab::sim {

namespace {

// Returns the distance from p to face f of s (a triangle in 3D, a segment in 2D).
template <int D>
Real faceDistance(const Polytope<D>& s, size_t f, const VecD<D>& p) {
  const auto& loop = s.faces[f].loop;
  if constexpr (D == 3) {
    const auto q = physics::nearestOnTriangle(p, s.vertices[loop[0]], s.vertices[loop[1]],
                                              s.vertices[loop[2]]);
    return (p - q.point).norm();
  } else {
    const Vec2 a = s.vertices[loop[0]], e = s.vertices[loop[1]] - a;
    const Real len2 = e.squaredNorm();
    const Real t = len2 > 0 ? std::clamp((p - a).dot(e) / len2, Real{0}, Real{1}) : 0;
    return (p - (a + t * e)).norm();
  }
}

// Returns the unsigned distance from every node to the faces of s: exact within two nodes of a
// face, and beyond from the nearest faces of the neighbours, swept through the grid twice in
// each of its 2^D diagonal directions (Bridson's closest-feature propagation).
template <int D>
std::vector<Real> distanceField(Real h, const std::array<int, D>& n, const VecD<D>& origin,
                                const Polytope<D>& s) {
  const size_t total = nodeCount<D>(n);
  std::vector<Real> dist(total, std::numeric_limits<Real>::infinity());
  std::vector<int64_t> nearest(total, -1);
  std::array<size_t, D> stride{};
  stride[0] = 1;
  for (int d = 1; d < D; ++d) stride[d] = stride[d - 1] * static_cast<size_t>(n[d - 1]);
  const auto at = [&](const std::array<int, D>& ix) {
    VecD<D> p;
    for (int d = 0; d < D; ++d) p[d] = origin[d] + h * ix[d];
    return p;
  };
  const auto index = [&](const std::array<int, D>& ix) {
    size_t i = 0;
    for (int d = 0; d < D; ++d) i += static_cast<size_t>(ix[d]) * stride[d];
    return i;
  };
  for (size_t f = 0; f < s.faces.size(); ++f) {
    if (f % 4096 == 0) pollInterrupt("level set");
    std::array<int, D> lo{}, hi{};
    for (int d = 0; d < D; ++d) {
      Real a = std::numeric_limits<Real>::infinity(), b = -a;
      for (uint32_t v : s.faces[f].loop) a = std::min(a, s.vertices[v][d]), b = std::max(b, s.vertices[v][d]);
      lo[d] = std::max(0, static_cast<int>(std::floor((a - origin[d]) / h)) - 2);
      hi[d] = std::min(n[d] - 1, static_cast<int>(std::ceil((b - origin[d]) / h)) + 2);
    }
    std::array<int, D> ix = lo;
    while (true) {
      const size_t i = index(ix);
      const Real dd = faceDistance<D>(s, f, at(ix));
      if (dd < dist[i]) dist[i] = dd, nearest[i] = static_cast<int64_t>(f);
      int d = 0;
      while (d < D && ++ix[d] > hi[d]) ix[d] = lo[d], ++d;
      if (d == D) break;
    }
  }
  for (int pass = 0; pass < 2; ++pass) {
    for (int dir = 0; dir < (1 << D); ++dir) {
      pollInterrupt("level set");
      for (size_t k = 0; k < total; ++k) {
        std::array<int, D> ix = nodeIndex<D>(k, n);
        for (int d = 0; d < D; ++d) {
          if (dir >> d & 1) ix[d] = n[d] - 1 - ix[d];
        }
        const size_t i = index(ix);
        for (int d = 0; d < D; ++d) {
          const int back = (dir >> d & 1) ? ix[d] + 1 : ix[d] - 1;
          if (back < 0 || back >= n[d]) continue;
          const size_t j = (dir >> d & 1) ? i + stride[d] : i - stride[d];
          if (nearest[j] < 0 || nearest[j] == nearest[i]) continue;
          const Real dd = faceDistance<D>(s, static_cast<size_t>(nearest[j]), at(ix));
          if (dd < dist[i]) dist[i] = dd, nearest[i] = nearest[j];
        }
      }
    }
  }
  return dist;
}

template <int D>
std::vector<double> packParams(Real h, const std::array<int, D>& n, const VecD<D>& origin,
                               const std::vector<Real>& phi) {
  std::vector<double> p;
  p.reserve(1 + 2 * D + phi.size());
  p.push_back(h);
  for (int d = 0; d < D; ++d) p.push_back(n[d]);
  for (int d = 0; d < D; ++d) p.push_back(origin[d]);
  p.insert(p.end(), phi.begin(), phi.end());
  return p;
}

[[noreturn]] void badSpacing(Real h, const std::string& why) {
  throw Error("bad spacing \"" + std::to_string(h) + "\": " + why, {"VALUE", "SPACING"});
}

}  // namespace

std::vector<double> levelSetFromMesh(std::span<const std::array<double, 9>> triangles, Real h) {
  if (!(h >= validity::kMinRadius && h <= validity::kMaxRadius)) {
    badSpacing(h, "must be a positive length within the validity policy's");
  }
  const physics::TriangleMesh mesh = physics::TriangleMesh::build(
      std::vector<std::array<double, 9>>(triangles.begin(), triangles.end()), "level set");
  // Closed: every edge in exactly two triangles.
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const auto& t : mesh.triangles) {
    for (int e = 0; e < 3; ++e) {
      ++edges[{std::min(t[e], t[(e + 1) % 3]), std::max(t[e], t[(e + 1) % 3])}];
    }
  }
  for (const auto& [e, count] : edges) {
    if (count != 2) {
      const Vec3 a = mesh.vertices[e.first], b = mesh.vertices[e.second];
      throw Error("bad mesh: not closed: the edge from (" + std::to_string(a.x()) + ", " +
                      std::to_string(a.y()) + ", " + std::to_string(a.z()) + ") to (" +
                      std::to_string(b.x()) + ", " + std::to_string(b.y()) + ", " +
                      std::to_string(b.z()) + ") has " + std::to_string(count) +
                      " triangles (a level set needs a closed surface: 2 at every edge)",
                  {"VALUE", "MESH"});
    }
  }
  // The grid: two and a half nodes beyond the bounds, so no node lies on a bounding plane.
  std::array<int, 3> n{};
  Vec3 origin;
  size_t total = 1;
  for (int d = 0; d < 3; ++d) {
    origin[d] = mesh.lo[d] - 2.5 * h;
    const double count = std::ceil((mesh.hi[d] - mesh.lo[d]) / h + 5) + 1;
    if (!(count <= kLevelSetMaxNodesPerAxis)) {
      badSpacing(h, "the mesh would need " + std::to_string(static_cast<long long>(count)) +
                        " nodes along an axis, more than " +
                        std::to_string(kLevelSetMaxNodesPerAxis));
    }
    n[d] = static_cast<int>(count);
    total *= static_cast<size_t>(n[d]);
  }
  if (total > kLevelSetMaxNodes) {
    badSpacing(h, "the mesh would need " + std::to_string(total) + " nodes, more than " +
                      std::to_string(kLevelSetMaxNodes));
  }
  Polytope<3> surface;
  surface.vertices = mesh.vertices;
  for (const auto& t : mesh.triangles) {
    Polytope<3>::Face f;
    f.normal = Vec3::Zero();
    f.loop = {t[0], t[1], t[2]};
    surface.faces.push_back(std::move(f));
  }
  std::vector<Real> phi = distanceField<3>(h, n, origin, surface);
  // The sign: rays along x, one per (y, z) row, crossing the triangles. Each triangle is taken
  // counterclockwise in the (y, z) plane, and a row through one of its edges counts only on
  // edges whose direction has dz > 0 (or dz = 0 and dy < 0): an edge shared by two triangles
  // seen from the same side counts once, a silhouette edge (seen from opposite sides) twice
  // or never, so the parity is right on every row.
  const size_t rows = static_cast<size_t>(n[1]) * static_cast<size_t>(n[2]);
  std::vector<std::vector<Real>> hits(rows);
  for (const auto& t : mesh.triangles) {
    Vec3 p[3] = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
    const auto cross2 = [](Real ay, Real az, Real by, Real bz) { return ay * bz - az * by; };
    Real area = cross2(p[1].y() - p[0].y(), p[1].z() - p[0].z(), p[2].y() - p[0].y(), p[2].z() - p[0].z());
    if (area == 0) continue;
    if (area < 0) std::swap(p[1], p[2]), area = -area;
    const Real ylo = std::min({p[0].y(), p[1].y(), p[2].y()}), yhi = std::max({p[0].y(), p[1].y(), p[2].y()});
    const Real zlo = std::min({p[0].z(), p[1].z(), p[2].z()}), zhi = std::max({p[0].z(), p[1].z(), p[2].z()});
    const int j0 = std::max(0, static_cast<int>(std::ceil((ylo - origin.y()) / h)));
    const int j1 = std::min(n[1] - 1, static_cast<int>(std::floor((yhi - origin.y()) / h)));
    const int k0 = std::max(0, static_cast<int>(std::ceil((zlo - origin.z()) / h)));
    const int k1 = std::min(n[2] - 1, static_cast<int>(std::floor((zhi - origin.z()) / h)));
    for (int k = k0; k <= k1; ++k) {
      for (int j = j0; j <= j1; ++j) {
        const Real y = origin.y() + h * j, z = origin.z() + h * k;
        Real w[3];
        bool in = true;
        for (int e = 0; e < 3 && in; ++e) {
          const Vec3& a = p[e];
          const Vec3& b = p[(e + 1) % 3];
          const Real dy = b.y() - a.y(), dz = b.z() - a.z();
          w[(e + 2) % 3] = cross2(dy, dz, y - a.y(), z - a.z());
          in = w[(e + 2) % 3] > 0 || (w[(e + 2) % 3] == 0 && (dz > 0 || (dz == 0 && dy < 0)));
        }
        if (!in) continue;
        const Real x = (w[0] * p[0].x() + w[1] * p[1].x() + w[2] * p[2].x()) / (w[0] + w[1] + w[2]);
        hits[static_cast<size_t>(j) + static_cast<size_t>(k) * n[1]].push_back(x);
      }
    }
  }
  for (size_t r = 0; r < rows; ++r) {
    std::vector<Real>& xs = hits[r];
    std::sort(xs.begin(), xs.end());
    size_t passed = 0;
    for (int i = 0; i < n[0]; ++i) {
      const Real x = origin.x() + h * i;
      while (passed < xs.size() && xs[passed] < x) ++passed;
      if (passed % 2 == 1) phi[r * n[0] + i] = -phi[r * n[0] + i];
    }
  }
  std::vector<double> params = packParams<3>(h, n, origin, phi);
  buildLevelSet<3>(params);  // the same checks as every level set's
  return params;
}

template <int D>
std::vector<double> levelSetFromValues(Real h, const std::array<int, D>& n, const VecD<D>& origin,
                                       std::span<const double> values) {
  if (!(h >= validity::kMinRadius && h <= validity::kMaxRadius)) {
    badSpacing(h, "must be a positive length within the validity policy's");
  }
  // The values must describe a closed body in the grid: the level set's own checks, except
  // that they need not be distances (only finite).
  std::vector<Real> raw(values.begin(), values.end());
  for (Real& v : raw) {
    if (!std::isfinite(v)) {
      throw Error("bad shape parameters: the level set's function gave " + std::to_string(v) +
                      " (its values must be finite numbers)",
                  {"VALUE", "SHAPE"});
    }
  }
  {
    std::vector<Real> scaled = raw;
    Real top = 0;
    for (Real v : scaled) top = std::max(top, std::abs(v));
    for (Real& v : scaled) v = v / top * h;  // within the grid's diagonal: only signs checked
    buildLevelSet<D>(packParams<D>(h, n, origin, scaled));
  }
  const Polytope<D> surface = zeroLevelSurface<D>(h, n, origin, raw);
  std::vector<Real> phi = distanceField<D>(h, n, origin, surface);
  for (size_t i = 0; i < phi.size(); ++i) {
    if (raw[i] < 0) phi[i] = -phi[i];
  }
  std::vector<double> params = packParams<D>(h, n, origin, phi);
  buildLevelSet<D>(params);
  return params;
}

template std::vector<double> levelSetFromValues<2>(Real, const std::array<int, 2>&, const Vec2&,
                                                   std::span<const double>);
template std::vector<double> levelSetFromValues<3>(Real, const std::array<int, 3>&, const Vec3&,
                                                   std::span<const double>);

}  // namespace demlab::sim
