// The size statistics grid algorithms scale their cell size from. A cell size is always
// "cell factor x statistic"; the statistic decides how the grid adapts to a distribution.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

#include "search/box.hpp"

namespace demlab::search {

// Sums over a set of boxes from which the size statistics below are computed, so that a
// caller already passing over the boxes can gather them on the way.
template <int D, class T>
struct SizeSums {
  double sumVolume = 0.0, sumLargest = 0.0, largest = 0.0;
  std::size_t count = 0;

  // Adds box b to the sums. Returns true if its extents are all finite and non-negative:
  // false for every box with a NaN or infinite coordinate or lo > hi, and for valid boxes
  // only if an extent overflows (so a caller can leave the exact check to validateBoxes).
  bool add(const Box<D, T>& b) {
    double volume = 1.0, extent = 0.0, smallest = 0.0, sum = 0.0;
    for (int k = 0; k < D; ++k) {
      const double e = static_cast<double>(b.hi[k]) - static_cast<double>(b.lo[k]);
      volume *= e;
      extent = std::max(extent, e);
      smallest = std::min(smallest, e);
      sum += e;
    }
    sumVolume += volume;
    sumLargest += extent;
    largest = std::max(largest, extent);
    ++count;
    // A NaN extent makes the sum NaN, which fails the comparison.
    return (smallest >= 0.0) & (sum < std::numeric_limits<double>::infinity());
  }

  // Returns volumeSizeStatistic of the boxes added.
  double volumeStatistic() const {
    if (count == 0) return 1.0;
    const double n = static_cast<double>(count);
    if (sumVolume > 0.0 && std::isfinite(sumVolume)) return std::pow(sumVolume / n, 1.0 / D);
    if (sumLargest > 0.0 && std::isfinite(sumLargest)) return sumLargest / n;
    return 1.0;
  }

  // Returns largestExtent of the boxes added.
  double largestExtent() const { return largest > 0.0 ? largest : 1.0; }
};

// Returns the D-th root of the mean box volume// Returns the D-th root of the mean box volume: the
// side of a cell that holds about one object of a bed packed at unit solid fraction. It follows the
// objects that fill the space, not the ones that are most numerous: in a bidisperse bed where 10%
// of the objects hold 99% of the volume it lies between the two sizes, where both the many small
// objects (few per cell) and the few large ones (few cells each) stay cheap. Thin walls have little
// volume and barely move it. Falls back to the mean largest extent when every box is flat, and to 1
// when every box is a point. Changes nothing.
template <int D, class T>
double volumeSizeStatistic(std::span<const Box<D, T>> boxes) {
  SizeSums<D, T> sums;
  for (const auto& b : boxes) sums.add(b);
  return sums.volumeStatistic();
}

// Returns the largest extent of any box on any axis (the cell size NBS and SGrid need), or 1
// if every box is a point. Changes nothing.
template <int D, class T>
double largestExtent(std::span<const Box<D, T>> boxes) {
  SizeSums<D, T> sums;
  for (const auto& b : boxes) sums.add(b);
  return sums.largestExtent();
}

}  // namespace demlab::search
