// Scene<D>: everything one simulation holds, as the modules see it. The SimulationManager owns
// one Scene and the SimLoop; modules read and write the Scene's arrays directly (they are the
// stages of one step, not independent objects), so no data crosses a virtual call.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "core/instance_interaction.hpp"
#include "core/math.hpp"
#include "physics/contact.hpp"
#include "physics/material.hpp"
#include "physics/pair_params.hpp"
#include "search/box.hpp"
#include "sim/shape_springs.hpp"
#include "sim/behavior.hpp"
#include "sim/bond.hpp"
#include "sim/boundaries.hpp"
#include "sim/contact_groups.hpp"
#include "sim/obj_manager.hpp"
#include "sim/options.hpp"
#include "sim/pair_springs.hpp"
#include "sim/periodic.hpp"
#include "sim/shape.hpp"
#include "sim/wall.hpp"

namespace demlab::sim {

enum class IntegratorKind : uint8_t { Synchronized, Verlet };

// The cumulated terms of the energy ledger; the state terms (kinetic, gravitational, elastic)
// are computed from the state when asked.
struct LedgerSums {
  double dampingLoss = 0, frictionLoss = 0, wallWork = 0, behaviorWork = 0;
  double springWork = 0;        // energy given to Hertz-Mindlin springs by their stiffening
  double bondReleased = 0;      // elastic energy bonds held when they broke
  double elastic = 0;           // elastic energy in the contacts after the last step
  bool started = false;         // reference taken
  double reference = 0;         // the balance sum when the ledger started (rebased on edits)
  double gravityReference = 0;  // the gravitational energy then (for the scale)
  double scale = 0;             // largest energy magnitude seen (for the relative residual)

