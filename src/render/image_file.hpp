// Image files by kind: the caller picks the format a frame is written in (the snapshot
// commands: by the file name's extension), and a file's first bytes the format it is read as.
#pragma once

#include <string>

#include "render/image.hpp"

namespace demlab::render {

enum class ImageFormat { png, jpeg };

// Returns nothing; writes image to path in format (quality for JPEG only). Throws what writePng
// or writeJpeg throw. Changes only path.
void writeImage(const Image& image, const std::string& path, ImageFormat format, int quality);

// Returns the image in path, PNG or JPEG by its first bytes. Throws demlab::Error {IO PNG} when
// the file can't be opened or is neither (the readers' errors otherwise).
Image readImage(const std::string& path);

}  // namespace demlab::render
