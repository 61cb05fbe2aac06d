// A distributed run's part of a scene (doc/plans/mpi.md): each rank owns the elements of its box
// of a recursive coordinate bisection and holds, after them in the same arrays, ghost copies of
// the other ranks' elements within reach of its own (Scene::ghosts). Each pair is computed once,
// on the rank owning its lower global id (the pair's A), which then sends the forces its ghosts
// took back to their owners; so every contact, spring, touch state, record and ledger term
// exists on one rank only, as in the serial run.
//
// The step: the integrator's drift over the owned elements; GhostModule sends their new states
// to the ranks holding their ghosts; at a neighbour search (taken by all ranks when one needs it)
// distributedSearch drops the ghosts, sends the elements that left their rank's box to their new
// owner with the springs of their pairs, bisects again when the counts drift apart, and makes
// the ghosts anew; the contact passes; GhostForceModule returns the ghosts' forces and torques;
// the second kick over the owned elements.
//
// 3D balls with walls, gravity, friction, rolling resistance, cohesion and the touch correction
// (tests/mpi/sim_ranks_test.cpp runs them against the serial run, with plane walls); the rest is
// refused by Simulation::distribute before anything changes. Every rank holds every wall and
// computes its own elements' wall contacts: a wall's force and work are each rank's part.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "core/name_lookup.hpp"
#include "core/tag_table.hpp"
#include "mpi/communicator.hpp"
#include "mpi/ghost_plan.hpp"
#include "mpi/partition.hpp"
#include "mpi/reach.hpp"
#include "mpi/records.hpp"
#include "sim/constraints.hpp"
#include "sim/history_store.hpp"
#include "sim/module_table.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// One element as it travels between ranks: its whole state (3D).
struct ElementRecord {
  double x[3], v[3], f[3], fPrev[3], w[3], t[3], tPrev[3], q[4];
  double r, invMass, invInertia;
  uint64_t globalId;
  uint32_t material, geometry;
};

// What a ghost takes from its owner every step: what the contact passes read (a ball's
// orientation enters no contact), and with the touch correction the last step's force, from
// which it reconstructs the step's start. The messages of a step are most of a distributed
// step's cost beyond the serial one's: each field is sent only where it is read.
struct GhostState {
  double x[3], v[3], w[3];
};
struct GhostStateTouch : GhostState {
  double fPrev[3];
};

// What a ghost's pairs gave it in a step, back to its owner: forces and torques, and with the
// touch correction the change of its velocity (the correction's impulses act on velocities).
struct GhostForce {
  double f[3], t[3];
};
struct GhostForceTouch : GhostForce {
  double dv[3];
};

template <int D>
struct Distribution {
  const mpi::Communicator* comm = nullptr;
  mpi::Partition<D> partition;
  // Every rank holds the whole scene (distribute() was called, no search since): the first
  // search keeps each rank's part and sends nothing.
  bool initial = true;
  mpi::GhostPlan<D> plan;
  // The largest rank's count over the mean past which a search bisects again.
  double rebalanceAbove = 1.1;
  // Decided once for the whole scene when it was distributed (every rank then held all of it):
  // what the per-rank scene would otherwise decide alone.
  SceneUse use;
  double skin = 0;
  double stepLimit = 0;
  double critical = 0, linearDuration = 0, hertzDuration = 0;  // the static step survey
  // What the run did (doc/performance.md): searches, bisections, elements migrated (sent),
  // and the copies sent a step at the last search.
  uint64_t searches = 0, bisections = 0, migrated = 0;
  size_t ghostCopiesSent = 0;
  // With the touch correction, the ghosts' states as last received: their velocities before
  // this rank's pairs acted, which the way back measures the changes from.
  std::vector<GhostStateTouch> states;
  // The handles scripts hold: each element keeps, wherever it moves, the one it had when the
  // scene was distributed. That is {gid, first life} for an element created before any
  // removal; the others (a scene that removed elements first) are listed here in runs: count
  // elements from global id `id` on whose handles are `bits` on (the next slots, the same
  // generation), as the elements made after a removal are. By id, and the same runs by handle.
  struct Renamed {
    uint64_t id, bits, count;
  };
  std::vector<Renamed> renamedById, renamedByHandle;
  // The rest of the whole scene's handle pool, which a checkpoint restores
  // (SimulationManager::gatheredScene) and an element added after distribute() takes its
  // handle from (allocateHandle): its slot count and its free slots (the recycling stack,
  // bottom to top) with their generations; the live slots' generations are their elements'
  // handles.
  uint32_t poolSlots = 0;
  std::vector<uint32_t> freeSlots, freeGenerations;
  // The global ids of the elements edits placed since the last step, on every rank (the
  // watchdog holds their contacts, ghosts' too, to its `placed` limit: Scene::placedElements).
  std::vector<uint64_t> placed;
  // The blocked elements this rank owns (ownedBlockedOf), as made after search `blockedAt`
  // from a list of `blockedListed` entries.
  std::vector<OwnedBlockedElement> ownedBlocked;
  uint64_t blockedAt = ~uint64_t{0};
  size_t blockedListed = 0;
  // The elements' names and tags under the scripts' handles, alike on every rank (the rank's
  // own store has none: its handles are its pool's, and they change as elements migrate).
  // tagEdits counts the changes to the tags, which the owned members' cache is keyed by.
  NameLookup<ElementId> names{"grain"};
  TagTable<ElementKind> tags;
  uint64_t tagEdits = 0;
  // Per tag, the dense indices of its members this rank owns, in the tag's order, with their
  // global ids (ownedTaggedOf), as made after search `at` and tag edit `edits`.
  struct OwnedTagged {
    std::vector<uint32_t> i;
    std::vector<uint64_t> globalId;
    uint64_t at = ~uint64_t{0}, edits = ~uint64_t{0};
  };
  std::map<std::string, OwnedTagged, std::less<>> ownedTagged;

