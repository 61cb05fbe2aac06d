// Colour maps: matplotlib's viridis, magma, inferno, plasma and coolwarm for continuous fields
// (speed, force, a user value; colour_tables.hpp) and a categorical palette for integer fields
// (id, material, tag). Grain colours are resolved on the
// CPU once per frame, so the GL side sees only RGBA bytes.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "render/scene.hpp"

namespace demlab::render {

// Returns viridis at t, clamped to [0, 1]: dark purple at 0, yellow at 1, with lightness rising
// monotonically (readable in grey print).
Rgb viridis(double t);

// Returns map m's colour at t in [0, 1] (clamped), matplotlib's entry floor(256 t); for the
// categorical map, category t.
Rgb mapColour(ColourMap m, double t);

// Every map, in the order the snapshot command lists them.
inline constexpr ColourMap kColourMaps[] = {ColourMap::viridis, ColourMap::magma,
                                            ColourMap::inferno, ColourMap::plasma,
                                            ColourMap::coolwarm, ColourMap::categorical};

// Returns the colour of a force chain carrying fraction t in [0, 1] of the largest force:
// light red for weak ones, dark red for the strongest, distinct from every colour map's ends.
Rgb chainColour(double t);

// Returns the colour of category k (any integer; the 10-colour palette repeats).
Rgb categorical(long k);

// Returns the map called name (colourMapName of one of kColourMaps). Throws demlab::Error
// {VALUE COLOURMAP}: bad colour map "x": must be categorical, coolwarm, ..., or viridis.
ColourMap colourMapNamed(std::string_view name);

// Returns the name of map m.
std::string_view colourMapName(ColourMap m);

// Returns the integer category of a field value (rounded to nearest).
long categoryOf(double value);

struct FieldRange {
  double lo = 0, hi = 1;
};

// Returns the range the field is mapped over: options.fieldMin/Max where given, else the
// field's own minimum/maximum; a degenerate range is widened to [v - 0.5, v + 0.5], or to
// [0, 1] for v = 0.
FieldRange fieldRange(const RenderScene& scene, const RenderOptions& options);

// Returns nothing; fills out with 4 bytes per grain (RGB, then 255) by the rule in RenderScene.
void grainColours(const RenderScene& scene, const RenderOptions& options,
                  std::vector<std::uint8_t>& out);

// Returns c as an 8-bit channel value.
inline std::uint8_t toByte(float c) {
  return std::uint8_t(c <= 0 ? 0 : c >= 1 ? 255 : c * 255.0f + 0.5f);
}

}  // namespace demlab::render
