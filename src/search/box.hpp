// Axis-aligned boxes (bounding volumes) and the pairs a neighbor search reports.
//
// Boxes are closed: two boxes that touch exactly at a face, edge or corner overlap. A contact
// at zero gap is a contact, and every algorithm in src/search/ follows the same rule, so the
// brute-force oracle and the grids agree bit for bit.
#pragma once

#include <array>
#include <cstdint>

namespace demlab::search {

template <int D, class T>
struct Box {
  static_assert(D >= 1, "a box needs at least one axis");
  std::array<T, D> lo;  // minimum corner
  std::array<T, D> hi;  // maximum corner, hi[k] >= lo[k]
};

// Returns true if the closed boxes a and b share at least one point.
template <int D, class T>
inline bool overlaps(const Box<D, T>& a, const Box<D, T>& b) noexcept {
  for (int k = 0; k < D; ++k) {
    if (a.lo[k] > b.hi[k] || b.lo[k] > a.hi[k]) return false;
  }
  return true;
}

// One reported pair of box indices, always first < second.
struct IndexPair {
  uint32_t first;
  uint32_t second;
  friend bool operator==(const IndexPair&, const IndexPair&) = default;
  friend auto operator<=>(const IndexPair&, const IndexPair&) = default;
};

// Returns the pair {min(a,b), max(a,b)}.
inline IndexPair makePair(uint32_t a, uint32_t b) noexcept {
  return a < b ? IndexPair{a, b} : IndexPair{b, a};
}

}  // namespace demlab::search