  // Returns the run of renamed handles holding global id gid, or nullptr. Changes nothing.
  const Renamed* renamedRun(uint64_t gid) const {
    auto r = std::upper_bound(renamedById.begin(), renamedById.end(), gid,
                              [](uint64_t g, const Renamed& run) { return g < run.id; });
    if (r == renamedById.begin() || gid - std::prev(r)->id >= std::prev(r)->count) return nullptr;
    return &*std::prev(r);
  }
  // Returns the handle the element of global id gid had when the scene was distributed: the
  // one scripts hold, wherever it is now. Changes nothing.
  ElementId handleOf(uint64_t gid) const {
    const Renamed* run = renamedRun(gid);
    return run != nullptr ? ElementId::fromBits(run->bits + (gid - run->id)) : firstLife(gid);
  }
  // Returns the global id of the element scripts know by handle h (from the renamed runs), or
  // nothing when h names no element's life. Changes nothing.
  std::optional<uint64_t> globalIdOf(ElementId h) const {
    // The run holding the handle, if any: the last whose first handle is at most it.
    const uint64_t bits = h.bits();
    auto r = std::upper_bound(renamedByHandle.begin(), renamedByHandle.end(), bits,
                              [](uint64_t b, const Renamed& run) { return b < run.bits; });
    if (r != renamedByHandle.begin() && bits - std::prev(r)->bits < std::prev(r)->count) {
      return std::prev(r)->id + (bits - std::prev(r)->bits);
    }
    // (The element made with this id has another handle now: this one names no element.)
    const uint64_t gid = h.index;
    if (h != firstLife(gid) || renamedRun(gid) != nullptr) return std::nullopt;
    return gid;
  }
  // Returns the handle of the first element a scene creates in slot gid (its global id too).
  static ElementId firstLife(uint64_t gid) { return ElementId{static_cast<uint32_t>(gid), 1}; }

  // Returns the handle the whole scene's pool gives its next element (HandlePool::allocate:
  // the most recently freed slot, one generation on, else a new slot) and takes it from the
  // pool; records it as the handle of global id gid (renamed runs) when it is not gid's first
  // life. Changes the pool's model and the runs.
  ElementId allocateHandle(uint64_t gid) {
    ElementId h;
    if (!freeSlots.empty()) {
      h = ElementId{freeSlots.back(), freeGenerations.back() + 1};
      freeSlots.pop_back();
      freeGenerations.pop_back();
    } else {
      h = ElementId{poolSlots++, 1};
    }
    if (h != firstLife(gid)) {
      appendRenamed(gid, h.bits());  // (gid is the largest yet)
      sortRenamedByHandle();
    }
    return h;
  }

  // Gives handle h of a removed element back to the pool's model (HandlePool::free: its slot
  // is the next one recycled, a generation on, unless the generation would wrap: then the slot
  // is retired). Changes the free slots.
  void freeHandle(ElementId h) {
    const uint32_t generation = h.generation + 1;
    if (generation == 0) return;
    freeSlots.push_back(h.index);
    freeGenerations.push_back(generation);
  }

