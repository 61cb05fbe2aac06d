// SweepAndPrune: the sort-based sweep of the DESS family (Double-Ended Spatial Sorting, the
// method of choice in MIMES before CGrid). It is a peer of CGrid in benchmarks, so it is tuned
// as a production sweep would be: one sweep axis chosen by the spread of box centres, an LSD
// radix sort on order-preserving integer images of the coordinates, and temporal coherence
// (the previous call's order re-sorted by insertion sort) when the same boxes move a little.
//
// It is insensitive to object size, but its cost grows with the number of boxes whose extents
// overlap on the sweep axis alone: in a dense 3-D packing that is about N^(5/3) tests, and a
// wall spanning the sweep axis stays active for the whole sweep.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "core/error.hpp"
#include "search/broad_phase.hpp"
#include "search/configs.hpp"
#include "search/validate.hpp"

namespace demlab::search {

template <int D, class T>
class SweepAndPrune final : public BroadPhase<D, T> {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>,
                "the radix keys are the bit patterns of float or double");

 public:
  std::string_view name() const override { return "sap"; }

  // Stores every overlapping pair once in `out` (see BroadPhase). Changes the member buffers
  // and the remembered order and axis used by the next call. Throws demlab::Error
  // {DEMLAB VALUE BOX} on a bad box and {DEMLAB LIMIT COUNT} if the indices overflow uint32.
  void findPairs(std::span<const Box<D, T>> boxes, std::vector<IndexPair>& out) override {
    out.clear();
    validateBoxes<D, T>(boxes);
    if (boxes.size() > std::numeric_limits<uint32_t>::max()) {
      throw Error("too many boxes for sap: " + std::to_string(boxes.size()), {"LIMIT", "COUNT"});
    }
    const auto n = static_cast<uint32_t>(boxes.size());
    sortBoxes(boxes, n);
    sweep(boxes, n, out);
  }

  // Returns true if the last findPairs kept the previous call's order and axis (the insertion
  // sort finished within its move budget), for benchmarks and tests. Changes nothing.
  bool reusedOrder() const noexcept { return reusedOrder_; }

  // Returns the capacity in bytes of the sort keys, the radix scratch and histograms and the
  // active list. Changes nothing.
  std::size_t workingBytes() const override {
    return (items_.capacity() + scratch_.capacity()) * sizeof(Item) +
           histogram_.capacity() * sizeof(uint32_t) + activeBytes() +
           expired_.capacity() * sizeof(uint32_t);
  }

 private:
  using Key = std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>;
  struct Item {
    Key key;       // order-preserving image of the box's lo on the sweep axis
    uint32_t idx;  // the box
  };
  static constexpr int kOther = D - 1;  // axes tested for each candidate
  // The current box's images on the other axes: lo, hi of each axis but the sweep axis.
  using OtherBounds = std::array<float, 2 * kOther>;

  static constexpr int kDigitBits = 11;  // 2048 counters per pass stay in L1
  static constexpr int kPasses = (8 * static_cast<int>(sizeof(Key)) + kDigitBits - 1) / kDigitBits;
  static constexpr std::size_t kBuckets = std::size_t{1} << kDigitBits;
  static constexpr uint32_t kRadixMin = 512;  // below this std::sort beats the counter sweeps

  // Returns the capacity in bytes of the active list buffers. Changes nothing.
  std::size_t activeBytes() const noexcept {
    std::size_t bytes = activeHi_.capacity() * sizeof(float) +
                        activeIdx_.capacity() * sizeof(uint32_t) + flags_.capacity();
    for (const auto& v : activeOther_) bytes += v.capacity() * sizeof(float);
    return bytes;
  }

  // Returns the unsigned integer whose order equals the order of v (for any non-NaN v; -0 sorts
  // just before +0, which compare equal, so the sweep's order is still nondecreasing).
  static Key toKey(T v) noexcept {
    const Key bits = std::bit_cast<Key>(v);
    constexpr Key kSign = Key{1} << (8 * sizeof(Key) - 1);
    return (bits & kSign) ? static_cast<Key>(~bits) : static_cast<Key>(bits | kSign);
  }

