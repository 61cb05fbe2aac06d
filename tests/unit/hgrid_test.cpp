// HGrid against the brute-force oracle on randomized scenes for D = 1..4 and float/double:
// the size distributions that need several levels (bidisperse 10/100/1000, power laws), the
// objects that cover many finer cells (domain-sized walls), degenerate input (points, one
// location, N = 0 and 1, far-away coordinates), bad boxes, and reuse between calls.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "search/hgrid.hpp"
#include "support/oracle_scenes.hpp"

namespace demlab::search {
namespace hgrid_test {

using namespace test_support;

template <class C>
class HGridTyped : public ::testing::Test {};

TYPED_TEST_SUITE(HGridTyped, Configs);

TYPED_TEST(HGridTyped, UniformMonodisperse) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(1);
  HGrid<D, T> hgrid;
  for (int n : {2, 3, 17, 400, 1500}) {
    auto boxes = randomCubes<D, T>(rng, n, sideFor<D>(n, 1.0), [](auto&) { return 1.0; });
    EXPECT_TRUE(matchesOracle(hgrid, boxes)) << "n = " << n;
    EXPECT_EQ(hgrid.levelCount(), 1);
  }
}

TYPED_TEST(HGridTyped, UniformRandomSizes) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> edge(0.5, 1.5);
  HGrid<D, T> hgrid;
  auto boxes = randomCubes<D, T>(rng, 1200, sideFor<D>(1200, 1.0), edge);
  EXPECT_TRUE(matchesOracle(hgrid, boxes));
}

TYPED_TEST(HGridTyped, Bidisperse) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  for (double ratio : {10.0, 100.0, 1000.0}) {
    std::mt19937_64 rng(3);
    std::bernoulli_distribution big(0.02);
    const int n = 1500;
    // The side follows the small objects, so the big ones cover many small cells.
    const double side = sideFor<D>(n, 1.0) * 2.0;
    auto boxes = randomCubes<D, T>(rng, n, side, [&](auto& r) { return big(r) ? ratio : 1.0; });
    HGrid<D, T> hgrid;
    EXPECT_TRUE(matchesOracle(hgrid, boxes)) << "ratio " << ratio;
    EXPECT_EQ(hgrid.levelCount(), 2) << "ratio " << ratio;
  }
}

TYPED_TEST(HGridTyped, PowerLawRadii) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  // Truncated power laws p(r) ~ r^exponent on [1, 50], drawn by inverting their distribution
  // functions.
  for (double exponent : {-2.0, -3.0}) {
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const double a = 1.0, b = 50.0, q = exponent + 1.0;
    auto radius = [&](auto& r) {
      return std::pow(std::pow(a, q) + u(r) * (std::pow(b, q) - std::pow(a, q)), 1.0 / q);
    };
    const int n = 1500;
    auto boxes =
        randomCubes<D, T>(rng, n, sideFor<D>(n, 4.0), [&](auto& r) { return 2 * radius(r); });
    HGrid<D, T> hgrid;
    EXPECT_TRUE(matchesOracle(hgrid, boxes)) << "exponent " << exponent;
    EXPECT_GE(hgrid.levelCount(), 2);
  }
}

TYPED_TEST(HGridTyped, DomainSizedThinWalls) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(5);
  const int n = 1000;
  const double side = sideFor<D>(n, 1.0);
  auto boxes = randomCubes<D, T>(rng, n, side, [](auto&) { return 1.0; });
  // Two walls per axis at the domain faces, of zero thickness, plus one through the middle
  // with thickness 0.1, and one box as large as the whole domain.
  for (int k = 0; k < D; ++k) {
    for (double at : {0.0, side, 0.5 * side}) {
      std::array<double, D> c, s;
      for (int j = 0; j < D; ++j) {
        c[j] = 0.5 * side;
        s[j] = side + 2.0;
      }
      c[k] = at;
      s[k] = at == 0.5 * side ? 0.1 : 0.0;
      boxes.push_back(makeBox<D, T>(c, s));
    }
  }
  std::array<double, D> c, s;
  c.fill(0.5 * side);
  s.fill(side);
  boxes.insert(boxes.begin() + 7, makeBox<D, T>(c, s));
  HGrid<D, T> hgrid;
  EXPECT_TRUE(matchesOracle(hgrid, boxes));
  EXPECT_GE(hgrid.levelCount(), 2);
}