  // Appends the renamed handle bits of global id gid, above every id listed: to the last run
  // when it continues it, else as a run of its own. Changes renamedById only.
  void appendRenamed(uint64_t gid, uint64_t bits) {
    Renamed* last = renamedById.empty() ? nullptr : &renamedById.back();
    if (last != nullptr && gid == last->id + last->count && bits == last->bits + last->count &&
        (bits & 0xFFFFFFFFu) != 0) {
      ++last->count;
    } else {
      renamedById.push_back({gid, bits, 1});
    }
  }
  // Makes renamedByHandle renamedById's runs in the order of their handles. Changes it.
  void sortRenamedByHandle() {
    renamedByHandle = renamedById;
    std::sort(renamedByHandle.begin(), renamedByHandle.end(),
              [](const Renamed& x, const Renamed& y) { return x.bits < y.bits; });
  }
};

// Replaces this rank's kinetic energy, potential energy, ledger sums (l's losses, works and
// elastic energy) and, when given, rotational energy by their sums over the ranks, added in rank
// order (every rank gets the same bits). Collective. The reference, scale and start of l are the
// whole scene's already and stay. eachHoldsWhole (a distributed scene before its first search,
// Distribution::initial): every rank's energies, the springs' too, are the whole scene's
// already and stay; only the losses and works are summed (rank 0's, the others' zero).
inline void reduceLedger(const mpi::Communicator& comm, double& kinetic, double& potential,
                         LedgerSums& l, double* rotational = nullptr, bool eachHoldsWhole = false) {
  std::vector<double> v{kinetic,        potential,     l.dampingLoss, l.frictionLoss,
                        l.wallWork,     l.behaviorWork, l.springWork,  l.bondReleased,
                        l.elastic,      rotational != nullptr ? *rotational : 0.0};
  comm.sum(v);
  l.dampingLoss = v[2], l.frictionLoss = v[3];
  l.wallWork = v[4], l.behaviorWork = v[5], l.springWork = v[6], l.bondReleased = v[7];
  if (eachHoldsWhole) return;
  kinetic = v[0], potential = v[1];
  l.elastic = v[8];
  if (rotational != nullptr) *rotational = v[9];
}

// Returns the dense index of the element scripts know by handle h among this rank's own, or
// kNpos when another rank owns it or none does (Scene::ownedIndexOfHandle): a scan of the owned
// elements' global ids, so a behavior on one element pays it each step. Changes nothing.
template <int D>
uint32_t ownedIndexOf(const Scene<D>& s, ElementId h) {
  const std::optional<uint64_t> gid = s.dist->globalIdOf(h);
  if (gid) {
    const ElementArrays<D>& a = s.elements.a;
    const size_t n = s.ownedCount();
    for (size_t i = 0; i < n; ++i) {
      if (a.globalId[i] == *gid) return static_cast<uint32_t>(i);
    }
  }
  return HandlePool<ElementKind>::kNpos;
}

// Returns the blocked elements (Scene::blocked, by the scripts' handles) this rank owns, with
// their dense indices, in the list's order (Scene::ownedBlocked). The last answer while it still
// holds (no search since, every entry still the list's and its element still at its index:
// edits between searches move an owned element or change the list), else made anew by one
// pass over the owned elements. Changes the distribution's copy of the answer.
template <int D>
const std::vector<OwnedBlockedElement>& ownedBlockedOf(const Scene<D>& s) {
  Distribution<D>& d = *s.dist;
  const ElementArrays<D>& a = s.elements.a;
  const size_t owned = s.ownedCount();
  // (An entry added or dropped changes the list's length; one changed is dropped and added.)
  bool holds = d.blockedAt == s.rebuilds && d.blockedListed == s.blocked.size();
  for (const OwnedBlockedElement& b : d.ownedBlocked) {
    if (!holds) break;
    holds = b.listed < s.blocked.size() && s.blocked[b.listed].dofs == b.dofs &&
            d.globalIdOf(s.blocked[b.listed].id) == b.globalId && b.i < owned &&
            a.globalId[b.i] == b.globalId;
  }
  if (holds) return d.ownedBlocked;
  std::unordered_map<uint64_t, size_t> wanted;  // global id -> place in the list
  for (size_t k = 0; k < s.blocked.size(); ++k) {
    if (const std::optional<uint64_t> gid = d.globalIdOf(s.blocked[k].id)) wanted.emplace(*gid, k);
  }
  d.ownedBlocked.clear();
  for (size_t i = 0; i < owned && d.ownedBlocked.size() < wanted.size(); ++i) {
    const auto it = wanted.find(a.globalId[i]);
    if (it == wanted.end()) continue;
    d.ownedBlocked.push_back({static_cast<uint32_t>(i), s.blocked[it->second].dofs, it->first, it->second});
  }
  std::sort(d.ownedBlocked.begin(), d.ownedBlocked.end(),
            [](const OwnedBlockedElement& x, const OwnedBlockedElement& y) { return x.listed < y.listed; });
  d.blockedAt = s.rebuilds;
  d.blockedListed = s.blocked.size();
  return d.ownedBlocked;
}

