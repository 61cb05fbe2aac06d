// The contact mask's storage and its sweep (see cgrid.hpp): the entries of one mask run held
// as columns (structure of arrays), and the scans that test an entry against the entries that
// start on the last axis before it ends, the NAND rule on their labels one more lane test.
//
// Why columns: a scan tests a block of candidates at once, and with each field of consecutive
// candidates side by side one vector load takes the same field of the whole block. On x86-64
// the scans of double boxes also come in an AVX2 build, chosen at run time (the library itself
// targets baseline x86-64): both produce the same pairs in the same order, since the wide scan
// computes the same tests a block at a time and packs the hits in candidate order.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "search/box.hpp"

#if defined(__x86_64__) && defined(__GNUC__)
#define DEMLAB_MASK_AVX2 1
#include <immintrin.h>
#endif

namespace demlab::search::mask {

// Candidates the portable and the AVX2 scans read at a time (most scans of a granular bed
// end within the first block, so the loop's branch is rarely taken); a run ends in kPad
// sentinels, enough for either.
inline constexpr std::size_t kBlock = 4;
inline constexpr std::size_t kWideBlock = 8;
inline constexpr std::size_t kPad = kWideBlock;

// Mask entries of D-dimensional boxes: for entry i, field f at values[f * stride + i], the
// fields being the last axis's minimum and maximum, then the minima of axes 0..D-2, then
// their maxima; and at index[i] the caller's index of the box in the low 32 - D bits, its
// label (bit k: lower-adjacent on axis k) in the top D, as in CGrid's entries.
template <int D, class T>
struct Columns {
  static constexpr uint32_t kLabels = ~((uint32_t{1} << (32 - D)) - 1);
  static constexpr int kFields = 2 * D;
  static constexpr int kLastLo = 0;
  static constexpr int kLastHi = 1;
  static constexpr int loField(int k) { return 2 + k; }
  static constexpr int hiField(int k) { return D + 1 + k; }

  std::vector<T> values;
  std::vector<uint32_t> index;
  std::size_t stride = 0;

  // Makes room for `size` entries, dropping the contents when it grows; grown to the largest
  // size seen plus an eighth, not geometrically (the mask is a large part of the working
  // memory of small scenes, and the slack keeps moved boxes from reallocating it).
  void fit(std::size_t size) {
    if (stride >= size) return;
    stride = size + size / 8 + 16;
    values.assign(stride * kFields, T{});
    index.assign(stride, 0);
  }

  // Returns the bytes held.
  std::size_t bytes() const {
    return values.capacity() * sizeof(T) + index.capacity() * sizeof(uint32_t);
  }

  // Stores entry `at`: the box b, known to the caller as `original`, with `label` in the top
  // bits. Changes that entry only.
  void put(std::size_t at, const Box<D, T>& b, uint32_t original, uint32_t label) {
    T* v = values.data() + at;
    v[kLastLo * stride] = b.lo[D - 1];
    v[kLastHi * stride] = b.hi[D - 1];
    for (int k = 0; k < D - 1; ++k) {
      v[loField(k) * stride] = b.lo[k];
      v[hiField(k) * stride] = b.hi[k];
    }
    index[at] = original | label;
  }

  // Makes entry i a sentinel: it starts after every box ends. Changes that entry only.
  void endAt(std::size_t i) { values[i] = std::numeric_limits<T>::infinity(); }
};

// One entry as the scanning side of a pair test: where it ends on the last axis, its bounds on
// the others, its index and label.
template <int D, class T>
struct Probe {
  T end;
  std::array<T, D - 1> lo, hi;
  uint32_t x;

