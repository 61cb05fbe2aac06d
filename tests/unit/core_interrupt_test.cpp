#include "core/interrupt.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <random>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace demlab {
namespace {

TEST(TouchRoom, LeavesSizeContentsAndCapacityAsTheyWere) {
  std::vector<double> v = {1, 2, 3};
  v.reserve(3 << 20);  // several slices
  const double* data = v.data();
  const size_t capacity = v.capacity();
  touchRoom(v, 3 << 20, 0.0, "test");
  EXPECT_EQ(v, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(v.capacity(), capacity);
  EXPECT_EQ(v.data(), data);  // no reallocation: appends up to the room stay in place
  for (int k = 0; k < (3 << 20) - 3; ++k) v.push_back(k);
  EXPECT_EQ(v.data(), data);
}

TEST(TouchRoom, NeverGrowsBeyondTheCapacity) {
  std::vector<int> v(5, 7);
  v.shrink_to_fit();
  const size_t capacity = v.capacity();
  touchRoom(v, 1000, 0, "test");
  EXPECT_EQ(v.capacity(), capacity);
  EXPECT_EQ(v, std::vector<int>(5, 7));
}

// An element whose copies set the stop flag once a few have been made: the touch is stopped
// after its first slice, at its next poll.
std::atomic<bool> g_stop{false};
int g_copies = 0;
struct StopsWhenCopied {
  double x = 0;
  StopsWhenCopied() = default;
  explicit StopsWhenCopied(double v) : x(v) {}
  StopsWhenCopied(const StopsWhenCopied& o) : x(o.x) {
    if (++g_copies == 10) g_stop.store(true);
  }
  StopsWhenCopied& operator=(const StopsWhenCopied&) = default;
};

TEST(TouchRoom, StoppedPartWayLeavesTheVectorAsItWas) {
  const InterruptScope scope(&g_stop);
  std::vector<StopsWhenCopied> v;
  v.reserve(1 << 22);  // eight slices
  v.emplace_back(4.0);
  v.emplace_back(5.0);
  g_copies = 0;
  try {
    touchRoom(v, 1 << 22, StopsWhenCopied(0.0), "touching");
    FAIL() << "not interrupted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "touching interrupted");
  }
  EXPECT_GT(g_copies, 10);  // stopped after a slice was touched
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].x, 4.0);
  EXPECT_EQ(v[1].x, 5.0);
  g_stop.store(false);
}

TEST(PolledSort, GivesStdSortsOrderOnRandomInputsOfEverySize) {
  std::mt19937_64 rng(7);
  for (size_t n : {size_t(0), size_t(1), size_t(5), size_t(65535), size_t(65536), size_t(65537),
                   size_t(200000), size_t(1) << 18}) {
    std::vector<std::pair<uint32_t, uint32_t>> v(n);
    for (auto& p : v) p = {uint32_t(rng() % 1000), uint32_t(rng() % 1000)};  // many equal
    auto expected = v;
    std::sort(expected.begin(), expected.end());
    polledSort(v, "test");
    EXPECT_EQ(v, expected) << n;
  }
}

TEST(PolledSort, StoppedLeavesAPermutation) {
  std::atomic<bool> stop{true};
  const InterruptScope scope(&stop);
  std::vector<int> v = {3, 1, 2};
  EXPECT_THROW(polledSort(v, "sorting"), Error);
  std::sort(v.begin(), v.end());
  EXPECT_EQ(v, (std::vector<int>{1, 2, 3}));
}

}  // namespace
}  // namespace demlab
