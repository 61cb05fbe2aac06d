// Spatial reordering of the grains' hot arrays (done at a neighbor search, every
// SimObjManager::reorderEvery-th search).
//
// The contact loop reads both grains of every candidate pair; with grains in arbitrary dense
// order (a shuffled data file, or grains that have mixed) every read is a cache miss, and the
// contact pass becomes bound by memory latency. Sorting the dense order along a Morton
// (Z-order) curve over cells about one grain diameter wide puts neighbors close in memory, as
// LAMMPS's periodic atom sort does. The order depends only on the positions and the current
// dense order (ties keep the dense order), so runs stay deterministic, and checkpoints save
// the dense order, so a loaded scene continues bit-identically.
//
// Handles stay valid: the HandlePool's dense table is permuted with the arrays. Pair springs
// are keyed by handle slots (sim/history_store.hpp), not dense indices, and must be collected
// before the permutation and handed back after the search.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Returns x's bits spread so that bit k lands on bit D*k (D = 2: 32 bits -> 64; D = 3:
// 21 bits -> 63).
template <int D>
inline uint64_t spreadBits(uint64_t x) {
  if constexpr (D == 2) {
    x &= 0xFFFFFFFFull;
    x = (x | (x << 16)) & 0x0000FFFF0000FFFFull;
    x = (x | (x << 8)) & 0x00FF00FF00FF00FFull;
    x = (x | (x << 4)) & 0x0F0F0F0F0F0F0F0Full;
    x = (x | (x << 2)) & 0x3333333333333333ull;
    x = (x | (x << 1)) & 0x5555555555555555ull;
  } else {
    x &= 0x1FFFFFull;
    x = (x | (x << 32)) & 0x001F00000000FFFFull;
    x = (x | (x << 16)) & 0x001F0000FF0000FFull;
    x = (x | (x << 8)) & 0x100F00F00F00F00Full;
    x = (x | (x << 4)) & 0x10C30C30C30C30C3ull;
    x = (x | (x << 2)) & 0x1249249249249249ull;
  }
  return x;
}

// Returns the permutation that sorts the grains along a Morton curve: perm[k] is the old
// dense index of the grain that goes to dense index k. Changes nothing.
template <int D>
std::vector<uint32_t> mortonOrder(const ElementArrays<D>& a) {
  const size_t n = a.size();
  std::vector<uint32_t> perm(n);
  if (n == 0) return perm;
  VecD<D> lo = a.x[0], hi = a.x[0];
  Real rMax = 0;
  for (size_t i = 0; i < n; ++i) {
    lo = lo.cwiseMin(a.x[i]);
    hi = hi.cwiseMax(a.x[i]);
    rMax = std::max(rMax, a.r[i]);
  }
  constexpr int kBits = D == 2 ? 32 : 21;
  const Real maxCells = static_cast<Real>((uint64_t{1} << kBits) - 1);
  Real cell = 2 * rMax;
  for (int k = 0; k < D; ++k) cell = std::max(cell, (hi[k] - lo[k]) / maxCells);
  if (!(cell > 0) || !std::isfinite(cell)) cell = 1;
  const Real inv = 1 / cell;
  std::vector<std::pair<uint64_t, uint32_t>> keys(n);
  for (size_t i = 0; i < n; ++i) {
    uint64_t key = 0;
    for (int k = 0; k < D; ++k) {
      const Real c = std::clamp((a.x[i][k] - lo[k]) * inv, Real(0), maxCells);
      key |= spreadBits<D>(static_cast<uint64_t>(c)) << k;
    }
    keys[i] = {key, static_cast<uint32_t>(i)};
  }
  std::sort(keys.begin(), keys.end());
  for (size_t k = 0; k < n; ++k) perm[k] = keys[k].second;
  return perm;
}

// Replaces v by its entries gathered through perm (v[k] = old v[perm[k]]).
template <class T, class A>
void gatherInPlace(std::vector<T, A>& v, const std::vector<uint32_t>& perm) {
  std::vector<T, A> out;
  out.reserve(v.size());
  for (uint32_t p : perm) out.push_back(v[p]);
  v.swap(out);
}

// Sorts the grains' dense order along a Morton curve. Returns true if the order changed.
// Changes every per-grain array, the handle pool's dense table and s.xAtBuild; invalidates
// every dense index held elsewhere (candidates, wall candidates, contact records): call it
// only where those are rebuilt next, with the pair springs collected by slot beforehand.
// Polls Ctrl-C between the sort and each array's gather (pollStep: may throw StepAbandoned,
// the scene then half permuted, as a step abandoned part way is).
template <int D>
bool reorderGrains(Scene<D>& s) {
  ElementArrays<D>& a = s.elements.a;
  const std::vector<uint32_t> perm = mortonOrder(a);
  bool identity = true;
  for (size_t k = 0; k < perm.size() && identity; ++k) identity = perm[k] == k;
  if (identity) return false;
  ElementArrays<D>::forEachArray(a, [&](auto& arr) {
    pollStep(s);
    gatherInPlace(arr, perm);
  });
  if (s.xAtBuild.size() == perm.size()) gatherInPlace(s.xAtBuild, perm);
  auto st = s.elements.pool().saveState();
  gatherInPlace(st.dense, perm);
  s.elements.pool().restoreState(st);
  s.contacts.clear();
  return true;
}

}  // namespace demlab::sim
