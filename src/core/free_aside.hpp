// Freeing what a stopped command made without making the user wait for it. Hundreds of
// megabytes (a half-made copy of a large scene, its serialized bytes) take tenths of a second
// to give back to the system on some virtual machines (every page's mapping is undone), which
// a command stopped by Ctrl-C would spend before it returns. Plain C++ memory only: never Tcl
// objects, which belong to their interpreter's thread.
#pragma once

#include <exception>
#include <thread>
#include <utility>

namespace demlab {

// Destroys x on a thread of its own and returns at once (or destroys it here when no thread
// can be made). Changes nothing the caller can see.
template <class T>
void freeAside(T x) noexcept {
  try {
    std::thread([held = std::move(x)] {}).detach();
  } catch (...) {  // no thread: the moved-into lambda has been destroyed here instead
  }
}

// Hands `held` to freeAside when the scope is left by an exception (a stop, a bad file), so
// that held's own destructor then finds it empty. Declared after held.
template <class T>
class FreeAsideOnThrow {
 public:
  explicit FreeAsideOnThrow(T& held) : held_(held), uncaught_(std::uncaught_exceptions()) {}
  ~FreeAsideOnThrow() {
    if (std::uncaught_exceptions() > uncaught_) freeAside(std::move(held_));
  }
  FreeAsideOnThrow(const FreeAsideOnThrow&) = delete;
  FreeAsideOnThrow& operator=(const FreeAsideOnThrow&) = delete;

 private:
  T& held_;
  int uncaught_;
};

}  // namespace demlab
