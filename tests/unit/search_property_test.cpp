// Every algorithm in the registry against the brute-force oracle, on randomized inputs for
// D = 1..4: the reported pair sets must be identical, each pair exactly once.
#include <gtest/gtest.h>

#include <random>

#include "search/brute_force.hpp"
#include "search/registry.hpp"
#include "support/random_boxes.hpp"

namespace demlab::search {
namespace search_property_test {

using testing::randomBoxes;
using testing::sorted;
using testing::uniform;

// Runs every algorithm of the table on `boxes` and checks its pairs equal the oracle's.
template <int D, class T>
void expectAllAgree(const std::vector<Box<D, T>>& boxes, const char* scene,
                    double cellFactor = 0.0) {
  std::vector<IndexPair> expected, got;
  BruteForce<D, T>().findPairs(boxes, expected);
  expected = sorted(expected);
  for (const auto& row : broadPhaseTable<D, T>()) {
    auto algorithm = row.make(SearchOptions{cellFactor});
    // Twice: the second call runs on warm buffers.
    for (int pass = 0; pass < 2; ++pass) {
      algorithm->findPairs(boxes, got);
      ASSERT_EQ(got.size(), expected.size())
          << row.name << " D=" << D << " scene " << scene << " pass " << pass;
      ASSERT_EQ(sorted(got), expected) << row.name << " D=" << D << " scene " << scene;
    }
  }
}

template <int D, class T>
void runScenes(uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double side = 40.0;
  auto mono = [](std::mt19937_64&) { return 0.6; };
  auto bidisperse = [](std::mt19937_64& r) { return uniform(r, 0, 1) < 0.1 ? 10.0 : 0.1; };
  auto powerLaw = [](std::mt19937_64& r) {
    // Radii on [0.2, 10] with density ~ r^-3 by inverse CDF.
    const double a = 0.2, b = 10.0, u = uniform(r, 0, 1);
    return 1.0 / std::sqrt(1.0 / (a * a) - u * (1.0 / (a * a) - 1.0 / (b * b)));
  };
  auto tiny = [](std::mt19937_64& r) { return uniform(r, 0, 2.0); };
  for (std::size_t n : {0, 1, 2, 3, 17, 200, 700}) {
    expectAllAgree<D, T>(randomBoxes<D, T>(rng, n, side, mono), "mono");
  }
  expectAllAgree<D, T>(randomBoxes<D, T>(rng, 600, side, bidisperse), "bidisperse");
  expectAllAgree<D, T>(randomBoxes<D, T>(rng, 600, side, powerLaw), "powerlaw");
  expectAllAgree<D, T>(randomBoxes<D, T>(rng, 400, side, tiny, 1.0), "touching grid");
  expectAllAgree<D, T>(randomBoxes<D, T>(rng, 400, side, tiny, 0.0, -1e9), "at -1e9");
  expectAllAgree<D, T>(randomBoxes<D, T>(rng, 400, 1e9, mono), "sparse 1e9");
  for (double factor : {0.1, 0.5, 2.0, 7.0}) {
    expectAllAgree<D, T>(randomBoxes<D, T>(rng, 300, side, powerLaw), "cell factor", factor);
  }
  // Domain-sized walls: thin boxes spanning everything but one axis, at both ends of axis 0.
  auto withWalls = randomBoxes<D, T>(rng, 500, side, mono);
  for (T at : {T(-1), T(side)}) {
    Box<D, T> wall;
    for (int k = 0; k < D; ++k) {
      wall.lo[k] = T(-1);
      wall.hi[k] = T(side + 1);
    }
    wall.lo[0] = at;
    wall.hi[0] = at + T(0.5);
    withWalls.push_back(wall);
  }
  expectAllAgree<D, T>(withWalls, "walls");
  // Every object at one point, and zero-size boxes.
  std::vector<Box<D, T>> point(50);
  for (auto& b : point) b.lo.fill(T(3)), b.hi.fill(T(3));
  expectAllAgree<D, T>(point, "one point");
  auto zero = randomBoxes<D, T>(rng, 300, 10.0, [](std::mt19937_64&) { return 0.0; }, 1.0);
  expectAllAgree<D, T>(zero, "zero size");
  // Two clusters far apart.
  auto clusters = randomBoxes<D, T>(rng, 300, 10.0, mono);
  auto far = randomBoxes<D, T>(rng, 300, 10.0, mono, 0.0, 1e7);
  clusters.insert(clusters.end(), far.begin(), far.end());
  expectAllAgree<D, T>(clusters, "clusters");
}

TEST(SearchProperty, AgreesWithBruteForce1D) { runScenes<1, double>(11); }
TEST(SearchProperty, AgreesWithBruteForce2D) { runScenes<2, double>(12); }
TEST(SearchProperty, AgreesWithBruteForce3D) { runScenes<3, double>(13); }
TEST(SearchProperty, AgreesWithBruteForce4D) { runScenes<4, double>(14); }
TEST(SearchProperty, AgreesWithBruteForce2DFloat) { runScenes<2, float>(15); }
TEST(SearchProperty, AgreesWithBruteForce3DFloat) { runScenes<3, float>(16); }

TEST(SearchProperty, ManySeeds3D) {
  for (uint64_t seed = 100; seed < 110; ++seed) runScenes<3, double>(seed);
}

// Bad input: every algorithm rejects it with the same error and reports nothing.
template <int D>
void expectRejects(const Box<D, double>& bad, const char* message) {
  std::mt19937_64 rng(5);
  auto boxes = randomBoxes<D, double>(rng, 50, 10.0, [](std::mt19937_64&) { return 0.5; });
  boxes.insert(boxes.begin() + 20, bad);
  for (const auto& row : broadPhaseTable<D, double>()) {
    auto algorithm = row.make({});
    std::vector<IndexPair> out = {{1, 2}};
    try {
      algorithm->findPairs(boxes, out);
      ADD_FAILURE() << row.name << " accepted a bad box";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", "BOX"})) << row.name;
      EXPECT_STREQ(e.what(), message) << row.name;
    }
    EXPECT_TRUE(out.empty()) << row.name;
    // Still usable afterwards.
    boxes.erase(boxes.begin() + 20);
    algorithm->findPairs(boxes, out);
    std::vector<IndexPair> expected;
    BruteForce<D, double>().findPairs(boxes, expected);
    EXPECT_EQ(sorted(out), sorted(expected)) << row.name;
    boxes.insert(boxes.begin() + 20, bad);
  }
}

TEST(SearchProperty, RejectsNanInvertedAndInfinite) {
  const double nan = std::nan("");
  expectRejects<3>({{0, 0, 0}, {1, nan, 1}}, "bad box 20: coordinate is NaN on axis 1");
  expectRejects<3>({{0, 0, 2}, {1, 1, 1}}, "bad box 20: minimum exceeds maximum on axis 2");
  expectRejects<2>({{-INFINITY, 0}, {1, 1}}, "bad box 20: coordinate is infinite on axis 0");
}

}  // namespace search_property_test
}  // namespace demlab::search
