// CGrid's own properties beyond agreement with the oracle (search_property_test.cpp): how it
// chooses its cell, how its work scales (by its work counters, never by a clock), and that
// it allocates nothing once warm.
#include <gtest/gtest.h>

#include <atomic>
#include <new>
#include <random>

#include "core/thread_pool.hpp"
#include "search/brute_force.hpp"
#include "search/cgrid.hpp"
#include "search/registry.hpp"
#include "support/random_boxes.hpp"

// Counts heap allocations made while `gCounting` is set, for the steady-state test. GCC
// cannot see that the replaced operator new and delete below are a matched pair.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace cgrid_test {
std::atomic<bool> gCounting{false};
std::atomic<long> gAllocations{0};
}  // namespace cgrid_test
using cgrid_test::gAllocations;
using cgrid_test::gCounting;

void* operator new(std::size_t size) {
  if (gCounting.load(std::memory_order_relaxed)) gAllocations.fetch_add(1);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
// The nothrow forms too (std::inplace_merge's temporary buffer, in another test of this
// program): left to the sanitizer's, they would be freed by the replacement above.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  if (gCounting.load(std::memory_order_relaxed)) gAllocations.fetch_add(1);
  return std::malloc(size ? size : 1);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}

namespace demlab::search {
namespace cgrid_test {

using testing::randomBoxes;

// Returns a bed of n equal spheres' boxes (diameter 2) at solid fraction ~0.6 in 3D.
std::vector<Box<3, double>> bed(std::size_t n, uint64_t seed, double offset = 0.0) {
  std::mt19937_64 rng(seed);
  const double side = std::cbrt(static_cast<double>(n) * 4.18879 / 0.6);
  return randomBoxes<3, double>(
      rng, n, side, [](std::mt19937_64&) { return 1.0; }, 0.0, offset);
}

// Returns `boxes` with every box moved by up to `step` on each axis.
std::vector<Box<3, double>> jitter(std::vector<Box<3, double>> boxes, double step, uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (auto& b : boxes) {
    for (int k = 0; k < 3; ++k) {
      const double d = testing::uniform(rng, -step, step);
      b.lo[k] += d;
      b.hi[k] += d;
    }
  }
  return boxes;
}

TEST(CGrid, EveryAlgorithmAllocatesNothingOnceWarm) {
  const auto a = bed(20000, 1);
  const auto b = jitter(a, 0.05, 2);
  for (const auto& row : broadPhaseTable<3, double>()) {
    if (row.name == "brute") continue;
    auto algorithm = row.make({});
    std::vector<IndexPair> out;
    algorithm->findPairs(a, out);  // warm-up on both inputs: buffers reach their sizes
    algorithm->findPairs(b, out);
    gAllocations = 0;
    gCounting = true;
    algorithm->findPairs(a, out);
    algorithm->findPairs(b, out);
    gCounting = false;
    EXPECT_EQ(gAllocations.load(), 0) << row.name;
    EXPECT_GT(out.size(), 0u);
  }
}

TEST(CGrid, ThreadedSearchAllocatesNothingOnceWarm) {
  // The threaded path (lowered threshold, a dozen slabs) on two threads: every slab keeps its
  // buffers, so which thread runs it changes nothing.
  const auto a = bed(20000, 11);
  const auto b = jitter(a, 0.05, 12);
  ThreadPool& pool = ThreadPool::global();
  const unsigned saved = pool.threads();
  pool.setThreads(2);
  CGrid<3, double> grid;
  grid.setThreadedSearch(1000, 1500);
  std::vector<IndexPair> out;
  grid.findPairs(a, out);
  grid.findPairs(b, out);
  gAllocations = 0;
  gCounting = true;
  grid.findPairs(a, out);
  grid.findPairs(b, out);
  gCounting = false;
  pool.setThreads(saved);
  EXPECT_EQ(gAllocations.load(), 0);
  EXPECT_GT(grid.lastSlabs(), 4u);
  EXPECT_GT(out.size(), 0u);
}

TEST(CGrid, CellFollowsTheVolumeOfTheObjects) {
  CGrid<3, double> grid;
  std::vector<IndexPair> out;
  grid.findPairs(bed(1000, 3), out);
  // The default factor x the cube root of the mean box volume, 2^3.
  constexpr double f = CGrid<3, double>::kDefaultCellFactor;
  EXPECT_NEAR(grid.cellSize(), f * 2.0, 1e-12);

  CGrid<3, double> coarse(SearchOptions{2.5});
  coarse.findPairs(bed(1000, 3), out);
  EXPECT_NEAR(coarse.cellSize(), 5.0, 1e-12);

  // Bidisperse 1:10, 10% large by count: the cell sits between the two sizes.
  std::mt19937_64 rng(4);
  auto mixed = randomBoxes<3, double>(rng, 2000, 100.0, [](std::mt19937_64& r) {
    return testing::uniform(r, 0, 1) < 0.1 ? 10.0 : 1.0;
  });
  grid.findPairs(mixed, out);
  EXPECT_GT(grid.cellSize(), f * 2.0);
  EXPECT_LT(grid.cellSize(), f * 20.0 / 2);

  // SGrid needs the largest extent.
  CGrid<3, double> sgrid({}, CGrid<3, double>::Extents::Fixed);
  sgrid.findPairs(mixed, out);
  EXPECT_NEAR(sgrid.cellSize(), 20.0, 1e-9);
  EXPECT_EQ(sgrid.name(), "sgrid");
}

TEST(CGrid, PointsAndFlatBoxesGetAUsableCell) {
  std::vector<Box<2, double>> points(10, Box<2, double>{{1, 1}, {1, 1}});
  CGrid<2, double> grid;
  std::vector<IndexPair> out;
  grid.findPairs(points, out);
  EXPECT_EQ(out.size(), 45u);
  constexpr double f = CGrid<2, double>::kDefaultCellFactor;
  EXPECT_EQ(grid.cellSize(), f);
  std::vector<Box<2, double>> flat = {{{0, 0}, {4, 0}}, {{2, 0}, {6, 0}}, {{5, 1}, {9, 1}}};
  grid.findPairs(flat, out);
  EXPECT_EQ(out.size(), 1u);
  EXPECT_EQ(grid.cellSize(), f * 4.0);  // the mean largest extent
}

TEST(CGrid, WorkPerObjectDoesNotGrowWithN) {
  CGrid<3, double> grid;
  std::vector<IndexPair> out;
  double perObject[2];
  const std::size_t sizes[2] = {10000, 160000};
  for (int i = 0; i < 2; ++i) {
    grid.findPairs(bed(sizes[i], 5), out);
    perObject[i] = static_cast<double>(grid.stats().maskEntries) / sizes[i];
  }
  EXPECT_NEAR(perObject[1] / perObject[0], 1.0, 0.1);
  // Each object spans 1 + d/h buckets per axis: (1 + 2/4)^2 ~ 2.3 rows at the default cell
  // (2 diameters), plus the edges.
  EXPECT_LT(perObject[1], 3.5);
}

TEST(CGrid, EmptySpaceCostsNothing) {
  // Two clusters about a million cells apart do the work of the two clusters alone.
  CGrid<3, double> grid;
  std::vector<IndexPair> out;
  auto one = bed(20000, 6);
  grid.findPairs(one, out);
  const auto workOne = grid.stats();
  const auto pairsOne = out.size();
  auto two = one;
  auto far = bed(20000, 6, 3e6);
  two.insert(two.end(), far.begin(), far.end());
  grid.findPairs(two, out);
  EXPECT_EQ(out.size(), 2 * pairsOne);
  // The far cluster's buckets may be aligned differently by rounding: equal within 2%.
  EXPECT_NEAR(static_cast<double>(grid.stats().maskEntries) / workOne.maskEntries, 2.0, 0.04);
  EXPECT_NEAR(static_cast<double>(grid.stats().forwarded) / workOne.forwarded, 2.0, 0.04);
}

TEST(CGrid, DomainSizedWallsBarelyAddWork) {
  CGrid<3, double> grid;
  std::vector<IndexPair> out;
  auto boxes = bed(50000, 7);
  grid.findPairs(boxes, out);
  const double base = static_cast<double>(grid.stats().maskEntries + grid.stats().forwarded);
  const std::size_t basePairs = out.size();
  const double side = std::cbrt(50000 * 4.18879 / 0.6);
  for (int axis = 0; axis < 2; ++axis) {
    for (double at : {-2.0, side}) {
      Box<3, double> wall{{-2, -2, -2}, {side + 2, side + 2, side + 2}};
      wall.lo[axis] = at;
      wall.hi[axis] = at + 2.0;
      boxes.push_back(wall);
    }
  }
  grid.findPairs(boxes, out);
  const double withWalls = static_cast<double>(grid.stats().maskEntries + grid.stats().forwarded);
  EXPECT_GT(out.size(), basePairs);
  EXPECT_LT(withWalls / base, 1.5);
}

// Returns the scenes the two builds of the mask's scans are compared on: beds, mixed sizes,
// domain-sized walls, touching faces, a sparse and a dense scene, in D dimensions.
template <int D>
std::vector<std::vector<Box<D, double>>> scanScenes(uint64_t seed) {
  std::mt19937_64 rng(seed);
  const double side = 30.0;
  std::vector<std::vector<Box<D, double>>> scenes;
  scenes.push_back(randomBoxes<D, double>(rng, 3000, side, [](std::mt19937_64&) { return 0.7; }));
  scenes.push_back(randomBoxes<D, double>(rng, 2000, side, [](std::mt19937_64& r) {
    return testing::uniform(r, 0, 1) < 0.05 ? 8.0 : 0.3;
  }));
  scenes.push_back(randomBoxes<D, double>(
      rng, 2000, side, [](std::mt19937_64& r) { return testing::uniform(r, 0, 1.5); }, 1.0));
  scenes.push_back(randomBoxes<D, double>(rng, 500, 1e6, [](std::mt19937_64&) { return 3e4; }));
  auto walls = randomBoxes<D, double>(rng, 2000, side, [](std::mt19937_64&) { return 0.7; });
  for (int axis = 0; axis < D; ++axis) {
    Box<D, double> wall;
    wall.lo.fill(-1.0);
    wall.hi.fill(side + 1.0);
    wall.hi[axis] = 0.0;
    walls.push_back(wall);
  }
  scenes.push_back(walls);
  // Dense enough (about 8 objects a cell) that the sort keys of discretization order objects
  // within their buckets too.
  const double denseSide = 3.6 * std::pow(3000.0 / 8, 1.0 / D);
  scenes.push_back(
      randomBoxes<D, double>(rng, 3000, denseSide, [](std::mt19937_64&) { return 1.0; }));
  return scenes;
}

// The AVX2 and the portable scans of the contact mask report the same pairs in the same
// order, and both the oracle's pairs.
template <int D>
void expectScansAgree(uint64_t seed) {
  CGrid<D, double> wide, portable;
  if (!wide.wideScans()) GTEST_SKIP() << "this CPU has no AVX2: only the portable scans run";
  portable.useWideScans(false);
  ASSERT_FALSE(portable.wideScans());
  std::vector<IndexPair> a, b, expected;
  int scene = 0;
  for (const auto& boxes : scanScenes<D>(seed)) {
    wide.findPairs(boxes, a);
    portable.findPairs(boxes, b);
    BruteForce<D, double>().findPairs(boxes, expected);
    EXPECT_EQ(a, b) << "D=" << D << " scene " << scene;
    EXPECT_EQ(testing::sorted(b), testing::sorted(expected)) << "D=" << D << " scene " << scene;
    EXPECT_GT(expected.size(), 0u);
    ++scene;
  }
}

TEST(CGrid, WideAndPortableScansReportTheSamePairs) {
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    expectScansAgree<1>(seed);
    expectScansAgree<2>(seed);
    expectScansAgree<3>(seed);
    expectScansAgree<4>(seed);
  }
}

}  // namespace cgrid_test
}  // namespace demlab::search
