// SweepAndPrune against the brute-force oracle on randomized scenes for D = 1..4 and
// float/double, with small (std::sort) and large (radix sort) inputs, and repeated calls that
// take the temporal-coherence path (insertion sort from the previous order) or fall back from it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "search/sweep_prune.hpp"
#include "support/oracle_scenes.hpp"

namespace demlab::search {
namespace sweep_prune_test {

using namespace test_support;

template <class C>
class SweepAndPruneTyped : public ::testing::Test {};
TYPED_TEST_SUITE(SweepAndPruneTyped, Configs);

TYPED_TEST(SweepAndPruneTyped, CoherenceAndFallback) {
  constexpr int D = TypeParam::D;
  using T = typename TypeParam::T;
  std::mt19937_64 rng(909 + D);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  // DEM steps move a grain by a small fraction of its size.
  std::uniform_real_distribution<double> jitter(-0.005, 0.005);
  for (int n : {300, 3000}) {  // std::sort and radix sort for the first order
    auto boxes = randomCubes<D, T>(rng, n, sideFor<D>(n, 0.6), size, -20.0);
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
    auto stretched = randomCubes<D, T>(rng, n, sideFor<D>(n, 0.6), size);
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
  auto boxes = randomCubes<D, T>(rng, 200, sideFor<D>(200, 2e-3), size, -1e9);
  auto far = randomCubes<D, T>(rng, 700, sideFor<D>(700, 2e-3), size, 1e9);
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
  auto boxes = randomCubes<D, T>(rng, 4000, side, size, -0.5 * side);
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

}  // namespace sweep_prune_test
}  // namespace demlab::search
