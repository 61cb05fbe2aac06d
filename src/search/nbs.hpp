// Nbs: the No Binary Search contact detection of Munjiza & Andrews (1998), generalized from its
// 2-D/3-D formulation to D axes. It is a peer of CGrid in benchmarks, so it is implemented as
// NBS is meant to run (tuned, not a straw man): one cell size equal to the largest object,
// every object in exactly one cell, singly linked bucket lists in int32 "next" arrays, and an
// object-driven traversal that visits occupied buckets only.
//
// Known weaknesses, kept on purpose because they are what the benchmarks measure:
// - The cell size is the largest extent of any object, so one big object (a domain-sized wall
//   or plate) makes every cell as big as the domain: all objects share a few cells and the
//   search degrades to all-pairs. Bidisperse scenes over-report in proportion to the size ratio.
// - The bucket arrays are sized by the extent of the domain in cells along each axis, not by
//   the number of objects, so sparse or spread-out scenes pay memory (and first-touch time) for
//   empty space. To keep memory bounded the cells along one axis are capped at 4N + 1024 by
//   widening that axis's cells, which only makes the search coarser, never wrong.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "search/broad_phase.hpp"
#include "search/configs.hpp"
#include "search/validate.hpp"

namespace demlab::search {

template <int D, class T>
class Nbs final : public BroadPhase<D, T> {
 public:
  std::string_view name() const override { return "nbs"; }

  // Stores every overlapping pair once in `out` (see BroadPhase). Changes the member buffers,
  // which keep their capacity for the next call. Throws demlab::Error {DEMLAB VALUE BOX} on a
  // bad box and {DEMLAB LIMIT COUNT} if there are more boxes than int32 list links can address.
  void findPairs(std::span<const Box<D, T>> boxes, std::vector<IndexPair>& out) override {
    out.clear();
    validateBoxes<D, T>(boxes);
    if (boxes.size() > static_cast<std::size_t>(std::numeric_limits<int32_t>::max())) {
      throw Error("too many boxes for nbs: " + std::to_string(boxes.size()), {"LIMIT", "COUNT"});
    }
    const auto n = static_cast<int32_t>(boxes.size());
    if (n < 2) return;
    if (!clean_) scrubBuckets();
    discretize(boxes);
    boxes_ = boxes.data();
    out_ = &out;
    // A throw from out.push_back leaves lists half built; clean_ makes the next call scrub.
    clean_ = false;
    level<0>(-1, nullptr, 0);
    clean_ = true;
    boxes_ = nullptr;
    out_ = nullptr;
  }

  // Returns the capacity in bytes of the cell coordinates, list links, bucket heads and
  // visited flags. Changes nothing.
  std::size_t workingBytes() const override {
    std::size_t bytes = node_.capacity() * sizeof(Node);
    for (int k = 0; k < D; ++k) {
      bytes += heads_[k].capacity() * sizeof(int32_t) + visited_[k].capacity() * sizeof(uint8_t);
    }
    return bytes;
  }

 private:
  static constexpr int pow3(int k) { return k == 0 ? 1 : 3 * pow3(k - 1); }

  // Neighbour groups entering level K: the cells whose offset from the pivot over axes 0..K-1
  // is lexicographically negative (first nonzero offset -1). Every such offset must be paired
  // with all offsets on the remaining axes, which is the NBS half mask generalized to D axes:
  // (3^D - 1) / 2 neighbour cells per pivot, 4 in 2-D and 13 in 3-D as in the paper.
  static constexpr int maxGroups(int k) { return (pow3(k) - 1) / 2; }

  static constexpr int32_t kEmpty = -1;

