#include "search/workload.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <set>

#include "search/brute_force.hpp"

namespace demlab::search {
namespace workload_test {

constexpr Distribution kAll[] = {Distribution::Uniform, Distribution::Bidisperse,
                                 Distribution::PowerLaw, Distribution::PowerLawWalls,
                                 Distribution::Clustered, Distribution::Rods};

template <int D>
bool sameBoxes(const std::vector<Box<D, double>>& a, const std::vector<Box<D, double>>& b) {
  // Bitwise, because determinism means the very same doubles, not nearly equal ones.
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

// Half the extent of a box on axis k: the radius of the ball it bounds.
template <int D>
double halfExtent(const Box<D, double>& b, int k) {
  return 0.5 * (b.hi[k] - b.lo[k]);
}

template <int D>
double meanNeighbours(const std::vector<Box<D, double>>& boxes) {
  BruteForce<D, double> bf;
  std::vector<IndexPair> pairs;
  bf.findPairs(boxes, pairs);
  return 2.0 * static_cast<double>(pairs.size()) / static_cast<double>(boxes.size());
}

TEST(Workload, NamesRoundTrip) {
  for (Distribution d : kAll) EXPECT_EQ(parseDistribution(distributionName(d)), d);
  EXPECT_EQ(distributionName(Distribution::PowerLawWalls), "powerlaw_walls");
  EXPECT_FALSE(parseDistribution("gaussian").has_value());
  EXPECT_FALSE(parseDistribution("").has_value());
}

template <int D>
void checkDeterminism() {
  for (Distribution d : kAll) {
    const WorkloadSpec spec{d, 500, 10.0, 42};
    const auto a = makeWorkload<D, double>(spec);
    const auto b = makeWorkload<D, double>(spec);
    EXPECT_TRUE(sameBoxes<D>(a, b)) << distributionName(d) << " D=" << D;
    WorkloadSpec other = spec;
    other.seed = 43;
    EXPECT_FALSE(sameBoxes<D>(a, makeWorkload<D, double>(other)))
        << distributionName(d) << " D=" << D;
  }
}

TEST(Workload, SameSeedSameBoxes) {
  checkDeterminism<1>();
  checkDeterminism<2>();
  checkDeterminism<3>();
  checkDeterminism<4>();
}

// Pins the generator's output, so a change of the real-number mapping (or a library whose
// <random> differs) shows up here rather than as an unexplained shift in benchmark tables.
TEST(Workload, FirstBoxIsPinned) {
  const auto boxes = makeWorkload<3, double>({Distribution::Uniform, 1000, 1.0, 1});
  ASSERT_EQ(boxes.size(), 1000u);
  const std::uint64_t first = std::mt19937_64(1)();
  const double u = static_cast<double>(first >> 11) * 0x1.0p-53;
  // Side of the cube for 1000 unit balls at 9.17 expected neighbours: 4 (1000 / k)^(1/3).
  const double side = 4.0 * std::cbrt(1000.0 / workload_detail::kNeighbours);
  EXPECT_NEAR(boxes[0].lo[0], side * u - 1.0, 1e-12);
  EXPECT_NEAR(boxes[0].hi[0], side * u + 1.0, 1e-12);
}

template <int D>
void checkCountsAndRadii() {
  for (Distribution d : kAll) {
    for (std::size_t n : {0u, 1u, 2u, 3u, 5u, 999u}) {
      for (double ratio : {1.0, 10.0, 1000.0}) {
        const auto boxes = makeWorkload<D, double>({d, n, ratio, 7});
        ASSERT_EQ(boxes.size(), n) << distributionName(d) << " D=" << D;
        const std::size_t nWalls =
            d == Distribution::PowerLawWalls ? std::min<std::size_t>(n, D == 1 ? 2 : 4) : 0;
        const double rMax = isMonodisperse(d) ? 1.0 : ratio;
        for (std::size_t i = 0; i + nWalls < n; ++i) {
          if (isElongated(d)) {
            // A rod of radius 1 and half length h = ratio - 1 along a unit direction u: its
            // box reaches 1 + h |u_k| on axis k, so sum_k (extent_k - 1)^2 = h^2.
            const double h = ratio - 1.0;
            double sum = 0.0;
            for (int k = 0; k < D; ++k) {
              const double e = halfExtent<D>(boxes[i], k) - 1.0;
              EXPECT_GE(e, -1e-9);
              sum += e * e;
            }
            EXPECT_NEAR(sum, h * h, 1e-9 * (1.0 + h * h)) << "rod " << i << " D=" << D;
            continue;
          }
          const double r = halfExtent<D>(boxes[i], 0);
          EXPECT_GE(r, 1.0 - 1e-9);
          EXPECT_LE(r, rMax * (1.0 + 1e-12));
          // Balls: the same extent on every axis.
          for (int k = 1; k < D; ++k) EXPECT_NEAR(halfExtent<D>(boxes[i], k), r, 1e-9 * r);
          if (d == Distribution::Bidisperse) {
            EXPECT_TRUE(std::abs(r - 1.0) < 1e-9 || std::abs(r - ratio) < 1e-9 * ratio) << r;
          }
        }
      }
    }
  }
}

TEST(Workload, CountsAndRadiiWithinBounds) {
  checkCountsAndRadii<1>();
  checkCountsAndRadii<2>();
  checkCountsAndRadii<3>();
  checkCountsAndRadii<4>();
}

TEST(Workload, BidisperseHasTenPercentLarge) {
  for (std::size_t n : {10u, 995u, 1000u, 12345u}) {
    const auto boxes = makeWorkload<3, double>({Distribution::Bidisperse, n, 100.0, 3});
    std::size_t large = 0;
    for (const auto& b : boxes) large += halfExtent<3>(b, 0) > 50.0;
    EXPECT_EQ(large, static_cast<std::size_t>(std::llround(0.1 * static_cast<double>(n)))) << n;
  }
}

TEST(Workload, PowerLawFollowsItsCdf) {
  // F(r) = (1 - r^-2) / (1 - R^-2): for R = 10, F(2) = 0.75 / 0.99 and F(5) = 0.96 / 0.99.
  const std::size_t n = 200000;
  const auto boxes = makeWorkload<2, double>({Distribution::PowerLaw, n, 10.0, 5});
  std::size_t below2 = 0, below5 = 0;
  for (const auto& b : boxes) {
    below2 += halfExtent<2>(b, 0) < 2.0;
    below5 += halfExtent<2>(b, 0) < 5.0;
  }
  EXPECT_NEAR(static_cast<double>(below2) / n, 0.75 / 0.99, 0.005);
  EXPECT_NEAR(static_cast<double>(below5) / n, 0.96 / 0.99, 0.003);
}

template <int D>
void checkWalls() {
  const std::size_t n = 3000;
  const auto boxes = makeWorkload<D, double>({Distribution::PowerLawWalls, n, 10.0, 9});
  const std::size_t nWalls = D == 1 ? 2 : 4;
  // The balls' centres fill [0, side]^D; recover side from the walls' spanning extent.
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i + nWalls < n; ++i) {
    for (int k = 0; k < D; ++k) {
      lo = std::min(lo, 0.5 * (boxes[i].lo[k] + boxes[i].hi[k]));
      hi = std::max(hi, 0.5 * (boxes[i].lo[k] + boxes[i].hi[k]));
    }
  }
  for (std::size_t w = 0; w < nWalls; ++w) {
    const auto& b = boxes[n - nWalls + w];
    const int axis = static_cast<int>(w / 2);
    const bool low = w % 2 == 0;
    for (int k = 0; k < D; ++k) {
      if (k == axis) {
        // 2 r_min thick across its face (1D: reaching outward from the face).
        if (low) {
          EXPECT_DOUBLE_EQ(b.hi[k], 1.0);
          if (D > 1) {
            EXPECT_DOUBLE_EQ(b.lo[k], -1.0);
          }
          EXPECT_LE(b.lo[k], lo);
        } else {
          EXPECT_GE(b.hi[k], hi);
          if (D > 1) {
            EXPECT_DOUBLE_EQ(b.hi[k] - b.lo[k], 2.0);
          }
        }
      } else {
        EXPECT_LE(b.lo[k], lo);  // spans every ball centre on the other axes
        EXPECT_GE(b.hi[k], hi);
      }
    }
    if (D == 1) {
      EXPECT_GE(b.hi[0] - b.lo[0], 0.9 * (hi - lo));  // domain-long in 1D too
    }
  }
}

TEST(Workload, WallsSpanTheDomain) {
  checkWalls<1>();
  checkWalls<2>();
  checkWalls<3>();
  checkWalls<4>();
}

template <int D>
void checkClusters() {
  const auto boxes = makeWorkload<D, double>({Distribution::Clustered, 8000, 1.0, 11});
  std::set<std::array<long, D>> cells;
  for (const auto& b : boxes) {
    std::array<long, D> cell;
    for (int k = 0; k < D; ++k) cell[k] = std::lround(b.lo[k] / 1e6);
    cells.insert(cell);
  }
  EXPECT_EQ(cells.size(), 8u) << "D=" << D;
  // Dense inside: the monodisperse neighbour count, far from any other cluster.
  const double k = meanNeighbours<D>(boxes);
  EXPECT_GT(k, 5.0) << "D=" << D;
  EXPECT_LT(k, 12.0) << "D=" << D;
}

TEST(Workload, ClustersAreDenseAndFarApart) {
  checkClusters<1>();
  checkClusters<2>();
  checkClusters<3>();
}

TEST(Workload, UniformHasGranularBedNeighbourCount) {
  // About 9 expected overlapping boxes per box, a little less at n = 2000 because balls near
  // the domain faces have fewer neighbours.
  const double k1 = meanNeighbours<1>(makeWorkload<1, double>({Distribution::Uniform, 2000, 1}));
  const double k2 = meanNeighbours<2>(makeWorkload<2, double>({Distribution::Uniform, 2000, 1}));
  const double k3 = meanNeighbours<3>(makeWorkload<3, double>({Distribution::Uniform, 2000, 1}));
  const double k4 = meanNeighbours<4>(makeWorkload<4, double>({Distribution::Uniform, 2000, 1}));
  for (double k : {k1, k2, k3, k4}) {
    EXPECT_GE(k, 6.0);
    EXPECT_LE(k, 12.0);
  }
}

TEST(Workload, BadSizeRatioIsRejected) {
  for (double ratio : {0.5, std::nan(""), static_cast<double>(INFINITY)}) {
    try {
      makeWorkload<2, double>({Distribution::PowerLaw, 10, ratio});
      FAIL() << "expected an error for ratio " << ratio;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", "WORKLOAD"}));
    }
  }
  // Monodisperse sets ignore the ratio.
  const auto uniform = makeWorkload<2, double>({Distribution::Uniform, 10, 0.5});
  EXPECT_EQ(uniform.size(), 10u);
}

TEST(Workload, FloatCoordinates) {
  const auto boxes = makeWorkload<3, float>({Distribution::Bidisperse, 100, 10.0});
  ASSERT_EQ(boxes.size(), 100u);
  for (const auto& b : boxes) EXPECT_LE(b.lo[0], b.hi[0]);
}

}  // namespace workload_test
}  // namespace demlab::search
