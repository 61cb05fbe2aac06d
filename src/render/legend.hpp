// The colour legend drawn in its strip (layout.hpp): for a continuous field a colour bar with
// round tick values (ticks.hpp), the quantity's name and its unit; for a categorical one a
// swatch and a name per category.
#pragma once

#include "render/image.hpp"
#include "render/layout.hpp"
#include "render/scene.hpp"
#include "render/text.hpp"

namespace demlab::render {

// Returns the width in pixels the legend of scene needs at text size px.
int legendWidth(const RenderScene& scene, const RenderOptions& options, const Typeface& face,
                int px);

// Returns nothing; draws the legend of scene into strip of image (its background already
// there), in ink. Changes only the strip's pixels.
void drawLegend(Image& image, const Rect& strip, const RenderScene& scene,
                const RenderOptions& options, const Typeface& face, int px, const Rgb& ink);

}  // namespace demlab::render
