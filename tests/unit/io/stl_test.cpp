// Tests of the STL reader (src/io/stl.hpp): ASCII and binary files read back exactly, and every
// malformed case it promises to name.
#include "io/stl.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace demlab::io {
namespace stl_test {

namespace fs = std::filesystem;

class StlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("demlab_stl_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name, const std::string& text) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // Returns the code and message of what readStl(p) throws ("no error" if nothing).
  static std::pair<std::vector<std::string>, std::string> failure(const std::string& p) {
    try {
      readStl(p);
    } catch (const Error& e) {
      return {e.code(), e.what()};
    }
    return {{}, "no error"};
  }
  fs::path dir_;
};

std::vector<std::array<double, 9>> randomTriangles(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-10, 10);
  std::vector<std::array<double, 9>> t(n);
  for (auto& x : t)
    for (double& c : x) c = u(rng);  // floats: what a binary file holds exactly
  return t;
}

TEST_F(StlTest, AsciiAndBinaryReadBackExactly) {
  const auto tris = randomTriangles(300, 3);
  writeStlAscii(path("a.stl"), tris, "part");
  const StlMesh a = readStl(path("a.stl"));
  EXPECT_FALSE(a.binary);
  EXPECT_EQ(a.triangles, tris);
  // The same triangles as a binary file, written here by the format's definition.
  std::string bin(80, ' ');
  const uint32_t n = static_cast<uint32_t>(tris.size());
  bin.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : tris) {
    float rec[12] = {};
    for (int k = 0; k < 9; ++k) rec[3 + k] = static_cast<float>(t[k]);
    bin.append(reinterpret_cast<const char*>(rec), 48);
    bin.append(2, '\0');
  }
  const StlMesh b = readStl(file("b.stl", bin));
  EXPECT_TRUE(b.binary);
  EXPECT_EQ(b.triangles, tris);
  // Two solids in one ASCII file, blank lines and indentation anywhere.
  const StlMesh two = readStl(file("two.stl",
      "solid a\n facet normal 0 0 1\n  outer loop\n\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n"
      "  endloop\n endfacet\nendsolid a\nsolid b\nfacet normal 0 0 0\nouter loop\nvertex 0 0 1\n"
      "vertex 1 0 1\nvertex 0 1 1\nendloop\nendfacet\nendsolid\n"));
  ASSERT_EQ(two.triangles.size(), 2u);
  EXPECT_EQ(two.triangles[1][2], 1.0);
}

TEST_F(StlTest, MalformedFilesAreNamed) {
  const std::string facet = "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  const struct {
    std::string text, code, words;
  } cases[] = {
      {"", "FORMAT", "neither a binary STL nor an ASCII one"},
      {"hello\n", "FORMAT", "bad line \"hello\""},
      {"solid x\n" + facet, "TRUNCATED", "ends inside a solid"},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n",
       "FORMAT", "2 vertices, a triangle has three"},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 nan\n", "NUMBER", "bad coordinate \"nan\""},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 1e999\n", "NUMBER", "bad coordinate \"1e999\""},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n", "FORMAT", "expected \"vertex x y z\""},
      {"solid x\nfacet 0 0 1\n", "FORMAT", "expected \"facet normal nx ny nz\""},
  };
  int k = 0;
  for (const auto& c : cases) {
    const std::string p = file("bad" + std::to_string(k++) + ".stl", c.text);
    const auto [code, message] = failure(p);
    ASSERT_GE(code.size(), 3u) << message;
    EXPECT_EQ(code[2], c.code) << message;
    EXPECT_NE(message.find(c.words), std::string::npos) << message;
    EXPECT_NE(message.find("file \"" + p + "\""), std::string::npos) << message;
  }
  EXPECT_EQ(failure(path("missing.stl")).first, (std::vector<std::string>{"DEMLAB", "IO", "OPEN"}));
  // A binary header claiming more triangles than the limit, its size made to match: refused
  // before anything is allocated for them.
  {
    std::string bin(80, ' ');
    const uint32_t n = kMaxStlTriangles + 1;
    bin.append(reinterpret_cast<const char*>(&n), 4);
    const std::string p = file("huge.stl", bin);
    fs::resize_file(p, 84 + 50 * uint64_t{n});
    EXPECT_EQ(failure(p).first, (std::vector<std::string>{"DEMLAB", "LIMIT", "TRIANGLES"}));
  }
  // A binary file with an infinite coordinate.
  {
    std::string bin(80, ' ');
    const uint32_t n = 1;
    bin.append(reinterpret_cast<const char*>(&n), 4);
    float rec[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, INFINITY, 0};
    bin.append(reinterpret_cast<const char*>(rec), 48);
    bin.append(2, '\0');
    const auto [code, message] = failure(file("inf.stl", bin));
    EXPECT_EQ(code, (std::vector<std::string>{"DEMLAB", "VALUE", "NUMBER"})) << message;
  }
}

}  // namespace stl_test
}  // namespace demlab::io
