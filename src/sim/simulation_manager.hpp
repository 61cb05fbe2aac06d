// SimulationManager<D> (thesis chapter 9): owns one Scene (time, the SimObjManager, walls,
// behaviors, materials) and the SimLoop, and implements the public Simulation interface.
// Every mutator checks its whole input before changing anything. The loop is rebuilt from the
// scene (only the modules it uses) and the pair constants mixed whenever the configuration
// changed since the last run.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <unordered_set>

#include "sim/module_table.hpp"
#include "sim/scene.hpp"
#include "sim/scene_io.hpp"
#include "sim/sim_loop.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim {

template <int D>
class OutputModule;
struct WatchdogHit;

template <int D>
class SimulationManager final : public Simulation {
 public:
  SimulationManager() = default;

  int dim() const override { return D; }

  void distribute() override;
  bool distributed() const override { return s_.dist != nullptr; }
  std::vector<ElementSnapshot> elementSnapshots() const override;
  ElementId ownedElement(ElementId original) const override;
  ElementId originalHandle(ElementId local) const override;
  // Returns the handle scripts know the element at dense index i by (owned or, in a
  // distributed scene, a ghost): its pool's handle, or the one it had at distribute().
  ElementId elementHandleAt(size_t i) const;
  DistributionReport distribution() const override;

  void setTimeStep(double dt) override;
  void setAutoTimeStep(double fraction, double stepsPerContact) override;
  using Simulation::setAutoTimeStep;
  double timeStep() const override;
  double criticalTimeStep() const override;
  double contactCriticalTimeStep() const override;
  double time() const override { return s_.time; }
  uint64_t stepCount() const override { return s_.steps; }

  void addMaterial(const std::string& name, const MaterialDef& def) override;
  void setMaterial(const std::string& name, const MaterialDef& def) override;
  MaterialDef material(const std::string& name) const override;
  std::vector<std::string> materialNames() const override { return s_.materialNames; }
  ElementMeshes elementMeshes() const override;
  std::vector<std::pair<std::string, std::string>> shapeTypes() const override {
    const ShapeTable<D>& t = ShapeTable<D>::get();
    std::vector<std::pair<std::string, std::string>> out;
    for (const std::string& n : t.names()) out.emplace_back(n, t.find(n)->parameters());
    return out;
  }
  std::vector<double> shapeParamsForBound(const std::string& shape,
                                          const std::vector<double>& params,
                                          double bound) const override {
    const ShapeTable<D>& t = ShapeTable<D>::get();
    // A packing asks for the same shape at every site: its Geometry (mass properties
    // integrated over a grid for overlapping clumps) is made once.
    if (!(boundShape_.shape == shape && boundShape_.params == params && boundShape_.type)) {
      const Geometry<D> g = t.makeGeometry(shape, params);
      boundShape_ = {shape, params, g.shape, g.boundRadius};
    }
    const BoundShape& g = boundShape_;
    const auto out = t.type(*g.type).scaled(params, bound / g.boundRadius);
    if (!out || g.boundRadius == 0) {
      throw Error("bad shape \"" + shape + "\": its size can't be drawn from a distribution",
                  {"VALUE", "SHAPE"});
    }
    t.type(*g.type).check(*out);  // still within the type's checks
    return *out;
  }
  void setContactLaw(LawKind law) override;
  LawKind contactLaw() const override { return s_.defaultLaw; }
  void setCoulombCriterion(physics::CoulombCriterion c) override;
  physics::CoulombCriterion coulombCriterion() const override { return s_.coulomb; }
  void setHertzDamping(physics::HertzDamping d) override;
  physics::HertzDamping hertzDamping() const override { return s_.hertzDamping; }
  void setPairLaw(const std::string& a, const std::string& b, LawKind law) override;
  LawKind pairLaw(const std::string& a, const std::string& b) const override;
  void setPairCoefficients(const std::string& a, const std::string& b,
                           const PairCoefficients& c) override;
  PairCoefficients pairCoefficients(const std::string& a, const std::string& b) const override;
  PairCoefficients pairOverrides(const std::string& a, const std::string& b) const override;