  // Returns entry i of c.
  static Probe of(const Columns<D, T>& c, std::size_t i) {
    Probe p;
    const T* v = c.values.data() + i;
    p.end = v[Columns<D, T>::kLastHi * c.stride];
    for (int k = 0; k < D - 1; ++k) {
      p.lo[k] = v[Columns<D, T>::loField(k) * c.stride];
      p.hi[k] = v[Columns<D, T>::hiField(k) * c.stride];
    }
    p.x = c.index[i];
    return p;
  }
};

// Reports the pairs of a with the entries b, b + 1, ... of c up to the first that starts after
// a ends on the last axis (the run's sentinels stop it at the end), where the labels pass the
// NAND rule (no axis on which both are lower-adjacent) and the boxes overlap on the other axes;
// the caller has made room for (entries up to that one) + kPad pairs. Branch-free but for the
// scan's end: every candidate pair is written and kept only on a hit, its order a select.
// Returns the end of the pairs written.
template <int D, class T>
inline IndexPair* scanPortable(const Probe<D, T>& a, const Columns<D, T>& c, std::size_t b,
                               IndexPair* o) {
  using C = Columns<D, T>;
  const T* const v = c.values.data();
  const std::size_t s = c.stride;
  const uint32_t x = a.x & ~C::kLabels;
  const uint32_t label = a.x & C::kLabels;
  bool more;
  do {
    for (std::size_t i = b; i < b + kBlock; ++i) {
      bool hit = v[i] <= a.end;
      for (int k = 0; k < D - 1; ++k) {
        hit &= (a.lo[k] <= v[C::hiField(k) * s + i]) & (v[C::loField(k) * s + i] <= a.hi[k]);
      }
      const uint32_t y = c.index[i];
      hit &= (y & label) == 0;
      const uint32_t yi = y & ~C::kLabels;
      const uint32_t first = x < yi ? x : yi;
      *o = IndexPair{first, x ^ yi ^ first};
      o += hit;
    }
    more = v[b + kBlock - 1] <= a.end;
    b += kBlock;
  } while (more);
  return o;
}

#if defined(DEMLAB_MASK_AVX2)
#define DEMLAB_AVX2_TARGET __attribute__((target("avx2,popcnt")))

// Returns true if this CPU (and its operating system) runs AVX2 code; decided once. The
// detection is initialized here because a search may be built before the constructors that
// would otherwise do it have run.
inline bool avx2Available() {
  static const bool available = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
  }();
  return available;
}

// For each 4-bit hit mask, the permutation of 8 dwords (4 pairs) that packs the hit pairs
// first, in candidate order.
alignas(32) inline constexpr std::array<std::array<uint32_t, 8>, 16> kPackPairs = [] {
  std::array<std::array<uint32_t, 8>, 16> table{};
  for (uint32_t mask = 0; mask < 16; ++mask) {
    uint32_t slot = 0;
    for (uint32_t lane = 0; lane < 4; ++lane) {
      if (mask & (1u << lane)) {
        table[mask][2 * slot] = 2 * lane;
        table[mask][2 * slot + 1] = 2 * lane + 1;
        ++slot;
      }
    }
  }
  return table;
}();

// The probe of a scan in AVX2 registers: each value in every lane.
template <int D>
struct WideProbe {
  __m256d end;
  __m256d lo[D > 1 ? D - 1 : 1], hi[D > 1 ? D - 1 : 1];
  __m128i x, label;
};

