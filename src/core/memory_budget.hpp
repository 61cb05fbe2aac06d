// A check made before a large allocation whose size the input chose (a lattice's sites, an
// image's pixels), so a request the machine cannot hold fails at once with a clear error
// instead of swapping or being killed.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <string>

#include "core/error.hpp"

namespace demlab {

// Returns the machine's physical memory in bytes (0 when unknown).
inline double physicalMemory() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? double(pages) * double(size) : 0.0;
}

// Returns nothing. Throws {MEMORY} ("can't make <what>: it needs about N GB, more than half of
// this machine's M GB") when bytes exceeds half the physical memory. Changes nothing.
inline void checkMemoryBudget(double bytes, const std::string& what) {
  const double memory = physicalMemory();
  if (memory > 0 && bytes > memory / 2) {
    char text[160];
    std::snprintf(text, sizeof text, ": it needs about %.3g GB, more than half of this machine's %.3g GB",
                  bytes / 1e9, memory / 1e9);
    throw Error("can't make " + what + text, {"MEMORY"});
  }
}

}  // namespace demlab
