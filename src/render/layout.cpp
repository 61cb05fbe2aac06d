#include "render/layout.hpp"

#include <algorithm>
#include <cmath>

#include "core/interrupt.hpp"
#include "render/colour_map.hpp"
#include "render/legend.hpp"

namespace demlab::render {

int textSize(int imageHeight) {
  return std::max(10, int(std::lround(imageHeight / 40.0)));
}

FrameLayout frameLayout(const RenderScene& scene, const RenderOptions& o, const Typeface& face) {
  FrameLayout l;
  l.textPx = textSize(o.height);
  l.scene = {0, 0, o.width, o.height};
  const bool header = !scene.title.empty() || (o.timeStamp && std::isfinite(scene.time));
  const int headerH = face.lineHeight(l.textPx) + l.textPx / 2;
  if (header && headerH <= o.height / 4) {
    l.header = {0, 0, o.width, headerH};
    l.scene.y0 = headerH;
  }
  if (o.legend && !scene.field.empty()) {
    const int w = o.legendWidth > 0 ? o.legendWidth : legendWidth(scene, o, face, l.textPx);
    if (w <= o.width / 3) {
      l.legend = {o.width - w, l.scene.y0, o.width, o.height};
      l.scene.x1 = o.width - w;
    }
  }
  return l;
}

RenderOptions sceneOptions(const RenderOptions& options, const FrameLayout& layout) {
  RenderOptions inner = options;
  inner.width = layout.scene.width();
  inner.height = layout.scene.height();
  return inner;
}

Image composeFrame(Image scene, const FrameLayout& layout, const RenderOptions& o) {
  if (scene.width == o.width && scene.height == o.height) return scene;
  Image img = blankImage(o.width, o.height);
  const std::uint8_t bg[4] = {toByte(o.background[0]), toByte(o.background[1]),
                              toByte(o.background[2]), 255};
  // Row by row, Ctrl-C polled every 64 rows: a frame of tens of megapixels takes a while.
  for (int y = 0; y < img.height; ++y) {
    if ((y & 63) == 0) pollInterrupt("snapshot");
    std::uint8_t* row = img.at(0, y);
    for (size_t i = 0; i < 4 * size_t(img.width); i += 4) std::copy(bg, bg + 4, row + i);
    const int sy = y - layout.scene.y0;
    if (sy >= 0 && sy < scene.height)
      std::copy(scene.at(0, sy), scene.at(0, sy) + 4 * size_t(scene.width),
                img.at(layout.scene.x0, y));
  }
  return img;
}

}  // namespace demlab::render
