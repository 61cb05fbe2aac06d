// What frames show: grains at their projected pixel positions with their colours, background
// elsewhere, correct depth where grains overlap, the 2D rotation mark, walls, supersampling.
#include <numbers>
#include <random>
#include <vector>

#include "render/colour_map.hpp"
#include "render/occlusion.hpp"
#include "render/view.hpp"
#include "render_support.hpp"

namespace demlab::render {
namespace render_frame_test {

using test::dominant;
using test::isColour;
using test::isWhite;
using test::sharedRenderer;
using test::topView;

constexpr int kRed = 0, kGreen = 1, kBlue = 2;

struct Grains {
  std::vector<double> centres, radii;
  std::vector<float> colours;
  void add(const Vec3& c, double r, const Rgb& rgb, int dim = 3) {
    for (int k = 0; k < dim; ++k) centres.push_back(c[k]);
    radii.push_back(r);
    colours.insert(colours.end(), rgb.begin(), rgb.end());
  }
  RenderScene scene(int dim = 3) const {
    RenderScene s;
    s.dim = dim;
    s.centres = centres;
    s.radii = radii;
    s.colours = colours;
    return s;
  }
};

const Rgb red{1, 0, 0}, green{0, 1, 0}, blue{0, 0, 1};

TEST(RenderFrame, OrthographicSpheresAtTheirPixels) {
  Grains g;
  g.add(Vec3(-2, 2, 0), 1, red);
  g.add(Vec3(2, 2, 0), 1, green);
  g.add(Vec3(0, -2, 0), 1.5, blue);
  const Image img = sharedRenderer().render(g.scene(), topView(true));
  ASSERT_EQ(img.width, 200);
  ASSERT_EQ(img.height, 200);
  // x = 100 + 20 X, y = 100 - 20 Y.
  const struct {
    double x, y, r;
    int colour;
  } want[] = {{60, 60, 20, kRed}, {140, 60, 20, kGreen}, {100, 140, 30, kBlue}};
  for (const auto& w : want) {
    EXPECT_EQ(dominant(img, w.x, w.y), w.colour) << w.x << "," << w.y;
    // Just inside the rim on four sides, and just outside it: the radius scales right.
    for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      EXPECT_EQ(dominant(img, w.x + dx * (w.r - 3), w.y + dy * (w.r - 3)), w.colour);
      EXPECT_TRUE(isWhite(img, w.x + dx * (w.r + 3), w.y + dy * (w.r + 3)));
    }
  }
  EXPECT_TRUE(isWhite(img, 0, 0));
  EXPECT_TRUE(isWhite(img, 199, 199));
  EXPECT_TRUE(isWhite(img, 100, 100));
  EXPECT_TRUE(isWhite(img, 160, 150));
}

TEST(RenderFrame, PerspectiveSpheresAtProjectedPixels) {
  Grains g;
  g.add(Vec3(2, 0, 0), 0.5, red);     // ndc x = f 2 / 10, f = 1 / tan 30 deg
  g.add(Vec3(0, 3, -5), 0.5, green);  // ndc y = f 3 / 15
  g.add(Vec3(-3, -3, 2), 0.5, blue);  // ndc = f (-3, -3) / 8
  const Image img = sharedRenderer().render(g.scene(), topView(false));
  const double f = 1 / std::tan(M_PI / 6);
  const struct {
    double x, y, rpx;
    int colour;
  } want[] = {{100 + 100 * f * 0.2, 100, 100 * f * 0.5 / 10, kRed},
              {100, 100 - 100 * f * 0.2, 100 * f * 0.5 / 15, kGreen},
              {100 - 100 * f * 3 / 8, 100 + 100 * f * 3 / 8, 100 * f * 0.5 / 8, kBlue}};
  for (const auto& w : want) {
    EXPECT_EQ(dominant(img, w.x, w.y), w.colour) << w.x << "," << w.y;
    EXPECT_EQ(dominant(img, w.x + 0.6 * w.rpx, w.y), w.colour);
    EXPECT_EQ(dominant(img, w.x, w.y - 0.6 * w.rpx), w.colour);
    EXPECT_TRUE(isWhite(img, w.x + w.rpx + 3, w.y));
    EXPECT_TRUE(isWhite(img, w.x, w.y + w.rpx + 3));
  }
  // The view agrees with the hand-computed projection.
  const View v = makeView(g.scene(), topView(false));
  const Vec3 p = v.project(Vec3(2, 0, 0));
  EXPECT_NEAR(p.x(), want[0].x, 1e-9);
  EXPECT_NEAR(p.y(), 100, 1e-9);
}

// A big red sphere behind a small blue one whose centre is nearer the eye: at x = 1.45 the red
// surface is nearer (z 1.377 against 0.857), at x = 1.95 the blue one is (0.977 against 0.444);
// the surfaces cross at x = 1.7345. Ordering by centres, or by draw order, gets one wrong.
TEST(RenderFrame, DepthIsPerPixelWhereSpheresOverlap) {
  for (bool redFirst : {true, false}) {
    Grains g;
    if (redFirst) g.add(Vec3(0, 0, 0), 2, red);
    g.add(Vec3(1.8, 0, 0.5), 0.5, blue);
    if (!redFirst) g.add(Vec3(0, 0, 0), 2, red);
    RenderOptions o = topView(true);
    o.outlineWidth = 0;
    const Image img = sharedRenderer().render(g.scene(), o);
    EXPECT_EQ(dominant(img, 100 + 20 * 1.45, 100), kRed) << redFirst;
    EXPECT_EQ(dominant(img, 100 + 20 * 1.95, 100), kBlue) << redFirst;
    EXPECT_EQ(dominant(img, 100 + 20 * 1.8, 100 - 20 * 0.3), kBlue) << redFirst;
    EXPECT_EQ(dominant(img, 100 + 20 * 1.4, 100 - 20 * 0.3), kRed) << redFirst;
  }
  // Perspective: a small sphere in front of a big one on the view axis.
  Grains g;
  g.add(Vec3(0, 0, 0), 2, red);
  g.add(Vec3(0, 0, 3), 0.5, blue);
  const Image img = sharedRenderer().render(g.scene(), topView(false));
  const double f = 1 / std::tan(M_PI / 6);
  EXPECT_EQ(dominant(img, 100, 100), kBlue);
  EXPECT_EQ(dominant(img, 100 + 100 * f * 1.2 / 10, 100), kRed);
}

TEST(RenderFrame, DiscsShowTheirRotationMark) {
  Grains g;
  g.add(Vec3(-1, 0, 0), 0.8, red, 2);
  g.add(Vec3(1, 0, 0), 0.8, green, 2);
  const std::vector<double> angles = {0.6, 0.6 + M_PI / 2};
  RenderScene s = g.scene(2);
  s.angles = angles;
  RenderOptions o = topView(true);
  o.camera.viewHeight = 4;  // 50 pixels per unit
  const Image img = sharedRenderer().render(s, o);
  for (int i = 0; i < 2; ++i) {
    const double cx = 100 + 50 * (i == 0 ? -1 : 1), cy = 100, a = angles[i], rr = 50 * 0.8;
    const int colour = i == 0 ? kRed : kGreen;
    for (double t : {0.3, 0.6, 0.85}) {
      // Along the mark: dark, not the disc's colour.
      EXPECT_EQ(dominant(img, cx + t * rr * std::cos(a), cy - t * rr * std::sin(a)), -1) << i << t;
      // Opposite and across the mark: the disc's colour.
      EXPECT_EQ(dominant(img, cx - t * rr * std::cos(a), cy + t * rr * std::sin(a)), colour);
      EXPECT_EQ(dominant(img, cx - t * rr * std::sin(a), cy - t * rr * std::cos(a)), colour);
    }
  }
  // Without angles there is no mark.
  s.angles = {};
  const Image plain = sharedRenderer().render(s, o);
  EXPECT_EQ(dominant(plain, 60 + 0.6 * 40 * std::cos(0.6), 100 - 0.6 * 40 * std::sin(0.6)), kRed);
}

TEST(RenderFrame, WallsAreDrawnWhereTheyAre) {
  RenderScene s;
  s.dim = 2;
  s.walls.push_back(RenderWall::segment(Vec3(-1.5, -1.5, 0), Vec3(1.5, -1.5, 0)));
  s.walls.push_back(RenderWall::drum(Vec3::Zero(), Vec3::UnitZ(), 1.8, 0));
  s.walls.push_back(RenderWall::plane(Vec3(0, 1, 0), Vec3(0, 1, 0)));
  for (auto& w : s.walls) w.colour = {0, 0, 1};
  RenderOptions o = topView(true);
  o.camera.viewHeight = 4;  // 50 pixels per unit
  o.wallWidth = 3;
  const Image img = sharedRenderer().render(s, o);
  EXPECT_EQ(dominant(img, 100, 100 + 75), kBlue);  // segment
  EXPECT_EQ(dominant(img, 60, 100 + 75), kBlue);
  EXPECT_TRUE(isWhite(img, 100 + 80, 100 + 75));   // beyond its end, inside the drum
  EXPECT_EQ(dominant(img, 100 + 90, 100), kBlue);  // drum
  EXPECT_EQ(dominant(img, 100 + 90 * std::cos(1), 100 - 90 * std::sin(1)), kBlue);
  EXPECT_EQ(dominant(img, 5, 50), kBlue);  // plane y = 1, across the frame
  EXPECT_EQ(dominant(img, 195, 50), kBlue);
  EXPECT_TRUE(isWhite(img, 100, 100));
  EXPECT_TRUE(isWhite(img, 100, 60));
}

TEST(RenderFrame, WallsIn3D) {
  RenderScene s;
  s.walls.push_back(RenderWall::box(Vec3(-2, -2, -1), Vec3(2, 2, 1)));
  s.walls.back().colour = {0, 0, 1};
  s.walls.push_back(RenderWall::plane(Vec3(0, 0, -0.5), Vec3(0, 0, 1)));
  s.walls.back().colour = {1, 0, 0};
  RenderOptions o = topView(true);  // 20 pixels per unit
  o.wallWidth = 3;
  o.wallAlpha = 0.5;
  const Image img = sharedRenderer().render(s, o);
  // Box edges x = +-2, y = +-2 seen from above.
  EXPECT_EQ(dominant(img, 140, 100), kBlue);
  EXPECT_EQ(dominant(img, 60, 70), kBlue);
  EXPECT_EQ(dominant(img, 100, 140), kBlue);
  // Inside: the translucent plane, half red over white, lit by the face shading.
  const auto p = img.pixel(100, 100);
  EXPECT_GT(p[0], 220);
  EXPECT_GT(p[1], 100);
  EXPECT_LT(p[1], 200);
  EXPECT_EQ(p[1], p[2]);
  // Outside the bounds (widened by 2% of their diagonal): background.
  EXPECT_TRUE(isWhite(img, 150, 100));
  EXPECT_TRUE(isWhite(img, 5, 5));
}

// A cube of half side h as 12 triangles, in its body frame.
std::vector<Vec3> cubeMesh(double h) {
  std::vector<Vec3> t;
  for (int axis = 0; axis < 3; ++axis) {
    for (double side : {-h, h}) {
      Vec3 c[4];
      for (int k = 0; k < 4; ++k) {
        c[k][axis] = side;
        c[k][(axis + 1) % 3] = (k == 1 || k == 2) ? h : -h;
        c[k][(axis + 2) % 3] = k >= 2 ? h : -h;
      }
      t.insert(t.end(), {c[0], c[1], c[2], c[0], c[2], c[3]});
    }
  }
  return t;
}

TEST(RenderFrame, MeshElementsAreDrawnTurnedWhereTheyAre) {
  Grains g;
  g.add(Vec3(-2, 0, 0), std::sqrt(3.0), red);  // a cube of half side 1, turned 45 degrees
  g.add(Vec3(2, 0, 0), 1, green);               // a ball beside it
  RenderScene s = g.scene();
  const std::vector<int32_t> meshOf{0, -1};
  const Quat q(AngleAxis(std::numbers::pi / 4, Vec3::UnitZ()));
  const std::vector<double> orientations{q.w(), q.x(), q.y(), q.z(), 1, 0, 0, 0};
  s.meshOf = meshOf;
  s.orientations = orientations;
  s.meshes = {cubeMesh(1)};
  const Image img = sharedRenderer().render(s, topView(true));  // 20 pixels per unit
  // The turned cube's top face is a diamond: its corners on the axes at sqrt(2) from the centre.
  EXPECT_EQ(dominant(img, 60, 100), kRed);
  EXPECT_EQ(dominant(img, 60 - 26, 100), kRed);
  EXPECT_EQ(dominant(img, 60, 100 - 26), kRed);
  // Inside its bounding ball but off the diamond: background, not a sphere.
  EXPECT_TRUE(isWhite(img, 60 - 22, 100 - 22));
  EXPECT_TRUE(isWhite(img, 60 - 31, 100));
  // The ball is drawn as a sphere.
  EXPECT_EQ(dominant(img, 140, 100), kGreen);
  EXPECT_TRUE(isWhite(img, 140 + 23, 100));
  // A bad mesh index is refused before drawing.
  const std::vector<int32_t> bad{1, -1};
  s.meshOf = bad;
  EXPECT_THROW(sharedRenderer().render(s, topView(true)), Error);
}

TEST(RenderFrame, ColourByFieldAndCategories) {
  Grains g;
  for (int i = 0; i < 3; ++i) g.add(Vec3(-1.2 + 1.2 * i, 0, 0), 0.5, red, 2);
  const std::vector<double> field = {0, 1, 2};
  RenderScene s = g.scene(2);
  s.field = field;
  RenderOptions o = topView(true);
  o.camera.viewHeight = 4;
  o.legend = false;
  o.colourMap = ColourMap::categorical;
  Image img = sharedRenderer().render(s, o);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(isColour(img, 100 - 60 + 60 * i, 100, categorical(i)));
  o.colourMap = ColourMap::viridis;
  img = sharedRenderer().render(s, o);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(isColour(img, 100 - 60 + 60 * i, 100, viridis(i / 2.0)));
  o.fieldMin = 0;
  o.fieldMax = 4;
  img = sharedRenderer().render(s, o);
  EXPECT_TRUE(isColour(img, 160, 100, viridis(0.5)));
}

// Returns the number of pixels in the rectangle that are exactly colour c.
int countColour(const Image& img, int x0, int y0, int x1, int y1, const Rgb& c) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) n += isColour(img, x, y, c, 0);
  return n;
}

