// CGrid's threaded search: for every thread count it reports exactly the serial search's
// pairs in the serial search's order (the slabs depend on the input alone), and those pairs
// are the oracle's. The inputs are small, with the threaded path's threshold and slab size
// lowered so that they still cut into many slabs.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "core/thread_pool.hpp"
#include "search/brute_force.hpp"
#include "search/cgrid.hpp"
#include "support/random_boxes.hpp"

namespace demlab::search {
namespace cgrid_threads_test {

using testing::randomBoxes;
using testing::sorted;
using testing::uniform;

// Sets the pool's thread count for the life of the guard and restores the former count.
class PoolThreads {
 public:
  explicit PoolThreads(unsigned n) : saved_(ThreadPool::global().threads()) {
    ThreadPool::global().setThreads(n);
  }
  ~PoolThreads() { ThreadPool::global().setThreads(saved_); }
  PoolThreads(const PoolThreads&) = delete;
  PoolThreads& operator=(const PoolThreads&) = delete;

 private:
  unsigned saved_;
};

// The threaded path from 1000 boxes on, about 150 objects a slab: a scene of a few thousand
// boxes makes a dozen slabs or more.
constexpr std::size_t kMinBoxes = 1000;
constexpr std::size_t kObjectsPerSlab = 150;

template <int D>
using Scene = std::vector<Box<D, double>>;

// Returns the scenes: equal balls; widely varying sizes with domain-sized boxes; dense
// clusters far apart; coordinates on a coarse lattice (many equal values, touching faces);
// everything in three thin sheets across axis 0 (few axis-0 buckets, long runs); a sparse
// scene (the grid too large to number: axis-0 order only, the Subdividers sort).
template <int D>
std::vector<std::pair<std::string, Scene<D>>> scenes(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::pair<std::string, Scene<D>>> list;
  const double side = 4.0 * std::pow(3000.0, 1.0 / D);
  list.emplace_back("uniform",
                    randomBoxes<D, double>(rng, 3000, side, [](std::mt19937_64&) { return 1.0; }));

  auto varied = randomBoxes<D, double>(rng, 2500, side, [](std::mt19937_64& r) {
    // Half-widths 0.2 .. 10 with density ~ r^-3 (inverse CDF).
    const double a = 0.2, b = 10.0, u = uniform(r, 0, 1);
    return 1.0 / std::sqrt(1.0 / (a * a) - u * (1.0 / (a * a) - 1.0 / (b * b)));
  });
  for (int axis = 0; axis < D; ++axis) {
    Box<D, double> wall;
    wall.lo.fill(-1.0);
    wall.hi.fill(side + 1.0);
    wall.hi[axis] = 0.0;
    varied.push_back(wall);
  }
  Box<D, double> everything;
  everything.lo.fill(-2.0);
  everything.hi.fill(side + 2.0);
  varied.insert(varied.begin() + 1000, everything);
  list.emplace_back("varied sizes and domain-sized boxes", varied);

  Scene<D> clustered;
  for (int c = 0; c < 6; ++c) {
    auto cluster = randomBoxes<D, double>(
        rng, 500, 12.0, [](std::mt19937_64& r) { return uniform(r, 0.3, 1.2); }, 0.0, 1e4 * c);
    clustered.insert(clustered.end(), cluster.begin(), cluster.end());
  }
  list.emplace_back("clustered", clustered);

  list.emplace_back("lattice", randomBoxes<D, double>(
                                   rng, 3000, side,
                                   [](std::mt19937_64& r) { return uniform(r, 0, 2.5); }, 1.0));

  auto sheets = randomBoxes<D, double>(rng, 3000, side, [](std::mt19937_64&) { return 0.8; });
  for (std::size_t i = 0; i < sheets.size(); ++i) {
    const double x = 5.0 * static_cast<double>(i % 3);
    sheets[i].lo[0] = x;
    sheets[i].hi[0] = x + 0.5 * static_cast<double>(i % 2);
  }
  list.emplace_back("three sheets", sheets);

  list.emplace_back("sparse", randomBoxes<D, double>(rng, 2000, 1e9,
                                                     [](std::mt19937_64&) { return 4e7; }));
  return list;
}

// Checks that the threaded search on `boxes` with 1, 2, 3, 4 and 7 threads reports the serial
// search's pairs in its order, and its counters, and the oracle's pairs.
template <int D>
void expectThreadedIsSerial(const Scene<D>& boxes, const std::string& scene,
                            typename CGrid<D, double>::Extents extents) {
  std::vector<IndexPair> serial, oracle;
  typename CGrid<D, double>::Stats serialStats;
  {
    PoolThreads one(1);
    CGrid<D, double> grid({}, extents);
    grid.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
    grid.findPairs(boxes, serial);
    serialStats = grid.stats();
    EXPECT_EQ(grid.lastSlabs(), 1u);
  }
  BruteForce<D, double>().findPairs(boxes, oracle);
  ASSERT_EQ(sorted(serial), sorted(oracle)) << scene << " D=" << D;
  EXPECT_GT(serial.size(), 0u) << scene;

  // One grid kept across the thread counts (its slabs' buffers reused) and a new one per count.
  CGrid<D, double> kept({}, extents);
  kept.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
  for (unsigned threads : {1u, 2u, 3u, 4u, 7u}) {
    PoolThreads pool(threads);
    CGrid<D, double> fresh({}, extents);
    fresh.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
    std::vector<IndexPair> got = {{7, 9}};  // replaced, not appended to
    fresh.findPairs(boxes, got);
    EXPECT_EQ(got, serial) << scene << " D=" << D << " threads " << threads;
    for (int pass = 0; pass < 2; ++pass) {
      kept.findPairs(boxes, got);
      EXPECT_EQ(got, serial) << scene << " D=" << D << " threads " << threads << " kept grid";
    }
    EXPECT_EQ(kept.stats().forwarded, serialStats.forwarded) << scene;
    EXPECT_EQ(kept.stats().maskEntries, serialStats.maskEntries) << scene;
    if (threads > 1) {
      // The slabs come from the input alone: the same count for every thread count.
      EXPECT_GT(kept.lastSlabs(), 1u) << scene << " D=" << D;
      EXPECT_EQ(kept.lastSlabs(), fresh.lastSlabs()) << scene;
    }
  }
}

template <int D>
void expectAllScenes(uint64_t seed) {
  for (const auto& [name, boxes] : scenes<D>(seed)) {
    expectThreadedIsSerial<D>(boxes, name, CGrid<D, double>::Extents::Arbitrary);
  }
}

TEST(CGridThreads, SameOutputAsSerial2D) { expectAllScenes<2>(21); }
TEST(CGridThreads, SameOutputAsSerial3D) { expectAllScenes<3>(31); }

TEST(CGridThreads, SGridSameOutputAsSerial) {
  // Fixed extents need no object wider than a cell: the uniform and lattice scenes.
  auto list = scenes<3>(41);
  expectThreadedIsSerial<3>(list[0].second, list[0].first, CGrid<3, double>::Extents::Fixed);
  expectThreadedIsSerial<3>(list[3].second, list[3].first, CGrid<3, double>::Extents::Fixed);
}

TEST(CGridThreads, FloatBoxesSameOutputAsSerial) {
  std::mt19937_64 rng(51);
  const auto boxes =
      randomBoxes<3, float>(rng, 3000, 60.0, [](std::mt19937_64& r) { return uniform(r, 0.5, 3); });
  std::vector<IndexPair> serial, got, oracle;
  {
    PoolThreads one(1);
    CGrid<3, float> grid;
    grid.findPairs(boxes, serial);
  }
  BruteForce<3, float>().findPairs(boxes, oracle);
  EXPECT_EQ(sorted(serial), sorted(oracle));
  CGrid<3, float> grid;
  grid.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
  for (unsigned threads : {2u, 3u}) {
    PoolThreads pool(threads);
    grid.findPairs(boxes, got);
    EXPECT_EQ(got, serial) << "threads " << threads;
    EXPECT_GT(grid.lastSlabs(), 1u);
  }
}

TEST(CGridThreads, ManyMoreThreadsThanCores) {
  const auto list = scenes<3>(61);
  std::vector<IndexPair> serial, got;
  CGrid<3, double> grid;
  grid.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
  {
    PoolThreads one(1);
    grid.findPairs(list[1].second, serial);
  }
  PoolThreads many(64);
  grid.findPairs(list[1].second, got);
  EXPECT_EQ(got, serial);
  EXPECT_GT(grid.lastSlabs(), 1u);
}

TEST(CGridThreads, SmallInputsAndOneThreadStaySerial) {
  std::mt19937_64 rng(71);
  const auto boxes =
      randomBoxes<3, double>(rng, 5000, 60.0, [](std::mt19937_64&) { return 1.0; });
  std::vector<IndexPair> out;
  PoolThreads two(2);
  CGrid<3, double> grid;  // default threshold: 5000 boxes are below it
  grid.findPairs(boxes, out);
  EXPECT_EQ(grid.lastSlabs(), 1u);
  grid.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
  grid.findPairs(boxes, out);
  EXPECT_GT(grid.lastSlabs(), 1u);
  ThreadPool::global().setThreads(1);
  grid.findPairs(boxes, out);
  EXPECT_EQ(grid.lastSlabs(), 1u);
}

// A stop flag that stays clear changes nothing: the output grows a slice at a time then, and
// the pairs are the serial search's, serially and threaded.
TEST(CGridThreads, ClearStopFlagChangesNothing) {
  const auto list = scenes<3>(81);
  const std::atomic<bool> clear{false};
  for (const auto& [name, boxes] : list) {
    std::vector<IndexPair> serial;
    {
      PoolThreads one(1);
      CGrid<3, double> grid;
      grid.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
      grid.findPairs(boxes, serial);
    }
    for (unsigned threads : {1u, 2u, 3u}) {
      PoolThreads pool(threads);
      CGrid<3, double> grid;
      grid.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
      grid.setStop(&clear);
      std::vector<IndexPair> got;
      grid.findPairs(boxes, got);
      EXPECT_FALSE(grid.stopped()) << name;
      EXPECT_EQ(got, serial) << name << " threads " << threads;
    }
  }
}

// A set stop flag stops the search: no pairs and stopped(); the same grid, the flag cleared,
// then searches as a new one does.
TEST(CGridThreads, SetStopFlagStopsTheSearch) {
  const auto boxes = scenes<3>(91)[1].second;
  std::vector<IndexPair> serial;
  {
    PoolThreads one(1);
    CGrid<3, double>().findPairs(boxes, serial);
  }
  for (unsigned threads : {1u, 2u}) {
    PoolThreads pool(threads);
    std::atomic<bool> stop{true};
    CGrid<3, double> grid;
    grid.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
    grid.setStop(&stop);
    std::vector<IndexPair> got = {{1, 2}};
    grid.findPairs(boxes, got);
    EXPECT_TRUE(grid.stopped()) << "threads " << threads;
    EXPECT_TRUE(got.empty()) << "threads " << threads;
    stop = false;
    grid.findPairs(boxes, got);
    EXPECT_FALSE(grid.stopped());
    EXPECT_EQ(got, serial) << "threads " << threads;
  }
}

// A flag set by another thread while a search of many pairs runs stops it part way or not at
// all: either no pairs and stopped(), or every pair.
TEST(CGridThreads, StopFlagSetDuringTheSearch) {
  std::mt19937_64 rng(95);
  const auto boxes =
      randomBoxes<3, double>(rng, 20000, 40.0, [](std::mt19937_64&) { return 2.0; });
  std::vector<IndexPair> serial;
  CGrid<3, double>().findPairs(boxes, serial);
  for (unsigned threads : {1u, 2u}) {
    PoolThreads pool(threads);
    for (int delayUs : {0, 200, 2000, 20000}) {
      std::atomic<bool> stop{false};
      CGrid<3, double> grid;
      grid.setThreadedSearch(kMinBoxes, kObjectsPerSlab);
      grid.setStop(&stop);
      std::vector<IndexPair> got;
      std::thread setter([&] {
        std::this_thread::sleep_for(std::chrono::microseconds(delayUs));
        stop = true;
      });
      grid.findPairs(boxes, got);
      setter.join();
      if (grid.stopped()) {
        EXPECT_TRUE(got.empty()) << threads << " " << delayUs;
      } else {
        EXPECT_EQ(got, serial) << threads << " " << delayUs;
      }
    }
  }
}

}  // namespace cgrid_threads_test
}  // namespace demlab::search
