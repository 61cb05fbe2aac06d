// Ctrl-C for long work anywhere in the code. While a command declared interruptible runs, the
// command layer points the process-wide interrupt flag at its stop flag (which the SIGINT
// handler sets); a loop that may run long polls now and then and stops at a point where it has
// changed nothing yet (or, for a run, at a step boundary).
#pragma once

#include <atomic>
#include <cstdint>
#include <string_view>

namespace demlab {

// Points the flag interruptRequested() reads at `flag` (nullptr: nothing can be interrupted).
// Returns the previous one, for a nested command to restore.
const std::atomic<bool>* setInterruptFlag(const std::atomic<bool>* flag) noexcept;

// Returns true when Ctrl-C asked the running command to stop. Two relaxed atomic loads.
bool interruptRequested() noexcept;

// Throws demlab::Error {INTERRUPTED} "<what> interrupted" when interruptRequested().
void pollInterrupt(std::string_view what);

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
