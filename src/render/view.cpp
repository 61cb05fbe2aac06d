#include "render/view.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace demlab::render {
namespace {

// Returns the 8 corners of b (4 distinct ones in 2D, repeated).
std::array<Vec3, 8> corners(const Bounds& b) {
  std::array<Vec3, 8> c;
  for (int i = 0; i < 8; ++i)
    c[i] =
        Vec3(i & 1 ? b.hi.x() : b.lo.x(), i & 2 ? b.hi.y() : b.lo.y(), i & 4 ? b.hi.z() : b.lo.z());
  return c;
}

void addWall(Bounds& b, const RenderWall& w, int dim) {
  const auto& p = w.p;
  switch (w.kind) {
    case WallKind::plane:
      break;
    case WallKind::segment:
      b.add(p[0]);
      b.add(p[1]);
      break;
    case WallKind::triangle:
      b.add(p[0]);
      b.add(p[1]);
      b.add(p[2]);
      break;
    case WallKind::rectangle:
      b.add(p[0]);
      b.add(p[0] + p[1]);
      b.add(p[0] + p[2]);
      b.add(p[0] + p[1] + p[2]);
      break;
    case WallKind::box:
      b.add(p[0]);
      b.add(p[1]);
      break;
    case WallKind::drum:
      if (dim == 2) {
        b.add(p[0], w.radius);
      } else {
        const Vec3 a = p[1].normalized() * (w.length / 2);
        // The end discs' bounds: per axis, radius * sqrt(1 - a_k^2).
        const Vec3 n = p[1].normalized();
        const Vec3 e = (Vec3::Ones() - n.cwiseProduct(n)).cwiseMax(0).cwiseSqrt() * w.radius;
        for (const Vec3& c : {Vec3(p[0] - a), Vec3(p[0] + a)}) {
          b.lo = b.lo.cwiseMin(c - e);
          b.hi = b.hi.cwiseMax(c + e);
        }
      }
      break;
  }
}

}  // namespace

Vec3 View::project(const Vec3& p) const {
  const Eigen::Vector4d clip =
      proj * view *
      Eigen::Vector4d(p.x() - anchor.x(), p.y() - anchor.y(), p.z() - anchor.z(), 1.0);
  const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
  return Vec3((ndc.x() + 1) / 2 * width, (1 - ndc.y()) / 2 * height, (ndc.z() + 1) / 2);
}

double View::pixelRadius(const Vec3& p, double r) const {
  double scale = proj(1, 1) * height / 2;
  if (!orthographic) {
    const Eigen::Vector4d e =
        view * Eigen::Vector4d(p.x() - anchor.x(), p.y() - anchor.y(), p.z() - anchor.z(), 1.0);
    scale /= std::max(-e.z(), 1e-300);
  }
  return r * scale;
}

Bounds sceneBounds(const RenderScene& s) {
  if (!s.bounds.empty()) {
    Bounds b = s.bounds;
    if (s.dim == 2) b.lo.z() = b.hi.z() = 0;
    return b;
  }
  Bounds b;
  for (size_t i = 0; i < s.size(); ++i) b.add(grainCentre(s, i), s.radii[i]);
  for (const RenderWall& w : s.walls) addWall(b, w, s.dim);
  if (s.dim == 2 && !b.empty()) b.lo.z() = b.hi.z() = 0;
  if (b.empty()) {
    b.lo = Vec3(-1, -1, s.dim == 2 ? 0 : -1);
    b.hi = Vec3(1, 1, s.dim == 2 ? 0 : 1);
  }
  return b;
}

View makeView(const RenderScene& scene, const RenderOptions& o) {
  const CameraDef& cam = o.camera;
  const Bounds b = sceneBounds(scene);
  const Vec3 centre = (b.lo + b.hi) / 2;
  const double radius = std::max((b.hi - b.lo).norm() / 2, 1e-12 * (1 + centre.norm()));
  const double aspect = double(o.width) / o.height;
  const bool flat = scene.dim == 2;

  View v;
  v.width = o.width;
  v.height = o.height;
  v.orthographic = flat || cam.orthographic;
  Vec3 f, up;
  if (flat) {
    f = -Vec3::UnitZ();
    up = Vec3::UnitY();
    v.anchor = cam.automatic ? centre : Vec3(cam.lookAt.x(), cam.lookAt.y(), 0);
  } else if (cam.automatic) {
    f = cam.direction.normalized();
    up = cam.up;
    v.anchor = centre;
  } else {
    f = (cam.lookAt - cam.position).normalized();
    up = cam.up;
    v.anchor = cam.lookAt;
  }
  const Vec3 right = f.cross(up).normalized();
  const Vec3 u = right.cross(f);

  // Fit: the camera-plane extents of the bounds' corners about the anchor, with a 4% margin.
  const auto box = corners(b);
  const double margin = 1.04;
  const double tanV = std::tan(cam.fov * std::numbers::pi / 360);
  double halfH = 0, dist = 0;
  for (const Vec3& q : box) {
    const Vec3 d = q - v.anchor;
    const double x = std::abs(d.dot(right)) * margin, y = std::abs(d.dot(u)) * margin;
    halfH = std::max({halfH, y, x / aspect});
    dist = std::max(dist, std::max(y / tanV, x / (tanV * aspect)) - d.dot(f));
  }
  const double toBounds = (centre - v.anchor).norm() + radius;
  if (v.orthographic) {
    if (cam.viewHeight > 0) halfH = cam.viewHeight / 2;
    halfH = std::max(halfH, 1e-12 * radius);
    // The eye stands outside the bounds so that every grain is in front of it.
    const double back = toBounds * 2 + radius;
    v.eye = (flat || cam.automatic) ? Vec3(v.anchor - f * back) : cam.position;
    const double toAnchor = (v.anchor - v.eye).dot(f);
    v.near = toAnchor - toBounds * 1.01;
    v.far = toAnchor + toBounds * 1.01;
    v.proj << 1 / (halfH * aspect), 0, 0, 0, 0, 1 / halfH, 0, 0, 0, 0, -2 / (v.far - v.near),
        -(v.far + v.near) / (v.far - v.near), 0, 0, 0, 1;
  } else {
    v.eye = cam.automatic ? Vec3(v.anchor - f * std::max(dist, 1e-3 * radius)) : cam.position;
    const double d = (v.anchor - v.eye).norm();
    v.far = d + toBounds * 1.01;
    v.near = std::max(d - toBounds * 1.01, v.far * 1e-4);
    const double fy = 1 / tanV;
    v.proj << fy / aspect, 0, 0, 0, 0, fy, 0, 0, 0, 0, (v.far + v.near) / (v.near - v.far),
        2 * v.far * v.near / (v.near - v.far), 0, 0, -1, 0;
  }
  Eigen::Matrix3d r;
  r.row(0) = right.transpose();
  r.row(1) = u.transpose();
  r.row(2) = -f.transpose();
  v.view.setIdentity();
  v.view.topLeftCorner<3, 3>() = r;
  v.view.topRightCorner<3, 1>() = -r * (v.eye - v.anchor);
  return v;
}

}  // namespace demlab::render
