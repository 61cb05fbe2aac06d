// CGrid: neighbor search for objects of arbitrary extent (Perkins 2001, chapter 4).
//
// The search is a chain of per-axis Subdividers. Subdivider k sweeps the buckets of axis k in
// increasing order; an object enters at the bucket of its minimum and stays until the bucket
// of its maximum. At each bucket the objects that enter there are its *current* bucket array
// and the objects still held over from lower buckets are its *lower-adjacent* array; both are
// forwarded to Subdivider k+1 with one bit of their label saying which array they came from
// (1 = lower-adjacent on axis k). The last Subdivider is the contact mask: it checks a pair
// only if the NAND rule holds, no axis on which both labels are lower-adjacent. That rule is
// the whole of the exactly-once argument: on every axis a pair of overlapping objects is
// current for one of them exactly at the bucket max(lo_a, lo_b), so the pair meets the mask at
// one bucket per axis with disjoint labels, and at no other (doc/design.md has the proof).
//
// Only occupied buckets are visited: a bucket is processed only where some object enters it,
// so empty space and long objects spanning it cost nothing, and with the cell near the size of
// the objects that fill the space, work is linear in N plus the number of reported pairs.
//
// With Extents::Fixed the same chain is the thesis's SGrid: every object is taken to reach
// exactly one bucket past the one it starts in and the cell is the largest extent, so each
// object sits in one current bucket and is seen once more as lower-adjacent.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "search/broad_phase.hpp"
#include "search/cell_size.hpp"
#include "search/configs.hpp"
#include "search/key_sort.hpp"
#include "search/mask_scan.hpp"
#include "search/validate.hpp"

namespace demlab::search {

template <int D, class T>
class CGrid final : public BroadPhase<D, T> {
  static_assert(D >= 1 && D <= 8, "labels use one bit per axis in a 32-bit entry");

 public:
  enum class Extents { Arbitrary, Fixed };

  // The default cell factor: cell = factor x volumeSizeStatistic (Arbitrary; 1 for Fixed,
  // where cell = factor x largest extent). Chosen from the cell-factor sweep in
  // doc/performance.md: the optimum is flat between 1.5 and 2.5 on every distribution, the
  // time lowest near 2 (the instruction count near 1.5: fewer entries cost less memory
  // traffic than the extra candidate pairs cost instructions).
  static constexpr double kDefaultCellFactor = 2.0;

  explicit CGrid(const SearchOptions& options = {}, Extents extents = Extents::Arbitrary)
      : cellFactor_(options.cellFactor > 0 ? options.cellFactor : kDefaultCellFactor),
        extents_(extents) {
    // Fixed extents are only correct when no object is wider than a cell, and are at their
    // best with the cell exactly the largest extent.
    if (extents_ == Extents::Fixed) {
      cellFactor_ = options.cellFactor > 0 ? std::max(options.cellFactor, 1.0) : 1.0;
    }
  }

  std::string_view name() const override { return extents_ == Extents::Fixed ? "sgrid" : "cgrid"; }

  // Work counters of the last search, for tests of how the work scales (never timed).
  struct Stats {
    std::size_t forwarded = 0;    // entries handed from one Subdivider to the next
    std::size_t maskEntries = 0;  // entries laid into contact-mask cells
  };

  // Returns the cell size used by the last search (0 before the first).
  double cellSize() const { return cellSize_; }

  // Returns the work counters of the last search.
  const Stats& stats() const { return stats_; }

  // Returns true if the contact mask scans with its AVX2 build (doubles, on CPUs that run it:
  // the default there), false if with the portable one.
  bool wideScans() const { return wide_; }

  // Selects the AVX2 scans (on: where wideScans() could be true) or the portable ones (off),
  // which report the same pairs in the same order; for the tests that compare the two.
  void useWideScans(bool on) { wide_ = on && wideAvailable(); }