TYPED_TEST(HGridTyped, SparseSceneWithHugeBox) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  // Few small objects spread over a vast region and one box covering it: the finer level has
  // far more cells under the box than occupied cells, so it must be scanned, not probed.
  std::mt19937_64 rng(6);
  auto boxes = randomCubes<D, T>(rng, 200, 1e6, [](auto&) { return 1.0; });
  std::array<double, D> c, s;
  c.fill(5e5);
  s.fill(1e6);
  boxes.push_back(makeBox<D, T>(c, s));
  c.fill(-3e5);
  s.fill(1e3);
  boxes.push_back(makeBox<D, T>(c, s));
  HGrid<D, T> hgrid;
  EXPECT_TRUE(matchesOracle(hgrid, boxes));
}

TYPED_TEST(HGridTyped, AllBoxesAtOnePoint) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::vector<Box<D, T>> boxes(60);
  for (auto& b : boxes) {
    b.lo.fill(T(3));
    b.hi.fill(T(3));
  }
  HGrid<D, T> hgrid;
  EXPECT_TRUE(matchesOracle(hgrid, boxes));
  std::vector<IndexPair> out;
  hgrid.findPairs(boxes, out);
  EXPECT_EQ(out.size(), 60u * 59u / 2u);
  EXPECT_EQ(hgrid.levelCount(), 1);
}

TYPED_TEST(HGridTyped, ZeroSizeBoxes) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(7);
  // Points on a coarse lattice (so some coincide), alone and mixed with sized boxes.
  std::uniform_int_distribution<int> lattice(0, 6);
  std::vector<Box<D, T>> points;
  for (int i = 0; i < 300; ++i) {
    Box<D, T> b;
    for (int k = 0; k < D; ++k) b.lo[k] = b.hi[k] = static_cast<T>(lattice(rng) * 0.5);
    points.push_back(b);
  }
  HGrid<D, T> hgrid;
  EXPECT_TRUE(matchesOracle(hgrid, points));
  auto mixed = randomCubes<D, T>(rng, 300, 3.5, [](auto& r) {
    return std::uniform_real_distribution<double>(0.0, 2.0)(r) < 0.3 ? 0.0 : 0.7;
  });
  mixed.insert(mixed.end(), points.begin(), points.end());
  EXPECT_TRUE(matchesOracle(hgrid, mixed));
}

TYPED_TEST(HGridTyped, EmptyAndSingle) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  HGrid<D, T> hgrid;
  std::vector<IndexPair> out = {{1, 2}};
  hgrid.findPairs({}, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(hgrid.levelCount(), 0);
  std::vector<Box<D, T>> one(1);
  one[0].lo.fill(T(-1));
  one[0].hi.fill(T(2));
  out = {{1, 2}};
  hgrid.findPairs(one, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(hgrid.levelCount(), 1);
}

TYPED_TEST(HGridTyped, ExactFaceTouching) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  // A lattice of unit cubes sharing faces, edges and corners exactly (integers are exact in
  // float too), plus cubes of edge 2 and 4 on the same lattice, so touching crosses levels.
  std::vector<Box<D, T>> boxes;
  const int per = D == 1 ? 40 : D == 2 ? 12 : D == 3 ? 6 : 4;
  int total = 1;
  for (int k = 0; k < D; ++k) total *= per;
  for (int code = 0; code < total; ++code) {
    Box<D, T> b;
    int rest = code;
    for (int k = 0; k < D; ++k) {
      b.lo[k] = static_cast<T>(rest % per);
      b.hi[k] = b.lo[k] + T(1);
      rest /= per;
    }
    boxes.push_back(b);
  }
  for (int edge : {2, 4}) {
    Box<D, T> b;
    for (int k = 0; k < D; ++k) {
      b.lo[k] = static_cast<T>(per);
      b.hi[k] = static_cast<T>(per + edge);
    }
    boxes.push_back(b);
    for (int k = 0; k < D; ++k) {
      b.lo[k] = T(1);
      b.hi[k] = static_cast<T>(1 + edge);
    }
    boxes.push_back(b);
  }
  HGrid<D, T> hgrid;
  EXPECT_TRUE(matchesOracle(hgrid, boxes));
}

