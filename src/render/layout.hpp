// Where the parts of a frame go: the scene, a header strip above it (title, time stamp) and a
// legend strip right of it, so text and colour bar never cover a grain. A strip that would
// take too much of a small image is left out.
#pragma once

#include "render/image.hpp"
#include "render/scene.hpp"
#include "render/text.hpp"

namespace demlab::render {

// A pixel rectangle [x0, x1) x [y0, y1), y down.
struct Rect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

struct FrameLayout {
  Rect scene;        // where the scene is drawn
  Rect header;       // the title and time stamp; empty for none
  Rect legend;       // the colour legend; empty for none
  int textPx = 12;   // the text size, pixels
};

// Returns the text size for an image of this height: a fortieth of it, at least 10 pixels.
int textSize(int imageHeight);

// Returns the layout of a frame of scene with options, text set in face; the legend strip
// options.legendWidth wide when that is given.
FrameLayout frameLayout(const RenderScene& scene, const RenderOptions& options,
                        const Typeface& face);

// Returns options for the scene part alone: options with layout.scene's size (what the scene
// is drawn, and picked, with).
RenderOptions sceneOptions(const RenderOptions& options, const FrameLayout& layout);

// Returns the frame: the scene image (layout.scene's size) placed at layout.scene in an image
// of options' size filled with the background colour; the scene image itself when it fills it.
Image composeFrame(Image scene, const FrameLayout& layout, const RenderOptions& options);

}  // namespace demlab::render