TEST(RenderFrame, TimeStampAndLegend) {
  Grains g;
  g.add(Vec3(-1, 0, 0), 0.3, red);
  const std::vector<double> field = {2.5};
  RenderScene s = g.scene();
  RenderOptions o;
  o.width = 400;
  o.height = 300;
  const Image none = sharedRenderer().render(s, o);
  s.time = 0.125;
  s.field = field;
  o.fieldMin = 0;
  o.fieldMax = 5;
  const Image both = sharedRenderer().render(s, o);
  // The stamp: dark (antialiased) text in the top-left corner only when there is a time.
  auto dark = [](const Image& img) {
    int n = 0;
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 120; ++x) {
        const auto p = img.pixel(x, y);
        n += p[0] < 100 && p[1] < 100 && p[2] < 100;
      }
    return n;
  };
  EXPECT_EQ(dark(none), 0);
  EXPECT_GT(dark(both), 40);
  // The legend: a viridis bar at the right edge, its top the map's top colour, its bottom the
  // map's bottom colour.
  int top = -1, bottom = -1;
  for (int y = 0; y < o.height; ++y)
    for (int x = o.width * 3 / 4; x < o.width; ++x) {
      if (top < 0 && isColour(both, x, y, viridis(1), 0)) top = y;
      if (isColour(both, x, y, viridis(0), 0)) bottom = y;
    }
  EXPECT_GE(top, 0);
  EXPECT_GT(bottom, top + 50);
  EXPECT_EQ(countColour(none, o.width * 3 / 4, 0, o.width, o.height, viridis(1)), 0);
}

