// Where the tangential springs of frictional contacts live.
//
// Between two neighbor searches the candidate pairs are fixed, so the contact loops reach each
// candidate's spring by index, with no hashing (a hash lookup per contact per step costs more
// than the contact law): a grain pair through its slot in the PairSprings pool
// (sim/pair_springs.hpp: one spring per contact, none for a candidate out of contact), a grain
// and a wall in an array parallel to the wall's candidate list, zeroed when the contact opens. At a
// search, and before any edit that renumbers the grains, the nonzero springs are parked in the
// InstanceInteractionManager under the pair's stable ids (handle slot indices, walls in the top
// half of the id space), and after the search each new candidate takes its spring back from there;
// the manager is then emptied.
//
// The neighbor search itself does not go through the hash table: SpringTransfer collects the
// nonzero springs into a flat table indexed by the slot of the pair's lower grain (a counting
// sort, no hashing), which the new candidates read back. With about one spring per contact a
// hash table big enough for them all was the largest allocation of a dense bed's run (it first
// filled at the second search, so memory grew there); the flat table takes a third of it and
// is freed again after each search. Springs an edit parked in the manager are still taken
// back from there.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "sim/scene.hpp"

namespace demlab::sim {

// Moves every nonzero spring of the current candidates into s.histories and empties the
// per-candidate arrays. Call before the candidates or the dense order change.
template <int D>
void parkSprings(Scene<D>& s) {
  if (!s.keepHistory) return;
  const ElementArrays<D>& a = s.elements.a;
  const size_t n = std::min(s.pairSprings.size(), s.candidates.size());
  for (size_t k = 0; k < n; ++k) {
    const physics::TangentialHistory<D> h = s.pairSprings.history(k);
    if (h.empty()) continue;
    const uint32_t p = a.slot[s.candidates[k].i], q = a.slot[s.candidates[k].j];
    // The loop keeps each spring in the orientation of the lower global id (A) to the higher;
    // the key is the unordered pair of slots.
    s.histories.touch(std::min(p, q), std::max(p, q)).state = h;
  }
  for (size_t w = 0; w < s.wallSprings.size() && w < s.wallCandidates.size(); ++w) {
    const uint32_t wid = wallPairId(s.walls.pool().handleAt(static_cast<uint32_t>(w)).index);
    const auto& springs = s.wallSprings[w];
    for (size_t k = 0; k < springs.size() && k < s.wallCandidates[w].size(); ++k) {
      if (springs[k].empty()) continue;
      s.histories.touch(a.slot[s.wallCandidates[w][k]], wid).state = springs[k];
    }
  }
  s.pairSprings.clear();
  s.wallSprings.clear();
}

// Gives every candidate its parked spring (zero if none) and empties s.histories.
template <int D>
void unparkSprings(Scene<D>& s) {
  if (!s.keepHistory) return;
  const ElementArrays<D>& a = s.elements.a;
  s.pairSprings.reset(s.candidates.size(), false);
  s.wallSprings.resize(s.wallCandidates.size());
  for (size_t w = 0; w < s.wallCandidates.size(); ++w) {
    s.wallSprings[w].assign(s.wallCandidates[w].size(), physics::TangentialHistory<D>{});
  }
  if (s.histories.empty()) return;
  for (size_t k = 0; k < s.candidates.size(); ++k) {
    const uint32_t p = a.slot[s.candidates[k].i], q = a.slot[s.candidates[k].j];
    if (const auto* h = s.histories.find(std::min(p, q), std::max(p, q))) {
      s.pairSprings.set(k, *h);
    }
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

// Calls f(aSlot, aDense, partner, history) for each parked spring (s.histories) whose
// elements this scene holds: the pair's A (the lower global id) by its slot and dense index,
// partner B's global id or a wall's wallPartner, as SpringTransfer keys them. Changes nothing.
template <int D, class F>
void forEachParkedSpring(const Scene<D>& s, F&& f) {
  const ElementArrays<D>& a = s.elements.a;
  const auto& pool = s.elements.pool();
  s.histories.forEach([&](auto key, const physics::TangentialHistory<D>& h) {
    const uint32_t p = pool.findDenseAt(key.first);
    if (h.empty() || p == pool.kNpos) return;
    if (key.second & 0x80000000u) return f(key.first, p, wallPartner(key.second & 0x7FFFFFFFu), h);
    const uint32_t q = pool.findDenseAt(key.second);
    if (q == pool.kNpos) return;
    if (a.globalId[p] < a.globalId[q]) return f(key.first, p, a.globalId[q], h);
    f(key.second, q, a.globalId[p], h);
  });
}

// Carries the tangential springs across a neighbor search, keyed by handle slots so the dense
// order may change in between (sim/reorder.hpp); and with the touch correction, the
// candidates' touch states (Scene::touchNow, wallTouchNow), so the first step after a search
// can take its events from them as any other (sim/touch.hpp).
template <int D>
class SpringTransfer {
 public:
  // Moves every nonzero spring and every touching state of the current candidates into this
  // table and empties the per-candidate spring arrays (keeping their capacity). Call before
  // the candidates or the dense order change.
  void collect(Scene<D>& s) {
    entries_.clear();
    rowStart_.clear();
    grainStates_ = s.touchCorrection && s.touchNowCurrent();
    wallStates_ = s.touchCorrection && s.wallTouchNowCurrent();
    if (!s.keepHistory && !grainStates_ && !wallStates_) return;
    // A distributed scene's parked springs (a gathered checkpoint's, sim/simulation_gather.cpp)
    // go into the table too: give() finds them by slot, which a ghost partner lacks.
    const bool drainParked = s.dist != nullptr && s.keepHistory && !s.histories.empty();
    const ElementArrays<D>& a = s.elements.a;
    const uint32_t rows = s.elements.pool().slotCount();
    rowStart_.assign(static_cast<size_t>(rows) + 1, 0);
    // Pass 1 counts the entries per row (lower slot), pass 2 places them.
    const physics::TangentialHistory<D> none;
    auto each = [&](auto&& put) {
      const size_t nSprings = s.keepHistory ? s.pairSprings.size() : 0;
      for (size_t k = 0; k < s.candidates.size(); ++k) {
        const physics::TangentialHistory<D> h = k < nSprings ? s.pairSprings.history(k) : none;
        const uint8_t state = grainStates_ ? s.touchNow[k] : 0;
        if (h.empty() && state == 0) continue;
        put(a.slot[s.candidates[k].i], a.globalId[s.candidates[k].j], h, state);
      }
      for (size_t w = 0; w < s.wallCandidates.size(); ++w) {
        const uint64_t wid = wallPartner(s.walls.pool().handleAt(static_cast<uint32_t>(w)).index);
        const auto* springs = s.keepHistory && w < s.wallSprings.size() ? &s.wallSprings[w] : nullptr;
        for (size_t k = 0; k < s.wallCandidates[w].size(); ++k) {
          const physics::TangentialHistory<D>& h =
              springs != nullptr && k < springs->size() ? (*springs)[k] : none;
          const uint8_t state = wallStates_ ? s.wallTouchNow[w][k] : 0;
          if (h.empty() && state == 0) continue;
          put(a.slot[s.wallCandidates[w][k]], wid, h, state);
        }
      }
      if (drainParked) {
        forEachParkedSpring(s, [&](uint32_t aSlot, uint32_t, uint64_t partner, const auto& h) {
          put(aSlot, partner, h, 0);
        });
      }
    };
    // (Drift velocities only where a history has one, the synchronized integrator's springs:
    // the plain Verlet scenes' table stays at a spring a contact.)
    size_t total = 0;
    bool drifts = false;
    each([&](uint32_t row, uint64_t, const physics::TangentialHistory<D>& h, uint8_t) {
      rowStart_[row + 1] += 1;
      total += 1;
      drifts = drifts || !std::isnan(h.drift[0]);
    });
    for (uint32_t r = 0; r < rows; ++r) rowStart_[r + 1] += rowStart_[r];
    entries_.resize(total);
    drifts_.assign(drifts ? total : 0, VecD<D>::Constant(std::numeric_limits<Real>::quiet_NaN()));
    std::vector<uint32_t> fill(rowStart_.begin(), rowStart_.end() - 1);
    each([&](uint32_t row, uint64_t partner, const physics::TangentialHistory<D>& h, uint8_t state) {
      const uint32_t e = fill[row]++;
      entries_[e] = {partner, state, h.spring};
      if (drifts) drifts_[e] = h.drift;
    });
    if (drainParked) s.histories.clear();
    // Freed, not just emptied: give() allocates the new arrays, and holding the old ones
    // through the search would add their size to the run's peak memory.
    if (s.keepHistory) {
      s.pairSprings.clear();
      std::vector<std::vector<physics::TangentialHistory<D>>>().swap(s.wallSprings);
    }
  }

  // Gives every candidate its spring (zero if none) from this table, or from s.histories for
  // springs an edit parked there, and its touch state (0 if none: the old candidates held
  // every pair touching at the last step); then empties both and frees this table's memory.
  // touching: the grain pairs in contact now, which sizes the spring pool.
  void give(Scene<D>& s, size_t touching) {
    if (s.keepHistory) giveSprings(s, touching);
    if (grainStates_) {
      s.touchNow.assign(s.candidates.size(), 0);
      for (size_t k = 0; k < s.candidates.size(); ++k) {
        if (const Entry* e = find(s, s.candidates[k])) s.touchNow[k] = static_cast<uint8_t>(e->state);
      }
      s.touchNowValid = true;
    }
    if (wallStates_) {
      const ElementArrays<D>& a = s.elements.a;
      s.wallTouchNow.resize(s.walls.size());
      for (size_t w = 0; w < s.walls.size(); ++w) {
        const size_t n = w < s.wallCandidates.size() ? s.wallCandidates[w].size() : 0;
        s.wallTouchNow[w].assign(n, 0);
        const uint64_t wid = wallPartner(s.walls.pool().handleAt(static_cast<uint32_t>(w)).index);
        for (size_t k = 0; k < n; ++k) {
          if (const Entry* e = find(a.slot[s.wallCandidates[w][k]], wid)) {
            s.wallTouchNow[w][k] = static_cast<uint8_t>(e->state);
          }
        }
      }
      s.wallTouchNowValid = true;
    }
    std::vector<Entry>().swap(entries_);
    std::vector<VecD<D>>().swap(drifts_);
    std::vector<uint32_t>().swap(rowStart_);
  }

  // A spring as it travels between ranks with the element of its row (a distributed search,
  // sim/distribution.hpp): the row by the element's global id. Plain data.
  struct MovedSpring {
    uint64_t rowId, partner;
    uint64_t state;
    double spring[D], drift[D];  // drift NaN: none
  };

  // Takes out the rows of the elements that leave: row slot r goes to out[dest(r)] when
  // dest(r) >= 0, each entry with rowId(r). Call between collect() and give(). Changes the
  // table and out.
  template <class Dest, class RowId>
  void takeRows(Dest&& dest, RowId&& rowId, std::vector<std::vector<MovedSpring>>& out) {
    const uint32_t rows = rowStart_.empty() ? 0 : static_cast<uint32_t>(rowStart_.size() - 1);
    std::vector<Entry> kept;
    std::vector<VecD<D>> keptDrifts;
    std::vector<uint32_t> start(rowStart_.size(), 0);
    for (uint32_t r = 0; r < rows; ++r) {
      const int to = rowStart_[r] < rowStart_[r + 1] ? dest(r) : -1;
      for (uint32_t e = rowStart_[r]; e < rowStart_[r + 1]; ++e) {
        if (to < 0) {
          kept.push_back(entries_[e]);
          if (!drifts_.empty()) keptDrifts.push_back(drifts_[e]);
          continue;
        }
        MovedSpring m{rowId(r), entries_[e].partner, entries_[e].state, {}, {}};
        for (int k = 0; k < D; ++k) {
          m.spring[k] = entries_[e].spring[k];
          m.drift[k] = drifts_.empty() ? std::numeric_limits<double>::quiet_NaN() : drifts_[e][k];
        }
        out[static_cast<size_t>(to)].push_back(m);
      }
      start[r + 1] = static_cast<uint32_t>(kept.size());
    }
    entries_ = std::move(kept);
    drifts_ = std::move(keptDrifts);
    rowStart_ = std::move(start);
  }

  // Adds springs that arrived with their rows' elements, row slot slotOf(rowId), the table
  // widened to rows slots. Call between collect() and give(). Changes the table.
  template <class SlotOf>
  void addRows(const std::vector<MovedSpring>& in, SlotOf&& slotOf, uint32_t rows) {
    if (in.empty() && rowStart_.size() == size_t{rows} + 1) return;
    const uint32_t old = rowStart_.empty() ? 0 : static_cast<uint32_t>(rowStart_.size() - 1);
    bool drifts = !drifts_.empty();
    for (const MovedSpring& m : in) drifts = drifts || !std::isnan(m.drift[0]);
    std::vector<uint32_t> count(size_t{rows} + 1, 0);
    for (uint32_t r = 0; r < std::min(old, rows); ++r) count[r + 1] = rowStart_[r + 1] - rowStart_[r];
    std::vector<uint32_t> slots(in.size());
    for (size_t k = 0; k < in.size(); ++k) {
      slots[k] = slotOf(in[k].rowId);
      count[slots[k] + 1] += 1;
    }
    for (uint32_t r = 0; r < rows; ++r) count[r + 1] += count[r];
    std::vector<Entry> entries(count[rows]);
    std::vector<VecD<D>> driftOut(drifts ? entries.size() : 0,
                                  VecD<D>::Constant(std::numeric_limits<Real>::quiet_NaN()));
    std::vector<uint32_t> fill(count.begin(), count.end() - 1);
    for (uint32_t r = 0; r < std::min(old, rows); ++r) {
      for (uint32_t e = rowStart_[r]; e < rowStart_[r + 1]; ++e) {
        const uint32_t at = fill[r]++;
        entries[at] = entries_[e];
        if (!drifts_.empty()) driftOut[at] = drifts_[e];
      }
    }
    for (size_t k = 0; k < in.size(); ++k) {
      const uint32_t at = fill[slots[k]]++;
      entries[at].partner = in[k].partner;
      entries[at].state = in[k].state;
      for (int d = 0; d < D; ++d) {
        entries[at].spring[d] = in[k].spring[d];
        if (drifts) driftOut[at][d] = in[k].drift[d];
      }
    }
    entries_ = std::move(entries);
    drifts_ = std::move(driftOut);
    rowStart_ = std::move(count);
  }

  // Returns the bytes of the table (none between searches: give() frees it).
  size_t workingBytes() const {
    return entries_.capacity() * sizeof(Entry) + drifts_.capacity() * sizeof(VecD<D>) +
           rowStart_.capacity() * sizeof(uint32_t);
  }

 private:
  // A spring and a touch state across the search, and beside them (drifts_, when any history
  // has one) the spring's drift velocity: the damper's owed loss (the history's last two
  // numbers, one step's O(dt^2) correction) is dropped, so the table, at the search's memory
  // peak beside the new pool, stays at 32 bytes a contact in 3D (56 with drifts) instead of 72.
  struct Entry {
    uint64_t partner : 56;  // the global id of the pair's B, or wallPartner of the wall
    uint64_t state : 8;     // the touch state (0: none kept, or not touching)
    VecD<D> spring;
  };
  std::vector<Entry> entries_;
  std::vector<VecD<D>> drifts_;     // per entry, or empty
  std::vector<uint32_t> rowStart_;  // per slot of the pairs' A: first entry; one more for the end
  bool grainStates_ = false, wallStates_ = false;  // collect() took the touch states

  // Returns the entry of the pair whose A has slot row and whose B is partner, or null.
  // Changes nothing.
  const Entry* find(uint32_t row, uint64_t partner) const {
    if (row + size_t{1} >= rowStart_.size()) return nullptr;
    for (uint32_t e = rowStart_[row]; e < rowStart_[row + 1]; ++e) {
      if (entries_[e].partner == partner) return &entries_[e];
    }
    return nullptr;
  }
  // Returns the entry of grain candidate c, or null. Changes nothing.
  const Entry* find(const Scene<D>& s, CandidatePair c) const {
    return find(s.elements.a.slot[c.i], s.elements.a.globalId[c.j]);
  }

  // The springs' part of give().
  void giveSprings(Scene<D>& s, size_t touching) {
    const ElementArrays<D>& a = s.elements.a;
    s.pairSprings.reset(s.candidates.size(), true);
    // Room for the pairs touching now and a sixteenth more, for the contacts that form before
    // the next search. Past that the pool grows by an eighth, and each growth holds the old
    // copy and the new at once: grown from empty at a bed's first step it set the run's peak.
    const size_t expect = std::max(touching, entries_.size() + s.histories.size());
    s.pairSprings.reserve(expect + expect / 16);
    s.wallSprings.resize(s.wallCandidates.size());
    for (size_t w = 0; w < s.wallCandidates.size(); ++w) {
      s.wallSprings[w].assign(s.wallCandidates[w].size(), physics::TangentialHistory<D>{});
    }
    const bool parked = !s.histories.empty();
    // The table is keyed by the pair's A slot and B global id, the parked springs by the
    // unordered pair of slots (wall: the wall's pair id).
    auto lookup = [&](uint32_t row, uint64_t partner, uint32_t lo, uint32_t hi,
                      physics::TangentialHistory<D>& out) {
      if (const Entry* e = find(row, partner)) {
        out.spring = e->spring;
        if (!drifts_.empty()) out.drift = drifts_[static_cast<size_t>(e - entries_.data())];
        return;
      }
      if (parked) {
        if (const auto* h = s.histories.find(lo, hi)) out = *h;
      }
    };
    if (!entries_.empty() || parked) {
      for (size_t k = 0; k < s.candidates.size(); ++k) {
        const CandidatePair c = s.candidates[k];
        const uint32_t p = a.slot[c.i], q = a.slot[c.j];
        physics::TangentialHistory<D> h;
        lookup(p, a.globalId[c.j], std::min(p, q), std::max(p, q), h);
        s.pairSprings.set(k, h);
      }
      for (size_t w = 0; w < s.wallCandidates.size(); ++w) {
        const uint32_t slot = s.walls.pool().handleAt(static_cast<uint32_t>(w)).index;
        for (size_t k = 0; k < s.wallCandidates[w].size(); ++k) {
          const uint32_t row = a.slot[s.wallCandidates[w][k]];
          lookup(row, wallPartner(slot), row, wallPairId(slot), s.wallSprings[w][k]);
        }
      }
    }
    if (parked) s.histories.clear();
  }
};

}  // namespace demlab::sim