  // Returns the axis whose box centres have the largest variance (the lowest such axis on a
  // tie), so the sweep axis separates the boxes best. Changes nothing.
  static int chooseAxis(std::span<const Box<D, T>> boxes) {
    if (boxes.empty()) return 0;
    std::array<double, D> shift, sum, sumSq;
    for (int k = 0; k < D; ++k) {
      // Shifting by one centre avoids the cancellation of sumSq/n - mean^2 far from the origin.
      shift[k] = 0.5 * (static_cast<double>(boxes[0].lo[k]) + static_cast<double>(boxes[0].hi[k]));
      sum[k] = sumSq[k] = 0.0;
    }
    for (const auto& b : boxes) {
      for (int k = 0; k < D; ++k) {
        const double c =
            0.5 * (static_cast<double>(b.lo[k]) + static_cast<double>(b.hi[k])) - shift[k];
        sum[k] += c;
        sumSq[k] += c * c;
      }
    }
    const double n = static_cast<double>(boxes.size());
    int best = 0;
    double bestVariance = -1.0;
    for (int k = 0; k < D; ++k) {
      const double mean = sum[k] / n;
      const double variance = sumSq[k] / n - mean * mean;
      if (variance > bestVariance) {
        bestVariance = variance;
        best = k;
      }
    }
    return best;
  }

  // Returns true if the insertion sort of items_ by key finished within maxMoves element moves;
  // otherwise stops early, leaving items_ a permutation of its input. Changes items_.
  bool insertionSort(uint32_t n, std::size_t maxMoves) {
    Item* a = items_.data();
    std::size_t moves = 0;
    for (uint32_t i = 1; i < n; ++i) {
      if (!(a[i].key < a[i - 1].key)) continue;
      const Item x = a[i];
      uint32_t j = i;
      do {
        a[j] = a[j - 1];
        --j;
        ++moves;
      } while (j > 0 && x.key < a[j - 1].key);
      a[j] = x;
      if (moves > maxMoves) return false;
    }
    return true;
  }

  // Sorts items_[0, n) by key with an LSD radix sort, skipping digits all keys share. Returns
  // nothing; changes items_, scratch_ (swapped with items_ when the passes end there) and
  // histogram_.
  void radixSort(uint32_t n) {
    scratch_.resize(n);
    histogram_.assign(kPasses * kBuckets, 0);
    uint32_t* hist = histogram_.data();
    for (uint32_t i = 0; i < n; ++i) {
      const Key key = items_[i].key;
      for (int p = 0; p < kPasses; ++p) {
        ++hist[p * kBuckets + ((key >> (p * kDigitBits)) & (kBuckets - 1))];
      }
    }
    Item* src = items_.data();
    Item* dst = scratch_.data();
    for (int p = 0; p < kPasses; ++p) {
      const int shift = p * kDigitBits;
      uint32_t* count = hist + p * kBuckets;
      if (count[(src[0].key >> shift) & (kBuckets - 1)] == n) continue;
      uint32_t offset = 0;
      for (std::size_t d = 0; d < kBuckets; ++d) {
        const uint32_t c = count[d];
        count[d] = offset;
        offset += c;
      }
      for (uint32_t i = 0; i < n; ++i)
        dst[count[(src[i].key >> shift) & (kBuckets - 1)]++] = src[i];
      std::swap(src, dst);
    }
    if (src != items_.data()) items_.swap(scratch_);
  }

