// Force chains: a line between the centres of touching grains, drawn over them, wider and
// darker the larger the force; a bad link is refused before drawing.
#include <vector>

#include "render/colour_map.hpp"
#include "render_support.hpp"

namespace demlab::render {
namespace render_chains_test {

using test::dominant;
using test::errorCode;
using test::sharedRenderer;

TEST(RenderChains, DrawnBetweenCentresOverTheGrains) {
  // Three green spheres in a row along x, touching; seen from +z, 20 pixels a unit.
  std::vector<double> c = {-2, 0, 0, 0, 0, 0, 2, 0, 0}, r = {1, 1, 1};
  std::vector<float> green = {0, 1, 0, 0, 1, 0, 0, 1, 0};
  RenderScene s;
  s.centres = c;
  s.radii = r;
  s.colours = green;
  RenderOptions o = test::topView(true);
  const Image plain = sharedRenderer().render(s, o);
  s.chains = {{0, 1, 10.0}, {1, 2, 2.0}};
  const Image chained = sharedRenderer().render(s, o);
  // On the line y = 0 between the centres (x pixels 60..140; the spheres touch at 80 and
  // 120): chain red over the green spheres.
  EXPECT_EQ(dominant(plain, 70, 100), 1);
  EXPECT_EQ(dominant(chained, 70, 100), 0);
  EXPECT_EQ(dominant(chained, 130, 100), 0);
  // Off the line: the spheres as before.
  EXPECT_EQ(chained.pixel(70, 110), plain.pixel(70, 110));
  // The strong chain is wider than the weak one and darker.
  auto width = [&](int x) {
    int n = 0;
    for (int y = 90; y < 110; ++y) n += dominant(chained, x, y) == 0;
    return n;
  };
  EXPECT_GT(width(70), width(130));
  EXPECT_LT(chained.pixel(70, 100)[0], chained.pixel(130, 100)[0]);
  // A link to a grain that is not there is refused.
  s.chains = {{0, 3, 1.0}};
  EXPECT_EQ(errorCode([&] { sharedRenderer().render(s, o); }), "DEMLAB VALUE CHAIN");
}

}  // namespace render_chains_test
}  // namespace demlab::render
