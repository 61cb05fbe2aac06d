// SimulationManager<D>: spreading a scene over the ranks of an MPI run (sim/distribution.hpp)
// and the queries that gather it back.
#include <algorithm>
#include <cstring>
#include <string>
#include <unordered_map>

#include "mpi/communicator.hpp"
#include "mpi/error_bytes.hpp"
#include "mpi/records.hpp"
#include "sim/convert.hpp"
#include "sim/distribution.hpp"
#include "sim/simulation_manager.hpp"
#include "sim/watchdog.hpp"

namespace demlab::sim {

namespace {

// Returns the handle of the first element a scene creates in slot gid (its global id too).
ElementId firstLife(uint64_t gid) { return Distribution<3>::firstLife(gid); }

// Fills d's runs of renamed handles (Distribution::renamedById) from the whole scene s.
template <int D>
void renameRuns(const Scene<D>& s, Distribution<D>& d) {
  std::vector<std::pair<uint64_t, uint64_t>> renamed;  // (global id, handle bits)
  for (size_t i = 0; i < s.elements.size(); ++i) {
    const ElementId h = s.elements.pool().handleAt(static_cast<uint32_t>(i));
    const uint64_t gid = s.elements.a.globalId[i];
    if (h != firstLife(gid)) renamed.emplace_back(gid, h.bits());
  }
  std::sort(renamed.begin(), renamed.end());
  for (const auto& [gid, bits] : renamed) d.appendRenamed(gid, bits);
  d.sortRenamedByHandle();
}

// Returns what in scene s a distributed run cannot do yet, or "" when it can run it.
template <int D>
std::string unsupported(const Scene<D>& s, std::ptrdiff_t outputs) {
  if (D != 3) return "two dimensions";
  const ElementArrays<D>& a = s.elements.a;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a.geometry[i] != 0) return "elements that are not balls";
  }
  if (!s.bonds.empty()) return "bonds";
  for (const Wall<D>& w : s.walls.items) {
    if (w.kind == WallShape::Mesh) return "a mesh wall";
  }
  if (s.periodic.any()) return "periodic boundaries";
  if (!s.sources.empty()) return "a source";
  if (!s.sinks.empty()) return "a sink";
  // (Gravity acts on every element; a load or a torque ramp on one element finds it among the
  // rank's own through Scene::ownedIndexOfHandle, on a tag its members there: ownedTagged.)
  for (const auto& b : s.behaviors.items()) {
    const std::string_view t = b->type();
    if (t != "gravity" && t != "load" && t != "torque-ramp") return "a " + std::string(t) + " behavior";
  }
  if (outputs > 0) return "an output distributed runs do not write yet";
  return "";
}

}  // namespace

