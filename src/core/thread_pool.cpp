#include "core/thread_pool.hpp"

#include <cerrno>
#include <chrono>
#include <cstdlib>

namespace demlab {

thread_local bool ThreadPool::insideRegion_ = false;

namespace {

// One spin-wait iteration: the CPU's pause hint where there is one.
inline void relax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

// How long a waiting thread spins before it sleeps: longer than the serial stretches between a
// step's regions (a wall pass, the watchdog's scan of the contacts: a fraction of a millisecond
// on a 10^5 bed), since waking a sleeper costs tens of microseconds in a virtual machine; far
// shorter than a user's pause between commands.
constexpr auto kSpinTime = std::chrono::microseconds(2000);

// Returns true while a spin that started at start should go on; pauses a little first.
inline bool keepSpinning(std::chrono::steady_clock::time_point start, int& k) {
  relax();
  if ((++k & 63) != 0) return true;
  return std::chrono::steady_clock::now() - start < kSpinTime;
}

unsigned cores() {
  const unsigned c = std::thread::hardware_concurrency();
  return c == 0 ? 1 : c;
}

}  // namespace

ThreadPool& ThreadPool::global() {
  static ThreadPool pool;
  static const bool sized = [] {
    pool.setThreads(threadsFromEnvironment());
    return true;
  }();
  (void)sized;
  return pool;
}

unsigned ThreadPool::threadsFromEnvironment(const char** error) {
  const char* env = std::getenv("DEMLAB_THREADS");
  if (env == nullptr || *env == '\0') return cores();
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(env, &end, 10);
  if (errno != 0 || *end != '\0' || v < 1 || v > static_cast<long>(kMaxThreads)) {
    if (error != nullptr) *error = "DEMLAB_THREADS must be a whole number from 1 to 1024";
    return cores();
  }
  return static_cast<unsigned>(v);
}

ThreadPool::~ThreadPool() { stopWorkers(); }

void ThreadPool::stopWorkers() {
  if (workers_.empty()) return;
  stop_.store(true, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& t : workers_) t.join();
  workers_.clear();
  stop_.store(false, std::memory_order_relaxed);
}

void ThreadPool::setThreads(unsigned n) {
  if (n < 1) n = 1;
  if (n > kMaxThreads) n = kMaxThreads;
  if (n == threads_ && workers_.size() + 1 == n) return;
  stopWorkers();
  threads_ = n;
  shares_ = std::vector<Share>(n);
  // More threads than cores: a spinning waiter would take the core a working thread needs.
  spin_ = n <= cores();
  const uint32_t start = generation_.load(std::memory_order_relaxed);
  for (unsigned t = 1; t < n; ++t) {
    workers_.emplace_back([this, t, start] {
      uint32_t seen = start;
      for (;;) {
        uint32_t g = generation_.load(std::memory_order_acquire);
        if (g == seen && spin_) {
          const auto start = std::chrono::steady_clock::now();
          int k = 0;
          while (g == seen && keepSpinning(start, k)) g = generation_.load(std::memory_order_acquire);
        }
        while (g == seen) {
          generation_.wait(seen, std::memory_order_acquire);
          g = generation_.load(std::memory_order_acquire);
        }
        seen = g;
        if (stop_.load(std::memory_order_relaxed)) return;
        work(t);
      }
    });
  }
}

void ThreadPool::drain(unsigned thread) {
  insideRegion_ = true;
  // Thread t runs the t-th share of the tasks first, in order: with cores of one speed the
  // same thread then takes the same part of the scene at every step and in every stage (the
  // groups of element blocks, the element chunks), and finds its data in its own core's
  // cache. Then it takes what the other shares have not yet started, the next one first.
  for (unsigned i = 0; i < threads_; ++i) {
    Share& share = shares_[(thread + i) % threads_];
    for (size_t k = share.next.fetch_add(1, std::memory_order_relaxed); k < share.end;
         k = share.next.fetch_add(1, std::memory_order_relaxed)) {
      try {
        fn_(context_, k, thread);
      } catch (...) {
        std::lock_guard<std::mutex> lock(errorMutex_);
        if (!error_ || k < errorTask_) {
          error_ = std::current_exception();
          errorTask_ = k;
        }
      }
    }
  }
  insideRegion_ = false;
}

void ThreadPool::work(unsigned thread) {
  drain(thread);
  if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) busy_.notify_all();
}

void ThreadPool::run(size_t n, TaskFn fn, void* context) {
  fn_ = fn;
  context_ = context;
  error_ = nullptr;
  for (unsigned t = 0; t < threads_; ++t) {
    shares_[t].next.store(n * t / threads_, std::memory_order_relaxed);
    shares_[t].end = n * (t + 1) / threads_;
  }
  busy_.store(static_cast<unsigned>(workers_.size()), std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  drain(0);
  unsigned b = busy_.load(std::memory_order_acquire);
  if (b != 0 && spin_) {
    const auto start = std::chrono::steady_clock::now();
    int k = 0;
    while (b != 0 && keepSpinning(start, k)) b = busy_.load(std::memory_order_acquire);
  }
  while (b != 0) {
    busy_.wait(b, std::memory_order_acquire);
    b = busy_.load(std::memory_order_acquire);
  }
  if (error_) {
    std::exception_ptr e = error_;
    error_ = nullptr;
    std::rethrow_exception(e);
  }
}

}  // namespace demlab
