// TriangleMesh (physics/triangle_mesh.hpp).
#include "physics/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/error.hpp"
#include "core/validity.hpp"

namespace demlab::physics {

TriangleMesh TriangleMesh::build(const std::vector<std::array<double, 9>>& tris, std::string source) {
  TriangleMesh m;
  m.source = std::move(source);
  std::map<std::array<double, 3>, uint32_t> index;
  Real size = 0;
  for (const auto& t : tris) {
    for (double x : t) {
      if (!(std::abs(x) <= validity::kMaxCoordinate)) {
        throw Error("bad mesh: a corner coordinate is beyond " +
                        std::to_string(validity::kMaxCoordinate) + " m or not finite",
                    {"VALUE", "MESH"});
      }
      size = std::max(size, static_cast<Real>(std::abs(x)));
    }
  }
  // Only the corners of kept triangles are numbered, so a mesh rebuilt from its own triangles
  // (a checkpoint's) numbers them alike.
  for (const auto& t : tris) {
    const Vec3 a(t[0], t[1], t[2]), b(t[3], t[4], t[5]), c(t[6], t[7], t[8]);
    const Vec3 n = (b - a).cross(c - a);
    if (!(n.norm() > 1e-24 * size * size) || a == b || b == c || a == c) continue;
    std::array<uint32_t, 3> ids;
    for (int k = 0; k < 3; ++k) {
      const std::array<double, 3> key{t[3 * k], t[3 * k + 1], t[3 * k + 2]};
      const auto [it, added] = index.try_emplace(key, static_cast<uint32_t>(m.vertices.size()));
      if (added) m.vertices.emplace_back(key[0], key[1], key[2]);
      ids[k] = it->second;
    }
    m.triangles.push_back(ids);
    m.normals.push_back(n.normalized());
  }
  if (m.triangles.empty()) throw Error("bad mesh: it has no triangle with an area", {"VALUE", "MESH"});
  m.lo = m.hi = m.vertices[m.triangles[0][0]];
  for (const auto& t : m.triangles) {
    for (uint32_t v : t) m.lo = m.lo.cwiseMin(m.vertices[v]), m.hi = m.hi.cwiseMax(m.vertices[v]);
  }
  // Cells about the size of a triangle (the median longest edge), at most 8 per triangle and
  // 2^22 in all.
  std::vector<Real> edge;
  for (const auto& t : m.triangles) {
    Real e = 0;
    for (int c = 0; c < 3; ++c) e = std::max(e, (m.vertices[t[c]] - m.vertices[t[(c + 1) % 3]]).norm());
    edge.push_back(e);
  }
  std::nth_element(edge.begin(), edge.begin() + edge.size() / 2, edge.end());
  const Vec3 ext = m.hi - m.lo;
  m.cell = std::max(edge[edge.size() / 2], ext.maxCoeff() * 1e-6);
  const double most = std::min<double>(8.0 * m.triangles.size() + 64, 1 << 22);
  for (;;) {
    double cells = 1;
    for (int k = 0; k < 3; ++k) cells *= std::floor(ext[k] / m.cell) + 1;
    if (cells <= most) break;
    m.cell *= 1.5;
  }
  for (int k = 0; k < 3; ++k) m.dims[k] = static_cast<int>(std::floor(ext[k] / m.cell)) + 1;
  const size_t ncell = size_t(m.dims[0]) * m.dims[1] * m.dims[2];
  const auto cellRange = [&](const Vec3& lo, const Vec3& hi, std::array<int, 3>& a, std::array<int, 3>& b) {
    for (int k = 0; k < 3; ++k) {
      a[k] = std::clamp(static_cast<int>(std::floor((lo[k] - m.lo[k]) / m.cell)), 0, m.dims[k] - 1);
      b[k] = std::clamp(static_cast<int>(std::floor((hi[k] - m.lo[k]) / m.cell)), 0, m.dims[k] - 1);
    }
  };
  std::vector<uint32_t> count(ncell + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      for (size_t c = 0; c < ncell; ++c) count[c + 1] += count[c];
      m.cellStart = count;
      m.cellTriangles.resize(count[ncell]);
    }
    std::vector<uint32_t> at = pass == 1 ? m.cellStart : std::vector<uint32_t>();
    for (uint32_t t = 0; t < m.triangles.size(); ++t) {
      Vec3 lo = m.vertices[m.triangles[t][0]], hi = lo;
      for (uint32_t v : m.triangles[t]) lo = lo.cwiseMin(m.vertices[v]), hi = hi.cwiseMax(m.vertices[v]);
      std::array<int, 3> a, b;
      cellRange(lo, hi, a, b);
      for (int z = a[2]; z <= b[2]; ++z) {
        for (int y = a[1]; y <= b[1]; ++y) {
          for (int x = a[0]; x <= b[0]; ++x) {
            const size_t c = (size_t(z) * m.dims[1] + y) * m.dims[0] + x;
            if (pass == 0) count[c + 1] += 1;
            else m.cellTriangles[at[c]++] = t;
          }
        }
      }
    }
  }
  return m;
}

