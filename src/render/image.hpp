// Image: an 8-bit RGBA picture, rows top to bottom, the form every renderer returns and the PNG
// writer takes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace demlab::render {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // 4 * width * height bytes, row 0 at the top

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(size_t(4) * w * h, 0) {}

  // Returns a pointer to the 4 bytes of pixel (x, y), x to the right, y down.
  std::uint8_t* at(int x, int y) { return &rgba[(size_t(y) * width + x) * 4]; }
  const std::uint8_t* at(int x, int y) const { return &rgba[(size_t(y) * width + x) * 4]; }

  // Returns pixel (x, y) as {r, g, b, a}.
  std::array<std::uint8_t, 4> pixel(int x, int y) const {
    const std::uint8_t* p = at(x, y);
    return {p[0], p[1], p[2], p[3]};
  }
};

// Returns a w x h image of zero bytes, its memory first touched in slices of a few megabytes
// with Ctrl-C polled between them: on some machines (virtualised page faults) the first touch
// of a large frame's pages alone takes tenths of a second. Throws demlab::Error {INTERRUPTED}.
Image blankImage(int w, int h);

}  // namespace demlab::render
