#include "core/background_work.hpp"

#include <chrono>
#include <condition_variable>
#include <mutex>

namespace demlab {

namespace {

// Never destroyed: background threads may still count down while the process exits.
struct Counter {
  std::mutex m;
  std::condition_variable cv;
  int running = 0;
};

Counter& counter() {
  static Counter* c = new Counter;
  return *c;
}

}  // namespace

BackgroundWork::BackgroundWork() {
  Counter& c = counter();
  std::lock_guard<std::mutex> lock(c.m);
  ++c.running;
}

BackgroundWork::~BackgroundWork() {
  Counter& c = counter();
  std::lock_guard<std::mutex> lock(c.m);
  if (--c.running == 0) c.cv.notify_all();
}

bool awaitBackgroundWork(double seconds) {
  Counter& c = counter();
  std::unique_lock<std::mutex> lock(c.m);
  return c.cv.wait_for(lock, std::chrono::duration<double>(seconds), [&] { return c.running == 0; });
}

}  // namespace demlab
