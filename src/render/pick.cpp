#include "render/pick.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "render/layout.hpp"
#include "render/text.hpp"

namespace demlab::render {
namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

// Returns the ray parameter where r enters the sphere (c, radius), kNone when it misses.
double hitSphere(const Ray& r, const Vec3& c, double radius) {
  const Vec3 oc = r.origin - c;
  const double b = oc.dot(r.direction);
  const double disc = b * b - (oc.squaredNorm() - radius * radius);
  if (disc < 0) return kNone;
  const double root = std::sqrt(disc);
  const double t = -b - root >= 0 ? -b - root : -b + root;
  return t >= 0 ? t : kNone;
}

// Returns the ray parameter where r meets triangle (a, b, c) (Moller-Trumbore, both sides),
// kNone when it misses.
double hitTriangle(const Ray& r, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 p = r.direction.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return kNone;
  const Vec3 s = r.origin - a;
  const double u = s.dot(p) / det;
  if (u < 0 || u > 1) return kNone;
  const Vec3 q = s.cross(e1);
  const double v = r.direction.dot(q) / det;
  if (v < 0 || u + v > 1) return kNone;
  const double t = e2.dot(q) / det;
  return t >= 0 ? t : kNone;
}

// Returns whether the point (x, y) lies in the triangle (a, b, c) of the plane z = 0.
bool inTriangle2d(double x, double y, const Vec3& a, const Vec3& b, const Vec3& c) {
  auto side = [&](const Vec3& p, const Vec3& q) {
    return (q.x() - p.x()) * (y - p.y()) - (q.y() - p.y()) * (x - p.x());
  };
  const double s0 = side(a, b), s1 = side(b, c), s2 = side(c, a);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

// Returns where the ray meets grain i of scene (its ray parameter), kNone when it misses. 2D
// grains are met where the ray crosses z = 0 (the view looks straight down).
double hitGrain(const RenderScene& s, size_t i, const Ray& r) {
  const Vec3 c = grainCentre(s, i);
  const int mesh = s.meshOf.empty() ? -1 : s.meshOf[i];
  if (s.dim == 2) {
    if (std::abs(r.direction.z()) < 1e-300) return kNone;
    const double t = -r.origin.z() / r.direction.z();
    const double x = r.origin.x() + t * r.direction.x() - c.x();
    const double y = r.origin.y() + t * r.direction.y() - c.y();
    if (mesh < 0) return x * x + y * y <= s.radii[i] * s.radii[i] ? t : kNone;
    // Into the body frame: turned back by the grain's angle.
    const double a = s.angles.empty() ? 0.0 : s.angles[i];
    const double bx = std::cos(a) * x + std::sin(a) * y, by = -std::sin(a) * x + std::cos(a) * y;
    const auto& tri = s.meshes[size_t(mesh)];
    for (size_t k = 0; k + 2 < tri.size(); k += 3)
      if (inTriangle2d(bx, by, tri[k], tri[k + 1], tri[k + 2])) return t;
    return kNone;
  }
  const double ball = hitSphere(r, c, s.radii[i]);  // a mesh's bounding sphere first
  if (ball == kNone || mesh < 0) return ball;
  const double* q = &s.orientations[4 * i];
  const Eigen::Quaterniond turn(q[0], q[1], q[2], q[3]);
  const Eigen::Matrix3d back = turn.normalized().toRotationMatrix().transpose();
  const Ray body{back * (r.origin - c), back * r.direction};
  const auto& tri = s.meshes[size_t(mesh)];
  double best = kNone;
  for (size_t k = 0; k + 2 < tri.size(); k += 3)
    best = std::min(best, hitTriangle(body, tri[k], tri[k + 1], tri[k + 2]));
  return best;
}

}  // namespace

FrameView frameView(const RenderScene& scene, const RenderOptions& options) {
  const FrameLayout layout = frameLayout(scene, options, defaultTypeface());
  return {makeView(scene, sceneOptions(options, layout)), layout.scene.x0, layout.scene.y0};
}

Ray pixelRay(const View& v, double x, double y) {
  const Eigen::Matrix4d inv = (v.proj * v.view).inverse();
  const double nx = 2 * x / v.width - 1, ny = 1 - 2 * y / v.height;
  auto unproject = [&](double nz) {
    const Eigen::Vector4d h = inv * Eigen::Vector4d(nx, ny, nz, 1);
    return Vec3(h.head<3>() / h.w() + v.anchor);
  };
  const Vec3 a = unproject(-1), b = unproject(1);
  return {a, (b - a).normalized()};
}

long pickGrain(const RenderScene& scene, const RenderOptions& options, int px, int py) {
  checkScene(scene);
  checkOptions(options);
  const FrameView fv = frameView(scene, options);
  const double x = px - fv.x0 + 0.5, y = py - fv.y0 + 0.5;
  if (x < 0 || y < 0 || x > fv.view.width || y > fv.view.height) return -1;
  const Ray r = pixelRay(fv.view, x, y);
  long best = -1;
  double nearest = kNone;
  for (size_t i = 0; i < scene.size(); ++i) {
    const double t = hitGrain(scene, i, r);
    if (t < nearest) nearest = t, best = long(i);
  }
  return best;
}

}  // namespace demlab::render
