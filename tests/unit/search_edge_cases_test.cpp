// Every search algorithm of the registry against the brute-force oracle on the inputs that
// break them: walls, bidisperse sizes, points and zero sizes, exact touching, +-1e9 and extreme
// magnitudes, sparse scenes, bad boxes, and reuse on moved boxes; D = 1..4, float and double.
// The algorithm-specific behaviour (levels, coherence, cell sizes) is in each one's own file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "support/oracle_scenes.hpp"

namespace demlab::search {
namespace search_edge_cases_test {

using namespace test_support;

template <class C>
class EdgeCases : public ::testing::Test {};
TYPED_TEST_SUITE(EdgeCases, Configs);

TYPED_TEST(EdgeCases, UniformSmallBoxes) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(101 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    for (int n : {2, 3, 17, 400, 1500}) {
      auto boxes = randomCubes<D, T>(rng, n, sideFor<D>(n, 0.6), size);
      EXPECT_TRUE(matchesOracle(algo, boxes)) << "n=" << n;
    }
    // Negative coordinates far from the origin.
    auto boxes = randomCubes<D, T>(rng, 500, sideFor<D>(500, 0.6), size, -1234.5);
    EXPECT_TRUE(matchesOracle(algo, boxes));
  }
}

TYPED_TEST(EdgeCases, BidisperseRatio100) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(202 + D);
  std::bernoulli_distribution big(0.03);
  auto sizeOf = [&](std::mt19937_64& g) { return big(g) ? 10.0 : 0.1; };
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    auto boxes = randomCubes<D, T>(rng, 800, sideFor<D>(800, 0.6), sizeOf);
    EXPECT_TRUE(matchesOracle(algo, boxes));
  }
}

TYPED_TEST(EdgeCases, DomainSizedThinWalls) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(303 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  const double side = sideFor<D>(600, 0.6);
  auto boxes = randomCubes<D, T>(rng, 600, side, size);
  // Walls at both ends of every axis and one through the middle, spanning the whole domain.
  for (int k = 0; k < D; ++k) {
    for (double at : {0.0, 0.5 * side, side}) {
      std::array<double, D> c, s;
      for (int j = 0; j < D; ++j) {
        c[j] = j == k ? at : 0.5 * side;
        s[j] = j == k ? 0.01 : side + 2.0;
      }
      boxes.push_back(makeBox<D, T>(c, s));
    }
  }
  std::shuffle(boxes.begin(), boxes.end(), rng);
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    EXPECT_TRUE(matchesOracle(algo, boxes));
  }
}

TYPED_TEST(EdgeCases, DegenerateSizesAndPoints) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    // N = 0 and N = 1 report nothing.
    std::vector<Box<D, T>> boxes;
    EXPECT_TRUE(matchesOracle(algo, boxes));
    boxes.push_back(makeBox<D, T>({}, {}));
    EXPECT_TRUE(matchesOracle(algo, boxes));
    // Every box at one point: all pairs.
    std::array<double, D> p;
    p.fill(3.25);
    boxes.assign(60, makeBox<D, T>(p, {}));
    EXPECT_TRUE(matchesOracle(algo, boxes));
    // Zero-size boxes on a coarse lattice, so points coincide, plus unit boxes whose faces hold
    // some of the points.
    std::mt19937_64 rng(404 + D);
    std::uniform_int_distribution<int> lattice(0, 6);
    boxes.clear();
    for (int i = 0; i < 300; ++i) {
      std::array<double, D> c, s;
      const bool point = i % 3 != 0;
      for (int k = 0; k < D; ++k) {
        c[k] = lattice(rng) + (point ? 0.0 : 0.5);
        s[k] = point ? 0.0 : 1.0;
      }
      boxes.push_back(makeBox<D, T>(c, s));
    }
    EXPECT_TRUE(matchesOracle(algo, boxes));
  }
}

TYPED_TEST(EdgeCases, ExactFaceTouching) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  // A lattice of unit boxes [i, i+1]: every lattice neighbour, corners included, touches.
  const int perAxis = D == 1 ? 50 : D == 2 ? 12 : D == 3 ? 6 : 4;
  std::vector<Box<D, T>> boxes;
  int total = 1;
  for (int k = 0; k < D; ++k) total *= perAxis;
  for (int i = 0; i < total; ++i) {
    Box<D, T> b;
    for (int k = 0, r = i; k < D; ++k, r /= perAxis) {
      b.lo[k] = static_cast<T>(r % perAxis - 2);
      b.hi[k] = b.lo[k] + T{1};
    }
    boxes.push_back(b);
  }
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    EXPECT_TRUE(matchesOracle(algo, boxes));
    // Boxes at -0 and +0 touch.
    std::vector<Box<D, T>> signs(2);
    for (int k = 0; k < D; ++k) {
      signs[0].lo[k] = T{-1};
      signs[0].hi[k] = -T{0};
      signs[1].lo[k] = T{0};
      signs[1].hi[k] = T{1};
    }
    EXPECT_TRUE(matchesOracle(algo, signs));
  }
}

