// Colour maps: a viridis-like map for continuous fields (speed, force, a user value) and a
// categorical palette for integer fields (id, material, tag). Grain colours are resolved on the
// CPU once per frame, so the GL side sees only RGBA bytes.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "render/scene.hpp"

namespace demlab::render {

// Returns the viridis-like colour at t, clamped to [0, 1]: dark purple at 0, yellow at 1, with
// lightness rising monotonically (readable in grey print).
Rgb viridis(double t);

// Returns the colour of category k (any integer; the 10-colour palette repeats).
Rgb categorical(long k);

// Returns the map called name ("viridis", "categorical"), the names the snapshot command takes.
// Throws demlab::Error {VALUE COLOURMAP}: bad colour map "x": must be categorical or viridis.
ColourMap colourMapNamed(std::string_view name);

// Returns the name of map m.
std::string_view colourMapName(ColourMap m);

// Returns the integer category of a field value (rounded to nearest).
long categoryOf(double value);

struct FieldRange {
  double lo = 0, hi = 1;
};

// Returns the range the field is mapped over: options.fieldMin/Max where given, else the
// field's own minimum/maximum; a degenerate range is widened to [v - 0.5, v + 0.5].
FieldRange fieldRange(const RenderScene& scene, const RenderOptions& options);

// Returns nothing; fills out with 4 bytes per grain (RGB, then 255) by the rule in RenderScene.
void grainColours(const RenderScene& scene, const RenderOptions& options,
                  std::vector<std::uint8_t>& out);

// Returns c as an 8-bit channel value.
inline std::uint8_t toByte(float c) {
  return std::uint8_t(c <= 0 ? 0 : c >= 1 ? 255 : c * 255.0f + 0.5f);
}

}  // namespace demlab::render