  // Leaves items_[0, n) holding every box index sorted by lo on axis_. When the previous call
  // had as many boxes, starts from its order (boxes that moved a little need few moves) and
  // keeps its axis; if that needs more than ~8N moves, re-chooses the axis and radix sorts.
  // Changes items_, scratch_, histogram_, axis_ and the remembered order.
  void sortBoxes(std::span<const Box<D, T>> boxes, uint32_t n) {
    if (hasOrder_ && items_.size() == n) {
      for (uint32_t i = 0; i < n; ++i) items_[i].key = toKey(boxes[items_[i].idx].lo[axis_]);
      reusedOrder_ = insertionSort(n, 8 * std::size_t{n} + 64);
      if (reusedOrder_) return;
    }
    reusedOrder_ = false;
    hasOrder_ = false;
    axis_ = chooseAxis(boxes);
    items_.resize(n);
    for (uint32_t i = 0; i < n; ++i) items_[i] = {toKey(boxes[i].lo[axis_]), i};
    if (n < kRadixMin) {
      std::sort(items_.begin(), items_.end(),
                [](const Item& a, const Item& b) { return a.key < b.key; });
    } else {
      radixSort(n);
    }
    hasOrder_ = true;
  }

  // The active list holds a filter image of each box: every coordinate x stored as
  // float(x - origin) for one fixed origin per axis. That map is monotone, so a <= b implies
  // image(a) <= image(b): boxes that overlap always overlap in the image, and a box whose hi
  // image is below the current lo image has truly ended. The image only flags candidates; each
  // flagged one is decided exactly on the input boxes. Float compares vectorize on baseline
  // x86-64 (double masks need SSE4.2) and take half the memory traffic.
  //
  // Returns the image of x relative to origin: monotone in x, and infinite beyond float's range
  // instead of undefined. Changes nothing.
  static float image(T x, double origin) noexcept {
    const double d = static_cast<double>(x) - origin;
    constexpr double kMax = std::numeric_limits<float>::max();
    constexpr float kInf = std::numeric_limits<float>::infinity();
    return d > kMax ? kInf : d < -kMax ? -kInf : static_cast<float>(d);
  }

