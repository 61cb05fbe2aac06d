// The size statistics grid algorithms scale their cell size from. A cell size is always
// "cell factor x statistic"; the statistic decides how the grid adapts to a distribution.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>

#include "search/box.hpp"

namespace demlab::search {

// Returns the D-th root of the mean box volume: the side of a cell that holds about one
// object of a bed packed at unit solid fraction. It follows the objects that fill the space,
// not the ones that are most numerous: in a bidisperse bed where 10% of the objects hold 99%
// of the volume it lies between the two sizes, where both the many small objects (few per
// cell) and the few large ones (few cells each) stay cheap. Thin walls have little volume and
// barely move it. Falls back to the mean largest extent when every box is flat, and to 1 when
// every box is a point. Changes nothing.
template <int D, class T>
double volumeSizeStatistic(std::span<const Box<D, T>> boxes) {
  if (boxes.empty()) return 1.0;
  double sumVolume = 0.0, sumLargest = 0.0;
  for (const auto& b : boxes) {
    double volume = 1.0, largest = 0.0;
    for (int k = 0; k < D; ++k) {
      const double e = static_cast<double>(b.hi[k]) - static_cast<double>(b.lo[k]);
      volume *= e;
      largest = std::max(largest, e);
    }
    sumVolume += volume;
    sumLargest += largest;
  }
  const double n = static_cast<double>(boxes.size());
  if (sumVolume > 0.0 && std::isfinite(sumVolume)) return std::pow(sumVolume / n, 1.0 / D);
  if (sumLargest > 0.0 && std::isfinite(sumLargest)) return sumLargest / n;
  return 1.0;
}

// Returns the largest extent of any box on any axis (the cell size NBS and SGrid need), or 1
// if every box is a point. Changes nothing.
template <int D, class T>
double largestExtent(std::span<const Box<D, T>> boxes) {
  double largest = 0.0;
  for (const auto& b : boxes) {
    for (int k = 0; k < D; ++k) {
      largest = std::max(largest, static_cast<double>(b.hi[k]) - static_cast<double>(b.lo[k]));
    }
  }
  return largest > 0.0 ? largest : 1.0;
}

}  // namespace demlab::search
