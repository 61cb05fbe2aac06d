// The recursive coordinate bisection (mpi/partition.hpp) on one rank, against brute force:
// every point of space has exactly one box and ownerOf finds it, the boxes hold their shares
// of the points (of the weight) to within what ties allow, the cuts go through the points
// where a bed fills part of its box, and forEachNear lists exactly the boxes within reach.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "mpi/partition.hpp"

namespace demlab::mpi {
namespace mpi_partition_test {

template <int D>
std::vector<Point<D>> randomPoints(size_t n, unsigned seed, double height = 1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Point<D>> points(n);
  for (auto& p : points) {
    for (int a = 0; a < D; ++a) p[a] = u(rng);
    p[D - 1] *= height;
  }
  return points;
}

// Returns the ranks whose box holds p, by brute force.
template <int D>
std::vector<int> holders(const Partition<D>& part, const std::type_identity_t<Point<D>>& p) {
  std::vector<int> out;
  for (int k = 0; k < part.parts(); ++k) {
    if (part.box(k).contains(p)) out.push_back(k);
  }
  return out;
}

template <int D, class Points>
void checkTiling(const Partition<D>& part, const Points& points, unsigned seed) {
  for (const auto& p : points) {
    const std::vector<int> h = holders(part, p);
    ASSERT_EQ(h.size(), 1u);
    EXPECT_EQ(part.ownerOf(p), h[0]);
  }
  // Probes anywhere, far outside the points too.
  std::mt19937_64 rng(seed + 99);
  std::uniform_real_distribution<double> u(-1e3, 1e3);
  for (int i = 0; i < 500; ++i) {
    Point<D> p;
    for (int a = 0; a < D; ++a) p[a] = i % 2 ? u(rng) : u(rng) * 1e-3;
    const std::vector<int> h = holders(part, p);
    ASSERT_EQ(h.size(), 1u);
    EXPECT_EQ(part.ownerOf(p), h[0]);
  }
}

template <int D>
void evenSplits() {
  for (int parts : {1, 2, 3, 5, 8, 13}) {
    for (unsigned seed = 1; seed <= 3; ++seed) {
      SCOPED_TRACE("parts " + std::to_string(parts) + " seed " + std::to_string(seed));
      const size_t n = 3000 + 517 * seed;
      const auto points = randomPoints<D>(n, seed);
      const Partition<D> part = Partition<D>::bisect(points, {}, parts, Communicator::self());
      ASSERT_EQ(part.parts(), parts);
      checkTiling(part, points, seed);
      std::vector<double> count(static_cast<size_t>(parts), 0.0);
      for (const auto& p : points) count[static_cast<size_t>(part.ownerOf(p))] += 1;
      // Distinct coordinates: each level's cut is within half a point of its target, so a box
      // is within a point a level of its share.
      const double levels = std::ceil(std::log2(parts)) + 1;
      for (double c : count) EXPECT_LE(std::abs(c - double(n) / parts), levels);
    }
  }
}

TEST(Partition, RandomPointsSplitEvenlyIntoBoxesThatTileSpace2D) { evenSplits<2>(); }
TEST(Partition, RandomPointsSplitEvenlyIntoBoxesThatTileSpace3D) { evenSplits<3>(); }

TEST(Partition, WeightsAreBalancedNotCounts) {
  auto points = randomPoints<3>(4000, 5);
  std::vector<double> weights(points.size());
  // A box twice as long in x, whose points at x < 0.6 cost ten times as much (a dense region
  // among loose ones): the first cut goes across x, far from the middle.
  for (size_t i = 0; i < points.size(); ++i) {
    points[i][0] *= 2;
    weights[i] = points[i][0] < 0.6 ? 10.0 : 1.0;
  }
  for (int parts : {2, 4, 7}) {
    const Partition<3> part = Partition<3>::bisect(points, weights, parts, Communicator::self());
    std::vector<double> w(static_cast<size_t>(parts), 0.0), c(static_cast<size_t>(parts), 0.0);
    for (size_t i = 0; i < points.size(); ++i) {
      w[static_cast<size_t>(part.ownerOf(points[i]))] += weights[i];
      c[static_cast<size_t>(part.ownerOf(points[i]))] += 1;
    }
    // Within a heaviest point (10) a level of the mean weight; the counts are far from even.
    double total = 0;
    for (double x : weights) total += x;
    const double levels = std::ceil(std::log2(parts)) + 1;
    EXPECT_LE(Partition<3>::imbalance(w), 1 + levels * 10.0 * parts / total) << parts;
    EXPECT_GT(Partition<3>::imbalance(c), 1.3) << parts;
  }
}

// A settled bed fills the bottom tenth of a tall box: the cuts must go through the grains (the
// axis the points spread along), not through the empty top.
TEST(Partition, ASettledBedIsCutThroughItsGrains) {
  const auto points = randomPoints<3>(6000, 7, 0.1);
  for (int parts : {2, 4, 6}) {
    const Partition<3> part = Partition<3>::bisect(points, {}, parts, Communicator::self());
    std::vector<double> count(static_cast<size_t>(parts), 0.0);
    for (const auto& p : points) count[static_cast<size_t>(part.ownerOf(p))] += 1;
    EXPECT_LT(Partition<3>::imbalance(count), 1.01) << parts;
    for (const auto& node : part.nodes()) {
      if (node.axis >= 0) {
        EXPECT_NE(node.axis, 2) << "a cut across the bed's thin axis";
      }
    }
  }
}

// Points that cannot be told apart (coincident, or one coordinate shared): the bisection ends
// and every point still has one box.
TEST(Partition, CoincidentPointsEndAndKeepOneOwnerEach) {
  std::vector<Point<2>> same(500, Point<2>{0.25, -3.5});
  const Partition<2> a = Partition<2>::bisect(same, {}, 4, Communicator::self());
  checkTiling(a, same, 1);
  auto line = randomPoints<2>(800, 3);
  for (auto& p : line) p[0] = 0.5;  // all on one vertical line: the cuts go along y
  const Partition<2> b = Partition<2>::bisect(line, {}, 4, Communicator::self());
  checkTiling(b, line, 2);
  std::vector<double> count(4, 0.0);
  for (const auto& p : line) count[static_cast<size_t>(b.ownerOf(p))] += 1;
  EXPECT_LT(Partition<2>::imbalance(count), 1.02);
  // No points at all: boxes still tile space.
  const Partition<3> empty = Partition<3>::bisect({}, {}, 5, Communicator::self());
  checkTiling(empty, randomPoints<3>(50, 4), 3);
}

TEST(Partition, ForEachNearListsExactlyTheBoxesWithinReach) {
  const auto points = randomPoints<3>(5000, 11);
  const Partition<3> part = Partition<3>::bisect(points, {}, 11, Communicator::self());
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-0.2, 1.2), reach(0, 0.5);
  for (int i = 0; i < 2000; ++i) {
    const Point<3> p{u(rng), u(rng), u(rng)};
    const double r = reach(rng);
    std::vector<int> got, want;
    part.forEachNear(p, r * r, [&](int k) { got.push_back(k); });
    for (int k = 0; k < part.parts(); ++k) {
      if (part.box(k).distance2(p) < r * r) want.push_back(k);
    }
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want);
  }
}

