#include "render/wall_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "render/colour_map.hpp"

namespace demlab::render {
namespace {

constexpr int kCircleSegments = 96;

struct Emitter {
  WallGeometry& out;
  Vec3 anchor;
  std::uint8_t line[4], face[4];

  void segment(const Vec3& a, const Vec3& b) {
    LineInstance l;
    for (int k = 0; k < 3; ++k) {
      l.a[k] = float(a[k] - anchor[k]);
      l.b[k] = float(b[k] - anchor[k]);
    }
    std::copy(line, line + 4, l.rgba);
    out.lines.push_back(l);
  }

  void vertex(const Vec3& p, const Vec3& n) {
    FaceVertex v;
    for (int k = 0; k < 3; ++k) {
      v.p[k] = float(p[k] - anchor[k]);
      v.n[k] = float(n[k]);
    }
    std::copy(face, face + 4, v.rgba);
    out.triangles.push_back(v);
  }

  void triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n) {
    vertex(a, n);
    vertex(b, n);
    vertex(c, n);
  }

  void loop(const std::vector<Vec3>& pts) {
    for (size_t i = 0; i < pts.size(); ++i) segment(pts[i], pts[(i + 1) % pts.size()]);
  }
};

// Returns an orthonormal pair spanning the plane perpendicular to unit vector n.
std::pair<Vec3, Vec3> basis(const Vec3& n) {
  const Vec3 t = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = n.cross(t).normalized();
  return {e1, n.cross(e1)};
}

// Returns the points of circle (centre c, unit axis n, radius r).
std::vector<Vec3> circle(const Vec3& c, const Vec3& n, double r) {
  const auto [e1, e2] = basis(n);
  std::vector<Vec3> pts(kCircleSegments);
  for (int i = 0; i < kCircleSegments; ++i) {
    const double a = 2 * std::numbers::pi * i / kCircleSegments;
    pts[i] = c + r * (std::cos(a) * e1 + std::sin(a) * e2);
  }
  return pts;
}

// Returns the convex polygon where the plane (point x0, unit normal n) cuts box b, in order
// around its centroid; empty when it misses.
std::vector<Vec3> clipPlane(const Vec3& x0, const Vec3& n, const Bounds& b, int dim) {
  std::vector<Vec3> pts;
  const int nc = dim == 2 ? 4 : 8;
  auto corner = [&](int i) {
    return Vec3(i & 1 ? b.hi.x() : b.lo.x(), i & 2 ? b.hi.y() : b.lo.y(),
                i & 4 ? b.hi.z() : b.lo.z());
  };
  for (int i = 0; i < nc; ++i)
    for (int k = 0; k < dim; ++k) {
      if (i & (1 << k)) continue;
      const Vec3 p = corner(i), q = corner(i | (1 << k));
      const double sp = n.dot(p - x0), sq = n.dot(q - x0);
      if ((sp <= 0 && sq >= 0) || (sp >= 0 && sq <= 0)) {
        if (sp == sq) continue;  // edge in the plane: its ends come from the crossing edges
        pts.push_back(p + (q - p) * (sp / (sp - sq)));
      }
    }
  if (pts.size() < 2) return {};
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : pts) c += p;
  c /= double(pts.size());
  const auto [e1, e2] = basis(n);
  std::sort(pts.begin(), pts.end(), [&](const Vec3& p, const Vec3& q) {
    return std::atan2((p - c).dot(e2), (p - c).dot(e1)) <
           std::atan2((q - c).dot(e2), (q - c).dot(e1));
  });
  return pts;
}

// Returns nothing; draws the hole of a rectangle (corner p0, edges u, v) of radius hole at its
// centre: the rim's circle and, with faces, the face between the rim and the edges as quads
// cut along rays from the centre, each ray's outer end where it meets the edges (a corner
// between two rays is cut off by less than the rays' spacing).
void holedRectangle(Emitter& e, const Vec3& p0, const Vec3& u, const Vec3& v, double hole,
                    bool faces) {
  const Vec3 c = p0 + 0.5 * (u + v), n = u.cross(v).normalized();
  const Vec3 eu = u.normalized(), ev = n.cross(eu);
  const double hu = 0.5 * u.norm(), hv = 0.5 * std::abs(v.dot(ev));
  std::vector<Vec3> rim(kCircleSegments), edge(kCircleSegments);
  for (int i = 0; i < kCircleSegments; ++i) {
    const double a = 2 * std::numbers::pi * i / kCircleSegments;
    const double cu = std::cos(a), sv = std::sin(a);
    const Vec3 dir = cu * eu + sv * ev;
    const double reach = std::min(std::abs(cu) > 0 ? hu / std::abs(cu) : hu * 1e9,
                                  std::abs(sv) > 0 ? hv / std::abs(sv) : hv * 1e9);
    rim[i] = c + hole * dir;
    edge[i] = c + reach * dir;
  }
  e.loop(rim);
  if (!faces) return;
  for (int i = 0; i < kCircleSegments; ++i) {
    const int j = (i + 1) % kCircleSegments;
    e.triangle(rim[i], edge[i], edge[j], n);
    e.triangle(rim[i], edge[j], rim[j], n);
  }
}

}  // namespace