  // Sweeps the boxes in items_ order, keeping the boxes whose sweep-axis extent still reaches
  // the current lo in a compact active list, and tests the other axes of each active box
  // against the current one. Returns nothing; appends the overlapping pairs to out and changes
  // the active list buffers and expired_.
  void sweep(std::span<const Box<D, T>> boxes, uint32_t n, std::vector<IndexPair>& out) {
    if (n == 0) return;
    if (activeIdx_.empty()) growActive();
    const int axis = axis_;
    // Any fixed origin keeps the image monotone; a box of the scene keeps it precise there.
    std::array<double, D> origin;
    for (int k = 0; k < D; ++k) origin[k] = static_cast<double>(boxes[items_[0].idx].lo[k]);
    std::size_t count = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t idx = items_[i].idx;
      const Box<D, T>& box = boxes[idx];
      const float lo = image(box.lo[axis], origin[axis]);
      OtherBounds bounds;
      for (int k = 0, w = 0; k < D; ++k) {
        if (k == axis) continue;
        bounds[w++] = image(box.lo[k], origin[k]);
        bounds[w++] = image(box.hi[k], origin[k]);
      }
      flagActive(count, lo, bounds);
      // Nearly every flag is 0: skip them eight at a time.
      expired_.clear();
      const uint8_t* flag = flags_.data();
      for (std::size_t t0 = 0; t0 < count; t0 += 8) {
        uint64_t word;
        std::memcpy(&word, flag + t0, sizeof(word));
        if (word == 0) continue;
        for (std::size_t t = t0; t < t0 + 8; ++t) {
          if (flag[t]) resolve(boxes, t, box, idx, out);
        }
      }
      // Dropping from the highest position down, the last entry moved into a hole is never
      // itself a dropped one.
      for (auto t = expired_.rbegin(); t != expired_.rend(); ++t) moveEntry(--count, *t);
      if (count == activeIdx_.size()) growActive();
      activeHi_[count] = image(box.hi[axis], origin[axis]);
      for (int w = 0; w < 2 * kOther; ++w) activeOther_[w][count] = bounds[w];
      activeIdx_[count] = idx;
      ++count;
    }
  }

  // Sets flags_[t] for each of the first `count` active entries to 1 if it may have ended
  // before lo or may overlap the current box on every other axis (judged on images), else 0
  // (certainly neither), and zeroes the 8 flags after them. Changes flags_.
  void flagActive(std::size_t count, float lo, const OtherBounds& bounds) noexcept {
    const float* __restrict hi = activeHi_.data();
    std::array<const float*, 2 * kOther> other;
    for (int w = 0; w < 2 * kOther; ++w) other[w] = activeOther_[w].data();
    uint8_t* __restrict flag = flags_.data();
    // Non-short-circuit and branch-free so that it vectorizes: each comparison alone is a coin
    // flip for a random active box, so branching on it would mispredict half the time.
    for (std::size_t t = 0; t < count; ++t) {
      bool overlap = true;
      for (int w = 0; w < 2 * kOther; w += 2) {
        overlap &= (other[w][t] <= bounds[w + 1]) & (bounds[w] <= other[w + 1][t]);
      }
      flag[t] = overlap | (hi[t] < lo);
    }
    std::memset(flag + count, 0, 8);
  }

  // Decides the flagged active entry at position t exactly against the current box idx:
  // records t in expired_ if the active box ends before the current lo on the sweep axis,
  // reports the pair if the two overlap. Returns nothing; appends to out or expired_.
  void resolve(std::span<const Box<D, T>> boxes, std::size_t t, const Box<D, T>& box, uint32_t idx,
               std::vector<IndexPair>& out) {
    const uint32_t other = activeIdx_[t];
    const Box<D, T>& a = boxes[other];
    if (a.hi[axis_] < box.lo[axis_]) {
      // Sorted by lo, so a box ending before this lo ends before every later lo too.
      expired_.push_back(static_cast<uint32_t>(t));
    } else if (overlaps(a, box)) {
      out.push_back(makePair(other, idx));
    }
  }

  // Copies active entry `from` over entry `to`. Returns nothing; changes the active list.
  void moveEntry(std::size_t from, std::size_t to) noexcept {
    activeHi_[to] = activeHi_[from];
    for (int w = 0; w < 2 * kOther; ++w) activeOther_[w][to] = activeOther_[w][from];
    activeIdx_[to] = activeIdx_[from];
  }

  // Doubles the active list's room (at least 64 entries). Returns nothing; changes the active
  // list buffers and flags_, keeping their entries.
  void growActive() {
    const std::size_t room = std::max<std::size_t>(64, 2 * activeIdx_.size());
    activeHi_.resize(room);
    for (auto& v : activeOther_) v.resize(room);
    activeIdx_.resize(room);
    flags_.resize(room + 8);  // +8: flagActive zeroes the 8 flags after the last entry
  }

  std::vector<Item> items_;          // sorted order; also the order the next call starts from
  std::vector<Item> scratch_;        // radix sort ping-pong buffer
  std::vector<uint32_t> histogram_;  // radix digit counters, kPasses x kBuckets
  // The active list, structure of arrays; the sizes are the room, the entries in use a prefix.
  std::vector<float> activeHi_;                             // sweep-axis hi images
  std::array<std::vector<float>, 2 * kOther> activeOther_;  // lo, hi images, other axes
  std::vector<uint32_t> activeIdx_;                         // the boxes
  std::vector<uint8_t> flags_;                              // flagActive's output
  std::vector<uint32_t> expired_;  // active positions to drop after the current box
  int axis_ = 0;                   // sweep axis of items_
  bool hasOrder_ = false;          // items_ is a sorted order of the previous call's boxes
  bool reusedOrder_ = false;       // the last call kept the previous order and axis
};

// Compiled once, in src/search (see search/configs.hpp).
DEMLAB_SEARCH_CONFIGS(DEMLAB_SEARCH_EXTERN_CLASS, SweepAndPrune)

}  // namespace demlab::search