// Returns the dense indices of the elements carrying tag that this rank owns, in the tag's
// order (Scene::ownedTagged): the last answer while it still holds (no search and no tag edit
// since, each entry's element still at its index: a removal between searches moves an owned
// element), else made anew by one pass over the tag's members and one over the owned elements.
// Changes the distribution's copy of the answer.
template <int D>
const std::vector<uint32_t>& ownedTaggedOf(const Scene<D>& s, std::string_view tag) {
  Distribution<D>& d = *s.dist;
  const ElementArrays<D>& a = s.elements.a;
  const size_t owned = s.ownedCount();
  using Cached = typename Distribution<D>::OwnedTagged;
  auto it = d.ownedTagged.find(tag);
  if (it == d.ownedTagged.end()) it = d.ownedTagged.emplace(std::string(tag), Cached{}).first;
  Cached& c = it->second;
  bool holds = c.at == s.rebuilds && c.edits == d.tagEdits;
  for (size_t k = 0; holds && k < c.i.size(); ++k) {
    holds = c.i[k] < owned && a.globalId[c.i[k]] == c.globalId[k];
  }
  if (holds) return c.i;
  std::unordered_map<uint64_t, size_t> place;  // global id -> place among the tag's members
  size_t members = 0;
  d.tags.forEach(tag, [&](ElementId h) {
    if (const std::optional<uint64_t> gid = d.globalIdOf(h)) place.emplace(*gid, members);
    ++members;
  });
  std::vector<uint32_t> at(members, HandlePool<ElementKind>::kNpos);
  for (size_t i = 0; i < owned && !place.empty(); ++i) {
    const auto p = place.find(a.globalId[i]);
    if (p != place.end()) at[p->second] = static_cast<uint32_t>(i);
  }
  c.i.clear(), c.globalId.clear();
  for (uint32_t i : at) {
    if (i == HandlePool<ElementKind>::kNpos) continue;
    c.i.push_back(i);
    c.globalId.push_back(a.globalId[i]);
  }
  c.at = s.rebuilds;
  c.edits = d.tagEdits;
  return c.i;
}

// Returns the centres of elements [0, n) of the 3D arrays a, as the bisection and the reach
// table take them.
inline std::vector<mpi::Point<3>> centresOf(const ElementArrays<3>& a, size_t n) {
  std::vector<mpi::Point<3>> c(n);
  for (size_t i = 0; i < n; ++i) c[i] = {a.x[i][0], a.x[i][1], a.x[i][2]};
  return c;
}

// Returns the element record of element i of the 3D arrays a.
inline ElementRecord recordOf(const ElementArrays<3>& a, size_t i) {
  ElementRecord r;
  for (int k = 0; k < 3; ++k) {
    r.x[k] = a.x[i][k], r.v[k] = a.v[i][k], r.f[k] = a.f[i][k], r.fPrev[k] = a.fPrev[i][k];
    r.w[k] = a.w[i][k], r.t[k] = a.t[i][k], r.tPrev[k] = a.tPrev[i][k];
  }
  r.q[0] = a.q[i].w(), r.q[1] = a.q[i].x(), r.q[2] = a.q[i].y(), r.q[3] = a.q[i].z();
  r.r = a.r[i], r.invMass = a.invMass[i], r.invInertia = a.invInertia[i];
  r.globalId = a.globalId[i];
  r.material = a.material[i], r.geometry = a.geometry[i];
  return r;
}

// Appends the element of record r to a, under slot (kNoSlot for a ghost). Changes every array.
inline void pushRecord(ElementArrays<3>& a, const ElementRecord& r, uint32_t slot) {
  const Vec3 x(r.x[0], r.x[1], r.x[2]), v(r.v[0], r.v[1], r.v[2]), w(r.w[0], r.w[1], r.w[2]);
  a.push(x, v, w, r.r, r.invMass, r.invInertia, r.material, slot, r.geometry, r.globalId);
  a.f.back() = Vec3(r.f[0], r.f[1], r.f[2]);
  a.fPrev.back() = Vec3(r.fPrev[0], r.fPrev[1], r.fPrev[2]);
  a.t.back() = Vec3(r.t[0], r.t[1], r.t[2]);
  a.tPrev.back() = Vec3(r.tPrev[0], r.tPrev[1], r.tPrev[2]);
  a.q.back() = Quat(r.q[0], r.q[1], r.q[2], r.q[3]);
}

