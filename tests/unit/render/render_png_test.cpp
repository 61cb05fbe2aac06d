// PNG writing: round trip through libpng, atomic replacement, errors for bad paths.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "render/png.hpp"
#include "render_support.hpp"

namespace demlab::render {
namespace render_png_test {

using test::errorCode;
using test::sharedRenderer;
using test::TempDir;

TEST(RenderPng, RoundTripOfARenderedFrame) {
  std::vector<double> c = {0, 0, 0, 1, 0.5, 0}, r = {0.5, 0.3};
  RenderScene s;
  s.centres = c;
  s.radii = r;
  s.time = 1.5;
  RenderOptions o;
  o.width = 123;  // odd sizes catch row-stride mistakes
  o.height = 77;
  const Image img = sharedRenderer().render(s, o);
  TempDir dir;
  const std::string path = dir.path + "/frame.png";
  writePng(img, path);
  const Image back = readPng(path);
  EXPECT_EQ(back.width, 123);
  EXPECT_EQ(back.height, 77);
  EXPECT_TRUE(back.rgba == img.rgba);
  EXPECT_EQ(dir.files(), std::vector<std::string>{"frame.png"});  // no temporary left
  // Rewriting replaces the file whole.
  Image other(5, 3);
  for (size_t i = 0; i < other.rgba.size(); ++i) other.rgba[i] = std::uint8_t(i * 7);
  writePng(other, path);
  EXPECT_TRUE(readPng(path).rgba == other.rgba);
  renderPng(sharedRenderer(), s, o, path);
  EXPECT_TRUE(readPng(path).rgba == img.rgba);
}

TEST(RenderPng, BadPathsAreErrors) {
  Image img(4, 4);
  TempDir dir;
  EXPECT_EQ(errorCode([&] { writePng(img, dir.path + "/no/such/folder/a.png"); }), "DEMLAB IO PNG");
  // A folder in the way: the rename fails and the temporary is removed.
  mkdir((dir.path + "/sub").c_str(), 0700);
  EXPECT_EQ(errorCode([&] { writePng(img, dir.path + "/sub"); }), "DEMLAB IO PNG");
  EXPECT_EQ(dir.files(), std::vector<std::string>{"sub"});
  rmdir((dir.path + "/sub").c_str());
  try {
    writePng(img, "/nonexistent_dir_demlab/x.png");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "couldn't open \"/nonexistent_dir_demlab/x.png\" for writing: no such file or directory");
  }
  // Reading: missing file, not a PNG.
  EXPECT_EQ(errorCode([&] { readPng(dir.path + "/missing.png"); }), "DEMLAB IO PNG");
  const std::string junk = dir.path + "/junk.png";
  std::ofstream(junk) << "this is not a png file at all";
  EXPECT_EQ(errorCode([&] { readPng(junk); }), "DEMLAB IO PNG");
  // An image whose buffer does not match its size.
  Image bad(4, 4);
  bad.rgba.pop_back();
  EXPECT_EQ(errorCode([&] { writePng(bad, dir.path + "/bad.png"); }), "DEMLAB VALUE IMAGE");
}

}  // namespace render_png_test
}  // namespace demlab::render
