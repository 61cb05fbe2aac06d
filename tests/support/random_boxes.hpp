// Random box sets for the search tests: small fixed-seed scenes that stress the corners the
// benchmark workloads do not (exact touching, shared corners, points, huge coordinates).
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include "search/box.hpp"
#include "search/broad_phase.hpp"

namespace demlab::search::testing {

// Returns a uniform double in [lo, hi) from the generator.
inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
}

// Returns n boxes with centres uniform in [0, side)^D and half-widths drawn from `halfWidth`;
// when `grid` > 0 every coordinate is snapped to multiples of it, so faces touch exactly.
template <int D, class T, class HalfWidth>
std::vector<Box<D, T>> randomBoxes(std::mt19937_64& rng, std::size_t n, double side,
                                   HalfWidth halfWidth, double grid = 0.0, double offset = 0.0) {
  std::vector<Box<D, T>> boxes(n);
  for (auto& b : boxes) {
    for (int k = 0; k < D; ++k) {
      double c = uniform(rng, 0.0, side);
      double h = halfWidth(rng);
      double lo = c - h, hi = c + h;
      if (grid > 0) {
        lo = std::floor(lo / grid) * grid;
        hi = std::max(lo, std::ceil(hi / grid) * grid);
      }
      b.lo[k] = static_cast<T>(lo + offset);
      b.hi[k] = static_cast<T>(hi + offset);
      if (b.hi[k] < b.lo[k]) b.hi[k] = b.lo[k];
    }
  }
  return boxes;
}

// Returns the pairs sorted, for comparison against the oracle.
inline std::vector<IndexPair> sorted(std::vector<IndexPair> pairs) {
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace demlab::search::testing
