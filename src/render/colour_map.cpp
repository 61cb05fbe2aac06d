#include "render/colour_map.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace demlab::render {
namespace {

// Nine samples of matplotlib's viridis (CC0), linearly interpolated: close enough to keep its
// perceptual ordering, small enough to read.
constexpr float kViridis[9][3] = {
    {0.267f, 0.005f, 0.329f}, {0.283f, 0.141f, 0.458f}, {0.229f, 0.322f, 0.546f},
    {0.172f, 0.448f, 0.558f}, {0.128f, 0.567f, 0.551f}, {0.135f, 0.659f, 0.518f},
    {0.369f, 0.789f, 0.383f}, {0.741f, 0.873f, 0.150f}, {0.993f, 0.906f, 0.144f}};

// Ten well-separated hues (the "tab10" family), in an order where neighbours contrast.
constexpr float kCategorical[10][3] = {{0.122f, 0.467f, 0.706f}, {1.000f, 0.498f, 0.055f},
                                       {0.173f, 0.627f, 0.173f}, {0.839f, 0.153f, 0.157f},
                                       {0.580f, 0.404f, 0.741f}, {0.549f, 0.337f, 0.294f},
                                       {0.890f, 0.467f, 0.761f}, {0.498f, 0.498f, 0.498f},
                                       {0.737f, 0.741f, 0.133f}, {0.090f, 0.745f, 0.812f}};

}  // namespace

Rgb viridis(double t) {
  if (!(t > 0)) t = 0;
  if (t > 1) t = 1;
  const double x = t * 8;
  const int i = std::min(int(x), 7);
  const float f = float(x - i);
  Rgb c;
  for (int k = 0; k < 3; ++k) c[k] = kViridis[i][k] + f * (kViridis[i + 1][k] - kViridis[i][k]);
  return c;
}

Rgb categorical(long k) {
  const long m = ((k % 10) + 10) % 10;
  return {kCategorical[m][0], kCategorical[m][1], kCategorical[m][2]};
}

ColourMap colourMapNamed(std::string_view name) {
  if (name == "viridis") return ColourMap::viridis;
  if (name == "categorical") return ColourMap::categorical;
  throw Error("bad colour map \"" + std::string(name) + "\": must be categorical or viridis",
              {"VALUE", "COLOURMAP"});
}

std::string_view colourMapName(ColourMap m) {
  return m == ColourMap::categorical ? "categorical" : "viridis";
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
    const double v = std::isnan(options.fieldMin) ? r.hi : r.lo;
    r = {v - 0.5, v + 0.5};
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
      for (size_t i = 0; i < n; ++i) put(i, viridis((scene.field[i] - r.lo) * scale));
    }
  } else if (!scene.colours.empty()) {
    for (size_t i = 0; i < n; ++i)
      put(i, {scene.colours[3 * i], scene.colours[3 * i + 1], scene.colours[3 * i + 2]});
  } else {
    for (size_t i = 0; i < n; ++i) put(i, options.defaultColour);
  }
}

}  // namespace demlab::render
