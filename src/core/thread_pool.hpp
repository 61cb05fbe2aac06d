// ThreadPool: the threads of the parallel step, one process-wide pool (like a runtime).
//
// A parallel region hands the pool n tasks (forEach); thread t of T starts on tasks n t / T ..
// n (t+1) / T - 1, in order (its share, so a thread keeps the same part of the scene, and its
// cache, from step to step), and a thread that finishes its share takes the tasks not yet
// started of the others' (cores are not always equally fast: on a shared virtual machine one
// core ran the same step 1.4 times slower than the other, and a fixed share left the fast
// one waiting). The call returns when all are done. Nothing a task computes may depend
// on which thread runs it or in what order the tasks run: the step's results are the same bits
// for any number of threads because every task writes its own part (a range of elements, a
// group of contacts that shares no element with the others running at once) and every sum over
// tasks is taken afterwards, in task order, by the caller.
//
// Workers wait for work by spinning briefly (a step hands out a dozen regions, microseconds
// apart) and then sleeping on the region counter (std::atomic::wait, a futex); with more
// threads than cores they sleep at once, so an oversubscribed pool stays correct and only
// slower. A region started from inside a task runs inline on that thread.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace demlab {

class ThreadPool {
 public:
  // The most threads setThreads accepts.
  static constexpr unsigned kMaxThreads = 1024;

  // Returns the process's pool; its first call sizes it from $DEMLAB_THREADS (a count 1 ..
  // kMaxThreads) or else from the cores the machine has.
  static ThreadPool& global();

  // Returns the threads a region uses (the caller included), at least 1.
  unsigned threads() const { return threads_; }

  // Sets the threads regions use to n (1 .. kMaxThreads), starting or stopping workers. Must
  // not be called from inside a region. Changes the workers.
  void setThreads(unsigned n);

  // Returns the thread count $DEMLAB_THREADS asks for, the default otherwise (the cores), and
  // sets *error to a message when the variable is set but not a count 1 .. kMaxThreads.
  static unsigned threadsFromEnvironment(const char** error = nullptr);

  // Runs task(k, thread) for every k in [0, n), thread being 0 .. threads() - 1 (which of the
  // threads runs it; 0 is the caller), and returns when all have run. A task's exception is
  // rethrown here after all tasks end (the one of the lowest k). Changes what the tasks change.
  template <class F>
  void forEach(size_t n, F&& task) {
    if (n == 0) return;
    if (threads_ == 1 || n == 1 || insideRegion_) {
      for (size_t k = 0; k < n; ++k) task(k, 0u);
      return;
    }
    using Fn = std::remove_reference_t<F>;
    run(n, [](void* ctx, size_t k, unsigned t) { (*static_cast<Fn*>(ctx))(k, t); }, &task);
  }

  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;
  ~ThreadPool();

 private:
  ThreadPool() = default;
  using TaskFn = void (*)(void* context, size_t k, unsigned thread);
  void run(size_t n, TaskFn fn, void* context);
  void work(unsigned thread);
  void drain(unsigned thread);
  void stopWorkers();

  unsigned threads_ = 1;
  std::vector<std::thread> workers_;
  // The region in hand; published by the release increment of generation_.
  TaskFn fn_ = nullptr;
  void* context_ = nullptr;
  // Per thread, its share's next task to hand out and its end: the owner and thieves take
  // tasks from `next` alike, so each is taken once.
  struct alignas(64) Share {
    std::atomic<size_t> next{0};
    size_t end = 0;
  };
  std::vector<Share> shares_;
  // Each counter on a cache line of its own: the threads spin on them.
  alignas(64) std::atomic<unsigned> busy_{0};  // workers still in the current region
  alignas(64) std::atomic<uint32_t> generation_{0};  // a futex word: wraps harmlessly
  std::atomic<bool> stop_{false};
  bool spin_ = true;
  std::mutex errorMutex_;
  std::exception_ptr error_;
  size_t errorTask_ = 0;
  static thread_local bool insideRegion_;
};

}  // namespace demlab