  void findPairs(std::span<const Box<D, T>> boxes, std::vector<IndexPair>& out) override {
    out.clear();
    if (boxes.size() < 2 || boxes.size() > kIndexMask) {
      validateBoxes<D, T>(boxes);
      if (boxes.size() > kIndexMask) {
        throw Error("too many boxes: " + std::to_string(boxes.size()) + " exceeds " +
                        std::to_string(kIndexMask),
                    {"LIMIT", "COUNT"});
      }
      stats_ = {};
      return;
    }
    discretize(boxes);  // validates the boxes on its first pass
    stats_ = {};
    // The output is sized ahead (to the last search's count, within its capacity) and cut
    // back at the end, so reporting writes without checks per pair.
    const std::size_t want = lastPairs_ + lastPairs_ / 8 + 1024;
    out.resize(out.capacity() >= 1024 ? std::min(out.capacity(), want) : want);
    sink_ = {&out, out.data(), out.data() + out.size()};
    subdivideFirstAxis();
    lastPairs_ = static_cast<std::size_t>(sink_.next - out.data());
    out.resize(lastPairs_);
    sink_ = {};
  }

  std::size_t workingBytes() const override {
    std::size_t bytes = order_.capacity() * sizeof(uint32_t) +
                        boxes_.capacity() * sizeof(Box<D, T>) +
                        cells_.capacity() * sizeof(CellRange) + scratch_.bytes() + mask_.bytes();
    for (const auto& s : subdividers_) {
      bytes +=
          (s.input.capacity() + s.current.capacity() + s.held.capacity() + s.merged.capacity()) * 4;
    }
    return bytes;
  }

 private:
  // An entry is an object's position in the sorted order in the low bits and its label (bit
  // k set = lower-adjacent on axis k) in the top D bits: half the memory traffic of a pair.
  static constexpr int kLabelShift = 32 - D;
  static constexpr uint32_t kIndexMask = (uint32_t{1} << kLabelShift) - 1;
  static constexpr uint32_t kLabelMask = ~kIndexMask;
  // Bucket indices stay below 2^30 so that lo + 1 and differences never overflow.
  static constexpr double kMaxBucket = 1073741823.0;
  // Most steps within a bucket the sort key of discretize() may order the objects by.
  static constexpr int kFineBits = 3;

  struct CellRange {
    std::array<uint32_t, D> lo;
    std::array<uint32_t, D> hi;
  };

  // One Subdivider's bucket arrays: the objects forwarded to it, the same sorted by bucket,
  // and the lower-adjacent array (objects held over from lower buckets).
  struct Subdivider {
    std::vector<uint32_t> input;    // Subdivider 0 only: every object, in order
    std::vector<uint32_t> current;  // objects entering the bucket, sorted on the next axis
    std::vector<uint32_t> held;     // objects spanning the bucket, sorted on the next axis
    std::vector<uint32_t> merged;   // scratch for merging the two
  };

  static_assert(std::numeric_limits<T>::has_infinity, "mask sentinels need an infinity");
  static constexpr std::size_t kPad = mask::kPad;

  // Returns true if this build and CPU have the AVX2 scans for this T.
  static bool wideAvailable() {
#if defined(DEMLAB_MASK_AVX2)
    if constexpr (std::is_same_v<T, double>) return mask::avx2Available();
#endif
    return false;
  }
  static_assert(mask::Columns<D, T>::kLabels == ~((uint32_t{1} << (32 - D)) - 1),
                "the mask's entries carry the labels where CGrid's do");

  static constexpr uint32_t labelBit(int k) {
    return uint32_t{1} << (kLabelShift + k);
  }

  // Returns the bucket of coordinate x on axis k: floor((x - origin) / cell), clamped to
  // [0, kMaxBucket]. Monotone in x in floating point, which is all correctness needs.
  uint32_t bucket(T x, int k) const {
    // x >= origin, so the scaled value is >= 0 and truncation is floor.
    const double b = (static_cast<double>(x) - origin_[k]) * inverseCell_;
    return static_cast<uint32_t>(b < kMaxBucket ? b : kMaxBucket);
  }