void TriangleMesh::near(const Vec3& p, Real reach, std::vector<uint32_t>& out) const {
  out.clear();
  std::array<int, 3> a, b;
  for (int k = 0; k < 3; ++k) {
    const Real lo = (p[k] - reach - this->lo[k]) / cell, hi = (p[k] + reach - this->lo[k]) / cell;
    if (hi < 0 || lo >= dims[k]) return;
    a[k] = std::max(0, static_cast<int>(std::floor(lo)));
    b[k] = std::min(dims[k] - 1, static_cast<int>(std::floor(hi)));
  }
  for (int z = a[2]; z <= b[2]; ++z) {
    for (int y = a[1]; y <= b[1]; ++y) {
      for (int x = a[0]; x <= b[0]; ++x) {
        const size_t c = (size_t(z) * dims[1] + y) * dims[0] + x;
        for (uint32_t k = cellStart[c]; k < cellStart[c + 1]; ++k) out.push_back(cellTriangles[k]);
      }
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

size_t TriangleMesh::heapBytes() const {
  return vertices.capacity() * sizeof(Vec3) + triangles.capacity() * sizeof(triangles[0]) +
         normals.capacity() * sizeof(Vec3) + (cellStart.capacity() + cellTriangles.capacity()) * 4;
}

TrianglePoint nearestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  TrianglePoint r;
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {TrianglePoint::Vertex, 0, a};
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {TrianglePoint::Vertex, 1, b};
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return {TrianglePoint::Edge, 0, Vec3(a + d1 / (d1 - d3) * ab)};
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {TrianglePoint::Vertex, 2, c};
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return {TrianglePoint::Edge, 2, Vec3(a + d2 / (d2 - d6) * ac)};
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return {TrianglePoint::Edge, 1, Vec3(b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))};
  }
  const Real denom = 1 / (va + vb + vc);
  r.point = a + ab * (vb * denom) + ac * (vc * denom);
  return r;
}

void FacingTriangles::prepare(const TriangleMesh& mesh, std::span<const uint32_t> near,
                              const Vec3& centre) {
  ids.assign(near.begin(), near.end());
  normals.resize(ids.size());
  corners.resize(ids.size());
  for (size_t k = 0; k < ids.size(); ++k) {
    const uint32_t t = ids[k];
    corners[k] = mesh.vertices[mesh.triangles[t][0]];
    normals[k] = mesh.normals[t].dot(centre - corners[k]) >= 0 ? mesh.normals[t] : Vec3(-mesh.normals[t]);
  }
}

Real FacingTriangles::depthBehind(const TriangleMesh& mesh, const Vec3& x, Real reach,
                                  Vec3& normal) const {
  Real deepest = 0;
  for (size_t k = 0; k < ids.size(); ++k) {
    const Real h = normals[k].dot(x - corners[k]);
    if (!(h < 0) || -h <= deepest || -h > reach) continue;
    const auto& v = mesh.triangles[ids[k]];
    const Vec3 foot = x - h * normals[k];
    bool over = true;
    for (int e = 0; e < 3 && over; ++e) {
      const Vec3 p = mesh.vertices[v[e]], q = mesh.vertices[v[(e + 1) % 3]];
      over = (q - p).cross(foot - p).dot(mesh.normals[ids[k]]) >= 0;
    }
    if (over) deepest = -h, normal = -normals[k];
  }
  return deepest;
}

}  // namespace demlab::physics