TEST(RenderFrame, SupersamplingSmoothsEdges) {
  Grains g;
  g.add(Vec3(0, 0, 0), 1.3, red, 2);
  RenderOptions o = topView(true);
  o.outlineWidth = 0;
  auto mixed = [&](int aa) {
    o.antialias = aa;
    const Image img = sharedRenderer().render(g.scene(2), o);
    int n = 0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const auto p = img.pixel(x, y);
        n += p[0] == 255 && p[1] > 10 && p[1] < 245;  // between red and white
      }
    return n;
  };
  EXPECT_EQ(mixed(1), 0);
  EXPECT_GT(mixed(4), 80);  // the rim, about 2 pi 26 pixels long
}

TEST(RenderFrame, AutomaticFramingShowsEveryGrain) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-50, 50);
  Grains g;
  for (int i = 0; i < 40; ++i) g.add(Vec3(u(rng), 0.3 * u(rng), 0), 1.0, i % 2 ? red : green, 2);
  // Keep only discs that do not overlap, so each one's centre shows its colour.
  Grains apart;
  for (size_t i = 0; i < g.radii.size(); ++i) {
    bool clear = true;
    for (size_t j = 0; j < g.radii.size(); ++j)
      if (j != i && std::hypot(g.centres[2 * i] - g.centres[2 * j],
                               g.centres[2 * i + 1] - g.centres[2 * j + 1]) < 2.2)
        clear = false;
    if (clear)
      apart.add(Vec3(g.centres[2 * i], g.centres[2 * i + 1], 0), 1.0,
                apart.radii.size() % 2 ? green : red, 2);
  }
  ASSERT_GT(apart.radii.size(), 20u);
  RenderOptions o;
  o.width = 640;
  o.height = 360;
  const RenderScene s = apart.scene(2);
  const Image img = sharedRenderer().render(s, o);
  const View v = makeView(s, o);
  for (size_t i = 0; i < s.size(); ++i) {
    const Vec3 p = v.project(grainCentre(s, i));
    ASSERT_TRUE(p.x() > 0 && p.x() < o.width && p.y() > 0 && p.y() < o.height);
    EXPECT_EQ(dominant(img, p.x(), p.y()), i % 2 == 0 ? kRed : kGreen) << i;
  }
  // 3D: nothing touches the frame's border.
  Grains h;
  for (int i = 0; i < 200; ++i) h.add(Vec3(u(rng), u(rng), 0.2 * u(rng)), 2.0, blue);
  const Image img3 = sharedRenderer().render(h.scene(), o);
  int touched = 0;
  for (int x = 0; x < o.width; ++x)
    touched += !isWhite(img3, x, 0) + !isWhite(img3, x, o.height - 1);
  for (int y = 0; y < o.height; ++y)
    touched += !isWhite(img3, 0, y) + !isWhite(img3, o.width - 1, y);
  EXPECT_EQ(touched, 0);
}

