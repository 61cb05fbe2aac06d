// What is drawn around the rendered scene on the CPU, after read-back, in the margins the
// layout sets aside (layout.hpp): the title and simulated time stamp in the header strip, the
// colour legend in the legend strip. Drawn at final resolution, so text stays crisp whatever
// the supersampling, and never over a grain.
#pragma once

#include <string>

#include "render/image.hpp"
#include "render/layout.hpp"
#include "render/scene.hpp"

namespace demlab::render {

// Returns the text of the time stamp for time t, e.g. "t = 0.0125 s".
std::string timeStampText(double t);

// Returns nothing; draws the header (time stamp when scene.time is finite and
// options.timeStamp, then scene.title) and the legend into their strips of layout, in face.
// Changes only the strips' pixels.
void drawOverlay(Image& image, const RenderScene& scene, const RenderOptions& options,
                 const FrameLayout& layout, const Typeface& face);

}  // namespace demlab::render
