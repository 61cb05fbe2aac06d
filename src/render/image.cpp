#include "render/image.hpp"

#include "core/interrupt.hpp"

namespace demlab::render {

Image blankImage(int w, int h) {
  Image img;
  img.width = w;
  img.height = h;
  img.rgba = polledFill<std::uint8_t>(size_t(4) * size_t(w) * size_t(h), 0, "snapshot");
  return img;
}

}  // namespace demlab::render