// The slot of a ghost: it has no handle.
inline constexpr uint32_t kNoSlot = 0xFFFFFFFFu;

// Appends the element of record r to this rank's own elements, before the ghosts (the dense
// order is the owned elements, then the ghosts): each ghost moves one place on, and so does
// every dense index of a ghost held until the next search (candidates, contact records, the
// deepest contact). The positions at the last search stop following the arrays (the
// displacement is then not tracked: the caller sets the search that follows). Changes every
// per-element array, the handle pool and those indices.
template <int D>
void insertOwned(Scene<D>& s, const ElementRecord& r) {
  ElementArrays<D>& a = s.elements.a;
  const uint32_t owned = static_cast<uint32_t>(s.ownedCount());
  // (The pool holds the owned elements only: the new handle's dense index is `owned`.)
  pushRecord(a, r, s.elements.adopt(r.globalId).index);
  if (s.ghosts == 0) return;
  ElementArrays<D>::forEachArray(a, [&](auto& arr) {
    std::rotate(arr.begin() + owned, arr.end() - 1, arr.end());
  });
  const auto moved = [owned](uint32_t i) { return i >= owned ? i + 1 : i; };
  for (CandidatePair& c : s.candidates) c.i = moved(c.i), c.j = moved(c.j);
  const auto movedRecord = [&](ContactRecord<D>& c) {
    c.a = moved(c.a);
    if (!c.wall) c.b = moved(c.b) & 0x7FFFFFFFu;
  };
  for (ContactRecord<D>& c : s.contacts) movedRecord(c);
  movedRecord(s.deepest.record);
}

// Removes this rank's owned element of local handle h, keeping the dense order (the owned
// elements, then the ghosts): the last owned element takes its place and each ghost moves one
// place back. What holds dense indices until the next search follows them: the grain and wall
// candidates (the removed element's dropped, with their springs) and the ghost plan's sent
// lists. The caller drops the contact records on every rank (forgetContactRecords) and sets the
// search that follows. Changes every per-element array, the pool, the candidates, their springs
// and the plan.
template <int D>
void removeOwned(Scene<D>& s, ElementId h) {
  ElementArrays<D>& a = s.elements.a;
  // (The pool holds the owned elements only: from is the last owned one.)
  const SwapRemove m = s.elements.pool().free(h);
  const uint32_t gone = m.to, from = m.from;
  ElementArrays<D>::forEachArray(a, [&](auto& arr) {
    if (from != gone) arr[gone] = std::move(arr[from]);
    std::rotate(arr.begin() + from, arr.begin() + from + 1, arr.end());
    arr.resize(arr.size() - 1);
  });
  constexpr uint32_t kGone = 0xFFFFFFFFu;
  const auto moved = [&](uint32_t i) {
    return i == gone ? kGone : i == from ? gone : i > from ? i - 1 : i;
  };
  std::vector<char> dead(s.candidates.size(), 0);
  size_t kept = 0;
  for (size_t k = 0; k < s.candidates.size(); ++k) {
    CandidatePair c = s.candidates[k];
    c.i = moved(c.i), c.j = moved(c.j);
    dead[k] = c.i == kGone || c.j == kGone;
    if (!dead[k]) s.candidates[kept++] = c;
  }
  s.candidates.resize(kept);
  s.pairSprings.eraseCandidates([&](size_t k) { return k < dead.size() && dead[k] != 0; });
  for (size_t w = 0; w < s.wallCandidates.size(); ++w) {
    std::vector<uint32_t>& list = s.wallCandidates[w];
    auto* springs = w < s.wallSprings.size() && s.wallSprings[w].size() == list.size()
                        ? &s.wallSprings[w]
                        : nullptr;
    size_t out = 0;
    for (size_t k = 0; k < list.size(); ++k) {
      const uint32_t i = moved(list[k]);
      if (i == kGone) continue;
      if (springs != nullptr) (*springs)[out] = (*springs)[k];
      list[out++] = i;
    }
    list.resize(out);
    if (springs != nullptr) springs->resize(out);
  }
  s.contactGroups.clear();
  s.dist->plan.ownedRemoved(gone, from);
}