  // Chooses the cell size, sorts the objects by their bucket on axis 0 and stores, in that
  // order, their boxes and bucket ranges. Changes every buffer.
  void discretize(std::span<const Box<D, T>> boxes) {
    const std::size_t n = boxes.size();
    // One pass over the input checks it, finds its bounds and sums its sizes.
    std::array<double, D> origin, top;
    for (int k = 0; k < D; ++k) {
      origin[k] = static_cast<double>(boxes[0].lo[k]);
      top[k] = static_cast<double>(boxes[0].hi[k]);
    }
    SizeSums<D, T> sizes;
    bool valid = true;
    for (const auto& b : boxes) {
      for (int k = 0; k < D; ++k) {
        origin[k] = std::min(origin[k], static_cast<double>(b.lo[k]));
        top[k] = std::max(top[k], static_cast<double>(b.hi[k]));
      }
      valid &= sizes.add(b);
    }
    // Every bad box fails the quick check; validateBoxes decides exactly and throws, naming
    // the first bad box, before anything is changed.
    if (!valid) validateBoxes<D, T>(boxes);
    origin_ = origin;
    const double statistic =
        extents_ == Extents::Fixed ? sizes.largestExtent() : sizes.volumeStatistic();
    // Fixed extents need a cell at least as wide as every box; wider than the largest double
    // cannot be bucketed, so say so rather than miss pairs.
    if (!std::isfinite(statistic)) {
      throw Error("bad box set: sgrid needs every extent to be a finite double (use cgrid)",
                  {"VALUE", "BOX"});
    }
    double span = 0.0;
    for (int k = 0; k < D; ++k) span = std::max(span, top[k] - origin_[k]);
    // A cell so small that the scene spans more than kMaxBucket buckets would only pile
    // objects into the clamped last bucket; widen it instead.
    cellSize_ = std::max(cellFactor_ * statistic, span / kMaxBucket);
    if (!(cellSize_ > 0.0)) cellSize_ = 1.0;
    inverseCell_ = 1.0 / cellSize_;

    // Sort the objects by bucket, lexicographically over the axes when the bucket grid is
    // small enough to number in 32 bits (dense scenes: neighbours in space become neighbours
    // in memory, and every Subdivider finds its current arrays already in order), by axis 0
    // alone otherwise (sparse scenes, where locality matters less than the range).
    std::array<uint64_t, D> ranks{};
    uint64_t cellsInGrid = 1;
    for (int k = D - 1; k >= 0; --k) {
      ranks[k] = cellsInGrid;
      cellsInGrid *= uint64_t{bucket(static_cast<T>(top[k]), k)} + 1;
      if (cellsInGrid > UINT32_MAX) break;
    }
    const bool lexicographic = cellsInGrid <= UINT32_MAX;
    // In lexicographic order the key also says where in its bucket an object starts on the
    // last axis, in 2^fine steps, as long as there are no more keys than objects (the counting
    // sort's array stays within 4 bytes an object): a bucket of a granular bed holds about 9
    // objects at the default cell, and ordering them by an insertion alone costs a
    // mispredicted branch per object.
    int fine = 0;
    while (lexicographic && fine < kFineBits &&
           (cellsInGrid << (fine + 1)) <= std::min<uint64_t>(UINT32_MAX, uint64_t{n} + 256)) {
      ++fine;
    }
    constexpr int L = D - 1;
    const double fineScale = inverseCell_ * static_cast<double>(uint64_t{1} << fine);
    const uint64_t fineMask = (uint64_t{1} << fine) - 1;
    // Returns the bucket ranges of box b, bucket() for every coordinate (Fixed: hi = lo + 1).
    const bool fixed = extents_ == Extents::Fixed;
#if defined(__SSE2__)
    // 3D doubles: the six coordinates two at a time, (lo0 lo1) (lo2 hi0) (hi1 hi2), by the
    // same arithmetic as bucket(), so the values are the same.
    const __m128d o01 = _mm_set_pd(origin_[1], origin_[0]);
    const __m128d o20 = _mm_set_pd(origin_[0], origin_[D > 2 ? 2 : 0]);
    const __m128d o12 = _mm_set_pd(origin_[D > 2 ? 2 : 0], origin_[D > 1 ? 1 : 0]);
    const __m128d scale = _mm_set1_pd(inverseCell_);
    const __m128d most = _mm_set1_pd(kMaxBucket);
#endif
    auto rangeOf = [&](const Box<D, T>& b) {
      CellRange c;
#if defined(__SSE2__)
      if constexpr (D == 3 && std::is_same_v<T, double>) {
        auto scaled = [&](__m128d x, __m128d o) {
          return _mm_cvttpd_epi32(_mm_min_pd(_mm_mul_pd(_mm_sub_pd(x, o), scale), most));
        };
        const __m128i lo01 = scaled(_mm_loadu_pd(b.lo.data()), o01);
        const __m128i x20 = scaled(_mm_loadh_pd(_mm_load_sd(&b.lo[2]), &b.hi[0]), o20);
        const __m128i hi12 = scaled(_mm_loadu_pd(&b.hi[1]), o12);
        _mm_storel_epi64(reinterpret_cast<__m128i*>(c.lo.data()), lo01);
        c.lo[2] = static_cast<uint32_t>(_mm_cvtsi128_si32(x20));
        c.hi[0] = static_cast<uint32_t>(_mm_cvtsi128_si32(_mm_shuffle_epi32(x20, 1)));
        _mm_storel_epi64(reinterpret_cast<__m128i*>(&c.hi[1]), hi12);
        if (fixed) {
          for (int k = 0; k < D; ++k) c.hi[k] = c.lo[k] + 1;
        }
        return c;
      }
#endif
      for (int k = 0; k < D; ++k) {
        c.lo[k] = bucket(b.lo[k], k);
        c.hi[k] = fixed ? c.lo[k] + 1 : bucket(b.hi[k], k);
      }
      return c;
    };
    // The keys go in Subdivider 0's input array, which subdivideFirstAxis() refills.
    auto& keys = subdividers_[0].input;
    keys.resize(n);
    order_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (lexicographic) {
        const CellRange c = rangeOf(boxes[i]);
        uint64_t key = 0;
        for (int k = 0; k < D; ++k) key += ranks[k] * c.lo[k];
        // lo >= origin, so the scaled value is >= 0; any value would do, the insertion below
        // deciding the order within a bucket, but this one leaves it little to do.
        const double within = (static_cast<double>(boxes[i].lo[L]) - origin_[L]) * fineScale;
        key = key << fine | (static_cast<uint64_t>(within) & fineMask);
        keys[i] = static_cast<uint32_t>(key);
      } else {
        keys[i] = bucket(boxes[i].lo[0], 0);
      }
    }
    sortIndicesByKey(keys.data(), n, order_.data(), scratch_);

