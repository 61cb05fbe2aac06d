// A tiny built-in 5x7 bitmap font (digits, letters, a little punctuation) for the time stamp and
// the legend, so frames need no font files.
#pragma once

#include <string_view>

#include "render/image.hpp"
#include "render/scene.hpp"

namespace demlab::render {

// kGlyphHeight rows from the top of the cell to the baseline; descenders (g, p, q, y) reach
// kGlyphDescent rows further, so a line of text covers kGlyphCellHeight rows.
inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6, kGlyphDescent = 2;
inline constexpr int kGlyphCellHeight = kGlyphHeight + kGlyphDescent;

// Returns whether pixel (col, row) of character ch's cell is set (unknown characters: '?');
// row runs over the kGlyphCellHeight rows of the cell.
bool glyphPixel(char ch, int col, int row);

// Returns the width in pixels of s drawn at scale.
inline int textWidth(std::string_view s, int scale) {
  return s.empty() ? 0 : (int(s.size()) * kGlyphAdvance - 1) * scale;
}

// Returns nothing; draws s into image with its top-left corner at (x, y), each font pixel a
// scale x scale block, clipped to the image. Changes only the covered pixels.
void drawText(Image& image, int x, int y, std::string_view s, int scale, const Rgb& colour);

// Returns nothing; blends colour with opacity alpha over the rectangle [x0, x1) x [y0, y1),
// clipped to the image.
void fillRect(Image& image, int x0, int y0, int x1, int y1, const Rgb& colour, float alpha = 1);

}  // namespace demlab::render