  // Stores the cell coordinates of every box along every axis in node_ (shifted by one so
  // that the neighbours c-1 and c+1 of any occupied cell are valid indices) and sizes the
  // bucket arrays for them. Returns nothing; changes node_, heads_, visited_ and stride_.
  void discretize(std::span<const Box<D, T>> boxes) {
    const std::size_t n = boxes.size();
    // Work in double, in quarter units: float inputs convert exactly, scaling by a power of two
    // is exact above the subnormals, and a quarter keeps every difference and the widened cell
    // below it finite even for coordinates near the largest double.
    const auto scaled = [](T v) { return static_cast<double>(v) * 0.25; };
    std::array<double, D> minLo;
    std::array<double, D> maxLo;
    minLo.fill(std::numeric_limits<double>::infinity());
    maxLo.fill(-std::numeric_limits<double>::infinity());
    double extent = 0.0;
    double magnitude = 0.0;
    for (const auto& b : boxes) {
      for (int k = 0; k < D; ++k) {
        const double lo = scaled(b.lo[k]);
        const double hi = scaled(b.hi[k]);
        minLo[k] = std::min(minLo[k], lo);
        maxLo[k] = std::max(maxLo[k], lo);
        extent = std::max(extent, hi - lo);
        magnitude = std::max(magnitude, std::max(std::abs(lo), std::abs(hi)));
      }
    }
    // Two overlapping boxes have lo corners at most `extent` apart on every axis, so with the
    // cell at least that wide their cells differ by at most one. The factor and the term in
    // `magnitude` absorb the rounding of hi - lo, lo - minLo and the division (each at most
    // 2^-53 relative, on values up to 2 * magnitude), so the bound also holds for the computed
    // coordinates; the last term covers subnormal rounding and keeps the quotients finite.
    const double base = extent > 0.0 ? extent : 0.25;
    const double cell = base * (1.0 + 0x1p-40) + magnitude * 0x1p-48 + 0x1p-1000;
    // Caps the array length; widening an axis's cells keeps the at-most-one-apart property.
    const int32_t cap = static_cast<int32_t>(std::min<std::size_t>(4 * n + 1024, 1u << 30));
    std::array<double, D> width;
    for (int k = 0; k < D; ++k) width[k] = std::max(cell, (maxLo[k] - minLo[k]) / (cap - 2));

    node_.resize(n);
    std::array<int32_t, D> top;
    top.fill(0);
    for (std::size_t i = 0; i < n; ++i) {
      for (int k = 0; k < D; ++k) {
        // Clamping after floor is monotone and shrinks gaps, so neighbours stay neighbours.
        const double q = std::floor((scaled(boxes[i].lo[k]) - minLo[k]) / width[k]);
        const int32_t c = 1 + static_cast<int32_t>(std::clamp(q, 0.0, double(cap - 2)));
        node_[i].cell[k] = c;
        top[k] = std::max(top[k], c);
      }
    }
    for (int k = 0; k < D; ++k) {
      stride_[k] = top[k] + 2;
      const std::size_t heads = static_cast<std::size_t>(maxGroups(k) + 1) * stride_[k];
      // Growing fills with the empty marker; the buckets are always left empty after a call,
      // so old contents are already empty whatever the stride was.
      if (heads_[k].size() < heads) heads_[k].resize(heads, kEmpty);
      if (visited_[k].size() < static_cast<std::size_t>(stride_[k])) {
        visited_[k].resize(stride_[k], 0);
      }
    }
  }

  // Restores the all-empty state of the bucket heads and visited flags after an interrupted
  // call. Changes heads_, visited_ and clean_.
  void scrubBuckets() {
    for (int k = 0; k < D; ++k) {
      std::fill(heads_[k].begin(), heads_[k].end(), kEmpty);
      std::fill(visited_[k].begin(), visited_[k].end(), uint8_t{0});
    }
    clean_ = true;
  }

  // Calls fn(object) for each object of the level-K input list starting at head; level 0's
  // input is every object. Changes nothing itself.
  template <int K, class Fn>
  void forEachIn(int32_t head, Fn&& fn) const {
    if constexpr (K == 0) {
      const auto n = static_cast<int32_t>(node_.size());
      for (int32_t o = 0; o < n; ++o) fn(o);
    } else {
      const Node* node = node_.data();
      for (int32_t o = head; o != kEmpty; o = node[o].next[K - 1]) fn(o);
    }
  }

