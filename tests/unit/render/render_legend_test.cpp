// The frame's margins: round tick values, the legend strip beside the scene (never over it),
// TrueType text with its bitmap fallback, and a fixed colour range shared by frames.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "render/colour_map.hpp"
#include "render/layout.hpp"
#include "render/overlay.hpp"
#include "render/text.hpp"
#include "render/ticks.hpp"
#include "render_support.hpp"

namespace demlab::render {
namespace render_legend_test {

using test::isColour;
using test::sharedRenderer;

TEST(RenderTicks, ThreeToSixRoundValuesInsideTheRange) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, std::round(u(rng) * 2)), lo = u(rng) * scale;
    const double hi = lo + std::abs(u(rng)) * scale + 1e-3 * scale;
    const Ticks t = niceTicks(lo, hi);
    ASSERT_GE(t.values.size(), 3u) << lo << " " << hi;
    ASSERT_LE(t.values.size(), 6u) << lo << " " << hi;
    const double m = t.step / std::pow(10.0, std::floor(std::log10(t.step) + 1e-9));
    EXPECT_TRUE(std::abs(m - 1) < 1e-9 || std::abs(m - 2) < 1e-9 || std::abs(m - 2.5) < 1e-9 ||
                std::abs(m - 5) < 1e-9)
        << t.step;
    for (size_t i = 0; i < t.values.size(); ++i) {
      EXPECT_GE(t.values[i], lo - 1e-9 * scale);
      EXPECT_LE(t.values[i], hi + 1e-9 * scale);
      EXPECT_NEAR(std::remainder(t.values[i], t.step), 0, 1e-9 * t.step);
    }
  }
  EXPECT_EQ(niceTicks(0, 5).values, (std::vector<double>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(niceTicks(0, 1).step, 0.2);
}

TEST(RenderTicks, LabelsShowTheDecimalsTheStepNeedsAndOnePowerOfTen) {
  using Labels = std::vector<std::string>;
  EXPECT_EQ(tickLabels(niceTicks(0, 1)), (Labels{"0", "0.2", "0.4", "0.6", "0.8", "1.0"}));
  EXPECT_EQ(tickLabels(niceTicks(0, 0.12)), (Labels{"0", "0.05", "0.10"}));
  EXPECT_EQ(tickLabels({{-1e-17, 0.2, 0.4}, 0.2}), (Labels{"0", "0.2", "0.4"}));
  EXPECT_EQ(tickLabels({{20, 40, 60}, 20}), (Labels{"20", "40", "60"}));
  EXPECT_EQ(tickLabels({{0.25, 0.5, 0.75}, 0.25}), (Labels{"0.25", "0.50", "0.75"}));
  EXPECT_EQ(tickLabels(niceTicks(0, 2e5)), (Labels{"0", "0.5e5", "1.0e5", "1.5e5", "2.0e5"}));
  EXPECT_EQ(tickLabels({{-2e-4, 0, 2e-4}, 2e-4}), (Labels{"-2e-4", "0", "2e-4"}));
}

TEST(RenderText, TrueTypeIsAntialiasedAndAMissingFontFallsBack) {
  const Typeface& face = defaultTypeface();
  ASSERT_TRUE(face.trueType());  // fonts-dejavu-core is a build requirement (scripts/setup)
  EXPECT_GT(face.width("speed (m/s)", 16), face.width("speed", 16));
  EXPECT_GE(face.lineHeight(16), 16);
  Image img(120, 30);
  for (auto& b : img.rgba) b = 255;
  face.draw(img, 2, 2, "speed 0.5", 16, {0, 0, 0});
  int dark = 0, grey = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const int v = img.pixel(x, y)[0];
      dark += v < 60;
      grey += v >= 60 && v < 200;
    }
  EXPECT_GT(dark, 20);
  EXPECT_GT(grey, 10);  // coverage between ink and paper: antialiased
  const Typeface missing("/nonexistent/font.ttf");
  EXPECT_FALSE(missing.trueType());
  EXPECT_GT(missing.width("speed", 18), 0);
  Image other(120, 30);
  missing.draw(other, 2, 2, "speed", 18, {1, 1, 1});
  EXPECT_NE(other.rgba, Image(120, 30).rgba);
}

// A 2D frame of three discs filling the view, coloured by a field.
struct FieldScene {
  std::vector<double> centres = {-1, 0, 0, 0, 1, 0}, radii = {0.5, 0.5, 0.5};
  std::vector<double> field = {0, 1, 2};
  RenderScene scene() const {
    RenderScene s;
    s.dim = 2;
    s.centres = centres;
    s.radii = radii;
    s.field = field;
    s.fieldName = "speed";
    s.fieldUnit = "m/s";
    return s;
  }
};

