// PNG files through libpng. Writing is atomic: the image goes to a temporary file in the target's
// folder, which is then renamed over the target, so a reader (a movie maker polling the folder)
// never sees half a frame and a failed write leaves any old file untouched.
#pragma once

#include <string>

#include "render/image.hpp"

namespace demlab::render {

// Returns nothing; writes image (RGBA, 8 bits) to path. Throws demlab::Error {IO PNG} with the
// system's reason when the folder is missing or unwritable; no temporary file is left behind.
void writePng(const Image& image, const std::string& path);

// Returns the image in path converted to 8-bit RGBA. Throws demlab::Error {IO PNG} when the file
// cannot be opened or is not a PNG.
Image readPng(const std::string& path);

}  // namespace demlab::render