    boxes_.resize(n);
    cells_.resize(n);
    // The gather below reads the caller's boxes in random order; asking for them a few
    // iterations ahead overlaps the cache misses, which dominate at a million objects. Both
    // ends of the box: half of them straddle two cache lines. 32 ahead: the gather at 1e6
    // took 21 ns an object against 25 at 16 (48: the same as 32).
    constexpr std::size_t kAhead = 32;
    // In lexicographic order, objects of the same bucket are also put in order of their
    // minimum on the last axis (insertion: they only move within their bucket). Then every
    // run of a Subdivider's input is already in the order the next Subdivider needs, down to
    // the last axis's coordinates, and no Subdivider sorts.
    for (std::size_t j = 0; j < n; ++j) {
      if (j + kAhead < n) {
        const char* ahead = reinterpret_cast<const char*>(&boxes[order_[j + kAhead]]);
        __builtin_prefetch(ahead);
        __builtin_prefetch(ahead + sizeof(Box<D, T>) - 1);
      }
      const uint32_t original = order_[j];
      const Box<D, T> b = boxes[original];
      const CellRange c = rangeOf(b);
      std::size_t i = j;
      if (lexicographic) {
        while (i > 0 && boxes_[i - 1].lo[L] > b.lo[L] && sameBucket(cells_[i - 1], c)) {
          boxes_[i] = boxes_[i - 1];
          cells_[i] = cells_[i - 1];
          order_[i] = order_[i - 1];
          --i;
        }
      }
      boxes_[i] = b;
      cells_[i] = c;
      order_[i] = original;
    }
    presorted_ = lexicographic;
  }

