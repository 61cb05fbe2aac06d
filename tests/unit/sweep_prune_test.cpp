// SweepAndPrune against the brute-force oracle on randomized scenes for D = 1..4 and
// float/double, with small (std::sort) and large (radix sort) inputs, and repeated calls that
// take the temporal-coherence path (insertion sort from the previous order) or fall back from it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "search/brute_force.hpp"
#include "search/sweep_prune.hpp"

namespace demlab::search {
namespace {

template <int D_, class T_>
struct Config {
  static constexpr int D = D_;
  using T = T_;
};

// Returns a box with the given centre and edge lengths, rounded to T (rounding is monotone, so
// lo <= hi survives). Changes nothing.
template <int D, class T>
Box<D, T> makeBox(const std::array<double, D>& centre, const std::array<double, D>& size) {
  Box<D, T> b;
  for (int k = 0; k < D; ++k) {
    b.lo[k] = static_cast<T>(centre[k] - 0.5 * size[k]);
    b.hi[k] = static_cast<T>(centre[k] + 0.5 * size[k]);
  }
  return b;
}

// Returns n cubes with sizes drawn by sizeOf(rng) and centres uniform in [offset, offset+side)^D.
// Changes rng.
template <int D, class T, class SizeFn>
std::vector<Box<D, T>> randomBoxes(std::mt19937_64& rng, int n, double side, SizeFn sizeOf,
                                   double offset = 0.0) {
  std::uniform_real_distribution<double> pos(offset, offset + side);
  std::vector<Box<D, T>> boxes;
  for (int i = 0; i < n; ++i) {
    std::array<double, D> c, s;
    const double edge = sizeOf(rng);
    for (int k = 0; k < D; ++k) {
      c[k] = pos(rng);
      s[k] = edge;
    }
    boxes.push_back(makeBox<D, T>(c, s));
  }
  return boxes;
}

// Returns the side of a cube in which n boxes of edge `edge` give a few contacts per box.
template <int D>
double sideFor(int n, double edge) {
  return edge * std::pow(static_cast<double>(n), 1.0 / D) * 1.3;
}

// Returns success if algo finds exactly the oracle's pairs on boxes, else the first
// difference. Changes algo's buffers.
template <int D, class T>
::testing::AssertionResult matchesOracle(BroadPhase<D, T>& algo,
                                         const std::vector<Box<D, T>>& boxes) {
  BruteForce<D, T> oracle;
  std::vector<IndexPair> want, got;
  oracle.findPairs(boxes, want);
  algo.findPairs(boxes, got);
  std::sort(want.begin(), want.end());
  std::sort(got.begin(), got.end());
  if (got == want) return ::testing::AssertionSuccess();
  auto r = ::testing::AssertionFailure();
  r << algo.name() << " found " << got.size() << " pairs, oracle " << want.size();
  const auto [g, w] = std::mismatch(got.begin(), got.end(), want.begin(), want.end());
  if (g != got.end()) r << "; first extra or misplaced " << g->first << "," << g->second;
  if (w != want.end()) r << "; first missing " << w->first << "," << w->second;
  return r;
}

template <class C>
class SweepAndPruneTyped : public ::testing::Test {};

using Configs =
    ::testing::Types<Config<1, double>, Config<2, double>, Config<3, double>, Config<4, double>,
                     Config<1, float>, Config<2, float>, Config<3, float>, Config<4, float>>;
TYPED_TEST_SUITE(SweepAndPruneTyped, Configs);

TYPED_TEST(SweepAndPruneTyped, UniformSmallBoxes) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(101 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  SweepAndPrune<D, T> sap;
  for (int n : {2, 3, 17, 400, 1500}) {
    auto boxes = randomBoxes<D, T>(rng, n, sideFor<D>(n, 0.6), size);
    EXPECT_TRUE(matchesOracle(sap, boxes)) << "n=" << n;
  }
  // Negative coordinates far from the origin.
  auto boxes = randomBoxes<D, T>(rng, 500, sideFor<D>(500, 0.6), size, -1234.5);
  EXPECT_TRUE(matchesOracle(sap, boxes));
}

TYPED_TEST(SweepAndPruneTyped, BidisperseRatio100) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(202 + D);
  std::bernoulli_distribution big(0.03);
  auto sizeOf = [&](std::mt19937_64& g) { return big(g) ? 10.0 : 0.1; };
  SweepAndPrune<D, T> sap;
  auto boxes = randomBoxes<D, T>(rng, 800, sideFor<D>(800, 0.6), sizeOf);
  EXPECT_TRUE(matchesOracle(sap, boxes));
}

TYPED_TEST(SweepAndPruneTyped, DomainSizedThinWalls) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(303 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  const double side = sideFor<D>(600, 0.6);
  auto boxes = randomBoxes<D, T>(rng, 600, side, size);
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
  SweepAndPrune<D, T> sap;
  EXPECT_TRUE(matchesOracle(sap, boxes));
}

TYPED_TEST(SweepAndPruneTyped, DegenerateSizesAndPoints) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  SweepAndPrune<D, T> sap;
  // N = 0 and N = 1 report nothing.
  std::vector<Box<D, T>> boxes;
  EXPECT_TRUE(matchesOracle(sap, boxes));
  boxes.push_back(makeBox<D, T>({}, {}));
  EXPECT_TRUE(matchesOracle(sap, boxes));
  // Every box at one point: all pairs.
  std::array<double, D> p;
  p.fill(3.25);
  boxes.assign(60, makeBox<D, T>(p, {}));
  EXPECT_TRUE(matchesOracle(sap, boxes));
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
  EXPECT_TRUE(matchesOracle(sap, boxes));
}

