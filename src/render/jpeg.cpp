#include "render/jpeg.hpp"

// jpeglib.h needs FILE and size_t declared before it.
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <vector>

#include <jpeglib.h>

#include "core/error.hpp"
#include "core/atomic_file.hpp"
#include "core/interrupt.hpp"

namespace demlab::render {
namespace {

// libjpeg's default error handler calls exit(); this one keeps the message and longjmps back
// to the setjmp of the function that started the (de)compression, which owns no objects with
// destructors between the setjmp and the libjpeg calls.
struct JpegErrorState {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = "unknown libjpeg error";
};

// libjpeg's warnings (a truncated file, say) would go to stderr; the error, if any, is thrown.
void onJpegMessage(j_common_ptr) {}

void onJpegError(j_common_ptr info) {
  auto* state = reinterpret_cast<JpegErrorState*>(info->err);
  (*info->err->format_message)(info, state->message);
  std::longjmp(state->jump, 1);
}

// Returns state's error manager, set to keep libjpeg's message and longjmp to state.jump.
jpeg_error_mgr* errorManager(JpegErrorState& state) {
  jpeg_std_error(&state.mgr);
  state.mgr.error_exit = onJpegError;
  state.mgr.output_message = onJpegMessage;
  return &state.mgr;
}

// Returns true when the JPEG was written to f; on false, state.message holds libjpeg's reason.
// Each row is packed to RGB into `row` (the caller's, so that nothing of it leaks when libjpeg
// jumps out) just before it is written: a whole packed copy of a large frame took longer than
// Ctrl-C may wait.
bool encode(std::FILE* f, const Image& image, std::vector<JSAMPLE>& row, int quality,
            JpegErrorState& state) {
  const int width = image.width, height = image.height;
  row.resize(size_t(width) * 3);
  jpeg_compress_struct c;
  c.err = errorManager(state);
  if (setjmp(state.jump)) {
    jpeg_destroy_compress(&c);
    return false;
  }
  jpeg_create_compress(&c);
  jpeg_stdio_dest(&c, f);
  c.image_width = JDIMENSION(width);
  c.image_height = JDIMENSION(height);
  c.input_components = 3;
  c.in_color_space = JCS_RGB;
  jpeg_set_defaults(&c);
  jpeg_set_quality(&c, quality, TRUE);
  if (quality >= 90) {
    // No chroma subsampling: coloured 1-pixel lines and antialiased text stay sharp.
    for (int k = 0; k < c.num_components; ++k)
      c.comp_info[k].h_samp_factor = c.comp_info[k].v_samp_factor = 1;
  }
  jpeg_start_compress(&c, TRUE);
  while (c.next_scanline < c.image_height) {
    // Ctrl-C every 64 rows: libjpeg's state is freed first, then the interrupt is thrown
    // (writeFileAtomically removes the partial file).
    if ((c.next_scanline & 63) == 0 && interruptRequested()) {
      jpeg_destroy_compress(&c);
      pollInterrupt("snapshot");
    }
    const std::uint8_t* p = image.at(0, int(c.next_scanline));
    for (size_t x = 0; x < size_t(width); ++x)
      for (size_t k = 0; k < 3; ++k) row[3 * x + k] = p[4 * x + k];
    JSAMPROW r = row.data();
    jpeg_write_scanlines(&c, &r, 1);
  }
  jpeg_finish_compress(&c);
  jpeg_destroy_compress(&c);
  return true;
}

// Returns true when f held a JPEG, now in image as RGBA; the objects libjpeg fills live in the
// caller (see encode). row is scratch for one packed RGB row.
bool decode(std::FILE* f, Image& image, std::vector<JSAMPLE>& row, JpegErrorState& state) {
  jpeg_decompress_struct d;
  d.err = errorManager(state);
  if (setjmp(state.jump)) {
    jpeg_destroy_decompress(&d);
    return false;
  }
  jpeg_create_decompress(&d);
  jpeg_stdio_src(&d, f);
  jpeg_read_header(&d, TRUE);
  d.out_color_space = JCS_RGB;
  jpeg_start_decompress(&d);
  image = Image(int(d.output_width), int(d.output_height));
  row.resize(size_t(d.output_width) * 3);
  while (d.output_scanline < d.output_height) {
    const int y = int(d.output_scanline);
    JSAMPROW r = row.data();
    jpeg_read_scanlines(&d, &r, 1);
    for (int x = 0; x < image.width; ++x) {
      std::uint8_t* p = image.at(x, y);
      p[0] = row[3 * size_t(x)], p[1] = row[3 * size_t(x) + 1], p[2] = row[3 * size_t(x) + 2];
      p[3] = 255;
    }
  }
  jpeg_finish_decompress(&d);
  jpeg_destroy_decompress(&d);
  return true;
}

}  // namespace

void writeJpeg(const Image& image, const std::string& path, int quality) {
  if (quality < 1 || quality > 100)
    throw Error("bad quality \"" + std::to_string(quality) + "\": must be 1 to 100",
                {"VALUE", "QUALITY"});
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != size_t(4) * image.width * image.height)
    throw Error("bad image for \"" + path + "\": pixel buffer does not match its size",
                {"VALUE", "IMAGE"});
  std::vector<JSAMPLE> row;
  const FileEncoder encodeInto = [&](std::FILE* f) {
    JpegErrorState state;
    return encode(f, image, row, quality, state) ? std::string()
                                                                      : std::string(state.message);
  };
  writeFileAtomically(path, encodeInto, "JPEG");
}

Image readJpeg(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f)
    throw Error("couldn't open \"" + path + "\": " + posixMessage(errno), {"IO", "JPEG"});
  JpegErrorState state;
  Image image;
  std::vector<JSAMPLE> row;
  const bool ok = decode(f, image, row, state);
  std::fclose(f);
  if (!ok)
    throw Error("couldn't read \"" + path + "\": " + state.message, {"IO", "JPEG"});
  return image;
}

}  // namespace demlab::render