  // Returns the balance sum for the state terms given: kinetic + potential + elastic + losses
  // - work done on the grains (simulation.hpp, EnergyLedger). The one formula of the ledger:
  // the ledger's reference, its report and the watchdog's check all call it.
  double balanceSum(double kinetic, double potential) const {
    return kinetic + potential + elastic + dampingLoss + frictionLoss + bondReleased - wallWork -
           behaviorWork - springWork;
  }
  // Returns the energy scale the residual is relative to: the largest of the magnitudes seen and
  // those of the terms now (the reference's only when withReference).
  double scaleWith(double kinetic, double potential, bool withReference) const {
    return std::max({scale, kinetic, std::abs(potential - gravityReference), elastic,
                     dampingLoss + frictionLoss + bondReleased, std::abs(wallWork),
                     std::abs(behaviorWork),
                     withReference ? std::abs(reference) : 0.0});
  }
};

// One grain-grain candidate pair (dense indices) from the last neighbor search.
struct CandidatePair {
  uint32_t i, j;
};

// One contact of the last step (for queries, the watchdog and checkpoints). The wall flag
// shares b's word: 32 bytes a record in 3D instead of 40 with a bool and its padding, which is
// 20 bytes a grain of a dense bed's memory (2.4 contacts a grain with the walls').
template <int D>
struct ContactRecord {
  uint32_t a;       // grain dense index
  uint32_t b : 31;  // grain or wall dense index (< HandlePool::kMaxSlots = 2^31 - 1)
  uint32_t wall : 1;
  VecD<D> force;  // on b
};
static_assert(sizeof(ContactRecord<3>) == 32);

// The contact whose overlap is the largest fraction of its smaller radius (a wall's: of the
// grain's), as the watchdog measures it (recordOverlapRatio); ratio -1 when none is known. Its
// record names the pair; the force is not kept (zero: the SIMD kernel finds the deepest contact
// before its force).
template <int D>
struct DeepestContact {
  Real ratio = -1;
  ContactRecord<D> record{0, 0, 0, VecD<D>::Zero()};
  // Keeps c if its ratio is larger than the one kept (ties keep the earlier). Changes *this.
  void consider(Real r, const ContactRecord<D>& c) {
    if (r > ratio) {
      ratio = r;
      record = c;
      record.force.setZero();
    }
  }
};

// Appends r to records. A full array grows by an eighth, not by doubling: the detection module
// sizes it for about the contacts of the last recorded step, and a doubled copy would hold up to
// twice the records' memory for the rest of the skin's life. Changes records.
template <int D>
inline void appendRecord(std::vector<ContactRecord<D>>& records, const ContactRecord<D>& r) {
  if (records.size() == records.capacity())
    records.reserve(records.size() + records.size() / 8 + 16);
  records.push_back(r);
}

// The coefficients one pair of materials has of its own (Simulation::setPairCoefficients):
// few pairs have any, so a list; a < b or a == b.
struct PairOverride {
  uint32_t a, b;
  PairCoefficients c;
};

// Changes to the set of elements asked for during a step (by a source, a sink, a breaking
// bond: Box2D's deferred creation and destruction). The modules only append here; the manager
// applies them at the end of the step (SimulationManager::applyDeferred), when no pass holds a
// dense index, and the loop goes on from the changed scene.
struct DeferredChanges {
  std::vector<ElementDef> create;  // checked when applied, all or none
  std::vector<ElementId> destroy;  // a handle already gone is skipped
  std::vector<PendingBreak> breakBonds;  // bonds whose strength the step exceeded (sim/bond.hpp)
  bool empty() const { return create.empty() && destroy.empty() && breakBonds.empty(); }
};

// A source's state (sim/source.hpp): its checked Def and what it has done. Its generator's
// state and the radius it has drawn but not yet placed are part of the scene, so a run resumed
// from a checkpoint inserts the same elements as one that never stopped.
struct SourceState {
  SourceDef def;
  uint32_t material = 0;
  double start = 0;          // the scene time it was added at
  uint64_t count = 0;        // inserted so far
  double mass = 0;           // kg inserted so far
  uint64_t rng = 0;          // SplitMix64 state
  double pendingRadius = 0;  // drawn, not yet placed (0: none)
};

// A sink's state (sim/sink.hpp).
struct SinkState {
  SinkDef def;
  double start = 0;
  uint64_t count = 0;
  double mass = 0;
};

// An element with blocked degrees of freedom (sim/constraints.hpp). Few elements are: a list
// beside the hot arrays, so a scene without any pays nothing, not a byte per element.
struct BlockedElement {
  ElementId id;
  uint8_t dofs;  // dof:: mask, never 0 (an element with none blocked leaves the list)
};

// A blocked element a rank owns: its dense index, mask and global id, and its place in
// Scene::blocked (Scene::ownedBlocked).
struct OwnedBlockedElement {
  uint32_t i;
  uint8_t dofs;
  uint64_t globalId;
  size_t listed;  // its place in Scene::blocked
};


// Returns the Geometry list a new scene starts with: the ball's, at index 0.
template <int D>
std::vector<Shareable<Geometry<D>>> ballGeometryOnly() {
  return {Shareable<Geometry<D>>::make(ShapeTable<D>::get().makeGeometry(
      ShapeTable<D>::get().type(ShapeTable<D>::ball()).name(), {}))};
}

template <int D>
struct Distribution;

template <int D>
struct Scene {
  // ---- objects ----
  SimObjManager<D> elements;
  // A distributed run (sim/distribution.hpp; null in a serial scene): the elements' arrays end
  // with `ghosts` copies of other ranks' elements, which have no handles. Whatever moves,
  // forces, measures or writes elements runs over [0, ownedCount()).
  std::shared_ptr<Distribution<D>> dist;
  size_t ghosts = 0;
  size_t ownedCount() const { return elements.a.size() - ghosts; }
  // Returns the dense index of the element a script knows by handle h among this rank's own,
  // or kNpos when another rank owns it or none does: set by distribution (its handles are the
  // serial scene's, not the rank's pool's; ownedIndexOf, sim/distribution.hpp), null in a
  // serial scene, where the pool answers.
  uint32_t (*ownedIndexOfHandle)(const Scene& s, ElementId h) = nullptr;
  // Likewise the blocked elements (`blocked`, which holds the scripts' handles) this rank owns,
  // in the list's order: set by distribution (ownedBlockedOf), null in a serial scene.
  const std::vector<OwnedBlockedElement>& (*ownedBlocked)(const Scene& s) = nullptr;
  // Likewise the members of a tag (kept under the scripts' handles) this rank owns, as dense
  // indices in the tag's order: set by distribution (ownedTaggedOf), null in a serial scene.
  const std::vector<uint32_t>& (*ownedTagged)(const Scene& s, std::string_view tag) = nullptr;
  WallSet<D> walls;
  BehaviorManager<D> behaviors;
  std::vector<BlockedElement> blocked;  // in the order they were blocked
  DeferredChanges deferred;             // empty at every step boundary
  BondSet<D> bonds;                     // sim/bond.hpp
  std::vector<SourceState> sources;     // in creation order (sim/source.hpp)
  std::vector<SinkState> sinks;         // in creation order (sim/sink.hpp)
  // Elements and walls that edits placed (added, moved, grown, turned) since the scene's last
  // step, when it has had one: the next run's first check holds their contacts to the
  // watchdog's `placed` limit, since such an overlap is the user's doing, not the run's. Before
  // the first step every contact is held to it, so nothing is listed. Emptied by every run.
  std::vector<ElementId> placedElements;
  std::vector<WallId> placedWalls;
  // Periodic and Lees-Edwards boundaries (sim/periodic.hpp); none by default.
  PeriodicBox<D> periodic;

