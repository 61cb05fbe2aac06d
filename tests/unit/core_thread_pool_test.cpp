// ThreadPool: every task runs exactly once for any thread count (more threads than cores
// included), a region inside a task runs inline, the lowest task's exception reaches the
// caller after all tasks end, and the pool can be resized between regions.
#include <gtest/gtest.h>

#include <atomic>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "core/thread_pool.hpp"

namespace demlab {
namespace core_thread_pool_test {

// Restores the pool's thread count when a test ends.
struct KeepThreads {
  unsigned before = ThreadPool::global().threads();
  ~KeepThreads() { ThreadPool::global().setThreads(before); }
};

TEST(ThreadPool, EveryTaskRunsOnceForAnyThreadCount) {
  KeepThreads keep;
  ThreadPool& pool = ThreadPool::global();
  for (unsigned t : {1u, 2u, 3u, 4u, 9u}) {
    pool.setThreads(t);
    ASSERT_EQ(pool.threads(), t);
    for (size_t n : {0u, 1u, 2u, 7u, 1000u}) {
      std::vector<int> hits(n, 0);
      std::vector<unsigned> by(n, 99);
      for (int rep = 0; rep < 20; ++rep) {
        pool.forEach(n, [&](size_t k, unsigned thread) {
          hits[k] += 1;
          by[k] = thread;
        });
      }
      for (size_t k = 0; k < n; ++k) {
        EXPECT_EQ(hits[k], 20) << "threads " << t << " task " << k;
        EXPECT_LT(by[k], t);
      }
    }
  }
}

TEST(ThreadPool, NestedRegionRunsInline) {
  KeepThreads keep;
  ThreadPool& pool = ThreadPool::global();
  pool.setThreads(3);
  std::vector<long> sums(16, 0);
  pool.forEach(sums.size(), [&](size_t k, unsigned thread) {
    pool.forEach(100, [&](size_t j, unsigned inner) {
      EXPECT_EQ(inner, 0u);
      sums[k] += static_cast<long>(j);
    });
    (void)thread;
  });
  for (long s : sums) EXPECT_EQ(s, 4950);
}

TEST(ThreadPool, LowestTaskExceptionAfterAllTasks) {
  KeepThreads keep;
  ThreadPool& pool = ThreadPool::global();
  for (unsigned t : {1u, 2u, 4u}) {
    pool.setThreads(t);
    std::atomic<int> ran{0};
    try {
      pool.forEach(64, [&](size_t k, unsigned) {
        ran += 1;
        if (k == 5 || k == 40) throw std::runtime_error("task " + std::to_string(k));
      });
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "task 5");
    }
    // One thread stops at the first throw; more threads finish the region.
    if (t > 1) {
      EXPECT_EQ(ran.load(), 64);
    }
    // The pool still works after a throw.
    std::atomic<int> after{0};
    pool.forEach(10, [&](size_t, unsigned) { after += 1; });
    EXPECT_EQ(after.load(), 10);
  }
}

TEST(ThreadPool, ThreadsFromEnvironmentRefusesBadCounts) {
  const char* error = nullptr;
  setenv("DEMLAB_THREADS", "3", 1);
  EXPECT_EQ(ThreadPool::threadsFromEnvironment(&error), 3u);
  EXPECT_EQ(error, nullptr);
  for (const char* bad : {"0", "-2", "abc", "3x", "100000"}) {
    error = nullptr;
    setenv("DEMLAB_THREADS", bad, 1);
    EXPECT_GE(ThreadPool::threadsFromEnvironment(&error), 1u);
    EXPECT_NE(error, nullptr) << bad;
  }
  unsetenv("DEMLAB_THREADS");
}

}  // namespace core_thread_pool_test
}  // namespace demlab
