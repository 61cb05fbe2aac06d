// Walls turned into what GL draws: line segments (every wall's edges; all of a 2D wall) and
// translucent triangles (3D planes, rectangles and drum mantles). Planes are clipped to the
// scene bounds. Points are made relative to the view's anchor (view.hpp) before going to float.
#pragma once

#include <cstdint>
#include <vector>

#include "render/scene.hpp"

namespace demlab::render {

struct LineInstance {
  float a[3], b[3];
  std::uint8_t rgba[4];
  float width = 1;  // times the line program's halfWidth
};

struct FaceVertex {
  float p[3], n[3];
  std::uint8_t rgba[4];
};

struct WallGeometry {
  std::vector<LineInstance> lines;
  std::vector<FaceVertex> triangles;  // 3 vertices per triangle
};

// Returns nothing; replaces out's contents with the geometry of scene.walls. bounds clips the
// planes (it is widened slightly, so a plane lying on a face of the bounds is still drawn);
// anchor is subtracted from every point; wallAlpha is the faces' opacity.
void wallGeometry(const RenderScene& scene, const Bounds& bounds, const Vec3& anchor,
                  double wallAlpha, WallGeometry& out);

}  // namespace demlab::render