template <int D>
void SimulationManager<D>::distribute() {
  if (s_.dist) {
    throw Error("can't distribute the scene: it is distributed already", {"MPI", "DISTRIBUTED"});
  }
  const std::string what = unsupported(
      s_, std::count_if(outputs_.begin(), outputs_.end(),
                        [](const Output& o) { return !o.def.distributable; }));
  if (!what.empty()) {
    throw Error("can't distribute the scene over ranks: it has " + what +
                    ", which distributed runs do not support yet",
                {"MPI", "UNSUPPORTED"});
  }
  if constexpr (D == 3) {
    // Every rank holds the whole scene: what it uses, its skin, its static step survey and the
    // watchdog's step limit are decided here for all.
    auto d = std::make_shared<Distribution<D>>();
    d->comm = &mpi::Communicator::world();
    const mpi::Communicator& comm = *d->comm;
    d->use = sceneUse(s_);
    d->skin = skinInUse();
    StepSurvey survey;
    staticCriticalStep(false, &survey);
    d->critical = survey.critical;
    d->linearDuration = survey.linearDuration;
    d->hertzDuration = survey.hertzDuration;
    d->stepLimit = watchdogStepLimit(s_, d->skin);
    renameRuns(s_, *d);
    // The names and tags, under the pool's handles (the scripts' now), go to the distribution
    // before any element leaves: each rank's pool names its own elements anew from here on.
    d->names = std::move(s_.elements.names());
    s_.elements.names() = NameLookup<ElementId>("grain");
    d->tags = std::move(s_.elements.tags());
    s_.elements.tags() = TagTable<ElementKind>{};
    {
      const auto pool = s_.elements.pool().saveState();
      d->poolSlots = static_cast<uint32_t>(pool.generations.size());
      d->freeSlots = pool.freeSlots;
      for (uint32_t k : pool.freeSlots) d->freeGenerations.push_back(pool.generations[k]);
    }
    // A scene that has run holds pair state (springs, touch states) by dense index: the first
    // search keeps each rank's part with it (migrate). One that has not is cut now, before it
    // costs any rank more than its part's memory.
    // (Parked springs, a gathered checkpoint's, are keyed by slots: each rank turns its
    // elements' into the search's table at that search, while it still holds their partners.)
    bool paired = !s_.candidates.empty() || !s_.histories.empty();
    for (const auto& w : s_.wallCandidates) paired = paired || !w.empty();
    if (!paired && comm.size() > 1) {
      ElementArrays<D>& a = s_.elements.a;
      std::vector<mpi::Point<D>> centres = centresOf(a, a.size());
      // (Every rank passes all the points: each counts p times, which moves no cut.)
      d->partition = mpi::Partition<D>::bisect(centres, {}, comm.size(), comm);
      d->bisections = 1;
      d->initial = false;
      std::vector<ElementId> others;
      for (size_t i = 0; i < a.size(); ++i) {
        if (d->partition.ownerOf(centres[i]) != comm.rank()) {
          others.push_back(s_.elements.pool().handleAt(static_cast<uint32_t>(i)));
        }
      }
      std::vector<mpi::Point<D>>().swap(centres);
      for (ElementId id : others) s_.elements.remove(id);
      // The arrays' room for the whole scene goes back to the system.
      ElementArrays<D>::forEachArray(a, [](auto& arr) { arr.shrink_to_fit(); });
      s_.forcesReady = false;
    }
    // The ledger's sums of what happened so far are the whole scene's on every rank: rank 0
    // keeps them, so the ranks' sums add up to them.
    if (comm.rank() != 0) {
      LedgerSums& l = s_.ledger;
      l.dampingLoss = l.frictionLoss = l.wallWork = l.behaviorWork = l.springWork = 0;
      l.bondReleased = 0;
      for (Wall<D>& w : s_.walls.items) w.work = 0;
    }
    // The first step searches and keeps each rank's part; on one rank the scene is its part
    // already, and its searches come when the serial run's would.
    s_.needRebuild = s_.needRebuild || comm.size() > 1;
    s_.dist = std::move(d);
    s_.ownedIndexOfHandle = &ownedIndexOf<D>;
    s_.ownedBlocked = &ownedBlockedOf<D>;
    s_.ownedTagged = &ownedTaggedOf<D>;
    configDirty_ = true;
  }
}

template <int D>
std::vector<Simulation::ElementSnapshot> SimulationManager<D>::elementSnapshots() const {
  const ElementArrays<D>& a = s_.elements.a;
  const size_t n = s_.ownedCount();
  std::vector<ElementSnapshot> mine(n);
  for (size_t i = 0; i < n; ++i) {
    ElementSnapshot& e = mine[i];
    e.id = a.globalId[i];
    e.position = fromVec<D>(a.x[i]);
    e.velocity = fromVec<D>(a.v[i]);
    e.angularVelocity = fromAngular(a.w[i]);
  }
  std::vector<ElementSnapshot> all =
      s_.dist ? mpi::gatherRecords(*s_.dist->comm, mine) : std::move(mine);
  std::sort(all.begin(), all.end(),
            [](const ElementSnapshot& x, const ElementSnapshot& y) { return x.id < y.id; });
  return all;
}

template <int D>
ElementId SimulationManager<D>::ownedElement(ElementId original) const {
  if (!s_.dist) {
    s_.elements.index(original);  // LOOKUP HANDLE when it names no element
    return original;
  }
  const uint32_t i = ownedIndexOf(s_, original);
  return i == HandlePool<ElementKind>::kNpos ? ElementId{} : s_.elements.pool().handleAt(i);
}