TYPED_TEST(SweepAndPruneTyped, ExactFaceTouching) {
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
  SweepAndPrune<D, T> sap;
  EXPECT_TRUE(matchesOracle(sap, boxes));
  // Boxes at -0 and +0 touch.
  std::vector<Box<D, T>> signs(2);
  for (int k = 0; k < D; ++k) {
    signs[0].lo[k] = T{-1};
    signs[0].hi[k] = -T{0};
    signs[1].lo[k] = T{0};
    signs[1].hi[k] = T{1};
  }
  EXPECT_TRUE(matchesOracle(sap, signs));
}

TYPED_TEST(SweepAndPruneTyped, CoordinatesNearPlusMinus1e9) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(505 + D);
  std::uniform_real_distribution<double> size(1.0, 300.0);
  auto boxes = randomBoxes<D, T>(rng, 300, sideFor<D>(300, 150.0), size, -1e9);
  auto far = randomBoxes<D, T>(rng, 300, sideFor<D>(300, 150.0), size, 1e9 - 3000.0);
  boxes.insert(boxes.end(), far.begin(), far.end());
  SweepAndPrune<D, T> sap;
  EXPECT_TRUE(matchesOracle(sap, boxes));
  // One box spanning both clusters makes the cell as large as the domain.
  std::array<double, D> c, s;
  c.fill(0.0);
  s.fill(2.1e9);
  boxes.push_back(makeBox<D, T>(c, s));
  EXPECT_TRUE(matchesOracle(sap, boxes));
}

TYPED_TEST(SweepAndPruneTyped, SparseScene) {
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
  SweepAndPrune<D, T> sap;
  EXPECT_TRUE(matchesOracle(sap, boxes));
  EXPECT_LT(sap.workingBytes(), std::size_t{1} << 20);
}

TYPED_TEST(SweepAndPruneTyped, ExtremeMagnitudes) {
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
  SweepAndPrune<D, T> sap;
  EXPECT_TRUE(matchesOracle(sap, boxes));
  boxes.erase(boxes.begin());
  EXPECT_TRUE(matchesOracle(sap, boxes));
}

TYPED_TEST(SweepAndPruneTyped, BadBoxesThrowAndLeaveOutEmpty) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(707 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  auto boxes = randomBoxes<D, T>(rng, 50, sideFor<D>(50, 0.6), size);
  SweepAndPrune<D, T> sap;
  std::vector<IndexPair> out = {{1, 2}};
  auto nan = boxes;
  nan[17].hi[D - 1] = std::numeric_limits<T>::quiet_NaN();
  try {
    sap.findPairs(nan, out);
    ADD_FAILURE() << "expected an error for NaN";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", "BOX"}));
  }
  EXPECT_TRUE(out.empty());
  auto inverted = boxes;
  std::swap(inverted[3].lo[0], inverted[3].hi[0]);
  out = {{1, 2}};
  EXPECT_THROW(sap.findPairs(inverted, out), Error);
  EXPECT_TRUE(out.empty());
  // Still usable afterwards.
  EXPECT_TRUE(matchesOracle(sap, boxes));
}

TYPED_TEST(SweepAndPruneTyped, RepeatedCallsOnMovedBoxes) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(808 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  auto boxes = randomBoxes<D, T>(rng, 700, sideFor<D>(700, 0.6), size);
  SweepAndPrune<D, T> sap;
  EXPECT_TRUE(matchesOracle(sap, boxes));
  const std::size_t warm = sap.workingBytes();
  EXPECT_TRUE(matchesOracle(sap, boxes));
  EXPECT_EQ(sap.workingBytes(), warm);
  for (int step = 0; step < 5; ++step) {
    for (auto& b : boxes) {
      for (int k = 0; k < D; ++k) {
        const T d = static_cast<T>(jitter(rng));
        b.lo[k] += d;
        b.hi[k] += d;
        if (b.hi[k] < b.lo[k]) b.hi[k] = b.lo[k];
      }
    }
    EXPECT_TRUE(matchesOracle(sap, boxes)) << "step " << step;
  }
  // A different count and scene reuses the same object.
  auto other = randomBoxes<D, T>(rng, 90, sideFor<D>(90, 0.6), size, 50.0);
  EXPECT_TRUE(matchesOracle(sap, other));
}