  // Processes one pivot bucket at level K: `pivot` is the list of objects sharing the pivot's
  // cell on axes 0..K-1, `groups` are the nonempty neighbour lists of the half mask (all in
  // links next[K-1]). Below the last axis it reports pairs; otherwise it splits the pivot and the
  // neighbours along axis K and recurses into each occupied cell of the pivot, in object order
  // so empty cells are never touched. Returns nothing; appends to *out_ and uses heads_[K],
  // the links next[K] and visited_[K], which it leaves empty again.
  template <int K>
  void level(int32_t pivot, const int32_t* groups, int groupCount) {
    if constexpr (K == D) {
      reportPairs(pivot, groups, groupCount);
    } else {
      int32_t* heads = heads_[K].data();
      uint8_t* visited = visited_[K].data();
      Node* node = node_.data();
      const int32_t stride = stride_[K];

      forEachIn<K>(pivot, [&](int32_t o) {
        const int32_t c = node[o].cell[K];
        node[o].next[K] = heads[c];
        heads[c] = o;
      });
      for (int g = 0; g < groupCount; ++g) {
        int32_t* h = heads + (g + 1) * stride;
        forEachIn<K>(groups[g], [&](int32_t o) {
          const int32_t c = node[o].cell[K];
          node[o].next[K] = h[c];
          h[c] = o;
        });
      }

      forEachIn<K>(pivot, [&](int32_t o) {
        const int32_t c = node[o].cell[K];
        if (visited[c]) return;
        visited[c] = 1;
        // The pivot's lower neighbour along K, then every neighbour group at offsets -1, 0, +1.
        std::array<int32_t, maxGroups(K + 1)> next{};
        int count = 0;
        if (heads[c - 1] != kEmpty) next[count++] = heads[c - 1];
        for (int g = 0; g < groupCount; ++g) {
          const int32_t* h = heads + (g + 1) * stride;
          for (int d = -1; d <= 1; ++d) {
            if (h[c + d] != kEmpty) next[count++] = h[c + d];
          }
        }
        level<K + 1>(heads[c], next.data(), count);
      });

      forEachIn<K>(pivot, [&](int32_t o) {
        const int32_t c = node[o].cell[K];
        visited[c] = 0;
        heads[c] = kEmpty;
      });
      for (int g = 0; g < groupCount; ++g) {
        int32_t* h = heads + (g + 1) * stride;
        forEachIn<K>(groups[g], [&](int32_t o) { h[node[o].cell[K]] = kEmpty; });
      }
    }
  }

  // Tests the objects of one cell against each other and against the neighbour cells' objects
  // (lists in links next[D-1]). Returns nothing; appends the overlapping pairs to *out_.
  void reportPairs(int32_t pivot, const int32_t* groups, int groupCount) {
    const Node* node = node_.data();
    for (int32_t a = pivot; a != kEmpty; a = node[a].next[D - 1]) {
      const Box<D, T>& boxA = boxes_[a];
      for (int32_t b = node[a].next[D - 1]; b != kEmpty; b = node[b].next[D - 1]) {
        if (overlaps(boxA, boxes_[b]))
          out_->push_back(makePair(static_cast<uint32_t>(a), static_cast<uint32_t>(b)));
      }
      for (int g = 0; g < groupCount; ++g) {
        for (int32_t b = groups[g]; b != kEmpty; b = node[b].next[D - 1]) {
          if (overlaps(boxA, boxes_[b]))
            out_->push_back(makePair(static_cast<uint32_t>(a), static_cast<uint32_t>(b)));
        }
      }
    }
  }

  // Per box: its cell coordinates and its link in the list of each level, side by side so
  // that following a list touches one cache line per box.
  struct Node {
    std::array<int32_t, D> cell;
    std::array<int32_t, D> next;
  };
  std::vector<Node> node_;
  std::array<std::vector<int32_t>, D> heads_;    // per level: pivot + neighbour-group buckets
  std::array<std::vector<uint8_t>, D> visited_;  // per level: pivot cells already processed
  std::array<int32_t, D> stride_{};              // bucket array length per level this call
  bool clean_ = true;                            // all heads empty and all flags clear
  const Box<D, T>* boxes_ = nullptr;             // the input, only during findPairs
  std::vector<IndexPair>* out_ = nullptr;        // the output, only during findPairs
};

// Compiled once, in src/search (see search/configs.hpp).
DEMLAB_SEARCH_CONFIGS(DEMLAB_SEARCH_EXTERN_CLASS, Nbs)

}  // namespace demlab::search