template <int D>
typename SimulationManager<D>::ElementEdit SimulationManager<D>::editElement(
    ElementId id, const std::function<void(uint32_t)>& change) {
  ElementEdit out;
  if (!s_.dist) {
    const uint32_t i = s_.elements.index(id);
    const double before = elementEnergy(i);
    change(i);
    out.energy = elementEnergy(i) - before;
    return out;
  }
  // The owner's answer travels as a tag byte and then: the energy and the global id (1), or
  // the error's message and code words, each ended by a NUL (2). Other ranks send nothing.
  std::vector<char> mine;
  const ElementId here = ownedElement(id);
  if (!here.isNull()) {
    const uint32_t i = s_.elements.index(here);
    try {
      const double before = elementEnergy(i);
      change(i);
      const ElementEdit e{elementEnergy(i) - before, s_.elements.a.globalId[i]};
      mine.resize(1 + sizeof e);
      mine[0] = 1;
      std::memcpy(mine.data() + 1, &e, sizeof e);
    } catch (const Error& e) {
      mine.push_back(2);
      mpi::appendErrorBytes(e, mine);
    }
  }
  for (const std::vector<char>& b : s_.dist->comm->gatherBytes(mine)) {
    if (b.empty()) continue;
    if (b[0] == 1) {
      std::memcpy(&out, b.data() + 1, sizeof out);
      // Every rank searches again before the edited state's forces: the ghosts' copies are
      // made anew there (a forcesOnly pass with a stale ghost would differ).
      s_.needRebuild = true;
      return out;
    }
    throw mpi::errorFromBytes(b, 1);
  }
  throw Error("invalid element id \"" + toString(id) + "\": no such element", {"LOOKUP", "HANDLE"});
}

template <int D>
ElementId SimulationManager<D>::addElementOnRanks(const ElementDef& def) {
  if constexpr (D != 3) {
    throw Error("can't add an element: only 3D scenes are distributed", {"MPI", "UNSUPPORTED"});
  } else {
    const auto refuse = [](const std::string& what) {
      throw Error("can't add an element with " + what +
                      " to a distributed scene: distributed runs do not support them yet",
                  {"MPI", "UNSUPPORTED"});
    };
    const CheckedElement c = checkElement(def);
    if (c.geometry.boundRadius != 0) refuse("a shape other than the ball");
    Distribution<D>& d = *s_.dist;
    const uint64_t gid = s_.elements.peekGlobalId();  // (the same on every rank)
    const ElementId h = d.allocateHandle(gid);
    s_.elements.setNextGlobalId(gid + 1);
    // The element as the serial scene makes it (forces zero), on the rank whose box holds it.
    ElementRecord r{};
    for (int k = 0; k < 3; ++k) r.x[k] = c.x[k], r.v[k] = c.v[k], r.w[k] = c.w[k];
    r.q[0] = c.q.w(), r.q[1] = c.q.x(), r.q[2] = c.q.y(), r.q[3] = c.q.z();
    r.r = c.r, r.invMass = c.invMass, r.invInertia = c.invInertia;
    r.globalId = gid, r.material = c.material, r.geometry = 0;
    // Its energy (what the serial scene adds to the ledger's reference) from that rank.
    // (Before the first search every rank holds the whole scene: each adds it, rank 0 counts.)
    double energy = 0;
    const int owner = d.initial ? 0 : d.partition.ownerOf({r.x[0], r.x[1], r.x[2]});
    if (d.initial || owner == d.comm->rank()) {
      insertOwned(s_, r);
      if (owner == d.comm->rank()) energy = elementEnergy(static_cast<uint32_t>(s_.ownedCount() - 1));
    }
    s_.ledger.reference += d.comm->sum(energy);
    // (Every rank lists it under the scripts' handle; its owner finds it: ownedBlockedOf.)
    if (c.blocked != 0) s_.blocked.push_back({h, c.blocked});
    // (Its name and tags, checked with the rest, under the scripts' handle on every rank.)
    if (!def.name.empty()) d.names.add(def.name, h);
    for (const std::string& t : def.tags) d.tags.add(h, t);
    if (!def.tags.empty()) ++d.tagEdits;
    // The next step searches, as the serial scene's does: the new element's pairs and ghosts.
    s_.needRebuild = true;
    if (s_.steps > 0) d.placed.push_back(gid);  // (as markPlaced)
    touchConfig();
    return h;
  }
}

