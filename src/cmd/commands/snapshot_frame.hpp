// One snapshot frame: the scene read into the renderer's arrays as the drawing options ask
// (colours, filters, force chains), rendered and written as PNG or JPEG.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "cmd/commands/snapshot_options.hpp"

#ifdef DEMLAB_HAVE_RENDER
#include "render/image.hpp"
#endif

namespace demlab::cmd {

// What a series keeps from its first frame so that later frames match it: the colour range
// (-range first), and with -camera fixed the framing's scene bounds {lo, hi} and the legend
// strip's width (which sets the scene's part of the image). Empty until fixed.
struct SeriesLock {
  std::optional<std::array<double, 2>> range;
  std::optional<std::array<double, 6>> bounds;
  std::optional<int> legendWidth;
};

#ifdef DEMLAB_HAVE_RENDER
// Returns nothing; renders s as o asks into path (atomically, PNG or JPEG as o.jpeg says).
// lock: a series' state, fixed here at its first frame (changes *lock), or nullptr for a lone
// frame. Throws the renderer's errors (RENDER CONTEXT, VALUE ..., IO PNG, IO JPEG); changes
// only the file and *lock.
void writeFrame(const sim::Simulation& s, const SnapOptions& o, const std::string& path,
                SeriesLock* lock);

// Returns the frame of s as o asks (the image writeFrame writes). Throws as writeFrame does;
// changes nothing.
render::Image renderFrame(const sim::Simulation& s, const SnapOptions& o);

// Returns the script id of the element that pixel (x, y) (from the top left) of the frame of s
// as o asks shows, or -1 for none (background, a wall, the header or legend). Changes nothing.
std::int64_t pickFrame(const sim::Simulation& s, const SnapOptions& o, int x, int y);

// The camera a frame is seen with, the automatic one resolved: where it stands, the point it
// looks at, its up direction, its vertical field of view (perspective) or the world height the
// frame shows (orthographic).
struct FrameCamera {
  sim::Vec3d position{}, lookAt{}, up{};
  double fov = 0, viewHeight = 0;
  bool orthographic = false;
};

// Returns the camera of the frame of s as o asks. Changes nothing.
FrameCamera frameCamera(const sim::Simulation& s, const SnapOptions& o);
#endif

}  // namespace demlab::cmd