  // Runs the Subdivider chain over all objects, which discretize() left in bucket order on
  // axis 0. Changes the Subdivider buffers and appends pairs to *out_.
  void subdivideFirstAxis() {
    auto& all = subdividers_[0].input;
    all.resize(cells_.size());
    std::iota(all.begin(), all.end(), 0u);
    if constexpr (D == 1) {
      refineOnLastAxis(all.data(), all.size());
      contactMask(all.data(), all.size());
    } else {
      subdivide<0>(all.data(), all.size());
    }
  }

  // Subdivider K < D-1. `in` holds m entries sorted by bucket on axis K. Sweeps the buckets
  // where some object enters; at each it keeps the held-over array (objects still spanning the
  // bucket, lower-adjacent on axis K) sorted on axis K+1, merges the current array (objects
  // entering the bucket, sorted on axis K+1) into it, and forwards the result, already in
  // bucket order for Subdivider K+1. Held-over arrays are reused, not subdivided again, as in
  // the thesis's SGrid; each object is sorted once per axis. Changes Subdividers >= K.
  template <int K>
  void subdivide(const uint32_t* in, std::size_t m) {
    Subdivider& s = subdividers_[K];
    s.held.clear();
    auto nextKey = [this](uint32_t e) { return cells_[e & kIndexMask].lo[K + 1]; };
    for (std::size_t begin = 0; begin < m;) {
      const uint32_t c = cells_[in[begin] & kIndexMask].lo[K];
      std::size_t end = begin + 1;
      while (end < m && cells_[in[end] & kIndexMask].lo[K] == c) ++end;

      // The current array: the run itself when discretize() left it in order.
      const uint32_t* current = in + begin;
      const std::size_t entering = end - begin;
      if (!presorted_) {
        s.current.resize(entering);
        sortByKey(in + begin, s.current.data(), entering, nextKey, scratch_);
        if constexpr (K + 1 == D - 1) refineOnLastAxis(s.current.data(), entering);
        current = s.current.data();
      }
      // Held-over objects that still reach bucket c become lower-adjacent on axis K.
      std::size_t kept = 0;
      uint32_t common = kLabelMask;
      for (uint32_t e : s.held) {
        // Branch-free: every entry is written, and kept if it still reaches c.
        const bool stays = cells_[e & kIndexMask].hi[K] >= c;
        e |= labelBit(K);
        common &= stays ? e : kLabelMask;
        s.held[kept] = e;
        kept += stays;
      }
      s.held.resize(kept);
      for (std::size_t i = 0; i < entering; ++i) common &= current[i];
      s.merged.resize(kept + entering);
      if constexpr (K + 1 == D - 1) {
        std::merge(s.held.begin(), s.held.end(), current, current + entering, s.merged.begin(),
                   [&](uint32_t a, uint32_t b) { return lastLo(a) < lastLo(b); });
      } else if (presorted_) {
        // Kept in the full order of the later axes, so that Subdivider K+1's runs are too.
        std::merge(s.held.begin(), s.held.end(), current, current + entering, s.merged.begin(),
                   [&](uint32_t a, uint32_t b) { return laterBefore<K + 1>(a, b); });
      } else {
        std::merge(s.held.begin(), s.held.end(), current, current + entering, s.merged.begin(),
                   [&](uint32_t a, uint32_t b) { return nextKey(a) < nextKey(b); });
      }
      s.held.swap(s.merged);
      // Where every object shares a lower-adjacent axis, the NAND rule accepts no pair.
      if (s.held.size() > 1 && (common & kLabelMask) == 0) {
        stats_.forwarded += s.held.size();
        if constexpr (K + 1 == D - 1) {
          contactMask(s.held.data(), s.held.size());
        } else {
          subdivide<K + 1>(s.held.data(), s.held.size());
        }
      }
      begin = end;
    }
    // held and merged trade places at every bucket, so which of them needed the room depends
    // on the parity of the bucket count; with both at the larger capacity, a later call on the
    // same input allocates nothing.
    const std::size_t room = std::max(s.held.capacity(), s.merged.capacity());
    s.held.reserve(room);
    s.merged.reserve(room);
  }

