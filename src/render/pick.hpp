// Picking: which grain a pixel of a frame shows. The pixel's ray is cast through the very view
// the renderer draws the frame's scene part with (frameView), and met against every drawn grain
// as drawn: spheres and discs exactly, meshes triangle by triangle.
#pragma once

#include "render/scene.hpp"
#include "render/view.hpp"

namespace demlab::render {

// The view of a frame's scene part and where that part sits in the frame (the header strip
// above it and the legend strip right of it take the rest).
struct FrameView {
  View view;       // in the scene part's pixels
  int x0 = 0, y0 = 0;  // the scene part's top-left corner in the frame
};

// Returns the view the renderer uses for scene with options (checked), as layout.hpp places it.
FrameView frameView(const RenderScene& scene, const RenderOptions& options);

// A ray: origin and unit direction, world coordinates.
struct Ray {
  Vec3 origin, direction;
};

// Returns the ray of the point (x, y) of the view's image (pixels, x right, y down): from the
// near plane away from the eye.
Ray pixelRay(const View& view, double x, double y);

// Returns the index of the grain of scene that pixel (px, py) of the frame shows (the one nearest
// the eye along the pixel centre's ray), or -1 where no grain is (background, walls, the header
// and legend strips, outside the frame). Reads only.
long pickGrain(const RenderScene& scene, const RenderOptions& options, int px, int py);

}  // namespace demlab::render