  ElementId addElement(const ElementDef& def) override;
  std::vector<ElementId> addElements(const std::vector<ElementDef>& defs) override;
  void reserveElements(size_t n) override;
  void removeElement(ElementId id) override;
  size_t removeElementList(const std::vector<ElementId>& ids) override;
  size_t removeElements(const std::string& tag) override;
  ElementState element(ElementId id) const override;
  ElementId findElement(const std::string& name) const override;
  void setElementPosition(ElementId id, const Vec3d& p) override;
  void setElementVelocity(ElementId id, const Vec3d& v) override;
  void setElementAngularVelocity(ElementId id, const Vec3d& w) override;
  void setElementOrientation(ElementId id, const std::vector<double>& o) override;
  void setElementBlocked(ElementId id, unsigned mask) override;
  void scaleElementRadii(const std::vector<ElementId>& ids, double factor) override;
  size_t elementCount() const override { return s_.elements.size(); }

  WallId addWall(const WallDef& def) override;
  void removeWall(WallId id) override;
  WallState wall(WallId id) const override;
  WallId findWall(const std::string& name) const override;
  std::vector<WallId> wallIds() const override;
  size_t wallCount() const override { return s_.walls.size(); }
  void setWallMotion(WallId id, const WallMotion& m) override;
  void setWallServo(WallId id, const WallServoDef& servo) override;

  void addSource(const SourceDef& def) override;
  void removeSource(const std::string& name) override;
  std::vector<BoundaryInfo> sources() const override;
  void addSink(const SinkDef& def) override;
  void removeSink(const std::string& name) override;
  std::vector<BoundaryInfo> sinks() const override;
  void setPeriodic(const PeriodicDef& def) override;
  PeriodicDef periodic() const override;

  void tagElement(ElementId id, const std::string& tag) override;
  void untagElement(ElementId id, const std::string& tag) override;
  std::vector<ElementId> elementsTagged(const std::string& tag) const override;
  std::vector<uint32_t> taggedIndices(const std::string& tag) const override;
  std::vector<std::string> elementNames() const override;
  std::vector<std::string> wallNames() const override;
  std::vector<std::string> tagNames() const override;
  void tagWall(WallId id, const std::string& tag) override;
  void untagWall(WallId id, const std::string& tag) override;
  std::vector<WallId> wallsTagged(const std::string& tag) const override;

  BehaviorId addGravity(const Vec3d& g) override;
  BehaviorId addLoad(const LoadDef& def) override;
  BehaviorId addBehavior(const std::string& type,
                         const std::vector<BehaviorParam>& params) override;
  void removeBehavior(BehaviorId id) override;
  std::vector<BehaviorInfo> behaviors() const override;

  void setOptions(const std::vector<OptionSetting>& settings) override;
  OptionValue option(std::string_view group, std::string_view name) const override;
  std::vector<std::string> listModules() const override;

  OutputId addOutput(const OutputDef& def) override;
  void removeOutput(OutputId id) override;
  std::vector<OutputInfo> outputs() const override;

  void addBondModel(const std::string& name, const std::string& type,
                    const std::vector<std::pair<std::string, double>>& values) override;
  std::vector<BondModelInfo> bondModels() const override;
  std::vector<uint32_t> addBonds(const std::vector<std::pair<ElementId, ElementId>>& pairs,
                                 const std::string& model) override;
  std::vector<uint32_t> addBondsWithin(const std::vector<ElementId>& among, double gap,
                                       const std::string& model) override;
  void removeBonds(const std::vector<uint32_t>& ids) override;
  std::vector<BondInfo> bonds() const override;
  std::optional<BondInfo> bond(uint32_t id) const override;
  BondCount bondCount() const override;
  std::vector<BondBreakInfo> bondBreaks() const override;

  RunReport run(const RunOptions& options) override;
  RunReport step() override;
  RelaxReport relax(double fraction, uint64_t maxIterations, const std::atomic<bool>* stop = nullptr,
                    double longPass = RunOptions{}.longStep) override;

