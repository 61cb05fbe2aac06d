// SimulationManager<D>::gatheredScene: a distributed scene made whole again on rank 0, as a
// serial run would hold it, so that its checkpoint loads on any number of ranks (one, or as
// many or more or fewer than wrote it: every rank of a run loads the whole scene and the first
// run spreads it, sim/distribution.hpp).
//
// What the ranks hold apart comes together: the owned elements under the handles scripts know,
// the springs of every pair (parked under the elements' slots, as an edit parks them: the
// loaded scene searches at its first step and each candidate takes its spring back), the last
// step's contact records, and the sums of the ledger and of the walls' forces and work. The
// candidates and the touch states are not kept: the first step after the load searches, and
// the touch correction takes that step's events from its reconstruction, as after any search
// that lacks states (sim/touch.hpp).
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "mpi/communicator.hpp"
#include "mpi/records.hpp"
#include "sim/distribution.hpp"
#include "sim/history_store.hpp"
#include "sim/simulation_manager.hpp"

namespace demlab::sim {

namespace {

// A pair's tangential spring on its way to rank 0: the global ids of its A and B (a wall's B:
// wallPartner of its slot) and the whole history.
struct SpringRecord {
  uint64_t a, b;
  double spring[3], drift[3], damperImpulse, damperPending;
};

// A contact record of the last step by global ids (a wall's b: its dense index).
struct GatheredContact {
  uint64_t a, b, wall;
  double force[3];
};

// Returns the record of spring h of the pair (a, b).
SpringRecord springRecord(uint64_t a, uint64_t b, const physics::TangentialHistory<3>& h) {
  SpringRecord r{a, b, {}, {}, h.damperImpulse, h.damperPending};
  for (int k = 0; k < 3; ++k) r.spring[k] = h.spring[k], r.drift[k] = h.drift[k];
  return r;
}

// Returns the springs of s's pairs as records: those of the candidates, of the wall candidates
// and any parked (a part not searched since it was distributed). Changes nothing.
std::vector<SpringRecord> springRecords(const Scene<3>& s) {
  std::vector<SpringRecord> out;
  if (!s.keepHistory) return out;
  const ElementArrays<3>& a = s.elements.a;
  const size_t n = std::min(s.pairSprings.size(), s.candidates.size());
  for (size_t k = 0; k < n; ++k) {
    const physics::TangentialHistory<3> h = s.pairSprings.history(k);
    if (h.empty()) continue;
    out.push_back(springRecord(a.globalId[s.candidates[k].i], a.globalId[s.candidates[k].j], h));
  }
  for (size_t w = 0; w < s.wallSprings.size() && w < s.wallCandidates.size(); ++w) {
    const uint64_t wall = wallPartner(s.walls.pool().handleAt(static_cast<uint32_t>(w)).index);
    for (size_t k = 0; k < s.wallSprings[w].size() && k < s.wallCandidates[w].size(); ++k) {
      const auto& h = s.wallSprings[w][k];
      if (!h.empty()) out.push_back(springRecord(a.globalId[s.wallCandidates[w][k]], wall, h));
    }
  }
  forEachParkedSpring(s, [&](uint32_t, uint32_t aDense, uint64_t partner, const auto& h) {
    out.push_back(springRecord(a.globalId[aDense], partner, h));
  });
  return out;
}

}  // namespace

template <int D>
Scene<D> SimulationManager<D>::gatheredScene() const {
  if constexpr (D != 3) {
    return copyScene();
  } else {
    if (!s_.dist) return copyScene();
    const Distribution<D>& d = *s_.dist;
    const mpi::Communicator& comm = *d.comm;
    // Until its first search every rank holds the whole scene: rank 0 gives it alone.
    const bool gives = !d.initial || comm.rank() == 0;
    const ElementArrays<D>& a = s_.elements.a;
    const size_t owned = s_.ownedCount();
    std::vector<ElementRecord> elements;
    std::vector<SpringRecord> springs;
    std::vector<GatheredContact> contacts;
    if (gives) {
      elements.reserve(owned);
      for (size_t i = 0; i < owned; ++i) elements.push_back(recordOf(a, i));
      springs = springRecords(s_);
      for (const ContactRecord<D>& c : s_.contacts) {
        contacts.push_back({a.globalId[c.a], c.wall ? uint64_t{c.b} : a.globalId[c.b], c.wall,
                            {c.force[0], c.force[1], c.force[2]}});
      }
    }
    // The sums (every rank takes part; rank 0 keeps them).
    LedgerSums ledger = s_.ledger;
    double kinetic = 0, potential = 0;
    reduceLedger(comm, kinetic, potential, ledger);
    std::vector<double> walls;
    for (const Wall<D>& w : s_.walls.items) {
      walls.insert(walls.end(), {w.force[0], w.force[1], w.force[2], w.work});
    }
    comm.sum(walls);
    const double fastest = comm.max(s_.fastestSpeed2);
    elements = mpi::gatherRecordsTo(comm, elements, 0);
    springs = mpi::gatherRecordsTo(comm, springs, 0);
    contacts = mpi::gatherRecordsTo(comm, contacts, 0);
    if (comm.rank() != 0) return Scene<D>{};

    Scene<D> g = s_;
    g.dist.reset();
    g.ownedIndexOfHandle = nullptr;
    g.ownedBlocked = nullptr;
    g.ownedTagged = nullptr;
    g.ghosts = 0;
    g.ledger = ledger;
    for (size_t k = 0; k < g.walls.items.size(); ++k) {
      Wall<D>& w = g.walls.items[k];
      w.force = VecD<D>(walls[4 * k], walls[4 * k + 1], walls[4 * k + 2]);
      w.work = walls[4 * k + 3];
    }
    g.fastestSpeed2 = fastest;
    g.deepest = DeepestContact<D>{};
    // The elements in global id order under their original handles, the pool as it was.
    std::sort(elements.begin(), elements.end(), [](const ElementRecord& x, const ElementRecord& y) {
      return x.globalId < y.globalId;
    });
    HandlePool<ElementKind>::State pool;
    pool.generations.assign(d.poolSlots, 0);
    pool.freeSlots = d.freeSlots;
    for (size_t k = 0; k < d.freeSlots.size(); ++k) {
      pool.generations[d.freeSlots[k]] = d.freeGenerations[k];
    }
    pool.dense.reserve(elements.size());
    for (const ElementRecord& r : elements) {
      const ElementId h = d.handleOf(r.globalId);
      pool.generations.at(h.index) = h.generation;
      pool.dense.push_back(h);
    }
    g.elements.pool().restoreState(pool);
    // (The pool's handles are the scripts' again: the names and tags are the store's.)
    g.elements.names() = d.names;
    g.elements.tags() = d.tags;
    ElementArrays<D>& ga = g.elements.a;
    ElementArrays<D>::forEachArray(ga, [](auto& arr) { arr.clear(); });
    ga.reserve(elements.size());
    for (size_t i = 0; i < elements.size(); ++i) pushRecord(ga, elements[i], pool.dense[i].index);
    const auto denseOf = [&](uint64_t gid) {
      const auto it = std::lower_bound(ga.globalId.begin(), ga.globalId.end(), gid);
      return static_cast<uint32_t>(it - ga.globalId.begin());
    };
    // No candidates: the loaded scene searches first, its springs parked by slot till then.
    g.candidates.clear();
    g.contactGroups = ContactGroups{};
    g.wallCandidates.clear();
    g.xAtBuild.clear();
    g.marginWeight.clear();
    g.maxDisp2 = 0;
    g.needRebuild = true;
    g.touchNow.clear(), g.touchPrev.clear(), g.wallTouchNow.clear(), g.wallTouchPrev.clear();
    g.touchNowValid = g.touchPrevValid = g.wallTouchNowValid = g.wallTouchPrevValid = false;
    g.pairSprings.clear();
    g.wallSprings.clear();
    g.histories.clear();
    for (const SpringRecord& r : springs) {
      physics::TangentialHistory<D> h;
      for (int k = 0; k < 3; ++k) h.spring[k] = r.spring[k], h.drift[k] = r.drift[k];
      h.damperImpulse = r.damperImpulse;
      h.damperPending = r.damperPending;
      const uint32_t p = ga.slot[denseOf(r.a)];
      if (r.b > kMaxGlobalId) {
        g.histories.touch(p, wallPairId(static_cast<uint32_t>(r.b - kMaxGlobalId - 1))).state = h;
      } else {
        const uint32_t q = ga.slot[denseOf(r.b)];
        g.histories.touch(std::min(p, q), std::max(p, q)).state = h;
      }
    }
    g.contacts.clear();
    g.contacts.reserve(contacts.size());
    for (const GatheredContact& c : contacts) {
      const uint32_t b = c.wall ? static_cast<uint32_t>(c.b) : denseOf(c.b);
      ContactRecord<D> r{denseOf(c.a), b, static_cast<uint32_t>(c.wall),
                         VecD<D>(c.force[0], c.force[1], c.force[2])};
      g.contacts.push_back(r);
    }
    g.lastRecorded = g.contacts.size();
    return g;
  }
}

template class SimulationManager<2>;
template class SimulationManager<3>;

}  // namespace demlab::sim
