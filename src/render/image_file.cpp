#include "render/image_file.hpp"

#include <cstdio>

#include "render/jpeg.hpp"
#include "render/png.hpp"

namespace demlab::render {

void writeImage(const Image& image, const std::string& path, ImageFormat format, int quality) {
  if (format == ImageFormat::jpeg)
    writeJpeg(image, path, quality);
  else
    writePng(image, path);
}

Image readImage(const std::string& path) {
  // JPEG starts with the SOI marker FF D8; anything else goes to the PNG reader, whose
  // errors say what is wrong with the file.
  unsigned char head[2] = {0, 0};
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    const size_t got = std::fread(head, 1, 2, f);
    std::fclose(f);
    if (got == 2 && head[0] == 0xFF && head[1] == 0xD8) return readJpeg(path);
  }
  return readPng(path);
}

}  // namespace demlab::render
