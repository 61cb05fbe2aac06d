// BruteForce: the O(N^2) all-pairs search. It is the oracle every other algorithm is tested
// against, so it stays as plain as possible.
#pragma once

#include "search/broad_phase.hpp"
#include "search/configs.hpp"
#include "search/validate.hpp"

namespace demlab::search {

template <int D, class T>
class BruteForce final : public BroadPhase<D, T> {
 public:
  std::string_view name() const override { return "brute"; }

  void findPairs(std::span<const Box<D, T>> boxes, std::vector<IndexPair>& out) override {
    out.clear();
    validateBoxes<D, T>(boxes);
    const auto n = static_cast<uint32_t>(boxes.size());
    for (uint32_t i = 0; i < n; ++i) {
      for (uint32_t j = i + 1; j < n; ++j) {
        if (overlaps(boxes[i], boxes[j])) out.push_back({i, j});
      }
    }
  }

  std::size_t workingBytes() const override { return 0; }
};

// Compiled once, in src/search (see search/configs.hpp).
DEMLAB_SEARCH_CONFIGS(DEMLAB_SEARCH_EXTERN_CLASS, BruteForce)

}  // namespace demlab::search