TEST(Partition, BadArgumentsAreRefused) {
  auto points = randomPoints<2>(10, 1);
  EXPECT_THROW(Partition<2>::bisect(points, {}, 0, Communicator::self()), std::invalid_argument);
  EXPECT_THROW(Partition<2>::bisect(points, {1.0, 2.0}, 2, Communicator::self()),
               std::invalid_argument);
  std::vector<double> weights(points.size(), 1.0);
  weights[3] = -1;
  EXPECT_THROW(Partition<2>::bisect(points, weights, 2, Communicator::self()),
               std::invalid_argument);
  weights[3] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(Partition<2>::bisect(points, weights, 2, Communicator::self()),
               std::invalid_argument);
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()}) {
    auto withBad = points;
    withBad[4][1] = bad;
    EXPECT_THROW(Partition<2>::bisect(withBad, {}, 3, Communicator::self()),
                 std::invalid_argument);
  }
}

// Coordinates near the largest doubles (their spread overflows): the bisection still ends,
// balanced, and every point has one box.
TEST(Partition, CoordinatesNearTheLargestDoublesStillSplit) {
  auto points = randomPoints<3>(2000, 21);
  for (size_t i = 0; i < points.size(); ++i) {
    points[i][0] = (points[i][0] - 0.5) * 2.0 * 1e308;  // a spread near 2e308: more than DBL_MAX
    points[i][1] *= i % 2 ? 1e-300 : 1e300;
  }
  for (int parts : {2, 5}) {
    const Partition<3> part = Partition<3>::bisect(points, {}, parts, Communicator::self());
    for (const auto& p : points) ASSERT_EQ(holders(part, p).size(), 1u);
    std::vector<double> count(static_cast<size_t>(parts), 0.0);
    for (const auto& p : points) count[static_cast<size_t>(part.ownerOf(p))] += 1;
    EXPECT_LT(Partition<3>::imbalance(count), 1.01) << parts;
  }
}

}  // namespace mpi_partition_test
}  // namespace demlab::mpi