  // ---- element shapes (sim/shape.hpp) ----
  // The shared Geometry components; ElementArrays::geometry indexes them. [0] is the ball's.
  std::vector<Shareable<Geometry<D>>> geometries = ballGeometryOnly<D>();
  // Cold bookkeeping beside it: the index of each geometry past the ball's by its shape type and
  // parameters, so that adding elements of many distinct shapes (a packing drawn from shape
  // distributions) finds or adds each in O(log G). Rebuilt by indexGeometries after a load.
  std::map<std::pair<uint32_t, std::vector<double>>, uint32_t> geometryLookup;
  void indexGeometries() {
    geometryLookup.clear();
    for (size_t k = 1; k < geometries.size(); ++k) {
      geometryLookup.emplace(std::make_pair(geometries[k]->shape.value, geometries[k]->params),
                             static_cast<uint32_t>(k));
    }
  }
  // Some element is not a ball (set when the loop is built): the search then hands the pairs
  // with such an element to the shape contact pass instead of the ball passes.
  bool anyShapes = false;
  std::vector<CandidatePair> shapeCandidates;                    // element-element
  std::vector<std::pair<uint32_t, uint32_t>> shapeWallCandidates;  // (element, wall) dense
  ShapeSpringStore<D> shapeSprings;  // sim/shape_springs.hpp

  // ---- materials and laws ----
  std::vector<std::string> materialNames;
  std::vector<physics::MaterialDef> materials;
  physics::LawKind defaultLaw = physics::LawKind::HertzMindlin;
  // Per material pair law overrides, row-major nMat x nMat (symmetric); -1: default.
  std::vector<int8_t> pairLawOverride;
  std::vector<PairOverride> pairOverrides;
  // What the Coulomb limit caps, for every pair (physics/tangential.hpp).
  physics::CoulombCriterion coulomb = physics::CoulombCriterion::Total;
  // How Hertz-Mindlin's e becomes its dampers (physics/pair_params.hpp).
  physics::HertzDamping hertzDamping = physics::HertzDamping::Calibrated;
  // Mixed once per run start (SimulationManager::prepare): row-major nMat x nMat.
  std::vector<physics::PairParams> pairParams;
  std::vector<physics::ContactLawFn<D>> pairLawFn;
  bool anyFriction = false;

  // ---- options ----
  double dt = 0;              // fixed step (when autoFraction == 0)
  double autoFraction = 0.2;  // > 0: dt = autoFraction x critical step
  IntegratorKind integrator = IntegratorKind::Synchronized;
  bool rotationEnabled = true;
  // The sub-step treatment of contact onset and release (sim/touch.hpp): it makes impacts
  // second order in dt under both integrators; on by default.
  bool touchCorrection = true;
  double cellFactor = 0;
  double skinOption = -1;
  bool wideMargins = true;  // DetectionModule::chooseMargins may widen fast grains' margins
  WatchdogOptions watchdog;  // sim/watchdog.hpp