TYPED_TEST(HGridTyped, FarCoordinates) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  for (double offset : {1e9, -1e9}) {
    std::mt19937_64 rng(8);
    // Edges of 100 survive float rounding near 1e9 (float's spacing there is 64).
    auto boxes = randomCubes<D, T>(
        rng, 800, sideFor<D>(800, 100.0),
        [](auto& r) { return std::uniform_real_distribution<double>(50.0, 200.0)(r); }, offset);
    HGrid<D, T> hgrid;
    EXPECT_TRUE(matchesOracle(hgrid, boxes)) << "offset " << offset;
  }
  // Both ends at once: one tiny cluster at -1e9, one at +1e9, and a box spanning both.
  std::mt19937_64 rng(9);
  auto boxes = randomCubes<D, T>(
      rng, 200, 2000.0, [](auto&) { return 100.0; }, -1e9);
  auto far = randomCubes<D, T>(
      rng, 200, 2000.0, [](auto&) { return 100.0; }, 1e9 - 2000.0);
  boxes.insert(boxes.end(), far.begin(), far.end());
  Box<D, T> span;
  span.lo.fill(static_cast<T>(-1e9));
  span.hi.fill(static_cast<T>(1e9));
  boxes.push_back(span);
  HGrid<D, T> hgrid;
  EXPECT_TRUE(matchesOracle(hgrid, boxes));
}

TYPED_TEST(HGridTyped, SecondCallOnJitteredBoxes) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(10);
  std::bernoulli_distribution big(0.05);
  const int n = 1200;
  auto boxes =
      randomCubes<D, T>(rng, n, sideFor<D>(n, 1.5), [&](auto& r) { return big(r) ? 8.0 : 1.0; });
  HGrid<D, T> hgrid;
  ASSERT_TRUE(matchesOracle(hgrid, boxes));
  const std::size_t bytes = hgrid.workingBytes();
  EXPECT_GT(bytes, 0u);
  std::normal_distribution<double> jitter(0.0, 0.05);
  for (int step = 0; step < 3; ++step) {
    for (auto& b : boxes) {
      for (int k = 0; k < D; ++k) {
        const T d = static_cast<T>(jitter(rng));
        b.lo[k] += d;
        b.hi[k] += d;
      }
    }
    EXPECT_TRUE(matchesOracle(hgrid, boxes)) << "step " << step;
  }
  // Moved boxes of the same count need no new memory.
  EXPECT_EQ(hgrid.workingBytes(), bytes);
}

TYPED_TEST(HGridTyped, BadBoxIsRejectedAndReportsNothing) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(11);
  auto boxes = randomCubes<D, T>(rng, 50, 5.0, [](auto&) { return 1.0; });
  HGrid<D, T> hgrid;
  std::vector<IndexPair> out;
  for (int bad = 0; bad < 3; ++bad) {
    auto broken = boxes;
    if (bad == 0) broken[17].hi[D - 1] = std::numeric_limits<T>::quiet_NaN();
    if (bad == 1) broken[17].lo[0] = broken[17].hi[0] + T(1);
    if (bad == 2) broken[17].lo[0] = -std::numeric_limits<T>::infinity();
    out = {{0, 1}};
    try {
      hgrid.findPairs(broken, out);
      ADD_FAILURE() << "expected an error for bad box kind " << bad;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", "BOX"}));
    }
    EXPECT_TRUE(out.empty());
    // The object stays usable.
    EXPECT_TRUE(matchesOracle(hgrid, boxes));
  }
}

TEST(HGrid, Name) {
  HGrid<3, double> hgrid;
  EXPECT_EQ(hgrid.name(), "hgrid");
}

TEST(HGrid, LevelCountGrowsWithSizeRatio) {
  int previous = 0;
  for (double ratio : {1.0, 3.0, 30.0, 300.0, 3000.0}) {
    // Sizes log-uniform on [1, ratio], in a cube they fill to about half (a granular bed).
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> logSize(0.0, std::log(ratio));
    std::vector<double> sizes(3000);
    double volume = 0.0;
    for (double& size : sizes) {
      size = std::exp(logSize(rng));
      volume += size * size * size;
    }
    std::size_t next = 0;
    auto boxes = randomCubes<3, double>(rng, 3000, std::cbrt(2.0 * volume),
                                        [&](auto&) { return sizes[next++]; });
    HGrid<3, double> hgrid;
    EXPECT_TRUE(matchesOracle(hgrid, boxes)) << "ratio " << ratio;
    if (ratio == 1.0) {
      EXPECT_EQ(hgrid.levelCount(), 1);
    } else {
      EXPECT_GE(hgrid.levelCount(), previous) << "ratio " << ratio;
    }
    EXPECT_LE(hgrid.levelCount(), (HGrid<3, double>::kDefaultMaxLevels));
    previous = hgrid.levelCount();
  }
  EXPECT_GE(previous, 2);
}

