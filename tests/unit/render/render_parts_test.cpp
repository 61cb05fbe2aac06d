// The renderer's CPU parts: colour maps, camera framing, wall geometry, the font.
#include <random>
#include <set>

#include "render/colour_map.hpp"
#include "render/font.hpp"
#include "render/overlay.hpp"
#include "render/view.hpp"
#include "render/wall_geometry.hpp"
#include "render_support.hpp"

namespace demlab::render {
namespace render_parts_test {

double luminance(const Rgb& c) {
  return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

TEST(RenderColourMap, ViridisRisesInLightness) {
  EXPECT_LT(luminance(viridis(0)), 0.1);
  EXPECT_GT(luminance(viridis(1)), 0.8);
  for (int i = 1; i <= 100; ++i)
    EXPECT_GT(luminance(viridis(i / 100.0)), luminance(viridis((i - 1) / 100.0)));
  EXPECT_EQ(viridis(-3), viridis(0));
  EXPECT_EQ(viridis(7), viridis(1));
  EXPECT_EQ(viridis(std::nan("")), viridis(0));
}

TEST(RenderColourMap, CategoriesAreDistinctAndRepeat) {
  std::set<Rgb> seen;
  for (int k = 0; k < 10; ++k) seen.insert(categorical(k));
  EXPECT_EQ(seen.size(), 10u);
  EXPECT_EQ(categorical(13), categorical(3));
  EXPECT_EQ(categorical(-1), categorical(9));
  EXPECT_EQ(categoryOf(2.4), 2);
  EXPECT_EQ(categoryOf(2.6), 3);
}

TEST(RenderColourMap, Names) {
  for (ColourMap m : kColourMaps) EXPECT_EQ(colourMapNamed(colourMapName(m)), m);
  EXPECT_EQ(test::errorCode([] { colourMapNamed("jet"); }), "DEMLAB VALUE COLOURMAP");
  try {
    colourMapNamed("jet");
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "bad colour map \"jet\": must be categorical, coolwarm, inferno, magma, plasma, or viridis");
  }
}

TEST(RenderColourMap, FieldRange) {
  std::vector<double> f = {3, -1, 7};
  RenderScene s;
  s.field = f;
  RenderOptions o;
  FieldRange r = fieldRange(s, o);
  EXPECT_EQ(r.lo, -1);
  EXPECT_EQ(r.hi, 7);
  o.fieldMax = 10;
  EXPECT_EQ(fieldRange(s, o).hi, 10);
  std::vector<double> flat = {2, 2};
  s.field = flat;
  r = fieldRange(s, RenderOptions{});
  EXPECT_EQ(r.lo, 1.5);
  EXPECT_EQ(r.hi, 2.5);
  std::vector<double> zeros = {0, 0};
  s.field = zeros;
  r = fieldRange(s, RenderOptions{});
  EXPECT_EQ(r.lo, 0);
  EXPECT_EQ(r.hi, 1);
}

TEST(RenderView, ManualCamerasProjectAsByHand) {
  std::vector<double> c = {0, 0, 0}, rad = {1};
  RenderScene s;
  s.centres = c;
  s.radii = rad;
  RenderOptions o;
  o.width = 400;
  o.height = 200;
  o.camera.automatic = false;
  o.camera.position = Vec3(10, 0, 0);  // looking along -x, z up: screen x is world y
  o.camera.lookAt = Vec3::Zero();
  o.camera.up = Vec3::UnitZ();
  o.camera.fov = 90;
  View v = makeView(s, o);
  // f = 1; ndc x = (y / depth) / aspect, ndc y = z / depth; depth = 10 - x.
  Vec3 p = v.project(Vec3(2, 3, 4));
  EXPECT_NEAR(p.x(), 200 + 200 * (3.0 / 8) / 2, 1e-9);
  EXPECT_NEAR(p.y(), 100 - 100 * (4.0 / 8), 1e-9);
  EXPECT_NEAR(v.pixelRadius(Vec3(2, 0, 0), 1), 100.0 / 8, 1e-9);
  o.camera.orthographic = true;
  o.camera.viewHeight = 8;
  v = makeView(s, o);
  p = v.project(Vec3(2, 3, 4));
  EXPECT_NEAR(p.x(), 200 + 3 * 25, 1e-9);
  EXPECT_NEAR(p.y(), 100 - 4 * 25, 1e-9);
  EXPECT_LT(v.project(Vec3(1, 0, 0)).z(), v.project(Vec3(-1, 0, 0)).z());  // nearer is less deep
}

TEST(RenderView, AutomaticFramingFitsTheBounds) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-5, 5);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> c, r;
    for (int i = 0; i < 30; ++i) {
      c.insert(c.end(), {u(rng) + 100, 0.3 * u(rng), 2 * u(rng)});
      r.push_back(0.5);
    }
    RenderScene s;
    s.centres = c;
    s.radii = r;
    RenderOptions o;
    o.camera.orthographic = trial % 2;
    o.camera.direction = Vec3(u(rng), u(rng), u(rng));
    o.camera.up = Vec3::UnitZ();
    const View v = makeView(s, o);
    const Bounds b = sceneBounds(s);
    double lo = 1e300, hi = -1e300;
    for (int k = 0; k < 8; ++k) {
      const Vec3 q(k & 1 ? b.hi.x() : b.lo.x(), k & 2 ? b.hi.y() : b.lo.y(),
                   k & 4 ? b.hi.z() : b.lo.z());
      const Vec3 p = v.project(q);
      EXPECT_GE(p.x(), 0);
      EXPECT_LE(p.x(), o.width);
      EXPECT_GE(p.y(), 0);
      EXPECT_LE(p.y(), o.height);
      EXPECT_GT(p.z(), 0);
      EXPECT_LT(p.z(), 1);
      lo = std::min({lo, p.x() / o.width, p.y() / o.height});
      hi = std::max({hi, p.x() / o.width, p.y() / o.height});
    }
    EXPECT_LT(std::min(lo, 1 - hi), 0.03);  // tight on at least one side
  }
}

