// Ctrl-C for long work anywhere in the code. While a command declared interruptible runs, the
// command layer points the process-wide interrupt flag at its stop flag (which the SIGINT
// handler sets); a loop that may run long polls now and then and stops at a point where it has
// changed nothing yet (or, for a run, at a step boundary).
#pragma once

#include <algorithm>
#include <atomic>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace demlab {

// Points the flag interruptRequested() reads at `flag` (nullptr: nothing can be interrupted).
// Returns the previous one, for a nested command to restore.
const std::atomic<bool>* setInterruptFlag(const std::atomic<bool>* flag) noexcept;

// Points the flag interruptRequested() reads at `flag` while it lives, then back at the one
// before (a run's outputs run with none, so that they finish; the copies it makes poll its own).
class InterruptScope {
 public:
  explicit InterruptScope(const std::atomic<bool>* flag) : outer_(setInterruptFlag(flag)) {}
  ~InterruptScope() { setInterruptFlag(outer_); }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

 private:
  const std::atomic<bool>* outer_;
};

// Returns true when Ctrl-C asked the running command to stop. Two relaxed atomic loads.
bool interruptRequested() noexcept;

// Throws demlab::Error {INTERRUPTED} "<what> interrupted" when interruptRequested().
void pollInterrupt(std::string_view what);

// The bytes of memory-bound work (a copy, a fill, a write) between two polls: a few
// milliseconds, page faults included.
inline constexpr std::size_t kPollSliceBytes = std::size_t(4) << 20;

// Returns n copies of value, the vector's memory first touched in slices of 4 MiB with poll()
// called before each (poll stops the work by throwing): on some machines (virtualised page
// faults) the first touch of a few hundred megabytes alone takes tenths of a second, which one
// fill would spend deaf. What it made is freed when poll throws.
template <class T, class Poll>
  requires std::invocable<Poll&>
std::vector<T> polledFill(std::size_t n, const T& value, Poll&& poll) {
  constexpr std::size_t kSlice = kPollSliceBytes / sizeof(T) + 1;
  std::vector<T> v;
  v.reserve(n);
  while (v.size() < n) {
    poll();
    v.resize(std::min(n, v.size() + kSlice), value);
  }
  return v;
}

// The same, polling Ctrl-C as `what`: throws demlab::Error {INTERRUPTED}.
template <class T>
std::vector<T> polledFill(std::size_t n, const T& value, std::string_view what) {
  return polledFill(n, value, [what] { pollInterrupt(what); });
}

// The loop iterations between two poll() calls of polledFor: a millisecond or less of the
// simple per-pair work it serves.
inline constexpr std::size_t kPolledForChunk = std::size_t(1) << 16;

// Returns nothing; runs body(k) for k = 0 .. n-1 in order, calling poll() before every
// kPolledForChunk of them (poll stops the loop by throwing). For loops over millions of pairs
// whose single pass would be deaf for a large part of a second.
template <class Poll, class Body>
void polledFor(std::size_t n, Poll&& poll, Body&& body) {
  for (std::size_t at = 0; at < n; at += kPolledForChunk) {
    poll();
    const std::size_t end = std::min(n, at + kPolledForChunk);
    for (std::size_t k = at; k < end; ++k) body(k);
  }
}

// Returns nothing; makes the memory of v's room for n elements resident (its pages first
// touched now, written with `fill` in polled slices of 4 MiB, as `what`) and leaves v's size and
// contents as they were, so that appending up to n elements later takes no page fault: a
// commit that cannot be interrupted (elements added to a scene) then runs at memory speed.
// Room beyond v.capacity() is not made. Throws demlab::Error {INTERRUPTED}, v as it was.
template <class T>
void touchRoom(std::vector<T>& v, std::size_t n, const T& fill, std::string_view what) {
  const std::size_t n0 = v.size();
  n = std::min(n, v.capacity());
  constexpr std::size_t kSlice = kPollSliceBytes / sizeof(T) + 1;
  try {
    while (v.size() < n) {
      pollInterrupt(what);
      v.resize(std::min(n, v.size() + kSlice), fill);
    }
  } catch (...) {
    v.erase(v.begin() + std::ptrdiff_t(n0), v.end());
    throw;
  }
  v.erase(v.begin() + std::ptrdiff_t(n0), v.end());
}

// Returns nothing; sorts v (operator<) as std::sort would, polling Ctrl-C (as `what`) between
// pieces of work of a few milliseconds: runs of 2^16 elements sorted one at a time, then merged
// pairwise, a poll between any two merges. One std::sort of millions of pairs took a tenth of
// a second, deaf. Throws demlab::Error {INTERRUPTED}, v then in some order of its elements.
template <class T>
void polledSort(std::vector<T>& v, std::string_view what) {
  constexpr std::size_t kRun = std::size_t(1) << 16;
  const std::size_t n = v.size();
  for (std::size_t at = 0; at < n; at += kRun) {
    pollInterrupt(what);
    std::sort(v.begin() + std::ptrdiff_t(at), v.begin() + std::ptrdiff_t(std::min(n, at + kRun)));
  }
  for (std::size_t width = kRun; width < n; width *= 2) {
    for (std::size_t at = 0; at + width < n; at += 2 * width) {
      pollInterrupt(what);
      std::inplace_merge(v.begin() + std::ptrdiff_t(at), v.begin() + std::ptrdiff_t(at + width),
                         v.begin() + std::ptrdiff_t(std::min(n, at + 2 * width)));
    }
  }
}

// Counts the iterations of a loop and polls once every 4096 of them, so a tight loop pays an
// increment and a test. Not for use from pool threads: it throws.
class InterruptPoll {
 public:
  explicit InterruptPoll(std::string_view what) : what_(what) {}
  void operator()() {
    if ((++count_ & 4095u) == 0) pollInterrupt(what_);
  }

 private:
  std::string_view what_;
  std::uint32_t count_ = 0;
};

}  // namespace demlab
