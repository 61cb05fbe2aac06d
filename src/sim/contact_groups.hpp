// ContactGroups: the candidate pairs in the order the threaded contact pass runs them.
//
// The elements, in dense order (spatially sorted: sim/reorder.hpp), fall into blocks of
// kBlockElements. A candidate belongs to the group of its two blocks (one block, or a pair of
// them). Two groups that share no block write no element in common, so they may run at once;
// the groups are put in phases: phase 0 holds every one-block group, and each later phase a
// set of two-block groups that share no block (a greedy colouring of the block graph's edges).
// The candidates are sorted by (phase, group), so the pass runs group after group in candidate
// order with one thread, and phase after phase with many, each phase's groups at once. Every
// element then receives its contacts' forces in candidate order either way, and each group's
// energy sums are added in group order: the bits are those of one thread for any thread count,
// and the grouping depends on the candidates and the element count alone, never on the threads.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

#include "core/free_aside.hpp"
#include "core/interrupt.hpp"

namespace demlab::sim {

struct ContactGroups {
  // Elements per block: small enough that a dense bed of 10^4 has tens of blocks to share out,
  // large enough that most candidates (about two thirds of a dense 3D bed's) lie in one block.
  static constexpr uint32_t kBlockElements = 512;

  struct Range {
    uint32_t begin = 0, end = 0;
  };
  std::vector<Range> groups;  // candidate ranges, in candidate order
  std::vector<Range> phases;  // group ranges; the groups of one phase share no block
  size_t candidates = 0;      // the candidate count they cover