  // Returns true if a and b start in the same bucket on every axis.
  static bool sameBucket(const CellRange& a, const CellRange& b) {
    bool same = true;
    for (int k = 0; k < D; ++k) same &= a.lo[k] == b.lo[k];
    return same;
  }

  // Returns true if entry a comes before entry b in the order of discretize() restricted to
  // axes K..D-1: by bucket on axes K..D-2, then by minimum coordinate on the last axis.
  template <int K>
  bool laterBefore(uint32_t a, uint32_t b) const {
    const CellRange& ca = cells_[a & kIndexMask];
    const CellRange& cb = cells_[b & kIndexMask];
    for (int k = K; k < D - 1; ++k) {
      if (ca.lo[k] != cb.lo[k]) return ca.lo[k] < cb.lo[k];
    }
    return lastLo(a) < lastLo(b);
  }

  // Returns the minimum coordinate of entry e on the last axis.
  T lastLo(uint32_t e) const {
    return boxes_[e & kIndexMask].lo[D - 1];
  }

  // Sorts entries a[0..m), already in bucket order on the last axis, by their minimum
  // coordinate there. Insertion sort: entries only move within their bucket.
  void refineOnLastAxis(uint32_t* a, std::size_t m) const {
    for (std::size_t i = 1; i < m; ++i) {
      const uint32_t e = a[i];
      const T lo = lastLo(e);
      std::size_t j = i;
      while (j > 0 && lastLo(a[j - 1]) > lo) {
        a[j] = a[j - 1];
        --j;
      }
      a[j] = e;
    }
  }

  // The contact mask. `in` holds m entries sorted by minimum coordinate on the last axis,
  // where the buckets shrink to the objects' own extents. Each entry meets the later entries
  // that start before it ends (a sweep) and checks those whose label passes the NAND rule (no
  // axis on which both are lower-adjacent), so every pair met here is a pair that meets
  // nowhere else. The rule is one more lane of the vector test rather than a split of the run
  // into cells by label walked pairwise: a walk of two cells in merged order is a chain of
  // dependent loads, and the rule rejects only about a fifth of the candidates of a granular
  // bed (doc/design.md). Appends the overlapping pairs to the output.
  void contactMask(const uint32_t* in, std::size_t m) {
    stats_.maskEntries += m;
    // The run ends in kPad sentinels that start after everything ends, so the scans stop on
    // the coordinate alone and may read kPad entries at a time.
    mask_.fit(m + kPad);
    for (std::size_t i = 0; i < m; ++i) {
      const uint32_t j = in[i] & kIndexMask;
      mask_.put(i, boxes_[j], order_[j], in[i] & kLabelMask);
    }
    for (std::size_t p = 0; p < kPad; ++p) mask_.endAt(m + p);
#if defined(DEMLAB_MASK_AVX2)
    if constexpr (std::is_same_v<T, double>) {
      if (wide_) return mask::sweepAvx2<D>(mask_, m, sink_);
    }
#endif
    mask::sweep<D, T>(mask_, m, sink_);
  }

  double cellFactor_;
  Extents extents_;
  double cellSize_ = 0.0;
  Stats stats_;
  double inverseCell_ = 1.0;
  std::array<double, D> origin_{};
  std::vector<uint32_t> order_;   // sorted position -> caller's index
  std::vector<Box<D, T>> boxes_;  // boxes in sorted order (hot for the contact mask)
  std::vector<CellRange> cells_;  // bucket ranges in sorted order
  bool presorted_ = false;        // sorted over all axes: Subdividers' runs arrive in order
  std::array<Subdivider, D> subdividers_;
  KeySortScratch scratch_;
  mask::Columns<D, T> mask_;  // the contact mask's cells, see contactMask()
  mask::PairSink sink_;       // the output, written ahead of its size during a search
  bool wide_ = wideAvailable();
  std::size_t lastPairs_ = 0;  // pairs of the last search, to size the next one's output
};

// Compiled once, in src/search (see search/configs.hpp).
DEMLAB_SEARCH_CONFIGS(DEMLAB_SEARCH_EXTERN_CLASS, CGrid)

}  // namespace demlab::search