// What a serial removal does to the whole scene's pair state, done by every rank of a
// distributed one, owner or not: the contact records dropped, the touch states stale. Changes
// those.
template <int D>
void forgetContactRecords(Scene<D>& s) {
  s.contacts.clear();
  s.touchNowValid = s.wallTouchNowValid = false;
}

// Drops the candidates of wall w (dense) with their springs before the walls' swap-removal takes
// it out: the last wall's lists move into its place, as the wall does. The grain candidates and
// their springs stay (a distributed scene cannot park them by slot: a ghost partner has none);
// the contact records are dropped and the touch states marked stale, as a serial removal does.
// The caller sets the search that follows. Changes the per-wall lists.
template <int D>
void dropWallCandidates(Scene<D>& s, uint32_t w) {
  const size_t walls = s.walls.size();
  const auto swapRemove = [&](auto& perWall) {
    perWall.resize(walls);  // (a wall added since the last search has none yet)
    if (w + 1 != walls) perWall[w] = std::move(perWall.back());
    perWall.pop_back();
  };
  swapRemove(s.wallCandidates);
  if (s.wallSprings.size() > w) swapRemove(s.wallSprings);
  s.wallTouchNow.clear();
  s.wallTouchPrev.clear();
  s.contactGroups.clear();
  s.wallTouchPrevValid = false;
  forgetContactRecords(s);
}

// Drops the ghosts from the arrays. Changes every array and s.ghosts.
template <int D>
void dropGhosts(Scene<D>& s) {
  const size_t owned = s.ownedCount();
  ElementArrays<D>::forEachArray(s.elements.a, [&](auto& arr) { arr.resize(owned); });
  s.ghosts = 0;
}

// The first half of a distributed search, after the springs' collect() and before the dense
// order is sorted: drops the ghosts, bisects when the ranks' counts drifted apart (or the first
// time), and sends every owned element outside its rank's box to its owner with the springs of
// the pairs it is A of. Collective. Changes the elements, their handles and springs.
template <int D>
void migrate(Scene<D>& s, SpringTransfer<D>& springs) {
  if constexpr (D == 3) {
    Distribution<D>& d = *s.dist;
    const mpi::Communicator& comm = *d.comm;
    dropGhosts(s);
    ElementArrays<D>& a = s.elements.a;
    const size_t n = a.size();
    const auto centre = [&](size_t i) { return mpi::Point<D>{a.x[i][0], a.x[i][1], a.x[i][2]}; };
    // (At the first search every rank passes all the points: each counts p times, which moves
    // no cut.)
    const std::vector<double> counts = comm.gather({static_cast<double>(n)});
    if (d.initial || mpi::Partition<D>::imbalance(counts) > d.rebalanceAbove) {
      d.partition = mpi::Partition<D>::bisect(centresOf(a, n), {}, comm.size(), comm);
      d.bisections += 1;
    }
    const size_t p = static_cast<size_t>(comm.size());
    std::vector<std::vector<ElementRecord>> out(p);
    // The leaving elements by slot: their new rank and global id (few: a map, not a table the
    // size of the slots, which would be the search's peak in a large scene).
    std::unordered_map<uint32_t, std::pair<int, uint64_t>> leavingSlot;
    std::vector<ElementId> leaving;
    for (size_t i = 0; i < n; ++i) {
      const int k = d.partition.ownerOf(centre(i));
      if (k == comm.rank()) continue;
      out[static_cast<size_t>(k)].push_back(recordOf(a, i));
      leavingSlot.emplace(a.slot[i], std::make_pair(k, a.globalId[i]));
      leaving.push_back(s.elements.pool().handleAt(static_cast<uint32_t>(i)));
    }
    using Moved = typename SpringTransfer<D>::MovedSpring;
    std::vector<std::vector<Moved>> springsOut(p);
    // (A search where nothing leaves, the usual one, leaves the table as it is.)
    if (!leaving.empty()) springs.takeRows(
        [&](uint32_t r) {
          const auto it = leavingSlot.find(r);
          return it == leavingSlot.end() ? -1 : it->second.first;
        },
        [&](uint32_t r) { return leavingSlot.at(r).second; }, springsOut);
    if (d.initial) {
      // The elements of the other boxes, and the springs of their pairs, are their owners'
      // already.
      for (auto& o : out) o.clear();
      for (auto& o : springsOut) o.clear();
    }
    const std::vector<ElementRecord> arrived = mpi::exchangeRecords(comm, out);
    const std::vector<Moved> arrivedSprings = mpi::exchangeRecords(comm, springsOut);
    if (!d.initial) d.migrated += leaving.size();
    d.initial = false;
    for (ElementId id : leaving) s.elements.remove(id);
    std::unordered_map<uint64_t, uint32_t> slotOfId;
    slotOfId.reserve(arrived.size());
    for (const ElementRecord& r : arrived) {
      const ElementId id = s.elements.adopt(r.globalId);
      pushRecord(a, r, id.index);
      slotOfId.emplace(r.globalId, id.index);
    }
    springs.addRows(arrivedSprings, [&](uint64_t gid) { return slotOfId.at(gid); },
                    s.elements.pool().slotCount());
  }
}