TYPED_TEST(EdgeCases, CoordinatesNearPlusMinus1e9) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(505 + D);
  std::uniform_real_distribution<double> size(1.0, 300.0);
  auto boxes = randomCubes<D, T>(rng, 300, sideFor<D>(300, 150.0), size, -1e9);
  auto far = randomCubes<D, T>(rng, 300, sideFor<D>(300, 150.0), size, 1e9 - 3000.0);
  boxes.insert(boxes.end(), far.begin(), far.end());
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    EXPECT_TRUE(matchesOracle(algo, boxes));
    // One box spanning both clusters makes the cell as large as the domain.
    std::array<double, D> c, s;
    c.fill(0.0);
    s.fill(2.1e9);
    auto spanned = boxes;
    spanned.push_back(makeBox<D, T>(c, s));
    EXPECT_TRUE(matchesOracle(algo, spanned));
  }
}

TYPED_TEST(EdgeCases, SparseSceneUsesLittleMemory) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(606 + D);
  // Tiny boxes spread over +-1e9: uncapped, that is ~1e12 cells per axis.
  std::uniform_real_distribution<double> pos(-1e9, 1e9);
  std::vector<Box<D, T>> boxes;
  for (int i = 0; i < 40; ++i) {
    std::array<double, D> c, s;
    for (int k = 0; k < D; ++k) c[k] = pos(rng);
    s.fill(1e-3);
    boxes.push_back(makeBox<D, T>(c, s));
    boxes.push_back(boxes.back());  // a coincident twin, so there is something to find
  }
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    EXPECT_TRUE(matchesOracle(algo, boxes));
    EXPECT_LT(algo.workingBytes(), std::size_t{1} << 20);
  }
}

TYPED_TEST(EdgeCases, ExtremeMagnitudes) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  const T big = std::numeric_limits<T>::max();
  const T tiny = std::numeric_limits<T>::denorm_min();
  std::vector<Box<D, T>> boxes(5);
  for (int k = 0; k < D; ++k) {
    boxes[0].lo[k] = -big, boxes[0].hi[k] = big;  // everything
    boxes[1].lo[k] = -big, boxes[1].hi[k] = -big;
    boxes[2].lo[k] = big, boxes[2].hi[k] = big;
    boxes[3].lo[k] = 0, boxes[3].hi[k] = tiny;
    boxes[4].lo[k] = tiny, boxes[4].hi[k] = 2 * tiny;
  }
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    // A box wider than the largest double leaves SGrid no fixed cell: a clear error, no pairs.
    if (algo.name() == "sgrid" && !std::isfinite(2.0 * static_cast<double>(big))) {
      std::vector<IndexPair> out = {{0, 1}};
      try {
        algo.findPairs(boxes, out);
        ADD_FAILURE() << "expected an error for an infinite extent";
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", "BOX"}));
      }
      EXPECT_TRUE(out.empty());
    } else {
      EXPECT_TRUE(matchesOracle(algo, boxes));
    }
    const std::vector<Box<D, T>> withoutEverything(boxes.begin() + 1, boxes.end());
    EXPECT_TRUE(matchesOracle(algo, withoutEverything));
  }
}

TYPED_TEST(EdgeCases, BadBoxesThrowAndLeaveOutEmpty) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(707 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  auto boxes = randomCubes<D, T>(rng, 50, sideFor<D>(50, 0.6), size);
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    std::vector<IndexPair> out = {{1, 2}};
    auto nan = boxes;
    nan[17].hi[D - 1] = std::numeric_limits<T>::quiet_NaN();
    try {
      algo.findPairs(nan, out);
      ADD_FAILURE() << "expected an error for NaN";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", "BOX"}));
    }
    EXPECT_TRUE(out.empty());
    auto inverted = boxes;
    std::swap(inverted[3].lo[0], inverted[3].hi[0]);
    out = {{1, 2}};
    EXPECT_THROW(algo.findPairs(inverted, out), Error);
    EXPECT_TRUE(out.empty());
    // Still usable afterwards.
    EXPECT_TRUE(matchesOracle(algo, boxes));
  }
}

TYPED_TEST(EdgeCases, RepeatedCallsOnMovedBoxes) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(808 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  auto boxes = randomCubes<D, T>(rng, 700, sideFor<D>(700, 0.6), size);
  for (const auto& owned : everyAlgorithm<D, T>()) {
    BroadPhase<D, T>& algo = *owned;
    SCOPED_TRACE(std::string(algo.name()));
    EXPECT_TRUE(matchesOracle(algo, boxes));
    const std::size_t warm = algo.workingBytes();
    EXPECT_TRUE(matchesOracle(algo, boxes));
    EXPECT_EQ(algo.workingBytes(), warm);
    for (int step = 0; step < 5; ++step) {
      for (auto& b : boxes) {
        for (int k = 0; k < D; ++k) {
          const T d = static_cast<T>(jitter(rng));
          b.lo[k] += d;
          b.hi[k] += d;
          if (b.hi[k] < b.lo[k]) b.hi[k] = b.lo[k];
        }
      }
      EXPECT_TRUE(matchesOracle(algo, boxes)) << "step " << step;
    }
    // A different count and scene reuses the same object.
    auto other = randomCubes<D, T>(rng, 90, sideFor<D>(90, 0.6), size, 50.0);
    EXPECT_TRUE(matchesOracle(algo, other));
  }
}

}  // namespace search_edge_cases_test
}  // namespace demlab::search