// Writes at o the pairs of p with the four candidates at b of c, tested as scanPortable does
// (end and NAND rule included), and sets `starts` to the candidates' last-axis test. Returns
// the end of the pairs written.
template <int D>
DEMLAB_AVX2_TARGET inline IndexPair* testFourAvx2(const WideProbe<D>& p,
                                                  const Columns<D, double>& c, std::size_t b,
                                                  IndexPair* o, __m256d& starts) {
  using C = Columns<D, double>;
  const double* const v = c.values.data();
  const std::size_t s = c.stride;
  starts = _mm256_cmp_pd(_mm256_loadu_pd(v + b), p.end, _CMP_LE_OQ);
  __m256d hit = starts;
  for (int k = 0; k < D - 1; ++k) {
    const __m256d cHi = _mm256_loadu_pd(v + C::hiField(k) * s + b);
    const __m256d cLo = _mm256_loadu_pd(v + C::loField(k) * s + b);
    hit = _mm256_and_pd(hit, _mm256_and_pd(_mm256_cmp_pd(p.lo[k], cHi, _CMP_LE_OQ),
                                           _mm256_cmp_pd(cLo, p.hi[k], _CMP_LE_OQ)));
  }
  const __m128i y = _mm_loadu_si128(reinterpret_cast<const __m128i*>(c.index.data() + b));
  const __m128i apart = _mm_cmpeq_epi32(_mm_and_si128(y, p.label), _mm_setzero_si128());
  const unsigned mask = static_cast<unsigned>(_mm256_movemask_pd(hit)) &
                        static_cast<unsigned>(_mm_movemask_ps(_mm_castsi128_ps(apart)));
  const __m128i yi = _mm_andnot_si128(_mm_set1_epi32(static_cast<int>(C::kLabels)), y);
  const __m128i first = _mm_min_epu32(p.x, yi);
  const __m128i second = _mm_max_epu32(p.x, yi);
  const __m256i pairs =
      _mm256_inserti128_si256(_mm256_castsi128_si256(_mm_unpacklo_epi32(first, second)),
                              _mm_unpackhi_epi32(first, second), 1);
  const __m256i pack = _mm256_load_si256(reinterpret_cast<const __m256i*>(kPackPairs[mask].data()));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(o), _mm256_permutevar8x32_epi32(pairs, pack));
  return o + __builtin_popcount(mask);
}

// scanPortable for doubles, kWideBlock candidates a block, four in one AVX2 vector per field;
// the same pairs in the same order. Returns the end of the pairs written.
template <int D>
DEMLAB_AVX2_TARGET inline IndexPair* scanAvx2(const Probe<D, double>& a,
                                              const Columns<D, double>& c, std::size_t b,
                                              IndexPair* o) {
  using C = Columns<D, double>;
  WideProbe<D> p;
  p.end = _mm256_set1_pd(a.end);
  for (int k = 0; k < D - 1; ++k) {
    p.lo[k] = _mm256_set1_pd(a.lo[k]);
    p.hi[k] = _mm256_set1_pd(a.hi[k]);
  }
  p.x = _mm_set1_epi32(static_cast<int>(a.x & ~C::kLabels));
  p.label = _mm_set1_epi32(static_cast<int>(a.x & C::kLabels));
  for (;; b += kWideBlock) {
    __m256d starts;
    for (std::size_t q = 0; q < kWideBlock; q += 4) o = testFourAvx2<D>(p, c, b + q, o, starts);
    if ((_mm256_movemask_pd(starts) & 8) == 0) return o;
  }
}
#endif

// Returns scanAvx2 if Wide, else scanPortable.
template <bool Wide, int D, class T>
[[gnu::always_inline]] inline IndexPair* scanWith(const Probe<D, T>& a, const Columns<D, T>& c,
                                                  std::size_t b, IndexPair* o) {
#if defined(DEMLAB_MASK_AVX2)
  if constexpr (Wide) return scanAvx2<D>(a, c, b, o);
#endif
  return scanPortable<D, T>(a, c, b, o);
}

// The output of the sweep, written ahead of its size: pairs go to next, the vector holds room
// up to end.
// The pairs a search output takes over or is extended by between two looks at a stop flag:
// 4 MiB, a few milliseconds with their page faults.
inline constexpr std::size_t kPairSlice = (std::size_t(4) << 20) / sizeof(IndexPair);

