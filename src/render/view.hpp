// The camera as matrices: automatic framing of the scene's bounds, or the user's position,
// look-at point, up vector and field of view; perspective or orthographic. 2D scenes are always
// seen orthographically from above (+z), x to the right and y up.
//
// GL works in float, so every point sent to GL is first made relative to View::anchor (the point
// looked at) in double: a drum 1e3 units from the origin keeps its sub-grain detail.
#pragma once

#include <Eigen/Core>

#include "render/scene.hpp"

namespace demlab::render {

struct View {
  Vec3 anchor = Vec3::Zero();  // world point subtracted before the view matrix
  Vec3 eye = Vec3::Zero();     // camera position (world)
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();  // (world - anchor) -> eye space
  Eigen::Matrix4d proj = Eigen::Matrix4d::Identity();  // eye space -> clip space
  bool orthographic = false;
  int width = 0, height = 0;  // of the final image, pixels
  double near = 0, far = 0;

  // Returns (x, y, depth): where world point p lands in the final image, x to the right and y
  // down in pixels (pixel (i, j) covers [i, i+1) x [j, j+1)), and its window depth in [0, 1].
  Vec3 project(const Vec3& p) const;

  // Returns the radius in final-image pixels of a sphere of radius r centred at p (exact for
  // orthographic views, the small-sphere value for perspective).
  double pixelRadius(const Vec3& p, double r) const;
};

// Returns the point of the scene's i-th grain centre (z = 0 in 2D).
inline Vec3 grainCentre(const RenderScene& s, size_t i) {
  const double* c = &s.centres[i * s.dim];
  return Vec3(c[0], c[1], s.dim == 3 ? c[2] : 0.0);
}

// Returns scene.bounds when given, else the bounds of the grains (with radii) and of the finite
// walls (planes excluded); the unit box about the origin for an empty scene. In 2D lo.z = hi.z
// = 0.
Bounds sceneBounds(const RenderScene& scene);

// Returns the view of a checked scene with checked options.
View makeView(const RenderScene& scene, const RenderOptions& options);

}  // namespace demlab::render
