// Input checking shared by every BroadPhase: a box with a NaN coordinate or with lo > hi is
// rejected before any work is done, with a message that names the box and the axis.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>
#include <string>

#include "core/error.hpp"
#include "search/box.hpp"

namespace demlab::search {

// Throws demlab::Error {DEMLAB VALUE BOX} naming the first bad box; returns normally
// otherwise. Changes nothing.
template <int D, class T>
void validateBoxes(std::span<const Box<D, T>> boxes) {
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (int k = 0; k < D; ++k) {
      const T lo = boxes[i].lo[k];
      const T hi = boxes[i].hi[k];
      // !(lo <= hi) is true for NaN in either bound as well as for inverted bounds.
      if (!(lo <= hi) || std::isinf(lo) || std::isinf(hi)) {
        const bool nan = std::isnan(lo) || std::isnan(hi);
        const bool inf = std::isinf(lo) || std::isinf(hi);
        throw Error("bad box " + std::to_string(i) + ": " +
                        (nan   ? "coordinate is NaN"
                         : inf ? "coordinate is infinite"
                               : "minimum exceeds maximum") +
                        " on axis " + std::to_string(k),
                    {"VALUE", "BOX"});
      }
    }
  }
}

}  // namespace demlab::search