TEST(RenderWalls, PlanesAreClippedToTheBounds) {
  RenderScene s;
  s.walls.push_back(RenderWall::plane(Vec3(0, 0, 0.5), Vec3(0, 0, 2)));
  Bounds b;
  b.add(Vec3::Zero());
  b.add(Vec3::Ones());
  WallGeometry g;
  wallGeometry(s, b, Vec3::Zero(), 0.2, g);
  ASSERT_EQ(g.lines.size(), 4u);      // the square's outline
  ASSERT_EQ(g.triangles.size(), 6u);  // two triangles
  double area = 0;
  for (size_t t = 0; t < g.triangles.size(); t += 3) {
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = Vec3(g.triangles[t + k].p[0], g.triangles[t + k].p[1], g.triangles[t + k].p[2]);
      EXPECT_NEAR(p[k].z(), 0.5, 1e-6);
    }
    area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
  }
  const double side = 1 + 2 * 0.02 * std::sqrt(3.0);  // the bounds widened by 2% of the diagonal
  EXPECT_NEAR(area, side * side, 1e-5);
  // A plane missing the bounds draws nothing; a box is 12 edges; a 3D drum two circles and a
  // mantle.
  s.walls = {RenderWall::plane(Vec3(0, 0, 5), Vec3::UnitZ()),
             RenderWall::box(Vec3::Zero(), Vec3::Ones())};
  wallGeometry(s, b, Vec3::Zero(), 0.2, g);
  EXPECT_EQ(g.lines.size(), 12u);
  EXPECT_TRUE(g.triangles.empty());
  s.walls = {RenderWall::drum(Vec3::Zero(), Vec3::UnitY(), 2, 3)};
  wallGeometry(s, b, Vec3(1, 1, 1), 0.2, g);
  for (const auto& l : g.lines) {
    const Vec3 a(l.a[0] + 1, l.a[1] + 1, l.a[2] + 1);  // anchor added back
    EXPECT_NEAR(std::hypot(a.x(), a.z()), 2, 1e-5);
    EXPECT_NEAR(std::abs(a.y()), 1.5, 1e-5);
  }
  EXPECT_FALSE(g.triangles.empty());
}

TEST(RenderFont, GlyphsAreDistinct) {
  const std::string chars = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz.:-+=";
  std::set<std::vector<bool>> shapes;
  for (char ch : chars) {
    std::vector<bool> bits;
    for (int r = 0; r < kGlyphCellHeight; ++r)
      for (int c = 0; c < kGlyphWidth; ++c) bits.push_back(glyphPixel(ch, c, r));
    shapes.insert(bits);
  }
  EXPECT_EQ(shapes.size(), chars.size());
  for (int r = 0; r < kGlyphCellHeight; ++r)
    for (int c = 0; c < kGlyphWidth; ++c) {
      EXPECT_EQ(glyphPixel('~', c, r), glyphPixel('?', c, r));
      EXPECT_FALSE(glyphPixel(' ', c, r));
    }
  EXPECT_EQ(textWidth("t = 1", 2), (5 * 6 - 1) * 2);
  // g, p, q and y hang below the baseline, the rest of the lower case sits on it, and the
  // bodies of "speed" share one x-height.
  const auto inkRows = [](char ch, int r0, int r1) {
    int n = 0;
    for (int r = r0; r < r1; ++r)
      for (int c = 0; c < kGlyphWidth; ++c) n += glyphPixel(ch, c, r);
    return n;
  };
  for (char ch : std::string("gpqy")) {
    EXPECT_GT(inkRows(ch, kGlyphHeight, kGlyphCellHeight), 0) << ch;
    EXPECT_EQ(inkRows(ch, 0, 2), 0) << ch;  // nothing above the x-height
  }
  for (char ch : std::string("aceosbdhkt0A."))
    EXPECT_EQ(inkRows(ch, kGlyphHeight, kGlyphCellHeight), 0) << ch;
  for (char ch : std::string("sped")) EXPECT_GT(inkRows(ch, 2, 3), 0) << ch;  // x-height row
  EXPECT_EQ(timeStampText(0.0125), "t = 0.0125 s");
  // Drawn text lands where asked, at the asked scale.
  Image img(40, 20);
  drawText(img, 3, 2, "1", 2, {1, 1, 1});
  EXPECT_EQ(img.pixel(3 + 2 * 2, 2)[0], 255);  // the 1's top stroke, column 2
  EXPECT_EQ(img.pixel(3, 2)[0], 0);
  EXPECT_EQ(img.pixel(3 + 2 * 2 + 1, 2 + 13)[0], 255);  // bottom row, scaled
}

}  // namespace render_parts_test
}  // namespace demlab::render
