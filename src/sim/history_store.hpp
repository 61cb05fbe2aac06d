// Where the tangential springs of frictional contacts live.
//
// Between two neighbor searches the candidate pairs are fixed, so each candidate pair (grain
// pair, or grain and wall) owns a spring slot in an array parallel to the candidate list: the
// contact loop reads and writes it by index, with no hashing (a hash lookup per contact per
// step costs more than the contact law). A candidate pair out of contact has its spring zeroed
// (the contact opened). At a search, and before any edit that renumbers the grains, the
// nonzero springs are parked in the InstanceInteractionManager under the pair's stable ids
// (handle slot indices, walls in the top half of the id space), and after the search each new
// candidate takes its spring back from there; the manager is then emptied. So the hash table
// is touched once per pair per search, not per step.
#pragma once

#include "sim/scene.hpp"

namespace demlab::sim {

// Moves every nonzero spring of the current candidates into s.histories and empties the
// per-candidate arrays. Call before the candidates or the dense order change.
template <int D>
void parkSprings(Scene<D>& s) {
  if (!s.keepHistory) return;
  const GrainArrays<D>& a = s.grains.a;
  const size_t n = std::min(s.pairSprings.size(), s.candidates.size());
  for (size_t k = 0; k < n; ++k) {
    const VecD<D>& sp = s.pairSprings[k].spring;
    if (sp.squaredNorm() == 0) continue;
    const uint32_t p = a.slot[s.candidates[k].i], q = a.slot[s.candidates[k].j];
    // The loop keeps each spring in the orientation of the lower slot (A) to the higher.
    s.histories.touch(std::min(p, q), std::max(p, q)).state.spring = sp;
  }
  for (size_t w = 0; w < s.wallSprings.size() && w < s.wallCandidates.size(); ++w) {
    const uint32_t wid = wallPairId(s.walls.pool().handleAt(static_cast<uint32_t>(w)).index);
    const auto& springs = s.wallSprings[w];
    for (size_t k = 0; k < springs.size() && k < s.wallCandidates[w].size(); ++k) {
      if (springs[k].spring.squaredNorm() == 0) continue;
      s.histories.touch(a.slot[s.wallCandidates[w][k]], wid).state.spring = springs[k].spring;
    }
  }
  s.pairSprings.clear();
  s.wallSprings.clear();
}

// Gives every candidate its parked spring (zero if none) and empties s.histories.
template <int D>
void unparkSprings(Scene<D>& s) {
  if (!s.keepHistory) return;
  const GrainArrays<D>& a = s.grains.a;
  s.pairSprings.assign(s.candidates.size(), physics::TangentialHistory<D>{});
  s.wallSprings.resize(s.wallCandidates.size());
  for (size_t w = 0; w < s.wallCandidates.size(); ++w) {
    s.wallSprings[w].assign(s.wallCandidates[w].size(), physics::TangentialHistory<D>{});
  }
  if (s.histories.empty()) return;
  for (size_t k = 0; k < s.candidates.size(); ++k) {
    const uint32_t p = a.slot[s.candidates[k].i], q = a.slot[s.candidates[k].j];
    if (const auto* h = s.histories.find(std::min(p, q), std::max(p, q))) s.pairSprings[k] = *h;
  }
  for (size_t w = 0; w < s.wallCandidates.size(); ++w) {
    const uint32_t wid = wallPairId(s.walls.pool().handleAt(static_cast<uint32_t>(w)).index);
    for (size_t k = 0; k < s.wallCandidates[w].size(); ++k) {
      if (const auto* h = s.histories.find(a.slot[s.wallCandidates[w][k]], wid)) {
        s.wallSprings[w][k] = *h;
      }
    }
  }
  s.histories.clear();
}

}  // namespace demlab::sim
