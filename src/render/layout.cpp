#include "render/layout.hpp"

#include <algorithm>
#include <cmath>

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

Image composeFrame(Image scene, const FrameLayout& layout, const RenderOptions& o) {
  if (scene.width == o.width && scene.height == o.height) return scene;
  Image img(o.width, o.height);
  const std::uint8_t bg[4] = {toByte(o.background[0]), toByte(o.background[1]),
                              toByte(o.background[2]), 255};
  for (size_t i = 0; i < img.rgba.size(); i += 4) std::copy(bg, bg + 4, &img.rgba[i]);
  for (int y = 0; y < scene.height; ++y)
    std::copy(scene.at(0, y), scene.at(0, y) + 4 * size_t(scene.width),
              img.at(layout.scene.x0, layout.scene.y0 + y));
  return img;
}

}  // namespace demlab::render
