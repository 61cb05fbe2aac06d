#include "render/colour_map.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "render/colour_tables.hpp"

namespace demlab::render {
namespace {

// Ten well-separated hues (the "tab10" family), in an order where neighbours contrast.
constexpr float kCategorical[10][3] = {{0.122f, 0.467f, 0.706f}, {1.000f, 0.498f, 0.055f},
                                       {0.173f, 0.627f, 0.173f}, {0.839f, 0.153f, 0.157f},
                                       {0.580f, 0.404f, 0.741f}, {0.549f, 0.337f, 0.294f},
                                       {0.890f, 0.467f, 0.761f}, {0.498f, 0.498f, 0.498f},
                                       {0.737f, 0.741f, 0.133f}, {0.090f, 0.745f, 0.812f}};

}  // namespace

Rgb viridis(double t) {
  return mapColour(ColourMap::viridis, t);
}

Rgb mapColour(ColourMap m, double t) {
  if (m == ColourMap::categorical) return categorical(categoryOf(t));
  const float(*table)[3] = m == ColourMap::magma     ? kMagmaTable
                           : m == ColourMap::inferno  ? kInfernoTable
                           : m == ColourMap::plasma   ? kPlasmaTable
                           : m == ColourMap::coolwarm ? kCoolwarmTable
                                                      : kViridisTable;
  // matplotlib's lookup: entry floor(t * 256), the top one for t = 1.
  const int i = !(t > 0) ? 0 : t >= 1 ? 255 : std::min(255, int(t * 256));
  return {table[i][0], table[i][1], table[i][2]};
}

Rgb chainColour(double t) {
  const float f = float(std::clamp(t, 0.0, 1.0));
  return {0.85f - 0.45f * f, 0.3f - 0.3f * f, 0.25f - 0.25f * f};
}

Rgb categorical(long k) {
  const long m = ((k % 10) + 10) % 10;
  return {kCategorical[m][0], kCategorical[m][1], kCategorical[m][2]};
}

ColourMap colourMapNamed(std::string_view name) {
  for (ColourMap m : kColourMaps)
    if (colourMapName(m) == name) return m;
  throw Error("bad colour map \"" + std::string(name) +
                  "\": must be categorical, coolwarm, inferno, magma, plasma, or viridis",
              {"VALUE", "COLOURMAP"});
}

std::string_view colourMapName(ColourMap m) {
  switch (m) {
    case ColourMap::magma: return "magma";
    case ColourMap::inferno: return "inferno";
    case ColourMap::plasma: return "plasma";
    case ColourMap::coolwarm: return "coolwarm";
    case ColourMap::categorical: return "categorical";
    case ColourMap::viridis: break;
  }
  return "viridis";
}

long categoryOf(double value) {
  return std::lround(value);
}

FieldRange fieldRange(const RenderScene& scene, const RenderOptions& options) {
  FieldRange r{0, 1};
  if (!scene.field.empty()) {
    const auto [lo, hi] = std::minmax_element(scene.field.begin(), scene.field.end());
    r = {*lo, *hi};
  }
  if (!std::isnan(options.fieldMin)) r.lo = options.fieldMin;
  if (!std::isnan(options.fieldMax)) r.hi = options.fieldMax;
  if (!(r.hi > r.lo)) {
    // A field of zeros (a bed at rest, no contacts) reads 0 to 1, not -0.5 to 0.5: the
    // fields that are magnitudes have no negative values to suggest.
    const double v = std::isnan(options.fieldMin) ? r.hi : r.lo;
    r = v == 0 ? FieldRange{0, 1} : FieldRange{v - 0.5, v + 0.5};
  }
  return r;
}

void grainColours(const RenderScene& scene, const RenderOptions& options,
                  std::vector<std::uint8_t>& out) {
  const size_t n = scene.size();
  out.resize(4 * n);
  auto put = [&](size_t i, const Rgb& c) {
    out[4 * i] = toByte(c[0]);
    out[4 * i + 1] = toByte(c[1]);
    out[4 * i + 2] = toByte(c[2]);
    out[4 * i + 3] = 255;
  };
  if (!scene.field.empty()) {
    if (options.colourMap == ColourMap::categorical) {
      for (size_t i = 0; i < n; ++i) put(i, categorical(categoryOf(scene.field[i])));
    } else {
      const FieldRange r = fieldRange(scene, options);
      const double scale = 1 / (r.hi - r.lo);
      for (size_t i = 0; i < n; ++i)
        put(i, mapColour(options.colourMap, (scene.field[i] - r.lo) * scale));
    }
  } else if (!scene.colours.empty()) {
    for (size_t i = 0; i < n; ++i)
      put(i, {scene.colours[3 * i], scene.colours[3 * i + 1], scene.colours[3 * i + 2]});
  } else {
    for (size_t i = 0; i < n; ++i) put(i, options.defaultColour);
  }
  for (uint32_t i : scene.highlighted) put(i, options.highlightColour);
}

}  // namespace demlab::render