TYPED_TEST(SweepAndPruneTyped, CoherenceAndFallback) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(909 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  // DEM steps move a grain by a small fraction of its size.
  std::uniform_real_distribution<double> jitter(-0.005, 0.005);
  for (int n : {300, 3000}) {  // std::sort and radix sort for the first order
    auto boxes = randomBoxes<D, T>(rng, n, sideFor<D>(n, 0.6), size, -20.0);
    SweepAndPrune<D, T> sap;
    EXPECT_TRUE(matchesOracle(sap, boxes));
    EXPECT_FALSE(sap.reusedOrder());
    // Jittered boxes: insertion sort from the previous order.
    for (int step = 0; step < 4; ++step) {
      for (auto& b : boxes) {
        for (int k = 0; k < D; ++k) {
          const T d = static_cast<T>(jitter(rng));
          b.lo[k] += d;
          b.hi[k] += d;
        }
      }
      EXPECT_TRUE(matchesOracle(sap, boxes)) << "n=" << n << " step " << step;
      EXPECT_TRUE(sap.reusedOrder()) << "n=" << n << " step " << step;
    }
    // Warm: the same count again allocates nothing.
    const std::size_t warm = sap.workingBytes();
    EXPECT_TRUE(matchesOracle(sap, boxes)) << "n=" << n;
    EXPECT_EQ(sap.workingBytes(), warm) << "n=" << n;
    // Mirrored: the previous order is exactly backwards, so the insertion sort gives up.
    for (auto& b : boxes) {
      for (int k = 0; k < D; ++k) {
        const T lo = b.lo[k];
        b.lo[k] = -b.hi[k];
        b.hi[k] = -lo;
      }
    }
    EXPECT_TRUE(matchesOracle(sap, boxes)) << "n=" << n;
    EXPECT_FALSE(sap.reusedOrder()) << "n=" << n;
    // Same count, a new scene stretched along the last axis: the axis choice changes.
    auto stretched = randomBoxes<D, T>(rng, n, sideFor<D>(n, 0.6), size);
    for (auto& b : stretched) {
      b.lo[D - 1] *= T{20};
      b.hi[D - 1] *= T{20};
    }
    EXPECT_TRUE(matchesOracle(sap, stretched)) << "n=" << n;
    EXPECT_TRUE(matchesOracle(sap, stretched)) << "n=" << n;
    // A different count starts over.
    stretched.resize(n / 2);
    EXPECT_TRUE(matchesOracle(sap, stretched)) << "n=" << n;
  }
}

TYPED_TEST(SweepAndPruneTyped, FilterImagesCollapseFarFromOrigin) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(1111 + D);
  std::uniform_real_distribution<double> size(1e-3, 3e-3);
  // The sweep's float images are taken relative to the lowest box, so in the far cluster whole
  // groups of distinct boxes share one image and only the exact test can tell them apart.
  auto boxes = randomBoxes<D, T>(rng, 200, sideFor<D>(200, 2e-3), size, -1e9);
  auto far = randomBoxes<D, T>(rng, 700, sideFor<D>(700, 2e-3), size, 1e9);
  boxes.insert(boxes.end(), far.begin(), far.end());
  std::shuffle(boxes.begin(), boxes.end(), rng);
  SweepAndPrune<D, T> sap;
  EXPECT_TRUE(matchesOracle(sap, boxes));
}

TYPED_TEST(SweepAndPruneTyped, LargeRadixSortedScenes) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(1010 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  SweepAndPrune<D, T> sap;
  // Straddling zero, so keys of both signs (and their ordering) are exercised.
  const double side = sideFor<D>(4000, 0.6);
  auto boxes = randomBoxes<D, T>(rng, 4000, side, size, -0.5 * side);
  EXPECT_TRUE(matchesOracle(sap, boxes));
  // Many equal keys: every lo on a coarse lattice.
  std::uniform_int_distribution<int> lattice(-8, 8);
  for (auto& b : boxes) {
    for (int k = 0; k < D; ++k) {
      b.lo[k] = static_cast<T>(lattice(rng));
      b.hi[k] = b.lo[k] + T{1};
    }
  }
  EXPECT_TRUE(matchesOracle(sap, boxes));
}

TEST(SweepAndPrune, NameAndNoWorkForTinyInputs) {
  SweepAndPrune<3, double> sap;
  EXPECT_EQ(sap.name(), "sap");
  std::vector<IndexPair> out = {{0, 1}};
  sap.findPairs(std::span<const Box<3, double>>{}, out);
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace demlab::search
