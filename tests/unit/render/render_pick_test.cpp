// Picking (render/pick.hpp) against the picture itself: random scenes of spheres, discs and
// meshes, each grain one of three pure colours, drawn by the renderer and picked pixel by
// pixel. Where a pick names a grain the pixel shows that grain's colour; where it names none
// the pixel is background. Pixels on a silhouette (the pick changes within one pixel) are left
// out: there the two can differ by rasterisation alone.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "render/pick.hpp"
#include "render_support.hpp"

namespace demlab::render::test {
namespace render_pick_test {

struct Grains {
  std::vector<double> centres, radii, angles, orientations;
  std::vector<float> colours;
  std::vector<int32_t> meshOf;
  std::vector<int> cls;  // the colour of each grain: 0 red, 1 green, 2 blue
};

// Returns n random grains in [-2, 2]^dim, radii 0.2 to 0.6, each one pure colour.
Grains randomGrains(int dim, int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> pos(-2, 2), rad(0.2, 0.6), ang(0, 6.283);
  Grains g;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < dim; ++k) g.centres.push_back(pos(rng));
    g.radii.push_back(rad(rng));
    g.cls.push_back(i % 3);
    for (int k = 0; k < 3; ++k) g.colours.push_back(k == i % 3 ? 1.0f : 0.0f);
    g.angles.push_back(ang(rng));
    const Eigen::Quaterniond q = Eigen::Quaterniond::UnitRandom();
    g.orientations.insert(g.orientations.end(), {q.w(), q.x(), q.y(), q.z()});
  }
  return g;
}

RenderScene sceneOf(const Grains& g, int dim) {
  RenderScene s;
  s.dim = dim;
  s.centres = g.centres;
  s.radii = g.radii;
  s.colours = g.colours;
  if (dim == 2) s.angles = g.angles;
  return s;
}

// Returns the number of pixels compared; fails the test at the first disagreement.
int comparePicks(const RenderScene& s, const RenderOptions& o, const std::vector<int>& cls) {
  const Image img = sharedRenderer().render(s, o);
  auto pick = [&](int x, int y) { return pickGrain(s, o, x, y); };
  int compared = 0;
  // The header and legend strips show text, not grains: only the scene part is compared.
  const FrameView fv = frameView(s, o);
  for (int y = fv.y0 + 1; y < fv.y0 + fv.view.height - 1; y += 3) {
    for (int x = fv.x0 + 1; x < fv.x0 + fv.view.width - 1; x += 3) {
      const long id = pick(x, y);
      if (id != pick(x - 1, y) || id != pick(x + 1, y) || id != pick(x, y - 1) ||
          id != pick(x, y + 1))
        continue;
      const auto p = img.pixel(x, y);
      const bool background = p[0] == 255 && p[1] == 255 && p[2] == 255;
      if (id < 0) {
        EXPECT_TRUE(background) << "pixel " << x << "," << y << " shows a grain, pick none";
        if (!background) return compared;
      } else {
        EXPECT_FALSE(background) << "pixel " << x << "," << y << " is background, pick " << id;
        const int d = dominant(img, x, y);
        if (d >= 0) {
          EXPECT_EQ(d, cls[size_t(id)]) << "pixel " << x << "," << y;
        }
        if (background || (d >= 0 && d != cls[size_t(id)])) return compared;
      }
      ++compared;
    }
  }
  return compared;
}

TEST(RenderPick, SpheresInRandomViewsAgreeWithThePicture) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> dir(-1, 1);
  for (int trial = 0; trial < 6; ++trial) {
    const Grains g = randomGrains(3, 25, rng);
    const RenderScene s = sceneOf(g, 3);
    RenderOptions o;
    o.width = 160;
    o.height = 120;
    o.antialias = 1;
    o.outlineWidth = 0;
    o.legend = false;
    o.camera.orthographic = trial % 2 == 1;
    if (trial >= 2) {
      o.camera.automatic = false;
      o.camera.position = Vec3(dir(rng), dir(rng), dir(rng)).normalized() * 12;
      o.camera.lookAt = Vec3(dir(rng), dir(rng), dir(rng));
      o.camera.viewHeight = 7;
    }
    EXPECT_GT(comparePicks(s, o, g.cls), 1000) << "trial " << trial;
  }
}

TEST(RenderPick, DiscsUnderATitleStripAgreeWithThePicture) {
  std::mt19937 rng(12);
  const Grains g = randomGrains(2, 20, rng);
  RenderScene s = sceneOf(g, 2);
  s.title = "a title shifts the scene down";
  RenderOptions o;
  o.width = 150;
  o.height = 130;
  o.antialias = 1;
  o.outlineWidth = 0;
  EXPECT_GT(frameView(s, o).y0, 0);
  EXPECT_GT(comparePicks(s, o, g.cls), 1000);
  // The title strip itself shows no grain.
  EXPECT_EQ(pickGrain(s, o, 75, 2), -1);
}

TEST(RenderPick, MeshesArePickedByTheirTrianglesNotTheirBoundingSphere) {
  // Unit cubes (12 triangles), turned at random, in 3D; bounding radius sqrt(3)/2.
  std::vector<Vec3> cube;
  const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  auto corner = [](int k) {
    return Vec3(k & 1 ? 0.5 : -0.5, k & 2 ? 0.5 : -0.5, k & 4 ? 0.5 : -0.5);
  };
  for (const auto& f : faces) {  // each face a loop of corners: triangles (0 1 2), (0 2 3)
    for (int t : {1, 2}) {
      cube.push_back(corner(f[0]));
      cube.push_back(corner(f[t]));
      cube.push_back(corner(f[t + 1]));
    }
  }
  std::mt19937 rng(13);
  Grains g = randomGrains(3, 12, rng);
  for (double& r : g.radii) r = std::sqrt(3.0) / 2;
  g.meshOf.assign(12, 0);
  RenderScene s = sceneOf(g, 3);
  s.meshes.push_back(cube);
  s.meshOf = g.meshOf;
  s.orientations = g.orientations;
  RenderOptions o;
  o.width = 160;
  o.height = 120;
  o.antialias = 1;
  o.outlineWidth = 0;
  o.camera.orthographic = true;
  EXPECT_GT(comparePicks(s, o, g.cls), 800);
  // A lone cube seen face on: a pixel inside its bounding sphere's disc but off the cube.
  Grains one;
  one.centres = {0, 0, 0};
  one.radii = {std::sqrt(3.0) / 2};
  one.colours = {1, 0, 0};
  one.orientations = {1, 0, 0, 0};
  one.meshOf = {0};
  RenderScene lone = sceneOf(one, 3);
  lone.meshes.push_back(cube);
  lone.meshOf = one.meshOf;
  lone.orientations = one.orientations;
  RenderOptions front = topView(true);  // 20 pixels per unit, centre at pixel 100
  front.camera.viewHeight = 10;
  front.legend = false;
  EXPECT_EQ(pickGrain(lone, front, 100, 100), 0);
  EXPECT_EQ(pickGrain(lone, front, 108, 108), 0);   // inside the face (half-width 10 px)
  EXPECT_EQ(pickGrain(lone, front, 115, 100), -1);  // off the face, inside the sphere's 17 px
}

}  // namespace render_pick_test
}  // namespace demlab::render::test
