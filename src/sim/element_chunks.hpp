// Element chunks: the per-element stages of the threaded step (the integrator, the behaviors,
// the watchdog's scans) split the dense arrays into chunks of kChunkElements (small enough to
// balance a 10^4 bed over several threads), a count fixed
// apart from the threads, so that any sum over chunks, taken in chunk order, has the same
// bits for any number of threads.
#pragma once

#include <algorithm>
#include <cstddef>

#include "core/thread_pool.hpp"

namespace demlab::sim {

inline constexpr size_t kChunkElements = 1024;

// Returns the number of chunks of n elements.
inline size_t elementChunks(size_t n) {
  return (n + kChunkElements - 1) / kChunkElements;
}

// Runs body(begin, end, chunk) for every chunk of [0, n) on the thread pool; the chunks may run
// at once in any order, so body writes only its own elements' data and its chunk's slots.
// Changes what body changes.
template <class Body>
void forEachElementChunk(size_t n, Body&& body) {
  ThreadPool::global().forEach(elementChunks(n), [&](size_t c, unsigned) {
    const size_t begin = c * kChunkElements;
    body(begin, std::min(n, begin + kChunkElements), c);
  });
}

}  // namespace demlab::sim