  // ---- time ----
  double time = 0;
  uint64_t steps = 0;
  double stepDt = 0;  // the step in use during a run (set by prepare)
  // The critical step of the ball contacts at their overlaps of the last neighbour search
  // (sim/contact_stiffness.hpp; +inf before one, or with none touching): the automatic step
  // is autoFraction x the least of it and the static estimate. Saved with the scene, so a
  // loaded run goes on with the step it had.
  double contactStep = std::numeric_limits<double>::infinity();
  // The automatic step's bound from motion (SimulationManager::motionBound): at the speed
  // motionSpeed the fastest element moves at most a share of the watchdog's step limit a
  // step, and a contact at twice that approach speed lasts stepsPerContact steps. Taken with
  // the contacts' step and whenever the fastest speed passes motionSpeed; saved with the scene
  // (with stepsPerContact, when any differs from its default).
  double stepsPerContact = kDefaultStepsPerContact;
  double motionStep = std::numeric_limits<double>::infinity();
  double motionSpeed = 0;
  // The largest squared element speed, as the watchdog's pass of the last step found it.
  double fastestSpeed2 = 0;

  // ---- contact detection state ----
  std::vector<CandidatePair> candidates;              // grain-grain
  ContactGroups contactGroups;  // the candidates' groups and phases (contact_groups.hpp)
  std::vector<std::vector<uint32_t>> wallCandidates;  // per wall (dense): grain dense indices
  std::vector<VecD<D>> xAtBuild;                      // grain positions at the last search
  double skin = 0;                                    // the skin in use
  // Per grain (dense, as xAtBuild) when some grain's margin at the last search exceeded half
  // the skin (DetectionModule::chooseMargins): (half skin / its margin)^2, so that maxDisp2,
  // the largest weighted squared displacement, compares with half the skin as before. Empty:
  // every margin is half the skin.
  std::vector<Real> marginWeight;
  double maxDisp2 = 0;  // largest (weighted) squared displacement since the build
  bool needRebuild = true;
  // The forces in f and t are those of the current state (velocity Verlet's first half kick
  // needs them); edits of the scene clear it and the next run computes them first.
  bool forcesReady = false;
  uint64_t rebuilds = 0;
  // With the touch correction on: per grain-grain candidate, what the contact pass found
  // (kTouching: within reach; kCutOff: touching with the law's normal force clamped to zero),
  // this step's and the last step's. The touch module compares the two to find the step's
  // events (sim/touch.hpp). Valid only while the candidates are the ones they were written for:
  // a search, a load without them, or an edit of the candidates clears touchNowValid.
  std::vector<uint8_t> touchNow, touchPrev;
  bool touchNowValid = false;
  bool touchPrevValid = false;  // set by the contact pass: touchPrev describes the candidates
  // The same for each wall's candidates (wallCandidates), written by the wall contact pass.
  std::vector<std::vector<uint8_t>> wallTouchNow, wallTouchPrev;
  bool wallTouchNowValid = false;
  bool wallTouchPrevValid = false;
  // Return true if touchNow (wallTouchNow) holds a state for each current grain-grain (wall)
  // candidate. Change nothing.
  bool touchNowCurrent() const { return touchNowValid && touchNow.size() == candidates.size(); }
  bool wallTouchNowCurrent() const {
    if (!wallTouchNowValid || wallTouchNow.size() != walls.size()) return false;
    for (size_t w = 0; w < walls.size(); ++w) {
      const size_t n = w < wallCandidates.size() ? wallCandidates[w].size() : 0;
      if (wallTouchNow[w].size() != n) return false;
    }
    return true;
  }

  // ---- pair state (sim/history_store.hpp) ----
  PairSprings<D> pairSprings;                                           // per contact
  std::vector<std::vector<physics::TangentialHistory<D>>> wallSprings;  // per wall candidate
  InstanceInteractionManager<physics::TangentialHistory<D>> histories;  // parked springs
  bool keepHistory = false;  // anyFriction, fixed at prepare

