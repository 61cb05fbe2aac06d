#include "render/overlay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "render/colour_map.hpp"
#include "render/font.hpp"

namespace demlab::render {
namespace {

// Returns black on a light background, white on a dark one.
Rgb inkFor(const Rgb& bg) {
  const float luma = 0.2126f * bg[0] + 0.7152f * bg[1] + 0.0722f * bg[2];
  return luma > 0.5f ? Rgb{0, 0, 0} : Rgb{1, 1, 1};
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

constexpr int kMaxCategories = 12;

void drawScalarLegend(Image& img, const RenderScene& scene, const RenderOptions& o, int s,
                      const Rgb& ink) {
  const FieldRange r = fieldRange(scene, o);
  const std::string hi = number(r.hi), lo = number(r.lo), title = scene.fieldName;
  const int barW = 4 * s * 3, barH = std::max(img.height * 2 / 5, 16 * s);
  const int labelW = std::max(textWidth(hi, s), textWidth(lo, s));
  const int pad = 4 * s;
  const int panelW = std::max(barW + pad + labelW, textWidth(title, s)) + 2 * pad;
  const int titleH = title.empty() ? 0 : (kGlyphHeight + 4) * s;
  const int panelH = titleH + barH + kGlyphHeight * s + 2 * pad;
  const int x0 = img.width - panelW - pad, y0 = (img.height - panelH) / 2;
  fillRect(img, x0, y0, x0 + panelW, y0 + panelH, o.background, 0.8f);
  if (!title.empty()) drawText(img, x0 + pad, y0 + pad, title, s, ink);
  const int bx = x0 + pad, by = y0 + pad + titleH + kGlyphHeight * s / 2;
  for (int y = 0; y < barH; ++y)
    fillRect(img, bx, by + y, bx + barW, by + y + 1, viridis(1 - double(y) / (barH - 1)));
  drawText(img, bx + barW + pad, by - kGlyphHeight * s / 2, hi, s, ink);
  drawText(img, bx + barW + pad, by + barH - 1 - kGlyphHeight * s / 2, lo, s, ink);
}

void drawCategoryLegend(Image& img, const RenderScene& scene, const RenderOptions& o, int s,
                        const Rgb& ink) {
  std::set<long> seen;
  for (double v : scene.field) {
    seen.insert(categoryOf(v));
    if (seen.size() > kMaxCategories) break;
  }
  std::vector<std::pair<long, std::string>> rows;
  for (long k : seen) {
    if (rows.size() == kMaxCategories) {
      rows.emplace_back(k, "...");
      break;
    }
    const bool named = k >= 0 && size_t(k) < scene.categoryNames.size();
    rows.emplace_back(k, named ? scene.categoryNames[k] : std::to_string(k));
  }
  const std::string& title = scene.fieldName;
  const int pad = 4 * s, box = kGlyphHeight * s, rowH = box + 3 * s;
  int labelW = textWidth(title, s);
  for (const auto& [k, text] : rows) labelW = std::max(labelW, box + pad + textWidth(text, s));
  const int titleH = title.empty() ? 0 : rowH + s;
  const int panelW = labelW + 2 * pad, panelH = titleH + int(rows.size()) * rowH + 2 * pad;
  const int x0 = img.width - panelW - pad, y0 = (img.height - panelH) / 2;
  fillRect(img, x0, y0, x0 + panelW, y0 + panelH, o.background, 0.8f);
  if (!title.empty()) drawText(img, x0 + pad, y0 + pad, title, s, ink);
  int y = y0 + pad + titleH;
  for (const auto& [k, text] : rows) {
    if (text != "...") fillRect(img, x0 + pad, y, x0 + pad + box, y + box, categorical(k));
    drawText(img, x0 + pad + box + pad, y, text, s, ink);
    y += rowH;
  }
}

}  // namespace

std::string timeStampText(double t) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "t = %.6g s", t);
  return buf;
}

int overlayScale(int height) {
  return std::max(1, (height + 180) / 360);
}

void drawOverlay(Image& img, const RenderScene& scene, const RenderOptions& o) {
  const int s = overlayScale(img.height);
  const Rgb ink = inkFor(o.background);
  if (o.timeStamp && std::isfinite(scene.time)) {
    const std::string text = timeStampText(scene.time);
    const int pad = 3 * s;
    fillRect(img, pad, pad, 3 * pad + textWidth(text, s), 3 * pad + kGlyphHeight * s, o.background,
             0.8f);
    drawText(img, 2 * pad, 2 * pad, text, s, ink);
  }
  if (o.legend && !scene.field.empty()) {
    if (o.colourMap == ColourMap::categorical)
      drawCategoryLegend(img, scene, o, s, ink);
    else
      drawScalarLegend(img, scene, o, s, ink);
  }
}

}  // namespace demlab::render
