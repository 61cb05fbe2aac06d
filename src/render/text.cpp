#include "render/text.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cstdint>
#include <vector>

#include "render/colour_map.hpp"
#include "render/font.hpp"

namespace demlab::render {
namespace {

// Returns the code points of UTF-8 text; a malformed byte stands for itself (Latin-1).
std::vector<char32_t> codePoints(std::string_view s) {
  std::vector<char32_t> out;
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const size_t more = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
    char32_t cp = c & (0x3F >> more);
    bool ok = more > 0 && i + more < s.size();
    for (size_t k = 1; ok && k <= more; ++k) {
      const auto n = static_cast<unsigned char>(s[i + k]);
      ok = (n & 0xC0) == 0x80;
      cp = (cp << 6) | (n & 0x3F);
    }
    out.push_back(ok ? cp : char32_t(c));
    i += ok ? more + 1 : 1;
  }
  return out;
}

// Returns the bitmap font's scale for text of size px.
int bitmapScale(int px) {
  return std::max(1, (px + kGlyphCellHeight / 2) / kGlyphCellHeight);
}

}  // namespace

struct Typeface::Face {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  int px = 0;  // the size set last
};

Typeface::Typeface(const std::string& path) : face_(std::make_unique<Face>()) {
  if (FT_Init_FreeType(&face_->library) != 0) {
    face_.reset();
    return;
  }
  if (FT_New_Face(face_->library, path.c_str(), 0, &face_->face) != 0) {
    FT_Done_FreeType(face_->library);
    face_.reset();
  }
}

Typeface::~Typeface() {
  if (!face_) return;
  FT_Done_Face(face_->face);
  FT_Done_FreeType(face_->library);
}

bool Typeface::trueType() const {
  return face_ != nullptr;
}

Typeface::Face* Typeface::sized(int px) const {
  if (!face_) return nullptr;
  if (face_->px != px) {
    FT_Set_Pixel_Sizes(face_->face, 0, FT_UInt(std::max(px, 1)));
    face_->px = px;
  }
  return face_.get();
}

int Typeface::lineHeight(int px) const {
  const Face* f = sized(px);
  if (!f) return kGlyphCellHeight * bitmapScale(px);
  const FT_Size_Metrics& m = f->face->size->metrics;
  return int((m.ascender - m.descender + 63) >> 6);
}

int Typeface::width(std::string_view text, int px) const {
  const Face* f = sized(px);
  if (!f) return textWidth(text, bitmapScale(px));
  long w = 0;
  for (char32_t cp : codePoints(text))
    if (FT_Load_Char(f->face, cp, FT_LOAD_DEFAULT) == 0) w += f->face->glyph->advance.x;
  return int((w + 63) >> 6);
}

void Typeface::draw(Image& img, int x, int y, std::string_view text, int px,
                    const Rgb& colour) const {
  const Face* f = sized(px);
  if (!f) {
    drawText(img, x, y, text, bitmapScale(px), colour);
    return;
  }
  const int baseline = y + int(f->face->size->metrics.ascender >> 6);
  long pen = long(x) << 6;
  const std::uint8_t ink[3] = {toByte(colour[0]), toByte(colour[1]), toByte(colour[2])};
  for (char32_t cp : codePoints(text)) {
    if (FT_Load_Char(f->face, cp, FT_LOAD_RENDER) != 0) continue;
    const FT_GlyphSlot g = f->face->glyph;
    const FT_Bitmap& bm = g->bitmap;
    const int gx = int(pen >> 6) + g->bitmap_left, gy = baseline - g->bitmap_top;
    for (unsigned r = 0; r < bm.rows; ++r) {
      const int py = gy + int(r);
      if (py < 0 || py >= img.height) continue;
      for (unsigned c = 0; c < bm.width; ++c) {
        const int pxl = gx + int(c);
        if (pxl < 0 || pxl >= img.width) continue;
        const unsigned a = bm.buffer[r * unsigned(bm.pitch) + c];
        if (!a) continue;
        std::uint8_t* p = img.at(pxl, py);
        for (int k = 0; k < 3; ++k) p[k] = std::uint8_t((ink[k] * a + p[k] * (255 - a) + 127) / 255);
      }
    }
    pen += g->advance.x;
  }
}

const Typeface& defaultTypeface() {
  static const Typeface t(kDefaultFontFile);
  return t;
}

}  // namespace demlab::render