// The second half of a distributed search, after the dense order is sorted: every rank
// publishes its elements' reach, and receives as ghosts the elements of the others within reach
// of its own (mpi/reach.hpp), appended after its owned ones. Collective. Changes the arrays,
// s.ghosts and the plan.
template <int D>
void makeGhosts(Scene<D>& s) {
  if constexpr (D == 3) {
    Distribution<D>& d = *s.dist;
    const mpi::Communicator& comm = *d.comm;
    ElementArrays<D>& a = s.elements.a;
    const size_t n = a.size();
    const std::vector<mpi::Point<D>> centres = centresOf(a, n);
    const std::vector<double> radii(a.r.begin(), a.r.end());
    const mpi::ReachTable<D> table = mpi::ReachTable<D>::gather(centres, radii, comm);
    d.plan = mpi::GhostPlan<D>::make(table, centres, radii, s.skin, comm);
    std::vector<ElementRecord> ghosts;
    d.plan.forwardWith([&](uint32_t i, ElementRecord& r) { r = recordOf(a, i); }, comm, ghosts);
    a.reserve(n + ghosts.size());
    d.states.resize(ghosts.size());
    for (size_t j = 0; j < ghosts.size(); ++j) {
      const ElementRecord& r = ghosts[j];
      pushRecord(a, r, kNoSlot);
      GhostStateTouch& g = d.states[j];
      std::copy(r.x, r.x + 3, g.x), std::copy(r.v, r.v + 3, g.v), std::copy(r.w, r.w + 3, g.w);
      std::copy(r.fPrev, r.fPrev + 3, g.fPrev);
    }
    s.ghosts = ghosts.size();
    d.ghostCopiesSent = d.plan.sent();
    d.searches += 1;
  }
}

// "ghosts" (level Predict, after the drift and the turn): the owned elements' new states to the
// ranks holding their ghosts; the ghosts' forces and torques zeroed for the contact passes.
template <int D>
class GhostModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "ghosts"; }
  SimLevel level() const override { return SimLevel::Predict; }
  void run(Scene<D>& s) override {
    if constexpr (D == 3) {
      // (The touch correction's states stay in Distribution::states: its velocity changes are
      // measured from them.)
      if (s.touchCorrection) {
        forward<GhostStateTouch>(s);
      } else {
        forward<GhostState>(s);
      }
    }
  }

 private:
  // Sends the owned elements' states as T (GhostState or GhostStateTouch) and sets the ghosts
  // from those that arrive (straight from the messages), their forces and torques zeroed.
  template <class T>
  static void forward(Scene<D>& s) {
    ElementArrays<D>& a = s.elements.a;
    Distribution<D>& d = *s.dist;
    constexpr bool touch = std::is_same_v<T, GhostStateTouch>;
    d.plan.template sendForward<T>(
        [&](uint32_t i, T& g) {
          for (int k = 0; k < 3; ++k) g.x[k] = a.x[i][k], g.v[k] = a.v[i][k], g.w[k] = a.w[i][k];
          if constexpr (touch) {
            for (int k = 0; k < 3; ++k) g.fPrev[k] = a.fPrev[i][k];
          }
        },
        *d.comm);
    const size_t first = s.ownedCount();
    if constexpr (touch) d.states.resize(s.ghosts);
    d.plan.template receiveForward<T>([&](size_t j, const T& g) {
      const size_t i = first + j;
      a.x[i] = Vec3(g.x[0], g.x[1], g.x[2]);
      a.v[i] = Vec3(g.v[0], g.v[1], g.v[2]);
      a.w[i] = Vec3(g.w[0], g.w[1], g.w[2]);
      if constexpr (touch) {
        a.fPrev[i] = Vec3(g.fPrev[0], g.fPrev[1], g.fPrev[2]);
        d.states[j] = g;
      }
      a.f[i].setZero();
      a.t[i].setZero();
    });
  }
};