// Occlusion culling changes no pixel, and on a dense packing it removes most grains.
TEST(RenderFrame, CullingKeepsTheImage) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 20), rad(0.4, 0.9);
  Grains g;
  for (int i = 0; i < 6000; ++i)
    g.add(Vec3(u(rng), u(rng), u(rng)), rad(rng), {float(u(rng) / 20), 0.5f, 0.3f});
  for (bool ortho : {false, true}) {
    RenderOptions o;
    o.width = 320;
    o.height = 240;
    o.antialias = 1;
    o.camera.orthographic = ortho;
    const RenderScene s = g.scene();
    std::vector<std::uint32_t> keep;
    cullHiddenGrains(s, makeView(s, o), keep);
    EXPECT_LT(keep.size(), s.size() / 2) << ortho;
    const Image culled = sharedRenderer().render(s, o);
    o.cullHidden = false;
    const Image full = sharedRenderer().render(s, o);
    EXPECT_TRUE(culled.rgba == full.rgba) << ortho;
  }
}

// Drawn in strips of a few rows (the framebuffer one strip tall, the viewport shifted), a frame
// must be pixel for pixel the frame drawn in one piece: grains in perspective and from above,
// a mesh, translucent walls and force chains, with strips that do not divide the height.
TEST(RenderFrame, StripsGiveTheImageOfOnePiece) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-3, 3), rad(0.2, 0.6);
  for (int dim : {2, 3}) {
    Grains g;
    for (int i = 0; i < 300; ++i)
      g.add(Vec3(u(rng), u(rng), dim == 3 ? u(rng) : 0), rad(rng),
            {float(u(rng) / 6 + 0.5), 0.4f, 0.7f}, dim);
    RenderScene s = g.scene(dim);
    s.walls.push_back(RenderWall::drum(Vec3::Zero(), Vec3::UnitZ(), 4, dim == 3 ? 3 : 0));
    s.walls.back().colour = {0, 0, 1};
    s.chains.push_back({0, 1, 1.0});
    s.chains.push_back({2, 3, 0.5});
    std::vector<int32_t> meshOf(g.radii.size(), -1);
    std::vector<double> orientations;
    for (size_t i = 0; i < g.radii.size(); ++i) orientations.insert(orientations.end(), {1, 0, 0, 0});
    if (dim == 3) {
      meshOf[0] = 0;
      s.meshOf = meshOf;
      s.orientations = orientations;
      s.meshes = {cubeMesh(0.3)};
    }
    for (bool ortho : {false, true}) {
      RenderOptions o;
      o.width = 203;
      o.height = 157;
      o.antialias = 2;
      o.camera.orthographic = ortho;
      const Image whole = sharedRenderer().render(s, o);
      for (long strip : {1L, 406L * 37, 406L * 100}) {
        o.stripPixels = strip;
        const Image strips = sharedRenderer().render(s, o);
        EXPECT_TRUE(strips.rgba == whole.rgba) << dim << " " << ortho << " " << strip;
      }
      // Grains cover much of the frame: the comparison has something to compare.
      int drawn = 0;
      for (int y = 0; y < whole.height; ++y)
        for (int x = 0; x < whole.width; ++x) drawn += isWhite(whole, x, y) ? 0 : 1;
      EXPECT_GT(drawn, whole.width * whole.height / 8) << dim << " " << ortho;
    }
  }
}

}  // namespace render_frame_test
}  // namespace demlab::render
