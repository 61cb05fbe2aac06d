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
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/thread_pool.hpp"
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

  // Returns the slabs the last search was cut into: 1 if it ran serially.
  std::size_t lastSlabs() const { return lastSlabs_; }

  // Returns true if the contact mask scans with its AVX2 build (doubles, on CPUs that run it:
  // the default there), false if with the portable one.
  bool wideScans() const { return wide_; }

  // Selects the AVX2 scans (on: where wideScans() could be true) or the portable ones (off),
  // which report the same pairs in the same order; for the tests that compare the two.
  void useWideScans(bool on) { wide_ = on && wideAvailable(); }

  // Sets the flag that stops a search part way (Ctrl-C), or none (nullptr, the default). A
  // search that saw it set leaves its output empty and stopped() true.
  void setStop(const std::atomic<bool>* stop) { stop_ = stop; }

  // Returns true if the last search stopped part way at the stop flag.
  bool stopped() const { return stopped_; }

  void findPairs(std::span<const Box<D, T>> boxes, std::vector<IndexPair>& out) override {
    stopped_ = false;
    if (boxes.size() < 2 || boxes.size() > kIndexMask) {
      out.clear();
      validateBoxes<D, T>(boxes);
      if (boxes.size() > kIndexMask) {
        throw Error("too many boxes: " + std::to_string(boxes.size()) + " exceeds " +
                        std::to_string(kIndexMask),
                    {"LIMIT", "COUNT"});
      }
      stats_ = {};
      return;
    }
    const bool threaded = takesThreads(boxes.size());
    // The threaded search keeps the output's elements until it knows the pair count, so that
    // it writes zeros only where the output grows (a serial pass over all of it otherwise).
    if (!threaded) out.clear();
    try {
      discretize(boxes);  // validates the boxes on its first pass
    } catch (...) {
      out.clear();
      throw;
    }
    stats_ = {};
    lastSlabs_ = 1;
    if constexpr (D > 1) {
      if (threaded && partitionSlabs() > 1) {
        lastSlabs_ = slabBegin_.size() - 1;
        return findPairsInSlabs(out);
      }
    }
    out.clear();
    // The output is sized ahead (to the last search's count, within its capacity) and cut
    // back at the end, so reporting writes without checks per pair.
    const std::size_t want = lastPairs_ + lastPairs_ / 8 + 1024;
    if (!sizeOutput(out, out.capacity() >= 1024 ? std::min(out.capacity(), want) : want)) {
      out.clear();
      return;
    }
    lane_.stats = {};
    lane_.sink = {&out, out.data(), out.data() + out.size(), stop_};
    subdivideFirstAxis();
    stopped_ = lane_.sink.stopped;
    lastPairs_ = stopped_ ? lastPairs_ : static_cast<std::size_t>(lane_.sink.next - out.data());
    out.resize(stopped_ ? 0 : lastPairs_);
    lane_.sink = {};
    stats_ = lane_.stats;
  }

  // The fewest boxes the threaded search takes by default. Below it one thread is as fast:
  // at 20000 boxes a serial search takes about 1.5 ms, and the threaded one's fixed costs
  // (three pool regions, rebuilding the held-over array at each slab's start, copying the
  // slabs' pairs into the output) stay within a few percent of that only from there up.
  static constexpr std::size_t kThreadedMinBoxes = 20000;
  // Objects a slab aims at, and the most slabs: more slabs than threads let the pool balance
  // slabs of unequal work, and every slab costs one rebuilt held-over array.
  static constexpr std::size_t kObjectsPerSlab = 10000;
  static constexpr std::size_t kMaxSlabs = 64;

  // Sets the fewest boxes the threaded search takes and the objects a slab aims at (defaults
  // kThreadedMinBoxes and kObjectsPerSlab), so that tests run the threaded search on inputs
  // small enough to check against the oracle. Changes only those settings.
  void setThreadedSearch(std::size_t minBoxes, std::size_t objectsPerSlab) {
    threadedMinBoxes_ = std::max<std::size_t>(minBoxes, 2);
    objectsPerSlab_ = std::max<std::size_t>(objectsPerSlab, 1);
  }

  std::size_t workingBytes() const override {
    std::size_t bytes = order_.capacity() * sizeof(uint32_t) +
                        boxes_.capacity() * sizeof(Box<D, T>) +
                        cells_.capacity() * sizeof(CellRange) + lane_.bytes() +
                        slabBegin_.capacity() * sizeof(uint32_t) +
                        slabs_.capacity() * sizeof(Slab);
    for (const Slab& slab : slabs_) {
      bytes += slab.lane.bytes() + slab.pairs.capacity() * sizeof(IndexPair) +
               (slab.near.capacity() + slab.far.capacity() + slab.incoming.capacity()) * 4;
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

  // The scratch of one sweep of the Subdivider chain and where it reports: the serial search
  // has one, the threaded search one per slab (kept from call to call with its slab, so that
  // which thread runs a slab changes no buffer's size).
  struct Lane {
    std::array<Subdivider, D> subdividers;
    KeySortScratch scratch;
    mask::Columns<D, T> mask;  // the contact mask's cells, see contactMask()
    mask::PairSink sink;       // the output, written ahead of its size during a sweep
    Stats stats;

    // Returns the bytes held.
    std::size_t bytes() const {
      std::size_t b = scratch.bytes() + mask.bytes();
      for (const auto& s : subdividers) {
        b += (s.input.capacity() + s.current.capacity() + s.held.capacity() +
              s.merged.capacity()) *
             4;
      }
      return b;
    }
  };

  // A contiguous range of axis-0 buckets the threaded search sweeps as one task, and what the
  // later slabs need from it.
  struct Slab {
    Lane lane;
    std::vector<IndexPair> pairs;    // the slab's pairs, in the serial search's order
    std::size_t pairCount = 0;       // how many of `pairs` this search wrote
    std::size_t lastPairs = 0;       // pairs of the last search, to size the next one's room
    bool stopped = false;            // the sweep stopped part way at the stop flag
    std::vector<uint32_t> near;      // objects reaching the next slab but not the one after
    std::vector<uint32_t> far;       // objects reaching past the next slab
    uint32_t farReach = 0;           // the highest axis-0 bucket an object of `far` reaches
    std::vector<uint32_t> incoming;  // objects of lower slabs reaching this one, in order
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
    auto& keys = lane_.subdividers[0].input;
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
    sortIndicesByKey(keys.data(), n, order_.data(), lane_.scratch);

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
  // axis 0. Changes the serial lane's buffers and appends pairs to its sink.
  void subdivideFirstAxis() {
    auto& all = lane_.subdividers[0].input;
    all.resize(cells_.size());
    std::iota(all.begin(), all.end(), 0u);
    if constexpr (D == 1) {
      refineOnLastAxis(all.data(), all.size());
      contactMask(lane_, all.data(), all.size());
    } else {
      subdivide<0>(lane_, all.data(), all.size());
    }
  }

  // Returns true if a search of n boxes takes the threaded path: the pool has more than one
  // thread and the input is large enough to pay for it.
  bool takesThreads(std::size_t n) const {
    return D > 1 && n >= threadedMinBoxes_ && ThreadPool::global().threads() > 1;
  }

  // Returns the first position in [from, to) whose object starts above axis-0 bucket c (to if
  // none); the objects are in bucket order on axis 0.
  std::size_t firstAbove(std::size_t from, std::size_t to, uint32_t c) const {
    while (from < to) {
      const std::size_t mid = from + (to - from) / 2;
      if (cells_[mid].lo[0] <= c) {
        from = mid + 1;
      } else {
        to = mid;
      }
    }
    return from;
  }

  // Cuts the sorted objects into slabs of whole axis-0 buckets, about objectsPerSlab_ objects
  // each (at most kMaxSlabs): every cut is moved from its even share to the nearer end of the
  // bucket it falls in. The cuts depend on the boxes and n alone, never on the thread count,
  // which is what makes the output the same for any number of threads. Returns the number of
  // slabs; changes slabBegin_ (slab s is positions [slabBegin_[s], slabBegin_[s + 1])).
  std::size_t partitionSlabs() {
    const std::size_t n = cells_.size();
    const std::size_t target = std::clamp<std::size_t>(n / objectsPerSlab_, 1, kMaxSlabs);
    slabBegin_.clear();
    slabBegin_.push_back(0);
    for (std::size_t k = 1; k < target; ++k) {
      const std::size_t share = k * n / target;
      const std::size_t previous = slabBegin_.back();
      if (share <= previous) continue;
      const uint32_t c = cells_[share].lo[0];
      // The bucket of `share` is [first, last): cut before or after it, whichever is nearer.
      const std::size_t last = firstAbove(share, n, c);
      std::size_t first = share;
      while (first > previous && cells_[first - 1].lo[0] == c) {
        // A bucket is rarely longer than a slab: the binary search only for long ones.
        if (share - first > 64) {
          first = c == 0 ? previous : firstAbove(previous, share, c - 1);
          break;
        }
        --first;
      }
      const std::size_t cut = (share - first <= last - share || last == n) ? first : last;
      if (cut > previous && cut < n) slabBegin_.push_back(static_cast<uint32_t>(cut));
    }
    slabBegin_.push_back(static_cast<uint32_t>(n));
    return slabBegin_.size() - 1;
  }

  // The threaded search over the slabs partitionSlabs() made: each slab sweeps its buckets
  // with its own lane, starting from the held-over array the serial sweep would have at its
  // first bucket, so that it reports exactly the serial search's pairs of those buckets in the
  // same order; the slabs' pairs are then put in slab order. Replaces out's contents with the
  // pairs; changes the slabs, the serial lane's input array and stats_.
  void findPairsInSlabs(std::vector<IndexPair>& out) {
    const std::size_t slabCount = slabBegin_.size() - 1;
    // Only grown: a slab's buffers stay with its number from one search to the next.
    if (slabs_.size() < slabCount) slabs_.resize(slabCount);
    auto& all = lane_.subdividers[0].input;
    all.resize(cells_.size());
    ThreadPool& pool = ThreadPool::global();
    pool.forEach(slabCount, [&](std::size_t s, unsigned) { findLeavers(s, slabCount); });
    pool.forEach(slabCount, [&](std::size_t s, unsigned) { sweepSlab(s); });

    std::size_t total = 0;
    stats_ = {};
    for (std::size_t s = 0; s < slabCount; ++s) {
      total += slabs_[s].pairCount;
      stats_.forwarded += slabs_[s].lane.stats.forwarded;
      stats_.maskEntries += slabs_[s].lane.stats.maskEntries;
      stopped_ = stopped_ || slabs_[s].stopped;
    }
    // With a stop flag, the slabs' pairs are copied into the output a slice at a time, the
    // flag looked at between (hundreds of megabytes with a wide skin).
    constexpr std::size_t kSlice = mask::kPairSlice;
    const auto halted = [&] { return stop_ != nullptr && stop_->load(std::memory_order_relaxed); };
    if (stopped_ || !sizeOutput(out, total)) {
      out.clear();
      return;
    }
    pool.forEach(slabCount, [&](std::size_t s, unsigned) {
      std::size_t at = 0;
      for (std::size_t r = 0; r < s; ++r) at += slabs_[r].pairCount;
      for (std::size_t done = 0; done < slabs_[s].pairCount; done += kSlice) {
        if (halted()) return;
        std::copy_n(slabs_[s].pairs.data() + done, std::min(kSlice, slabs_[s].pairCount - done),
                    out.data() + at + done);
      }
    });
    if (halted()) {
      stopped_ = true;
      out.clear();
      return;
    }
    lastPairs_ = total;
  }

  // Returns true with out resized to n, its old elements kept as far as they go (a grown one
  // reallocated empty first: they would only be copied to be overwritten), in slices with a
  // stop flag (mask::resizeInSlices): returns false, stopped_ set, if it stopped.
  bool sizeOutput(std::vector<IndexPair>& out, std::size_t n) {
    if (stop_ == nullptr || n <= out.size()) {
      out.resize(n);
      return true;
    }
    const std::size_t keep = out.capacity() >= n ? out.size() : 0;
    return mask::resizeInSlices(out, keep, n, *stop_) || !(stopped_ = true);
  }

  // Returns the first axis-0 bucket of slab s.
  uint32_t slabFirstBucket(std::size_t s) const { return cells_[slabBegin_[s]].lo[0]; }

  // Fills slab s's near and far lists with its objects that reach past its last bucket (in
  // position order). Changes slab s only, so the slabs may run at once.
  void findLeavers(std::size_t s, std::size_t slabCount) {
    Slab& slab = slabs_[s];
    const uint32_t begin = slabBegin_[s], end = slabBegin_[s + 1];
    slab.near.clear();
    slab.far.clear();
    slab.farReach = 0;
    if (s + 1 == slabCount) return;
    const uint32_t next = slabFirstBucket(s + 1);
    const uint32_t afterNext =
        s + 2 < slabCount ? slabFirstBucket(s + 2) : std::numeric_limits<uint32_t>::max();
    for (uint32_t i = begin; i < end; ++i) {
      const uint32_t reach = cells_[i].hi[0];
      if (reach < next) continue;
      if (reach < afterNext) {
        slab.near.push_back(i);
      } else {
        slab.far.push_back(i);
        slab.farReach = std::max(slab.farReach, reach);
      }
    }
  }

  // Sweeps slab s: gathers the objects of lower slabs that reach its first bucket (position
  // order), merges them bucket by bucket into the held-over array exactly as the serial sweep
  // does (the same current arrays and the same stable merge: an object that reaches the
  // slab was never dropped, and dropping others does not reorder it), then sweeps the slab's
  // buckets into its own pairs. Changes slab s and its part of the serial lane's input array
  // (it reads the other slabs' lists).
  void sweepSlab(std::size_t s) {
    // One axis has no Subdivider to sweep with; findPairs never comes here then.
    if constexpr (D > 1) {
      Slab& slab = slabs_[s];
      Lane& lane = slab.lane;
      lane.stats = {};
      Subdivider& first = lane.subdividers[0];
      first.held.clear();
      if (s > 0) {
        const uint32_t c = slabFirstBucket(s);
        auto& incoming = slab.incoming;
        incoming.clear();
        for (std::size_t r = 0; r + 1 < s; ++r) {
          if (slabs_[r].farReach < c) continue;
          for (uint32_t e : slabs_[r].far) {
            if (cells_[e].hi[0] >= c) incoming.push_back(e);
          }
        }
        // Every object the slab below lists reaches this slab.
        const Slab& below = slabs_[s - 1];
        const std::size_t before = incoming.size();
        incoming.resize(before + below.near.size() + below.far.size());
        std::merge(below.near.begin(), below.near.end(), below.far.begin(), below.far.end(),
                   incoming.begin() + static_cast<std::ptrdiff_t>(before));
        for (std::size_t begin = 0; begin < incoming.size();) {
          const uint32_t bucket = cells_[incoming[begin]].lo[0];
          std::size_t end = begin + 1;
          while (end < incoming.size() && cells_[incoming[end]].lo[0] == bucket) ++end;
          const std::size_t entering = end - begin;
          const uint32_t* current = currentArray<0>(lane, incoming.data() + begin, entering);
          first.merged.resize(first.held.size() + entering);
          mergeOnNextAxis<0>(first.held.data(), first.held.size(), current, entering,
                             first.merged.data());
          first.held.swap(first.merged);
          begin = end;
        }
      }
      // The room for the pairs: the last search's count for this slab, as the serial search
      // sizes its output, but never cut back, so that a warm search writes no zeros here.
      const std::size_t want = std::max(slab.lastPairs + slab.lastPairs / 8 + 1024,
                                        slab.pairs.capacity());
      if (slab.pairs.size() < want) slab.pairs.resize(want);
      lane.sink = {&slab.pairs, slab.pairs.data(), slab.pairs.data() + slab.pairs.size(), stop_};
      // The slab's part of the serial lane's input array: its positions, written here rather
      // than in one pass before, so that they are in this thread's cache when swept.
      const uint32_t begin = slabBegin_[s], end = slabBegin_[s + 1];
      uint32_t* in = lane_.subdividers[0].input.data() + begin;
      std::iota(in, in + (end - begin), begin);
      sweepBuckets<0>(lane, in, end - begin);
      slab.stopped = lane.sink.stopped;
      slab.pairCount = static_cast<std::size_t>(lane.sink.next - slab.pairs.data());
      if (!slab.stopped) slab.lastPairs = slab.pairCount;
      lane.sink = {};
    }
  }

  // Returns the current array of m entries in[0..m) entering one bucket of axis K, in the
  // order Subdivider K merges it: as they are when discretize() sorted over all axes, else
  // sorted on axis K+1 (and then by the minimum itself if K+1 is the last axis) into the
  // lane's current array. Changes the lane's current array and key-sort scratch.
  template <int K>
  const uint32_t* currentArray(Lane& lane, const uint32_t* in, std::size_t m) const {
    if (presorted_) return in;
    Subdivider& s = lane.subdividers[K];
    s.current.resize(m);
    sortByKey(
        in, s.current.data(), m,
        [this](uint32_t e) { return cells_[e & kIndexMask].lo[K + 1]; }, lane.scratch);
    if constexpr (K + 1 == D - 1) refineOnLastAxis(s.current.data(), m);
    return s.current.data();
  }

  // Merges held[0..a) and current[0..b), both in the order of axis K+1 that Subdivider K
  // keeps, into out[0..a+b): stably, held entries first among equals. Changes out only.
  template <int K>
  void mergeOnNextAxis(const uint32_t* held, std::size_t a, const uint32_t* current,
                       std::size_t b, uint32_t* out) const {
    if constexpr (K + 1 == D - 1) {
      std::merge(held, held + a, current, current + b, out,
                 [&](uint32_t x, uint32_t y) { return lastLo(x) < lastLo(y); });
    } else if (presorted_) {
      // Kept in the full order of the later axes, so that Subdivider K+1's runs are too.
      std::merge(held, held + a, current, current + b, out,
                 [&](uint32_t x, uint32_t y) { return laterBefore<K + 1>(x, y); });
    } else {
      std::merge(held, held + a, current, current + b, out, [&](uint32_t x, uint32_t y) {
        return cells_[x & kIndexMask].lo[K + 1] < cells_[y & kIndexMask].lo[K + 1];
      });
    }
  }

  // Subdivider K < D-1 over m entries in[0..m), sorted by bucket on axis K, starting with an
  // empty held-over array (see sweepBuckets). Changes the lane's Subdividers >= K.
  template <int K>
  void subdivide(Lane& lane, const uint32_t* in, std::size_t m) {
    lane.subdividers[K].held.clear();
    sweepBuckets<K>(lane, in, m);
  }

  // Subdivider K < D-1. `in` holds m entries sorted by bucket on axis K. Sweeps the buckets
  // where some object enters; at each it keeps the held-over array (objects still spanning the
  // bucket, lower-adjacent on axis K) sorted on axis K+1, merges the current array (objects
  // entering the bucket, sorted on axis K+1) into it, and forwards the result, already in
  // bucket order for Subdivider K+1. Held-over arrays are reused, not subdivided again, as in
  // the thesis's SGrid; each object is sorted once per axis. The held-over array starts as the
  // lane holds it (empty, or a slab's objects from lower buckets). Changes the lane's
  // Subdividers >= K, its counters, and appends pairs to its sink.
  template <int K>
  void sweepBuckets(Lane& lane, const uint32_t* in, std::size_t m) {
    Subdivider& s = lane.subdividers[K];
    for (std::size_t begin = 0; begin < m && !lane.sink.halted();) {
      const uint32_t c = cells_[in[begin] & kIndexMask].lo[K];
      std::size_t end = begin + 1;
      while (end < m && cells_[in[end] & kIndexMask].lo[K] == c) ++end;

      // The current array: the run itself when discretize() left it in order.
      const std::size_t entering = end - begin;
      const uint32_t* current = currentArray<K>(lane, in + begin, entering);
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
      mergeOnNextAxis<K>(s.held.data(), kept, current, entering, s.merged.data());
      s.held.swap(s.merged);
      // Where every object shares a lower-adjacent axis, the NAND rule accepts no pair.
      if (s.held.size() > 1 && (common & kLabelMask) == 0) {
        lane.stats.forwarded += s.held.size();
        if constexpr (K + 1 == D - 1) {
          contactMask(lane, s.held.data(), s.held.size());
        } else {
          subdivide<K + 1>(lane, s.held.data(), s.held.size());
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
  // bed (doc/design.md). Appends the overlapping pairs to the lane's sink.
  void contactMask(Lane& lane, const uint32_t* in, std::size_t m) {
    lane.stats.maskEntries += m;
    auto& columns = lane.mask;
    // The run ends in kPad sentinels that start after everything ends, so the scans stop on
    // the coordinate alone and may read kPad entries at a time.
    columns.fit(m + kPad);
    for (std::size_t i = 0; i < m; ++i) {
      const uint32_t j = in[i] & kIndexMask;
      columns.put(i, boxes_[j], order_[j], in[i] & kLabelMask);
    }
    for (std::size_t p = 0; p < kPad; ++p) columns.endAt(m + p);
#if defined(DEMLAB_MASK_AVX2)
    if constexpr (std::is_same_v<T, double>) {
      if (wide_) return mask::sweepAvx2<D>(columns, m, lane.sink);
    }
#endif
    mask::sweep<D, T>(columns, m, lane.sink);
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
  Lane lane_;  // the serial search's scratch; its Subdivider 0 input also serves the slabs
  std::vector<uint32_t> slabBegin_;  // the threaded search's slabs, see partitionSlabs()
  std::vector<Slab> slabs_;
  std::size_t threadedMinBoxes_ = kThreadedMinBoxes;
  std::size_t objectsPerSlab_ = kObjectsPerSlab;
  std::size_t lastSlabs_ = 0;
  bool wide_ = wideAvailable();
  std::size_t lastPairs_ = 0;  // pairs of the last search, to size the next one's output
  const std::atomic<bool>* stop_ = nullptr;  // see setStop()
  bool stopped_ = false;
};

// Compiled once, in src/search (see search/configs.hpp).
DEMLAB_SEARCH_CONFIGS(DEMLAB_SEARCH_EXTERN_CLASS, CGrid)

}  // namespace demlab::search