template <int D>
size_t SimulationManager<D>::removeElementsOnRanks(const std::vector<ElementId>& ids) {
  if constexpr (D != 3) {
    throw Error("can't remove an element: only 3D scenes are distributed", {"MPI", "UNSUPPORTED"});
  } else {
    Distribution<D>& d = *s_.dist;
    const size_t n = ids.size();
    // One pass over the owned elements finds every id this rank owns (ids hold no repeats).
    std::vector<std::optional<uint64_t>> gids(n);
    std::unordered_map<uint64_t, size_t> wanted;
    for (size_t k = 0; k < n; ++k) {
      gids[k] = d.globalIdOf(ids[k]);
      if (gids[k]) wanted.emplace(*gids[k], k);
    }
    std::vector<ElementId> local(n);
    std::vector<double> held(n, 0.0);
    const ElementArrays<D>& a = s_.elements.a;
    for (size_t i = 0; i < s_.ownedCount() && !wanted.empty(); ++i) {
      const auto it = wanted.find(a.globalId[i]);
      if (it == wanted.end()) continue;
      local[it->second] = s_.elements.pool().handleAt(static_cast<uint32_t>(i));
      held[it->second] = 1;
    }
    d.comm->sum(held);
    for (size_t k = 0; k < n; ++k) {
      if (held[k] == 0) {
        throw Error("no element with id " + std::to_string(ids[k].scriptId()), {"LOOKUP", "HANDLE"});
      }
    }
    // Each takes its energy out of the scene: the owner measures it, every rank moves the
    // ledger's reference by it, one after another as the serial scene does.
    std::vector<double> energy(n, 0.0);
    for (size_t k = 0; k < n; ++k) {
      if (local[k].isNull()) continue;
      energy[k] = elementEnergy(s_.elements.index(local[k]));
      if (s_.keepHistory) s_.histories.removeId(local[k].index);
      removeOwned(s_, local[k]);
    }
    forgetContactRecords(s_);
    d.comm->sum(energy);
    for (size_t k = 0; k < n; ++k) {
      s_.ledger.reference -= energy[k];
      std::erase_if(s_.blocked, [&](const BlockedElement& b) { return b.id == ids[k]; });
      d.names.remove(ids[k]);
      if (d.tags.removeObject(ids[k]) > 0) ++d.tagEdits;
      d.freeHandle(ids[k]);
      std::erase(d.placed, *gids[k]);
    }
    // The next step searches, as the serial scene's does: the ghosts of the removed go there.
    s_.needRebuild = true;
    touchConfig();
    return n;
  }
}

template <int D>
void SimulationManager<D>::decideWhole() {
  Distribution<D>& d = *s_.dist;
  ElementUse e = elementUse(s_);
  std::vector<double> flags(e.grainMaterials.begin(), e.grainMaterials.end());
  flags.insert(flags.end(), {double(e.spinning), double(e.shapes), double(e.rigid)});
  d.comm->max(flags);
  const size_t nm = e.grainMaterials.size();
  for (size_t m = 0; m < nm; ++m) e.grainMaterials[m] = flags[m] > 0;
  e.spinning = flags[nm] > 0, e.shapes = flags[nm + 1] > 0, e.rigid = flags[nm + 2] > 0;
  d.use = sceneUseWith(s_, e);
  StepSurvey survey;
  staticCriticalStep(false, &survey, true);  // (collective: the smallest grains over the ranks)
  d.critical = survey.critical;
  d.linearDuration = survey.linearDuration;
  d.hertzDuration = survey.hertzDuration;
}

template <int D>
void SimulationManager<D>::markPlacedEdit(ElementId id, const ElementEdit& e) {
  if (!s_.dist) return markPlaced(id);
  if (s_.steps > 0) s_.dist->placed.push_back(e.globalId);
}

template <int D>
ElementId SimulationManager<D>::originalHandle(ElementId local) const {
  const uint32_t i = s_.elements.index(local);
  return s_.dist ? elementHandleAt(i) : local;
}

template <int D>
ElementId SimulationManager<D>::elementHandleAt(size_t i) const {
  if (!s_.dist) return s_.elements.pool().handleAt(static_cast<uint32_t>(i));
  return s_.dist->handleOf(s_.elements.a.globalId[i]);
}


template <int D>
Simulation::DistributionReport SimulationManager<D>::distribution() const {
  DistributionReport r;
  r.owned = s_.ownedCount();
  if (!s_.dist) return r;
  const Distribution<D>& d = *s_.dist;
  r.rank = d.comm->rank();
  r.ranks = d.comm->size();
  r.ghosts = s_.ghosts;
  r.searches = d.searches;
  r.bisections = d.bisections;
  r.migrated = d.migrated;
  r.copiesSent = d.ghostCopiesSent;
  return r;
}

template <int D>
void SimulationManager<D>::refuseIfDistributed(const char* what) const {
  if (s_.dist) {
    throw Error(std::string("can't ") + what +
                    " in a distributed scene: its elements are spread over the ranks",
                {"MPI", "DISTRIBUTED"});
  }
}

template class SimulationManager<2>;
template class SimulationManager<3>;

}  // namespace demlab::sim
