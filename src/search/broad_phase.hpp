// BroadPhase: the interface every neighbor-search algorithm implements (CGrid and its peers),
// so that all of them run on the same input in one benchmark run and are checked against the
// same brute-force oracle.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "search/box.hpp"

namespace demlab::search {

// Options shared by the algorithms that have a cell size.
struct SearchOptions {
  // Cell size = cellFactor x the algorithm's size statistic; 0 means the algorithm's
  // automatic default. Algorithms without a cell-size parameter ignore it.
  double cellFactor = 0.0;
};

template <int D, class T>
class BroadPhase {
 public:
  virtual ~BroadPhase() = default;

  // Returns the algorithm's short name, as printed in benchmark tables ("cgrid", "nbs", ...).
  virtual std::string_view name() const = 0;

  // Finds every pair of overlapping boxes (closed boxes; see box.hpp), each exactly once, and
  // stores them in `out` in an unspecified order, replacing its contents. Buffers kept inside
  // the object are reused from call to call, so a search on moved boxes of the same count
  // allocates nothing once warm.
  // Throws demlab::Error (code DEMLAB VALUE BOX) if any box has a NaN coordinate or lo > hi;
  // `out` is then left empty and the object stays usable.
  virtual void findPairs(std::span<const Box<D, T>> boxes, std::vector<IndexPair>& out) = 0;

  // Returns the bytes of working memory the algorithm holds (capacity of its buffers), not
  // counting the input boxes or the output pairs.
  virtual std::size_t workingBytes() const = 0;
};

}  // namespace demlab::search
