// JPEG files through libjpeg (baseline, 4:2:0 at quality < 90, 4:4:4 from 90 up so thin legend
// text and chain lines keep their colour). Written atomically like PNG (atomic_file.hpp).
#pragma once

#include <string>

#include "render/image.hpp"

namespace demlab::render {

inline constexpr int kDefaultJpegQuality = 90;

// Returns nothing; writes image's RGB (alpha dropped) to path at quality 1-100. Throws
// demlab::Error {VALUE QUALITY} for a quality outside 1-100 and {IO JPEG} when the file can't
// be written; no temporary file is left behind. Changes only path.
void writeJpeg(const Image& image, const std::string& path, int quality = kDefaultJpegQuality);

// Returns the image in path as 8-bit RGBA (alpha 255). Throws demlab::Error {IO JPEG} when the
// file cannot be opened or is not a JPEG.
Image readJpeg(const std::string& path);

}  // namespace demlab::render
