#include "core/interrupt.hpp"

#include <string>

#include "core/error.hpp"

namespace demlab {

namespace {
std::atomic<const std::atomic<bool>*> g_flag{nullptr};
}

const std::atomic<bool>* setInterruptFlag(const std::atomic<bool>* flag) noexcept {
  return g_flag.exchange(flag);
}

bool interruptRequested() noexcept {
  const std::atomic<bool>* f = g_flag.load(std::memory_order_relaxed);
  return f && f->load(std::memory_order_relaxed);
}

void pollInterrupt(std::string_view what) {
  if (interruptRequested()) throw Error(std::string(what) + " interrupted", {"INTERRUPTED"});
}

}  // namespace demlab
