// Marks on elements for one round of a pass (a step's): which elements the pass has already
// taken, without clearing a per-element array every round. Each round has its own number; the
// marks are cleared only when that number wraps.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace demlab::sim {

class ElementMarks {
 public:
  // Starts a round over n elements (dense indices): none is marked. Changes the marks.
  void begin(size_t n) {
    if (round_.size() != n) round_.assign(n, 0);
    if (++now_ == 0) {  // the round numbers wrapped: clear the marks
      std::fill(round_.begin(), round_.end(), 0);
      now_ = 1;
    }
  }
  // Returns true the first time element i is marked this round, false after. Changes the marks.
  bool mark(uint32_t i) {
    if (round_[i] == now_) return false;
    round_[i] = now_;
    return true;
  }
  size_t heapBytes() const { return round_.capacity() * sizeof(uint32_t); }

 private:
  std::vector<uint32_t> round_;  // per element: the round it was last marked in
  uint32_t now_ = 0;
};

}  // namespace demlab::sim