TEST(RenderLegend, SitsInAStripBesideTheSceneNeverOverIt) {
  const FieldScene f;
  const RenderScene s = f.scene();
  RenderOptions o;
  o.width = 480;
  o.height = 240;
  o.timeStamp = false;
  const FrameLayout l = frameLayout(s, o, defaultTypeface());
  ASSERT_FALSE(l.legend.empty());
  EXPECT_EQ(l.scene.x1, l.legend.x0);
  EXPECT_EQ(l.legend.x1, o.width);
  EXPECT_TRUE(l.header.empty());
  const Image framed = sharedRenderer().render(s, o);
  // The scene part is exactly the frame drawn without a legend at the scene's size.
  RenderOptions bare = o;
  bare.legend = false;
  bare.width = l.scene.width();
  const Image alone = sharedRenderer().render(s, bare);
  int differ = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < l.scene.width(); ++x) differ += framed.pixel(x, y) != alone.pixel(x, y);
  EXPECT_EQ(differ, 0);
  // The strip holds the bar's ends and dark tick and label pixels.
  int top = 0, bottom = 0, ink = 0;
  for (int y = 0; y < o.height; ++y)
    for (int x = l.legend.x0; x < l.legend.x1; ++x) {
      top += isColour(framed, x, y, viridis(1), 0);
      bottom += isColour(framed, x, y, viridis(0), 0);
      ink += framed.pixel(x, y)[0] < 40 && framed.pixel(x, y)[1] < 40;
    }
  EXPECT_GT(top, 0);
  EXPECT_GT(bottom, 0);
  EXPECT_GT(ink, 50);
  // A title and time stamp take a header strip above the scene.
  RenderScene titled = s;
  titled.title = "drum";
  titled.time = 0.5;
  o.timeStamp = true;
  const FrameLayout h = frameLayout(titled, o, defaultTypeface());
  EXPECT_FALSE(h.header.empty());
  EXPECT_EQ(h.scene.y0, h.header.y1);
  EXPECT_EQ(h.legend.y0, h.header.y1);
  // Without the font file the bitmap font sets the same margins, with no error.
  const Typeface missing("/nonexistent/font.ttf");
  const FrameLayout fallback = frameLayout(titled, o, missing);
  EXPECT_FALSE(fallback.legend.empty());
  EXPECT_FALSE(fallback.header.empty());
  Image plain(o.width, o.height);
  for (auto& byte : plain.rgba) byte = 255;
  Image marked = plain;
  drawOverlay(marked, titled, o, fallback, missing);
  EXPECT_NE(marked.rgba, plain.rgba);
  // A tiny image keeps its scene and drops the strips.
  o.width = o.height = 32;
  const FrameLayout tiny = frameLayout(titled, o, defaultTypeface());
  EXPECT_TRUE(tiny.legend.empty());
  EXPECT_TRUE(tiny.header.empty());
  EXPECT_EQ(tiny.scene.width(), 32);
}

TEST(RenderLegend, AFixedRangeGivesAValueTheSameColourInEveryFrame) {
  FieldScene a, b;
  b.field = {1, 3, 4};  // the middle disc of a (value 1) is the left disc of b
  RenderOptions o;
  o.width = 300;
  o.height = 150;
  o.fieldMin = 0;
  o.fieldMax = 4;
  o.legend = false;
  o.camera.automatic = false;
  o.camera.lookAt = Vec3::Zero();
  o.camera.viewHeight = 3;
  const Image ia = sharedRenderer().render(a.scene(), o), ib = sharedRenderer().render(b.scene(), o);
  // 50 pixels a unit about the centre column 150: disc centres x = -1, 0, 1 at 100, 150, 200.
  const auto middleOfA = ia.pixel(150, 75), leftOfB = ib.pixel(100, 75);
  EXPECT_EQ(middleOfA, leftOfB);
  EXPECT_TRUE(isColour(ia, 150, 75, viridis(0.25)));
  // Without the fixed range each frame maps its own values: the colours differ.
  o.fieldMin = o.fieldMax = std::nan("");
  const Image ja = sharedRenderer().render(a.scene(), o), jb = sharedRenderer().render(b.scene(), o);
  EXPECT_NE(ja.pixel(150, 75), jb.pixel(100, 75));
}

TEST(RenderColourMaps, MatplotlibTablesAtTheirEnds) {
  // The first and last entries of matplotlib's tables, and coolwarm's white-ish middle.
  auto near = [](const Rgb& a, const Rgb& b) {
    return std::abs(a[0] - b[0]) < 1e-6 && std::abs(a[1] - b[1]) < 1e-6 && std::abs(a[2] - b[2]) < 1e-6;
  };
  EXPECT_TRUE(near(mapColour(ColourMap::viridis, 0), {0.267004f, 0.004874f, 0.329415f}));
  EXPECT_TRUE(near(mapColour(ColourMap::viridis, 1), {0.993248f, 0.906157f, 0.143936f}));
  EXPECT_TRUE(near(mapColour(ColourMap::magma, 1), {0.987053f, 0.991438f, 0.749504f}));
  EXPECT_TRUE(near(mapColour(ColourMap::inferno, 0), {0.001462f, 0.000466f, 0.013866f}));
  EXPECT_TRUE(near(mapColour(ColourMap::plasma, 0), {0.050383f, 0.029803f, 0.527975f}));
  EXPECT_TRUE(near(mapColour(ColourMap::coolwarm, 0), {0.229806f, 0.298718f, 0.753683f}));
  EXPECT_TRUE(near(mapColour(ColourMap::coolwarm, 1), {0.705673f, 0.015556f, 0.150233f}));
  const Rgb mid = mapColour(ColourMap::coolwarm, 0.5);
  EXPECT_GT(std::min({mid[0], mid[1], mid[2]}), 0.85f);
  for (ColourMap m : kColourMaps) EXPECT_EQ(colourMapNamed(colourMapName(m)), m);
}

}  // namespace render_legend_test
}  // namespace demlab::render
