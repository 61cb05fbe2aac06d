#include "core/background_work.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

namespace demlab {
namespace {

TEST(BackgroundWork, AwaitReturnsAtOnceWhenNothingRuns) {
  EXPECT_TRUE(awaitBackgroundWork(0.0));
}

TEST(BackgroundWork, AwaitWaitsForDetachedWorkAndGivesUpAfterItsTime) {
  std::atomic<bool> release{false};
  std::atomic<bool> finished{false};
  std::thread([&release, &finished, work = std::make_unique<BackgroundWork>()] {
    while (!release.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    finished.store(true);
  }).detach();
  // Counted before the thread runs: an exit straight after the start still waits.
  EXPECT_FALSE(awaitBackgroundWork(0.02));
  release.store(true);
  EXPECT_TRUE(awaitBackgroundWork(30.0));
  EXPECT_TRUE(finished.load());
}

TEST(BackgroundWork, NestedWorkCountsEachPiece) {
  auto a = std::make_unique<BackgroundWork>();
  auto b = std::make_unique<BackgroundWork>();
  a.reset();
  EXPECT_FALSE(awaitBackgroundWork(0.0));
  b.reset();
  EXPECT_TRUE(awaitBackgroundWork(0.0));
}

}  // namespace
}  // namespace demlab
