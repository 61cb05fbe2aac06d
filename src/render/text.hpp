// Antialiased text for the frame's margins (legend, title, time stamp) through FreeType, in
// DejaVu Sans. When the font file can't be loaded the built-in bitmap font (font.hpp) draws
// instead, at the nearest whole scale, with no error: a frame is still written.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "render/image.hpp"
#include "render/scene.hpp"

namespace demlab::render {

inline constexpr const char* kDefaultFontFile = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

class Typeface {
 public:
  // Loads the TrueType font in path; falls back to the bitmap font when that fails.
  explicit Typeface(const std::string& path);
  ~Typeface();
  Typeface(const Typeface&) = delete;
  Typeface& operator=(const Typeface&) = delete;

  // Returns whether the TrueType font loaded (false: the bitmap font draws).
  bool trueType() const;

  // Returns the height in pixels of a line of text at size px (ascent plus descent).
  int lineHeight(int px) const;

  // Returns the advance width in pixels of text (UTF-8) at size px.
  int width(std::string_view text, int px) const;

  // Returns nothing; draws text (UTF-8) at size px with the top of its line at (x, y), blending
  // colour by the glyphs' coverage, clipped to image. Changes only the covered pixels.
  void draw(Image& image, int x, int y, std::string_view text, int px, const Rgb& colour) const;

 private:
  struct Face;
  std::unique_ptr<Face> face_;
  // Returns the face set to size px, or nullptr for the bitmap font.
  Face* sized(int px) const;
};

// Returns the process's typeface: DejaVu Sans (kDefaultFontFile), or the bitmap font when the
// file is missing. Made on first use.
const Typeface& defaultTypeface();

}  // namespace demlab::render