TEST(HGrid, CellSizesFitTheObjectsOnEachLevel) {
  std::mt19937_64 rng(13);
  std::bernoulli_distribution big(0.01);
  auto boxes =
      randomCubes<2, double>(rng, 3000, 200.0, [&](auto& r) { return big(r) ? 50.0 : 0.5; });
  HGrid<2, double> hgrid;
  EXPECT_TRUE(matchesOracle(hgrid, boxes));
  ASSERT_EQ(hgrid.levelCount(), 2);
  EXPECT_NEAR(hgrid.cellSize(0), 0.5, 1e-4);
  EXPECT_NEAR(hgrid.cellSize(1), 50.0, 1e-2);
}

TEST(HGrid, CrossLevelDirectionFollowsTheCost) {
  // A few domain-sized walls over many small balls: the walls probe the strip of small cells
  // they cover (top-down).
  std::mt19937_64 rng(14);
  const double side = 60.0;
  auto walls = randomCubes<3, double>(rng, 4000, side, [](auto&) { return 1.0; });
  for (double at : {0.0, side}) {
    walls.push_back({{-1.0, -1.0, at - 0.5}, {side + 1.0, side + 1.0, at + 0.5}});
  }
  HGrid<3, double> hgrid;
  EXPECT_TRUE(matchesOracle(hgrid, walls));
  ASSERT_EQ(hgrid.levelCount(), 2);
  EXPECT_TRUE(hgrid.searches(1, 0));
  EXPECT_FALSE(hgrid.searches(0, 1));
  // Many large balls among the small ones: each small cell probes the few large cells around
  // it (bottom-up) instead of each large ball probing thousands of small cells.
  std::bernoulli_distribution big(0.05);
  auto beds =
      randomCubes<3, double>(rng, 4000, 220.0, [&](auto& r) { return big(r) ? 30.0 : 1.0; });
  EXPECT_TRUE(matchesOracle(hgrid, beds));
  ASSERT_EQ(hgrid.levelCount(), 2);
  EXPECT_TRUE(hgrid.searches(0, 1));
  EXPECT_FALSE(hgrid.searches(1, 0));
}

TEST(HGrid, LevelCapIsRespected) {
  // Sizes 2^0 .. 2^29, all present: 30 octaves, more than any cap below.
  std::mt19937_64 rng(15);
  std::uniform_int_distribution<int> exponent(0, 29);
  auto boxes =
      randomCubes<2, double>(rng, 600, 1e9, [&](auto& r) { return std::ldexp(1.0, exponent(r)); });
  for (int cap : {1, 2, 5, 16}) {
    HGrid<2, double> hgrid(SearchOptions{}, cap);
    EXPECT_TRUE(matchesOracle(hgrid, boxes)) << "cap " << cap;
    EXPECT_LE(hgrid.levelCount(), cap);
  }
}

TEST(HGrid, CellFactorKeepsResultsExact) {
  std::mt19937_64 rng(15);
  auto boxes = randomCubes<3, double>(
      rng, 1000, 12.0, [](auto& r) { return std::uniform_real_distribution<double>(0.2, 3.0)(r); });
  for (double factor : {0.0, 0.5, 1.0, 1.7, 3.0}) {
    HGrid<3, double> hgrid(SearchOptions{factor});
    EXPECT_TRUE(matchesOracle(hgrid, boxes)) << "factor " << factor;
  }
}

TEST(HGrid, ExtremeMagnitudes) {
  // Coordinates near the largest doubles (the span overflows) and tiny specks next to them.
  const double big = std::numeric_limits<double>::max() / 1.5;
  std::vector<Box<2, double>> boxes = {
      {{-big, -big}, {big, big}},
      {{0.0, 0.0}, {1e-300, 1e-300}},
      {{1e-300, 1e-300}, {1e-300, 1e-300}},
      {{big * 0.9, 0.0}, {big, 1.0}},
      {{-big, -big}, {-big, -big}},
      {{5.0, 5.0}, {6.0, 6.0}},
      {{5.5, 5.5}, {5.5, 5.5}},
      {{2e-300, 0.0}, {3e-300, 0.0}},
  };
  HGrid<2, double> hgrid;
  EXPECT_TRUE(matchesOracle(hgrid, boxes));
  std::vector<Box<3, float>> specks;
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<float> pos(-1e-30f, 1e-30f);
  for (int i = 0; i < 300; ++i) {
    Box<3, float> b;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = pos(rng);
      b.hi[k] = b.lo[k] + 1e-31f;
    }
    specks.push_back(b);
  }
  HGrid<3, float> small;
  EXPECT_TRUE(matchesOracle(small, specks));
}

}  // namespace hgrid_test
}  // namespace demlab::search
