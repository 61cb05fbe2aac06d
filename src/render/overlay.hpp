// What is drawn over the rendered frame on the CPU, after read-back: the simulated time stamp
// (top left) and the colour legend (right edge). Drawn at final resolution, so text stays crisp
// whatever the supersampling.
#pragma once

#include <string>

#include "render/image.hpp"
#include "render/scene.hpp"

namespace demlab::render {

// Returns the text of the time stamp for time t, e.g. "t = 0.0125 s".
std::string timeStampText(double t);

// Returns the font scale used on an image of this height (1 up to 360 rows, 2 at 720...).
int overlayScale(int height);

// Returns nothing; draws the time stamp (when scene.time is finite and options.timeStamp) and
// the legend (when the scene is coloured by a field and options.legend) onto image.
void drawOverlay(Image& image, const RenderScene& scene, const RenderOptions& options);

}  // namespace demlab::render
