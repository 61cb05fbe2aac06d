// JPEG writing: the file starts and ends with the SOI and EOI markers, decodes through libjpeg
// to the right size and nearly the right colours, is replaced atomically, and bad qualities or
// paths are errors that leave no file.
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "render/image_file.hpp"
#include "render/jpeg.hpp"
#include "render/png.hpp"
#include "render_support.hpp"

namespace demlab::render {
namespace render_jpeg_test {

using test::errorCode;
using test::TempDir;

std::vector<unsigned char> bytesOf(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// Returns the largest difference of any channel of any pixel between a and b (same size).
int largestDifference(const Image& a, const Image& b) {
  int d = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) d = std::max(d, std::abs(int(a.rgba[i]) - int(b.rgba[i])));
  return d;
}

// Returns the mean difference per channel between a and b (same size).
double meanDifference(const Image& a, const Image& b) {
  double d = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) d += std::abs(int(a.rgba[i]) - int(b.rgba[i]));
  return d / double(a.rgba.size());
}

TEST(RenderJpeg, DecodesToTheFrameWritten) {
  const Image img = test::oddSizedFrame();
  TempDir dir;
  const std::string path = dir.path + "/frame.jpg";
  writeJpeg(img, path, 95);
  const auto bytes = bytesOf(path);
  ASSERT_GT(bytes.size(), 4u);
  EXPECT_EQ(bytes[0], 0xFF);  // SOI
  EXPECT_EQ(bytes[1], 0xD8);
  EXPECT_EQ(bytes[bytes.size() - 2], 0xFF);  // EOI
  EXPECT_EQ(bytes[bytes.size() - 1], 0xD9);
  const Image back = readJpeg(path);
  EXPECT_EQ(back.width, 123);
  EXPECT_EQ(back.height, 77);
  EXPECT_LT(meanDifference(back, img), 3.0);
  EXPECT_EQ(dir.files(), std::vector<std::string>{"frame.jpg"});  // no temporary left
  // readImage tells the formats apart by their first bytes, whatever the name.
  EXPECT_EQ(readImage(path).rgba, back.rgba);
  writePng(img, dir.path + "/frame.png");
  EXPECT_EQ(readImage(dir.path + "/frame.png").rgba, img.rgba);
  // A lower quality makes a smaller file that still decodes to the same size.
  writeJpeg(img, path, 20);
  EXPECT_LT(bytesOf(path).size(), bytes.size());
  const Image rough = readJpeg(path);
  EXPECT_EQ(rough.width, 123);
  EXPECT_GT(largestDifference(rough, img), 0);
}

TEST(RenderJpeg, BadQualityPathOrFileIsAnError) {
  Image img(8, 8);
  TempDir dir;
  for (int q : {0, 101, -5})
    EXPECT_EQ(errorCode([&] { writeJpeg(img, dir.path + "/q.jpg", q); }), "DEMLAB VALUE QUALITY");
  EXPECT_EQ(errorCode([&] { writeJpeg(img, dir.path + "/no/such/folder/a.jpg"); }),
            "DEMLAB IO JPEG");
  EXPECT_TRUE(dir.files().empty());
  EXPECT_EQ(errorCode([&] { readJpeg(dir.path + "/missing.jpg"); }), "DEMLAB IO JPEG");
  const std::string junk = dir.path + "/junk.jpg";
  std::ofstream(junk, std::ios::binary) << "\xFF\xD8 this is not a jpeg";
  EXPECT_EQ(errorCode([&] { readJpeg(junk); }), "DEMLAB IO JPEG");
  EXPECT_EQ(errorCode([&] { readImage(junk); }), "DEMLAB IO JPEG");
}

}  // namespace render_jpeg_test
}  // namespace demlab::render
