#include "render/legend.hpp"

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "render/colour_map.hpp"
#include "render/font.hpp"
#include "render/ticks.hpp"

namespace demlab::render {
namespace {

constexpr int kMaxCategories = 12;

// What a legend shows, worked out once for its width and its drawing.
struct LegendPlan {
  std::vector<std::string> title;  // the field's name, then "(unit)" when it has one
  bool categorical = false;
  FieldRange range;
  Ticks ticks;
  std::vector<std::string> labels;  // tick labels, or category names
  std::vector<long> categories;     // categorical: the category of each label (-1: "...")
};

// Returns what the legend of scene shows under o: its title lines, and its ticks and labels (a
// continuous map) or its categories (at most kMaxCategories, then "...").
LegendPlan plan(const RenderScene& scene, const RenderOptions& o) {
  LegendPlan p;
  if (!scene.fieldName.empty()) p.title.push_back(scene.fieldName);
  if (!scene.fieldUnit.empty()) p.title.push_back("(" + scene.fieldUnit + ")");
  p.categorical = o.colourMap == ColourMap::categorical;
  if (p.categorical) {
    std::set<long> seen;
    for (double v : scene.field) {
      seen.insert(categoryOf(v));
      if (seen.size() > kMaxCategories) break;
    }
    for (long k : seen) {
      if (p.labels.size() == kMaxCategories) {
        p.labels.push_back("...");
        p.categories.push_back(-1);
        break;
      }
      const bool named = k >= 0 && size_t(k) < scene.categoryNames.size();
      p.labels.push_back(named ? scene.categoryNames[size_t(k)] : std::to_string(k));
      p.categories.push_back(k);
    }
  } else {
    p.range = fieldRange(scene, o);
    p.ticks = niceTicks(p.range.lo, p.range.hi);
    p.labels = tickLabels(p.ticks);
  }
  return p;
}

// The sizes a legend is laid out with at text size px.
struct Metrics {
  int pad, line, swatch, tick;
};

// Returns the legend's sizes at text size px in face: padding half the text size, the swatch
// and bar width the text size, ticks a third of it.
Metrics metrics(const Typeface& face, int px) {
  return {std::max(3, px / 2), face.lineHeight(px), std::max(8, px), std::max(3, px / 3)};
}

}  // namespace

int legendWidth(const RenderScene& scene, const RenderOptions& o, const Typeface& face, int px) {
  const LegendPlan p = plan(scene, o);
  const Metrics m = metrics(face, px);
  // Room for labels such as "-0.25" at least, so ranges of the same magnitude (a series whose
  // range is still to be fixed, say) give the strip one width.
  int labels = p.categorical ? 0 : face.width("-0.25", px), title = 0;
  for (const auto& s : p.labels) labels = std::max(labels, face.width(s, px));
  for (const auto& s : p.title) title = std::max(title, face.width(s, px));
  const int body = m.swatch + (p.categorical ? m.pad : m.tick + m.pad / 2) + labels;
  return std::max(body, title) + 2 * m.pad;
}

void drawLegend(Image& img, const Rect& strip, const RenderScene& scene, const RenderOptions& o,
                const Typeface& face, int px, const Rgb& ink) {
  const LegendPlan p = plan(scene, o);
  const Metrics m = metrics(face, px);
  const int x = strip.x0 + m.pad;
  const int titleH = int(p.title.size()) * m.line;
  // The block (title, then bar or rows) centred in the strip; the bar three fifths of it.
  const int bodyH = p.categorical ? int(p.labels.size()) * (m.line + m.pad / 2)
                                  : std::max(4 * m.line, strip.height() * 3 / 5);
  const int top = strip.y0 + std::max(m.pad, (strip.height() - titleH - m.pad - bodyH) / 2);
  for (size_t i = 0; i < p.title.size(); ++i)
    face.draw(img, x, top + int(i) * m.line, p.title[i], px, ink);
  int y = top + titleH + m.pad;
  if (p.categorical) {
    for (size_t i = 0; i < p.labels.size(); ++i) {
      const int sy = y + (m.line - m.swatch) / 2;
      if (p.categories[i] >= 0)
        fillRect(img, x, sy, x + m.swatch, sy + m.swatch, categorical(p.categories[i]));
      face.draw(img, x + m.swatch + m.pad, y, p.labels[i], px, ink);
      y += m.line + m.pad / 2;
    }
    return;
  }
  // The bar leaves half a line above and below for the end labels.
  const int barTop = y + m.line / 2, barBottom = std::min(y + bodyH, strip.y1 - m.line);
  const int barH = std::max(2, barBottom - barTop);
  for (int r = 0; r < barH; ++r)
    fillRect(img, x, barTop + r, x + m.swatch, barTop + r + 1,
             mapColour(o.colourMap, 1 - double(r) / (barH - 1)));
  const FieldRange& range = p.range;
  for (size_t i = 0; i < p.ticks.values.size(); ++i) {
    const double t = (p.ticks.values[i] - range.lo) / (range.hi - range.lo);
    const int ty = barTop + int(std::lround((1 - t) * (barH - 1)));
    fillRect(img, x + m.swatch, ty, x + m.swatch + m.tick, ty + 1, ink);
    face.draw(img, x + m.swatch + m.tick + m.pad / 2, ty - m.line / 2, p.labels[i], px, ink);
  }
}

}  // namespace demlab::render