// Returns true with v resized to n (at least keep), its first `keep` elements kept and the rest
// value-initialised, the pairs copied and the zeros written a kPairSlice at a time with `stop`
// looked at between slices (a gigabyte of pairs copied or zeroed in one call is deaf for a
// second); a buffer too small is replaced by one of capacity n. Returns false if stop was set:
// v then still holds its first `keep` elements where they were or, unchanged, all of them.
inline bool resizeInSlices(std::vector<IndexPair>& v, std::size_t keep, std::size_t n,
                           const std::atomic<bool>& stop) {
  const auto stopped = [&] { return stop.load(std::memory_order_relaxed); };
  std::vector<IndexPair> fresh;
  std::vector<IndexPair>* into = &v;
  if (v.capacity() < n) {
    fresh.reserve(n);
    for (std::size_t at = 0; at < keep; at += kPairSlice) {
      if (stopped()) return false;
      const auto from = v.begin() + static_cast<std::ptrdiff_t>(at);
      fresh.insert(fresh.end(), from, from + static_cast<std::ptrdiff_t>(std::min(kPairSlice, keep - at)));
    }
    into = &fresh;
  } else {
    v.resize(std::min(v.size(), keep));
  }
  while (into->size() < n) {
    if (stopped()) return false;
    into->resize(std::min(n, into->size() + kPairSlice));
  }
  if (into != &v) v.swap(fresh);
  return true;
}

struct PairSink {
  std::vector<IndexPair>* out = nullptr;
  IndexPair* next = nullptr;
  IndexPair* end = nullptr;
  // A flag that asks the search to stop part way (Ctrl-C), or none; stopped once it was seen.
  const std::atomic<bool>* stop = nullptr;
  bool stopped = false;

  // Returns true if the search is to stop: the stop flag is set now or was before. Changes
  // `stopped`.
  bool halted() {
    if (!stopped && stop != nullptr && stop->load(std::memory_order_relaxed)) stopped = true;
    return stopped;
  }

  // Makes room for `need` more pairs after o, within the vector's capacity first (so a warm
  // search allocates nothing). Changes o, end and the vector when it has to grow. With a stop
  // flag the vector grows in slices (resizeInSlices), doubling as resize() would: returns false,
  // the pairs before o kept and `stopped` set, if it stopped; else true.
  bool grow(IndexPair*& o, std::size_t need) {
    const std::size_t used = static_cast<std::size_t>(o - out->data());
    std::size_t size = std::max(out->capacity(), used + need);
    if (size == out->size()) size = std::max(2 * size, used + need);
    if (stop == nullptr) {
      out->resize(size);
    } else {
      if (size > out->capacity()) size = std::max(size, 2 * out->capacity());
      if (!resizeInSlices(*out, used, size, *stop)) return !(stopped = true);
    }
    o = out->data() + used;
    end = out->data() + out->size();
    return true;
  }
};

// Checks every pair of the m entries (plus sentinels) of c, sorted by the last axis's minimum:
// each entry meets the later entries that start before it ends and keeps those its label
// allows. Wide: with scanAvx2 (the caller runs it only where AVX2 code runs). Appends to the
// sink; stops part way, the sink's pairs so far kept, when the sink halts.
template <bool Wide, int D, class T>
[[gnu::always_inline]] inline void sweepWith(const Columns<D, T>& c, std::size_t m,
                                             PairSink& sink) {
  IndexPair* o = sink.next;
  for (std::size_t i = 0; i < m; ++i) {
    // A run of a wide skin's search holds thousands of entries, each meeting thousands.
    if ((i & 255) == 255 && sink.halted()) break;
    const std::size_t need = m - i + kPad;
    if (static_cast<std::size_t>(sink.end - o) < need && !sink.grow(o, need)) break;
    o = scanWith<Wide>(Probe<D, T>::of(c, i), c, i + 1, o);
  }
  sink.next = o;
}

// The sweep with the portable scan.
template <int D, class T>
void sweep(const Columns<D, T>& c, std::size_t m, PairSink& sink) {
  sweepWith<false>(c, m, sink);
}

#if defined(DEMLAB_MASK_AVX2)
// The sweep with the AVX2 scan, compiled for AVX2 as a whole so that the scan inlines; run
// only where avx2Available().
template <int D>
DEMLAB_AVX2_TARGET void sweepAvx2(const Columns<D, double>& c, std::size_t m, PairSink& sink) {
  sweepWith<true>(c, m, sink);
}
#endif

}  // namespace demlab::search::mask
