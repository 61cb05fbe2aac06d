#include "render/overlay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "render/legend.hpp"

namespace demlab::render {
namespace {

// Returns black on a light background, white on a dark one.
Rgb inkFor(const Rgb& bg) {
  const float luma = 0.2126f * bg[0] + 0.7152f * bg[1] + 0.0722f * bg[2];
  return luma > 0.5f ? Rgb{0, 0, 0} : Rgb{1, 1, 1};
}

}  // namespace

std::string timeStampText(double t) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "t = %.6g s", t);
  return buf;
}

void drawOverlay(Image& img, const RenderScene& scene, const RenderOptions& o,
                 const FrameLayout& layout, const Typeface& face) {
  const Rgb ink = inkFor(o.background);
  const int px = layout.textPx;
  if (!layout.header.empty()) {
    const Rect& h = layout.header;
    const int pad = std::max(3, px / 2);
    const int y = h.y0 + (h.height() - face.lineHeight(px)) / 2;
    int left = h.x0 + pad;
    if (o.timeStamp && std::isfinite(scene.time)) {
      const std::string stamp = timeStampText(scene.time);
      face.draw(img, left, y, stamp, px, ink);
      left += face.width(stamp, px) + 2 * pad;
    }
    if (!scene.title.empty()) {
      // Centred over the image, or after the time stamp when that would overlap it.
      const int x = std::max(left, (img.width - face.width(scene.title, px)) / 2);
      face.draw(img, x, y, scene.title, px, ink);
    }
  }
  if (!layout.legend.empty()) drawLegend(img, layout.legend, scene, o, face, px, ink);
}

}  // namespace demlab::render