void wallGeometry(const RenderScene& scene, const Bounds& bounds, const Vec3& anchor,
                  double wallAlpha, WallGeometry& out) {
  out.lines.clear();
  out.triangles.clear();
  const int dim = scene.dim;
  Bounds clip = bounds;
  const double pad = 0.02 * std::max((bounds.hi - bounds.lo).norm(), 1e-12);
  clip.lo -= Vec3::Constant(pad);
  clip.hi += Vec3::Constant(pad);
  if (dim == 2) clip.lo.z() = clip.hi.z() = 0;
  auto flat = [&](const Vec3& v) { return dim == 2 ? Vec3(v.x(), v.y(), 0) : v; };

  for (const RenderWall& w : scene.walls) {
    Emitter e{out, anchor, {}, {}};
    for (int k = 0; k < 3; ++k) e.line[k] = e.face[k] = toByte(w.colour[k]);
    e.line[3] = 255;
    e.face[3] = toByte(float(wallAlpha));
    const bool faces = dim == 3 && wallAlpha > 0;
    const Vec3 p0 = flat(w.p[0]), p1 = flat(w.p[1]), p2 = flat(w.p[2]);
    switch (w.kind) {
      case WallKind::plane: {
        const Vec3 n = p1.normalized();
        const std::vector<Vec3> poly = clipPlane(p0, n, clip, dim);
        if (dim == 2) {
          if (poly.size() >= 2) {
            // The line's extreme crossings along its direction.
            const Vec3 t(-n.y(), n.x(), 0);
            const auto [lo, hi] = std::minmax_element(
                poly.begin(), poly.end(),
                [&](const Vec3& a, const Vec3& b) { return a.dot(t) < b.dot(t); });
            e.segment(*lo, *hi);
          }
        } else if (poly.size() >= 3) {
          e.loop(poly);
          if (faces)
            for (size_t i = 1; i + 1 < poly.size(); ++i)
              e.triangle(poly[0], poly[i], poly[i + 1], n);
        }
        break;
      }
      case WallKind::segment:
        e.segment(p0, p1);
        break;
      case WallKind::triangle:
        e.loop({p0, p1, p2});
        if (faces) e.triangle(p0, p1, p2, (p1 - p0).cross(p2 - p0).normalized());
        break;
      case WallKind::rectangle: {
        const std::vector<Vec3> q = {p0, p0 + p1, p0 + p1 + p2, p0 + p2};
        e.loop(q);
        if (dim == 3 && w.radius > 0) {
          holedRectangle(e, p0, p1, p2, w.radius, faces);
          break;
        }
        if (faces) {
          const Vec3 n = p1.cross(p2).normalized();
          e.triangle(q[0], q[1], q[2], n);
          e.triangle(q[0], q[2], q[3], n);
        }
        break;
      }
      case WallKind::box:
        if (dim == 2) {
          e.loop({p0, Vec3(p1.x(), p0.y(), 0), p1, Vec3(p0.x(), p1.y(), 0)});
        } else {
          for (int i = 0; i < 8; ++i)
            for (int k = 0; k < 3; ++k) {
              if (i & (1 << k)) continue;
              const int j = i | (1 << k);
              auto c = [&](int m) {
                return Vec3(m & 1 ? p1.x() : p0.x(), m & 2 ? p1.y() : p0.y(),
                            m & 4 ? p1.z() : p0.z());
              };
              e.segment(c(i), c(j));
            }
        }
        break;
      case WallKind::drum:
        if (dim == 2) {
          e.loop(circle(p0, Vec3::UnitZ(), w.radius));
        } else {
          const Vec3 n = w.p[1].normalized(), h = n * (w.length / 2);
          const std::vector<Vec3> lo = circle(p0 - h, n, w.radius),
                                  hi = circle(p0 + h, n, w.radius);
          e.loop(lo);
          e.loop(hi);
          if (faces)
            for (int i = 0; i < kCircleSegments; ++i) {
              const int j = (i + 1) % kCircleSegments;
              const Vec3 ni = (lo[i] - (p0 - h)) / w.radius, nj = (lo[j] - (p0 - h)) / w.radius;
              e.vertex(lo[i], ni);
              e.vertex(lo[j], nj);
              e.vertex(hi[j], nj);
              e.vertex(lo[i], ni);
              e.vertex(hi[j], nj);
              e.vertex(hi[i], ni);
            }
        }
        break;
    }
  }
}

}  // namespace demlab::render