  // ---- per-step outputs ----
  std::vector<ContactRecord<D>> contacts;
  // Whether the contact passes record this step's contacts in `contacts`. SimulationManager::run
  // clears it for the steps nothing can look at (no outputs, progress or stop callbacks: every
  // step but the last), so the records after a run are the same either way.
  bool recordContacts = true;
  // Whether, with recordContacts off, the contact passes keep only the contact that overlaps
  // most (the watchdog's overlap check, the one reader of every step's contacts by default):
  // each group of a pass keeps its own, and they are compared in record order after it.
  bool trackDeepest = false;
  DeepestContact<D> deepest;
  size_t lastRecorded = 0;  // the records of the last step that recorded any
  bool rotating = false;    // the rotation modules run
  LedgerSums ledger;
  // The run's stop flag while a step may be abandoned part way (pollStep in sim_loop.hpp), else
  // null: set by SimulationManager::run only while it holds a copy of the scene at an earlier
  // step boundary to go back to. Read directly, not through the process-wide interrupt flag,
  // which a run points at nothing so that its outputs finish. Never saved.
  const std::atomic<bool>* abandonOn = nullptr;

  // ---- the law's sub-model choices (`law model`; sim/law_models.hpp names the values) ----
  uint8_t tangentialModel = 0;  // history, none
  uint8_t rollingModel = 2;     // on, off, auto (auto: when a coefficient is non-zero)
  uint8_t curvatureModel = 0;   // equivalent, local: the Hertz radius of shape pairs
  uint8_t cohesionModel = 2;    // on, off, auto

  size_t nMat() const { return materials.size(); }

  // Returns the two materials m and k as the pair's mixing should see them: copies with the
  // pair's own coefficients (pairOverrides) put in both, so that every mixing rule (geometric
  // mean, minimum) gives the pair's value. Changes nothing.
  std::pair<physics::MaterialDef, physics::MaterialDef> pairMaterials(size_t m, size_t k) const {
    std::pair<physics::MaterialDef, physics::MaterialDef> out{materials[m], materials[k]};
    const size_t lo = std::min(m, k), hi = std::max(m, k);
    for (const PairOverride& o : pairOverrides) {
      if (o.a != lo || o.b != hi) continue;
      for (physics::MaterialDef* d : {&out.first, &out.second}) {
        if (!std::isnan(o.c.restitution)) d->restitution = o.c.restitution;
        if (!std::isnan(o.c.friction)) d->friction = o.c.friction;
        if (!std::isnan(o.c.rolling)) d->rollingFriction = o.c.rolling;
        if (!std::isnan(o.c.cohesion)) d->cohesion = o.c.cohesion;
        // Each side's modulus such that the pair's mixing (physics/pair_params.cpp) gives E*.
        if (!std::isnan(o.c.young)) d->young = 2 * o.c.young * (1 - d->poisson * d->poisson);
      }
    }
    return out;
  }
};

// Returns where element j (dense) is seen from element i: its position, or in a periodic
// scene its nearest image's (sim/periodic.hpp). Changes nothing.
template <int D>
[[gnu::always_inline]] inline VecD<D> partnerPosition(const Scene<D>& s, uint32_t i, uint32_t j) {
  const ElementArrays<D>& a = s.elements.a;
  if (!s.periodic.any()) return a.x[j];
  return a.x[i] + s.periodic.nearest(a.x[j] - a.x[i]);
}

// Returns the id used for a wall in pair-history keys: walls live in the top half of the id
// space so they never collide with grain slot indices.
inline uint32_t wallPairId(uint32_t wallSlot) {
  return 0x80000000u | wallSlot;
}

// Returns the key of a wall as a pair's partner where partners are global element ids
// (SpringTransfer, sim/history_store.hpp): above every id an element can have, below 2^56.
inline uint64_t wallPartner(uint32_t wallSlot) {
  return kMaxGlobalId + 1 + wallSlot;
}

}  // namespace demlab::sim