  EnergyLedger energy() const override;
  size_t contactCount() const override { return s_.contacts.size(); }
  std::vector<ContactInfo> contacts() const override;
  MemoryReport memory() const override;
  std::array<Vec3d, 2> bounds() const override;
  std::vector<ElementId> elementIds() const override;
  std::vector<double> positions() const override;
  std::vector<double> velocities() const override;
  std::vector<double> angularVelocities() const override;
  std::vector<double> orientations() const override;
  std::vector<double> forces() const override;
  ElementTable elementTable() const override;
  std::vector<double> radii() const override;

  uint64_t stateDigest() const override;
  std::unique_ptr<Simulation> clone() const override;
  std::vector<std::string> save(std::ostream& out, bool skipCallbacks) const override;
  std::string saveBytes(bool skipCallbacks, std::vector<std::string>* skipped) const override;
  void load(std::istream& in) override;
  void loadBytes(std::string fileBytes) override;

  // For tests and the benchmark: the scene itself.
  const Scene<D>& scene() const { return s_; }

 private:
  // shapeParamsForBound's last shape: its name and parameters as given, its type and
  // bounding radius (type empty: none yet).
  struct BoundShape {
    std::string shape;
    std::vector<double> params;
    std::optional<TypeId> type;
    Real boundRadius = 0;
  };
  mutable BoundShape boundShape_;
  // Returns what queries see of bond b; broke is its break record (nullptr: none).
  BondInfo bondInfo(const Bond<D>& b, const BondBreak<D>* broke) const;
  // Returns the index of the material named name. Throws {LOOKUP MATERIAL}.
  uint32_t materialIndex(const std::string& name) const;
  // Checks a ElementDef; returns the converted values. Throws as addElement documents.
  struct CheckedElement {
    VecD<D> x, v;
    AngularD<D> w;
    Real r, invMass, invInertia;
    uint32_t material;
    uint8_t blocked;
    RotationD<D> q;
    Geometry<D> geometry;
  };
  // Returns the index of g in the scene's geometries, adding it if no equal one is there.
  uint32_t geometryIndex(const Geometry<D>& g);
  // same: a Geometry made from def's shape and parameters (the previous def's in a batch), or
  // null.
  CheckedElement checkElement(const ElementDef& def, const Geometry<D>* same = nullptr) const;
  // Throws {VALUE DOF} if mask has a degree of freedom this dimension lacks.
  void checkDofMask(unsigned mask) const;
  // Removes the blocked-list entries of the grains for which gone(id) is true.
  template <class Pred>
  void dropBlocked(Pred gone);
  Wall<D> checkWall(const WallDef& def) const;
  // Mixes the pair constants, picks dt and the skin, rebuilds the loop; called at each run
  // start, does its work only when the configuration changed. Throws VALUE TIMESTEP.
  void prepare();
  // The loop's modules: the module table's rows the scene wants (sim/module_table.hpp),
  // then the outputs.
  std::vector<std::unique_ptr<SimModule<D>>> makeModules(const SceneUse& u) const;
  // Throws {INTEGRATION NAN} naming the first grain whose position or velocity is not finite.
  void checkFinite() const;
  // Throws MPI DISTRIBUTED ("can't <what> in a distributed scene") when the scene is.
  void refuseIfDistributed(const char* what) const;
  // The elements' names and tags under the handles scripts hold: a distributed scene's are
  // its distribution's, alike on every rank (the rank's store then holds none), a serial
  // scene's its store's.
  NameLookup<ElementId>& elementNameTable();
  const NameLookup<ElementId>& elementNameTable() const;
  TagTable<ElementKind>& elementTagTable();
  const TagTable<ElementKind>& elementTagTable() const;
  // Throws LOOKUP HANDLE ("invalid element id") unless id names an element: in a distributed
  // scene the one a rank owns (collective: every rank answers alike). Changes nothing.
  void requireElement(ElementId id) const;
  // Returns the watchdog's finding hit as a trip: the elements, the likely cause and the fix.
  // In a distributed scene collective: every rank returns the description of the rank whose
  // element it is (hit.rank, or this one when it is -1).
  WatchdogTrip describeTrip(const WatchdogHit& hit, bool atStart) const;
  // Returns the check, the elements (by the handles scripts hold), the finding, the cause and
  // the fix of a hit on this rank's own elements.
  WatchdogTrip describeOwnTrip(const WatchdogHit& hit) const;
  // Returns the largest overlap / smaller radius over the contacts of the last force pass;
  // with push, first moves the grains of each contact overlapping by more than fraction x the
  // smaller radius apart, back to half of that (one relaxation pass), and returns the largest
  // found before moving. Sets *moved for each grain moved.
  double worstOverlap(double fraction, bool push, std::vector<bool>* moved = nullptr);
  // Returns the gravitational energy of the grains (0 without gravity).
  double potential() const;
  // Returns the ledger's balance sum now (state terms plus cumulated terms).
  double ledgerSum() const;
  // Returns the grain's kinetic plus gravitational energy (for rebasing the ledger on edits).
  double elementEnergy(uint32_t i) const;
  // Applies the changes the step's modules deferred (Scene::deferred): removes, then adds, then
  // makes the scene ready to step on (loop, step, forces of the changed scene). Returns true if
  // there were any. Throws as addElements does for a bad Def (the removals done stay done).
  bool applyDeferred();
  // Returns the index of the bond model named name. Throws {LOOKUP BONDMODEL}.
  uint32_t bondModelIndex(const std::string& name) const;
  // Makes the bonds of the checked pairs (dense indices) with model m; returns their ids.
  std::vector<uint32_t> makeBonds(const std::vector<std::pair<uint32_t, uint32_t>>& pairs,
                                  uint32_t m);
  // Marks the queued bonds broken, records each break and books its energy as released.
  // Returns true if any broke. Changes the scene (its forces are then stale).
  bool applyBondBreaks(const std::vector<PendingBreak>& breaks);
  // Drops the bonds of the elements whose slots are in slots (they are being removed).
  void dropBonds(const std::unordered_set<uint32_t>& slots);
  // Returns the smallest stable step the bonds allow (infinity without bonds). Polls the
  // process-wide Ctrl-C flag (throws {INTERRUPTED}); polled: the run's too (pollStep, may throw
  // StepAbandoned), as prepare() in a run may; never from queries.
  double bondCriticalStep(bool polled = false) const;
  // What the automatic step is made of besides the contacts' and the motion's bounds, from
  // the materials and the smallest grains (staticCriticalStep's pass).
  struct StepSurvey {
    double critical = std::numeric_limits<double>::infinity();  // the static estimate
    // The shortest contact of a linear pair (the same at any speed), and of a Hertz pair at
    // an approach speed of 1 m/s (it scales as v^(-1/5)): physics::contactDuration.
    double linearDuration = std::numeric_limits<double>::infinity();
    double hertzDuration = std::numeric_limits<double>::infinity();
  };
  // Returns the static part of criticalTimeStep(): materials, grain sizes, bonds (polled: as
  // bondCriticalStep); fills survey when given.
  // acrossRanks (a distributed scene; collective): the smallest grains of every rank's part.
  double staticCriticalStep(bool polled = false, StepSurvey* survey = nullptr,
                            bool acrossRanks = false) const;
  // Returns timeStep() given the survey (unused for a fixed step). Throws as timeStep.
  double timeStepFrom(const StepSurvey& survey) const;
  // Returns the automatic step: autoFraction x the least of the static estimate and 2.5 x the
  // contacts' step, and at most the linear contacts' duration over stepsPerContact and the
  // motion bound motionStep (Scene::motionStep in a run).
  double autoStep(const StepSurvey& survey, double motionStep) const;
  // Returns the motion bound at speed (m/s): the fastest element moves at most kMoveShare of
  // stepLimit (the watchdog's) a step, and a Hertz contact of the survey at the approach speed
  // 2 x speed lasts stepsPerContact steps; +inf at speed 0 or a non-finite speed. Changes
  // nothing.
  double motionBound(double speed, const StepSurvey& survey, double stepLimit) const;
  // Returns true if the motion bound is taken again: at a contacts' measure, or when the
  // fastest element (speed) has outrun the speed the bound was made for and moves more than
  // kMoveShare of stepLimit in a step of dt. Changes nothing.
  bool retakesMotion(bool measure, double speed, double dt, double stepLimit) const;
  // The share of the watchdog's step limit (SPEED) the fastest element may move in a step:
  // the bound is taken for kSpeedHeadroom times the fastest speed (so an accelerating element
  // does not change the step every step), and between the contacts' measures again only when
  // the element moves more than this share.
  static constexpr double kMoveShare = 0.5;
  static constexpr double kSpeedHeadroom = 1.25;
  // How often (steps) a run with the automatic step measures the contacts' stiffness again:
  // one measure costs about a step (bench_sim --contact-step), so about 1 % of a run, and
  // in 100 steps a loaded bed stiffens little against the factor of 2 the step keeps.
  static constexpr uint64_t kContactStepEvery = 100;
  // Returns true at the scene's step counts 1, 2, 4, ..., 64, where a run with the automatic
  // step measures the contacts too and takes their step if the step in force is beyond it, and
  // takes the motion bound again if an element is faster than it was made for: the first
  // contacts of a new scene (a level-set disc falling onto nine nodes, a multi-point contact the
  // static estimate cannot foresee) then set the step within a few steps of touching, not after
  // a hundred, and a stable run's step does not change within a contact.
  static bool checksContactsEarly(uint64_t steps) {
    return steps > 0 && steps < kContactStepEvery && (steps & (steps - 1)) == 0;
  }
  // A run with long steps keeps a copy of the scene to go back to (RunOptions::longStep),
  // taken again once the run has spent kCopyEvery times the last copy's time since: copies
  // cost at most 4 % of the run, and a stop drops at most that many copies' time of steps.
  // The copy's arrays stay between runs, so a later copy allocates nothing (a first copy of a
  // scene of hundreds of megabytes faults in its pages: twenty times slower).
  static constexpr double kCopyEvery = 25;
  // How often the ranks of a distributed run agree on Ctrl-C (steps): a reduction each time.
  static constexpr uint64_t kStopEvery = 64;
  std::optional<Scene<D>> rollback_;
  double rollbackSeconds_ = 0;
  double lastStepSeconds_ = 0;  // the last step's wall time: a run after long ones copies first
  // Returns true if a copy of the scene fits beside it: the scene's bytes at most half the
  // memory the system has free (else a long step answers Ctrl-C at its end). Changes nothing.
  bool rollbackFits() const;
  // Copies the scene into rollback_ (what a long step or relax pass goes back to), with the
  // scene's abandonOn cleared first (the copy must not carry it): the first time by the
  // serializing copy, which polls stop, after that by assignment into the last copy's arrays.
  // Returns false, keeping no copy, if stop ended the first copy. Sets rollbackSeconds_.
  bool refreshRollback(const std::atomic<bool>* stop);
  // staticCriticalStep()'s survey as the last configuration (prepare) found it, and the
  // watchdog's step limit then (radii and skin change only with the configuration).
  StepSurvey survey_;
  double stepLimit_ = std::numeric_limits<double>::infinity();
  // Removes the live grains ids (distinct), their springs, histories and blocked entries, the
  // ledger rebased. Changes the scene and marks the configuration changed.
  void removeElementSet(const std::vector<ElementId>& ids);
  // Parks the springs and drops the candidate pairs and contact records, which hold dense
  // indices: call before grains or walls are removed (the dense order changes).
  void forgetCandidates();
  // Lists the element or wall among those edits placed since the last step (Scene::
  // placedElements); nothing before the first step, when every contact counts as placed.
  void markPlaced(ElementId id) {
    if (s_.steps > 0) s_.placedElements.push_back(id);
  }
  // What editElement did: the energy the change moved (the element's kinetic and potential
  // energy after it less before; in a distributed scene, the owning rank's) and, distributed,
  // the element's global id.
  struct ElementEdit {
    double energy = 0;
    uint64_t globalId = 0;
  };
  // Runs change(i) on element id's dense index i: in a serial scene here, in a distributed one
  // on the rank owning the element scripts know as id, every rank then getting the same result
  // and the change's error (or LOOKUP HANDLE when no rank owns it) raised on every rank, having
  // changed nothing. change must check before it changes. Collective when distributed
  // (sim/simulation_distribute.cpp). The caller moves the ledger's reference and sets flags.
  ElementEdit editElement(ElementId id, const std::function<void(uint32_t)>& change);
  // Marks an edited element placed (markPlaced; distributed, by its global id on every rank).
  void markPlacedEdit(ElementId id, const ElementEdit& e);
  // A distributed scene's choices for the whole scene, taken again from every rank's part
  // before a run whose configuration changed (an edit of materials, say): what it uses
  // (sceneUseWith of every rank's ElementUse ORed) and its static step survey
  // (staticCriticalStep's smallest grains over the ranks). Collective. Changes s_.dist.
  void decideWhole();
  // addElement in a distributed scene (collective): the handle the serial scene would give,
  // the element put among its own elements by the rank whose box holds it (the next step
  // searches, as the serial scene's does), the ledger's reference moved on every rank.
  ElementId addElementOnRanks(const ElementDef& def);
  // removeElementList in a distributed scene (collective): every id checked to be owned by a
  // rank (LOOKUP HANDLE on every rank, nothing removed, when one is not), each removed by its
  // owner (removeOwned: the next step searches, as the serial scene's does), the ledger's
  // reference moved by their energies on every rank in the order given, their handles given
  // back to the pool's model. Returns ids.size() (ids hold no repeats).
  size_t removeElementsOnRanks(const std::vector<ElementId>& ids);
  void markPlaced(WallId id) {
    if (s_.steps > 0) s_.placedWalls.push_back(id);
  }
  // Marks the configuration changed: the next run mixes, chooses and rebuilds again.
  // Throws {VALUE CELL} when a periodic length is at most twice the largest pair reach (two
  // bounding radii and the skin given), {UNSUPPORTED PERIODIC} for what periodic scenes lack (bonds,
  // shape elements, the touch correction). Changes nothing.
  void checkPeriodic(double skin) const;
  // Returns the Verlet skin the next run uses: the option, or a fifth of the mean radius.
  double skinInUse() const;
  void touchConfig() {
    configDirty_ = true;
    s_.forcesReady = false;
  }
  std::string serialize(IoMode mode, const BehaviorManager<D>* behaviors = nullptr) const;
  // Returns a deep copy of the scene, as clone() and a run's undo need it. Changes nothing.
  Scene<D> copyScene() const;
  // Returns on rank 0 the whole of a distributed scene as a serial run holds it (its elements
  // under their original handles, springs parked by slot, the ledger and wall sums), on the
  // other ranks an empty scene; a serial scene's copy. Collective (sim/simulation_gather.cpp).
  Scene<D> gatheredScene() const;
  // Returns copyScene() with Ctrl-C polled through `stop` as it copies, or nothing when that
  // stopped it. Throws copyScene's other errors; changes nothing.
  std::optional<Scene<D>> copySceneUnlessStopped(const std::atomic<bool>* stop) const;

  // The output modules: none when there are no outputs (sim/simulation_outputs.cpp).
  std::vector<std::unique_ptr<SimModule<D>>> outputModules() const;

  // Outputs are the object's, not the scene's: outside s_, so never digested, cloned or saved.
  struct Output {
    OutputId id;
    OutputDef def;
  };
  friend class OutputModule<D>;

  Scene<D> s_;
  SimLoop<D> loop_;
  HandlePool<OutputKind> outputPool_{"output"};
  // Returns true if an output that reads contacts may be due at the end of the next step.
  bool outputsReadNextStep() const;
  std::vector<Output> outputs_;         // creation order, the order they fire in
  mutable bool firingOutputs_ = false;  // set while the callbacks run
  bool configDirty_ = true;
};

}  // namespace demlab::sim