  // Returns true if the groups cover exactly nc candidates (else the pass runs them as one).
  bool cover(size_t nc) const { return candidates == nc && !groups.empty(); }
  void clear() {
    groups.clear();
    phases.clear();
    candidates = 0;
  }
  size_t heapBytes() const { return (groups.capacity() + phases.capacity()) * sizeof(Range); }
};

// Returns nothing; sorts pairs (each with members .i and .j, dense element indices) into the
// order of ContactGroups, keeping the given order within each group, and sets *groups; when
// moved is not null, sets (*moved)[new position] = old position (for what is kept per pair).
// Changes pairs, *groups and *moved. A list already in that order keeps it.
// Calls poll() between slices of a millisecond or less of its passes (polledFor, polledFill):
// the passes over millions of pairs take seconds in all. When poll throws, pairs are as they
// were and *groups and *moved half made.
template <class Pair, class Poll>
void groupCandidates(std::vector<Pair>& pairs, ContactGroups* groups, std::vector<uint32_t>* moved,
                     Poll&& poll) {
  constexpr uint32_t B = ContactGroups::kBlockElements;
  const size_t nc = pairs.size();
  groups->clear();
  groups->candidates = nc;
  if (moved != nullptr) moved->clear();
  if (nc == 0) return;
  // The distinct block pairs: per lower block, the higher blocks met (a handful each, found
  // by a linear scan); a pair's local index into its lower block's list kept for the ranks.
  uint32_t blocks = 0;
  polledFor(nc, poll, [&](size_t k) {
    blocks = std::max({blocks, pairs[k].i / B + 1, pairs[k].j / B + 1});
  });
  std::vector<std::vector<uint32_t>> higher(blocks);
  std::vector<uint32_t> local = polledFill(nc, 0u, poll);
  const FreeAsideOnThrow asideLocal(local);  // stopped: megabytes not to free on the way out
  polledFor(nc, poll, [&](size_t k) {
    const uint32_t a = pairs[k].i / B, b = pairs[k].j / B;
    const uint32_t lo = std::min(a, b), hi = std::max(a, b);
    std::vector<uint32_t>& h = higher[lo];
    uint32_t at = 0;
    while (at < h.size() && h[at] != hi) ++at;
    if (at == h.size()) h.push_back(hi);
    local[k] = at;
  });
  poll();
  // The edges in (lo, hi) order; edgeOf[lo][local index] their number.
  struct Edge {
    uint32_t lo, hi;
  };
  std::vector<Edge> edges;
  std::vector<std::vector<uint32_t>> edgeOf(blocks);
  for (uint32_t lo = 0; lo < blocks; ++lo) {
    const std::vector<uint32_t>& h = higher[lo];
    std::vector<uint32_t> idx(h.size());
    std::iota(idx.begin(), idx.end(), 0u);
    std::sort(idx.begin(), idx.end(), [&](uint32_t x, uint32_t y) { return h[x] < h[y]; });
    edgeOf[lo].resize(h.size());
    for (uint32_t x : idx) {
      edgeOf[lo][x] = static_cast<uint32_t>(edges.size());
      edges.push_back({lo, h[x]});
    }
  }
  poll();
  // Colours: the one-block groups 0 (phase 0), the others greedily in (lo, hi) order, each
  // the lowest colour free at both its blocks.
  std::vector<uint32_t> colour(edges.size(), 0);
  std::vector<std::vector<bool>> used(blocks);
  uint32_t colours = 1;
  for (size_t e = 0; e < edges.size(); ++e) {
    const uint32_t lo = edges[e].lo, hi = edges[e].hi;
    if (lo == hi) continue;
    auto taken = [&](uint32_t blk, uint32_t col) {
      return col < used[blk].size() && used[blk][col];
    };
    uint32_t c = 1;
    while (taken(lo, c) || taken(hi, c)) ++c;
    for (uint32_t blk : {lo, hi}) {
      if (used[blk].size() <= c) used[blk].resize(c + 1, false);
      used[blk][c] = true;
    }
    colour[e] = c;
    colours = std::max(colours, c + 1);
  }
  // Each pair's group rank: edges ordered by (colour, lo, hi).
  std::vector<uint32_t> byRank(edges.size());
  std::iota(byRank.begin(), byRank.end(), 0u);
  std::stable_sort(byRank.begin(), byRank.end(),
                   [&](uint32_t a, uint32_t b) { return colour[a] < colour[b]; });
  std::vector<uint32_t> rankOfEdge(edges.size());
  for (uint32_t r = 0; r < byRank.size(); ++r) rankOfEdge[byRank[r]] = r;
  poll();
  // Each pair's rank, written over its local index, which is not needed after.
  std::vector<uint32_t>& rank = local;
  polledFor(nc, poll, [&](size_t k) {
    const uint32_t lo = std::min(pairs[k].i, pairs[k].j) / B;
    rank[k] = rankOfEdge[edgeOf[lo][local[k]]];
  });
  // A stable counting sort by rank.
  std::vector<uint32_t> start(edges.size() + 1, 0);
  polledFor(nc, poll, [&](size_t k) { start[rank[k] + 1] += 1; });
  for (size_t r = 0; r < edges.size(); ++r) start[r + 1] += start[r];
  std::vector<uint32_t> order = polledFill(nc, 0u, poll);
  const FreeAsideOnThrow asideOrder(order);
  {
    std::vector<uint32_t> at(start.begin(), start.end() - 1);
    polledFor(nc, poll, [&](size_t k) { order[at[rank[k]]++] = static_cast<uint32_t>(k); });
  }
  bool same = true;
  polledFor(nc, poll, [&](size_t k) { same = same && order[k] == k; });
  if (!same) {
    std::vector<Pair> sorted = polledFill(nc, Pair{}, poll);
    const FreeAsideOnThrow asideSorted(sorted);
    polledFor(nc, poll, [&](size_t k) { sorted[k] = pairs[order[k]]; });
    pairs.swap(sorted);
  }
  if (moved != nullptr) {
    moved->swap(order);
  }
  groups->groups.resize(edges.size());
  for (size_t r = 0; r < edges.size(); ++r) groups->groups[r] = {start[r], start[r + 1]};
  // The phases: runs of groups of one colour.
  uint32_t g = 0;
  for (uint32_t c = 0; c < colours && g < byRank.size(); ++c) {
    const uint32_t first = g;
    while (g < byRank.size() && colour[byRank[g]] == c) ++g;
    if (g > first) groups->phases.push_back({first, g});
  }
}

}  // namespace demlab::sim
