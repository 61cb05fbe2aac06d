// Bad scenes and options are rejected before any drawing, with DEMLAB VALUE codes and messages
// in Tcl's wording.
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "render_support.hpp"

namespace demlab::render {
namespace render_options_test {

using test::errorCode;
using test::sharedRenderer;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(RenderOptions, DefaultsAreValid) {
  EXPECT_NO_THROW(checkOptions(RenderOptions{}));
  EXPECT_NO_THROW(checkScene(RenderScene{}));
}

TEST(RenderOptions, BadOptionsAreRejected) {
  const struct {
    std::function<void(RenderOptions&)> change;
    const char* code;
  } cases[] = {
      {[](RenderOptions& o) { o.width = 0; }, "DEMLAB VALUE SIZE"},
      {[](RenderOptions& o) { o.height = -5; }, "DEMLAB VALUE SIZE"},
      {[](RenderOptions& o) { o.width = kMaxImageSize + 1; }, "DEMLAB VALUE SIZE"},
      {[](RenderOptions& o) { o.width = 5000, o.antialias = 4; }, "DEMLAB VALUE SIZE"},
      {[](RenderOptions& o) { o.antialias = 0; }, "DEMLAB VALUE ANTIALIAS"},
      {[](RenderOptions& o) { o.antialias = 5; }, "DEMLAB VALUE ANTIALIAS"},
      {[](RenderOptions& o) {
         o.background = {1.5f, 0, 0};
       },
       "DEMLAB VALUE COLOUR"},
      {[](RenderOptions& o) {
         o.outlineColour = {0, float(kNaN), 0};
       },
       "DEMLAB VALUE COLOUR"},
      {[](RenderOptions& o) { o.camera.fov = 0; }, "DEMLAB VALUE FOV"},
      {[](RenderOptions& o) { o.camera.fov = 180; }, "DEMLAB VALUE FOV"},
      {[](RenderOptions& o) { o.camera.fov = kNaN; }, "DEMLAB VALUE FOV"},
      {[](RenderOptions& o) { o.camera.automatic = false, o.camera.position = o.camera.lookAt; },
       "DEMLAB VALUE CAMERA"},
      {[](RenderOptions& o) { o.camera.up = Vec3::Zero(); }, "DEMLAB VALUE CAMERA"},
      {[](RenderOptions& o) { o.camera.up = o.camera.direction * 2; }, "DEMLAB VALUE CAMERA"},
      {[](RenderOptions& o) { o.camera.direction = Vec3::Zero(); }, "DEMLAB VALUE CAMERA"},
      {[](RenderOptions& o) { o.camera.lookAt = Vec3(kInf, 0, 0); }, "DEMLAB VALUE CAMERA"},
      {[](RenderOptions& o) { o.camera.viewHeight = -1; }, "DEMLAB VALUE CAMERA"},
      {[](RenderOptions& o) { o.fieldMin = 2, o.fieldMax = 1; }, "DEMLAB VALUE RANGE"},
      {[](RenderOptions& o) { o.fieldMax = kInf; }, "DEMLAB VALUE RANGE"},
      {[](RenderOptions& o) { o.outlineWidth = -1; }, "DEMLAB VALUE OUTLINE"},
      {[](RenderOptions& o) { o.wallWidth = 0; }, "DEMLAB VALUE WIDTH"},
      {[](RenderOptions& o) { o.wallAlpha = 2; }, "DEMLAB VALUE COLOUR"},
  };
  std::vector<double> c = {0, 0, 0}, r = {1};
  RenderScene s;
  s.centres = c;
  s.radii = r;
  for (const auto& k : cases) {
    RenderOptions o;
    k.change(o);
    EXPECT_EQ(errorCode([&] { checkOptions(o); }), k.code);
    EXPECT_EQ(errorCode([&] { sharedRenderer().render(s, o); }), k.code);
  }
}

TEST(RenderOptions, MessagesUseTclWording) {
  RenderOptions o;
  o.width = 0;
  o.height = 600;
  try {
    checkOptions(o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "bad size \"0x600\": must be two positive integers up to 16384");
  }
  std::vector<double> c = {0, 0, 0, 1, 1, 1}, r = {1, -1};
  RenderScene s;
  s.centres = c;
  s.radii = r;
  try {
    checkScene(s);
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "bad radius \"-1\" for grain 1: must be a positive number");
  }
}

TEST(RenderOptions, BadScenesAreRejected) {
  std::vector<double> c3 = {0, 0, 0, 1, 1, 1}, r2 = {1, 1}, one = {1};
  std::vector<double> nanc = {0, kNaN, 0, 1, 1, 1}, inff = {0, kInf};
  std::vector<float> col = {0, 0, 0, 1, 1, 2}, shortCol = {0, 0, 0};
  auto base = [&] {
    RenderScene s;
    s.centres = c3;
    s.radii = r2;
    return s;
  };
  const struct {
    std::function<void(RenderScene&)> change;
    const char* code;
  } cases[] = {
      {[&](RenderScene& s) { s.dim = 4; }, "DEMLAB VALUE DIMENSION"},
      {[&](RenderScene& s) { s.dim = 2; }, "DEMLAB VALUE LENGTH"},  // 6 numbers for 2 discs
      {[&](RenderScene& s) { s.radii = one; }, "DEMLAB VALUE LENGTH"},
      {[&](RenderScene& s) { s.centres = nanc; }, "DEMLAB VALUE POSITION"},
      {[&](RenderScene& s) { s.colours = col; }, "DEMLAB VALUE COLOUR"},
      {[&](RenderScene& s) { s.colours = shortCol; }, "DEMLAB VALUE LENGTH"},
      {[&](RenderScene& s) { s.field = inff; }, "DEMLAB VALUE FIELD"},
      {[&](RenderScene& s) { s.field = one; }, "DEMLAB VALUE LENGTH"},
      {[&](RenderScene& s) { s.angles = inff; }, "DEMLAB VALUE ANGLE"},
      {[&](RenderScene& s) { s.time = kInf; }, "DEMLAB VALUE TIME"},
      {[&](RenderScene& s) { s.walls.push_back(RenderWall::plane(Vec3::Zero(), Vec3::Zero())); },
       "DEMLAB VALUE WALL"},
      {[&](RenderScene& s) { s.walls.push_back(RenderWall::segment(Vec3::Ones(), Vec3::Ones())); },
       "DEMLAB VALUE WALL"},
      {[&](RenderScene& s) {
         s.walls.push_back(RenderWall::rectangle(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitX()));
       },
       "DEMLAB VALUE WALL"},
      {[&](RenderScene& s) { s.walls.push_back(RenderWall::box(Vec3::Ones(), Vec3::Zero())); },
       "DEMLAB VALUE WALL"},
      {[&](RenderScene& s) {
         s.walls.push_back(RenderWall::drum(Vec3::Zero(), Vec3::UnitZ(), -1, 1));
       },
       "DEMLAB VALUE WALL"},
      {[&](RenderScene& s) {
         s.walls.push_back(RenderWall::drum(Vec3::Zero(), Vec3::UnitZ(), 1, 0));
       },
       "DEMLAB VALUE WALL"},
      {[&](RenderScene& s) {
         RenderWall w = RenderWall::segment(Vec3::Zero(), Vec3::Ones());
         w.colour = {0, 2, 0};
         s.walls.push_back(w);
       },
       "DEMLAB VALUE WALL"},
  };
  for (const auto& k : cases) {
    RenderScene s = base();
    k.change(s);
    EXPECT_EQ(errorCode([&] { checkScene(s); }), k.code);
    EXPECT_EQ(errorCode([&] { sharedRenderer().render(s, RenderOptions{}); }), k.code);
  }
  // A 2D drum needs no length; a 3D one does.
  RenderScene s = base();
  s.dim = 2;
  std::vector<double> c2 = {0, 0, 1, 1};
  s.centres = c2;
  s.walls.push_back(RenderWall::drum(Vec3::Zero(), Vec3::UnitZ(), 1, 0));
  EXPECT_NO_THROW(checkScene(s));
}

}  // namespace render_options_test
}  // namespace demlab::render
