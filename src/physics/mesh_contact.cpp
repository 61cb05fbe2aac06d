// sphereMeshContacts (physics/mesh_contact.hpp).
#include "physics/mesh_contact.hpp"

#include <algorithm>
#include <vector>

#include "physics/triangle_mesh.hpp"

namespace demlab::physics {

namespace {

// A touching feature in the mesh's frame: kind 0 a triangle's inside (a = the triangle),
// 1 an edge (a < b its corners), 2 a corner (a).
struct Touch {
  int kind;
  uint32_t a, b;
  Real depth;
  Vec3 point, normal;  // the mesh's nearest point; from the centre to it
  bool operator<(const Touch& o) const {
    return kind != o.kind ? kind < o.kind : a != o.a ? a < o.a : b < o.b;
  }
  bool same(const Touch& o) const { return kind == o.kind && a == o.a && b == o.b; }
};

uint32_t featureOf(const Touch& t) {
  switch (t.kind) {
    case 0:
      return t.a & 0x3fffffffu;
    case 1:
      return 0x40000000u | (((t.a * 2654435761u) ^ t.b) & 0x3fffffffu);
    default:
      return 0x80000000u | (t.a & 0x7fffffffu);
  }
}

}  // namespace

template <int D>
int sphereMeshContacts(const SphereShape<D>& s, const MeshShape<D>& m, MeshContact<D>* out, int max) {
  if constexpr (D != 3) {
    return 0;
  } else {
    const TriangleMesh& mesh = *m.mesh;
    const Vec3 c = m.rotation.transpose() * (s.centre - m.offset);
    thread_local std::vector<uint32_t> near;
    thread_local std::vector<Touch> touch;
    mesh.near(c, s.radius, near);
    touch.clear();
    for (uint32_t t : near) {
      const auto& v = mesh.triangles[t];
      const TrianglePoint p = nearestOnTriangle(c, mesh.vertices[v[0]], mesh.vertices[v[1]], mesh.vertices[v[2]]);
      const Vec3 d = p.point - c;
      const Real dist = d.norm();
      if (!(dist < s.radius)) continue;
      Touch x;
      x.depth = s.radius - dist;
      x.point = p.point;
      // A centre on the surface itself: pushed out along the triangle's normal.
      x.normal = dist > 0 ? Vec3(d / dist) : Vec3(-mesh.normals[t]);
      if (p.kind == TrianglePoint::Face) {
        x.kind = 0, x.a = t, x.b = 0;
      } else if (p.kind == TrianglePoint::Edge) {
        const uint32_t u = v[p.k], w = v[(p.k + 1) % 3];
        x.kind = 1, x.a = std::min(u, w), x.b = std::max(u, w);
      } else {
        x.kind = 2, x.a = v[p.k], x.b = 0;
      }
      touch.push_back(x);
    }
    std::sort(touch.begin(), touch.end());
    touch.erase(std::unique(touch.begin(), touch.end(), [](const Touch& x, const Touch& y) { return x.same(y); }),
                touch.end());
    // A point on an edge or at a corner is the surface's nearest only if no triangle holding
    // that edge or corner runs towards the centre from it: (c - q) . d <= 0 for every direction
    // d into such a triangle (spanned by its two edges at a corner, by its in-plane normal to
    // the edge on an edge). Otherwise a triangle beside it is nearer there (a sphere over a
    // flat mesh near a corner sees the corner's other triangles' rims within its radius).
    const Real tol = 1e-9 * s.radius;
    const auto holds = [&](const std::array<uint32_t, 3>& v, uint32_t x) {
      return v[0] == x || v[1] == x || v[2] == x;
    };
    const auto genuine = [&](const Touch& x) {
      if (x.kind == 0) return true;
      const Vec3 out = c - x.point;
      for (uint32_t t : near) {
        const auto& v = mesh.triangles[t];
        if (x.kind == 1) {
          if (!holds(v, x.a) || !holds(v, x.b)) continue;
          const uint32_t w = v[0] != x.a && v[0] != x.b ? v[0] : v[1] != x.a && v[1] != x.b ? v[1] : v[2];
          const Vec3 e = (mesh.vertices[x.b] - mesh.vertices[x.a]).normalized();
          Vec3 in = mesh.vertices[w] - mesh.vertices[x.a];
          in -= in.dot(e) * e;
          if (out.dot(in.normalized()) > tol) return false;
        } else {
          if (!holds(v, x.a)) continue;
          for (uint32_t u : v) {
            if (u == x.a) continue;
            if (out.dot((mesh.vertices[u] - mesh.vertices[x.a]).normalized()) > tol) return false;
          }
        }
      }
      return true;
    };
    int n = 0;
    thread_local std::vector<MeshContact<D>> all;
    all.clear();
    for (const Touch& x : touch) {
      if (!genuine(x)) continue;
      MeshContact<D> mc;
      const Vec3 nrm = m.rotation * x.normal;
      mc.g.normal = nrm;
      mc.g.overlap = x.depth;
      mc.g.point = m.rotation * x.point + m.offset + 0.5 * x.depth * nrm;
      mc.feature = featureOf(x);
      all.push_back(mc);
    }
    // Points that coincide are one (a centre right over a corner can see it as the corner of
    // one triangle and the rim or inside of the next, by rounding).
    for (size_t i = 0; i < all.size(); ++i) {
      for (size_t j = i + 1; j < all.size();) {
        if ((all[i].g.point - all[j].g.point).norm() <= 1e-9 * s.radius) {
          all.erase(all.begin() + static_cast<std::ptrdiff_t>(j));
        } else {
          ++j;
        }
      }
    }
    // Deepest first; a point's feature is its rank, so that the tangential spring of a grain
    // rolling from one triangle to the next goes on (it is one surface), which keying it by
    // triangle would restart at every rim.
    std::sort(all.begin(), all.end(), [](const auto& x, const auto& y) {
      return x.g.overlap != y.g.overlap ? x.g.overlap > y.g.overlap : x.feature < y.feature;
    });
    if (static_cast<int>(all.size()) > max) all.resize(max);
    for (auto& mc : all) {
      mc.feature = static_cast<uint32_t>(n);
      out[n++] = mc;
    }
    return n;
  }
}

template int sphereMeshContacts<2>(const SphereShape<2>&, const MeshShape<2>&, MeshContact<2>*, int);
template int sphereMeshContacts<3>(const SphereShape<3>&, const MeshShape<3>&, MeshContact<3>*, int);

}  // namespace demlab::physics