// The ghosts' forces and torques of this rank's pairs (and with the touch correction the change
// of their velocities) sent to their owners.
template <int D>
void sendGhostForces(Scene<D>& s) {
  if constexpr (D == 3) {
    Distribution<D>& d = *s.dist;
    ElementArrays<D>& a = s.elements.a;
    const size_t first = s.ownedCount();
    if (s.touchCorrection) {
      d.plan.template sendBack<GhostForceTouch>(
          [&](size_t j, GhostForceTouch& g) {
            for (int k = 0; k < 3; ++k) {
              g.f[k] = a.f[first + j][k], g.t[k] = a.t[first + j][k];
              g.dv[k] = a.v[first + j][k] - d.states[j].v[k];
            }
          },
          *d.comm);
    } else {
      d.plan.template sendBack<GhostForce>(
          [&](size_t j, GhostForce& g) {
            for (int k = 0; k < 3; ++k) g.f[k] = a.f[first + j][k], g.t[k] = a.t[first + j][k];
          },
          *d.comm);
    }
  }
}

// "ghost-forces-out": the ghosts' forces on their way, sent right after the last module that
// acts on ghosts (placeGhostForceSend), so that the modules after it that act on owned
// elements only (SimModule::ownedOnly: the walls' pass, gravity) run while they travel.
template <int D>
class GhostForceSendModule final : public SimModule<D> {
 public:
  explicit GhostForceSendModule(SimLevel level) : level_(level) {}
  std::string_view name() const override { return "ghost-forces-out"; }
  SimLevel level() const override { return level_; }
  void run(Scene<D>& s) override { sendGhostForces(s); }

 private:
  SimLevel level_;
};

// "ghost-forces" (level Behaviors, after every force on pairs and before the constraints and
// the kick): what the ghosts took in the other ranks' pairs (sent by their "ghost-forces-out"),
// added to their owners' forces and torques (and velocities: the touch correction's impulses)
// in the same order every step.
template <int D>
class GhostForceModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "ghost-forces"; }
  SimLevel level() const override { return SimLevel::Behaviors; }
  void run(Scene<D>& s) override {
    if constexpr (D == 3) {
      if (s.touchCorrection) {
        add<GhostForceTouch>(s);
      } else {
        add<GhostForce>(s);
      }
    }
  }

 private:
  // Adds the values of T (GhostForce or GhostForceTouch) the other ranks sent back.
  template <class T>
  void add(Scene<D>& s) {
    ElementArrays<D>& a = s.elements.a;
    constexpr bool touch = std::is_same_v<T, GhostForceTouch>;
    // The touch correction's kicks from the other ranks' pairs are held along blocked degrees
    // of freedom, as the owner's own are (TouchModule::holdBlocked), the reaction's work booked.
    const bool holding = touch && !s.blocked.empty();
    if (holding) held_.collect(s);
    double work = 0;
    s.dist->plan.template receiveBack<T>([&](uint32_t i, const T& g) {
      a.f[i] += Vec3(g.f[0], g.f[1], g.f[2]);
      a.t[i] += Vec3(g.t[0], g.t[1], g.t[2]);
      if constexpr (touch) {
        Vec3 dv(g.dv[0], g.dv[1], g.dv[2]);
        if (holding) held_.hold(a, i, dv, work);
        // (Most ghosts' velocities are untouched: their zeros change no bits but a -0.)
        a.v[i] += dv;
      }
    });
    if (work != 0) s.ledger.behaviorWork += work;
  }

  BlockedKickHold held_;  // the rank's blocked elements (the touch correction's kicks)
};

// Moves the "ghost-forces-out" module of a level-ordered list m (made by the "ghost-forces"
// row just before "ghost-forces") back past every module that acts on owned elements only, to
// right after the last one that may act on ghosts, and gives it that module's level. Changes m.
template <int D>
void placeGhostForceSend(std::vector<std::unique_ptr<SimModule<D>>>& m) {
  size_t send = 0;
  while (send < m.size() && m[send]->name() != "ghost-forces-out") ++send;
  if (send == m.size()) return;
  size_t at = send;
  while (at > 0 && m[at - 1]->ownedOnly()) --at;
  if (at == send || at == 0) return;
  m.erase(m.begin() + static_cast<std::ptrdiff_t>(send));
  m.insert(m.begin() + static_cast<std::ptrdiff_t>(at),
           std::make_unique<GhostForceSendModule<D>>(m[at - 1]->level()));
}

}  // namespace demlab::sim
