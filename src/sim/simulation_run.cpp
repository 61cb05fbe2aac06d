// SimulationManager<D>: building the loop from the scene, running it, the energy ledger,
// queries, and whole-scene operations (digest, clone, save, load).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <istream>
#include <iterator>
#include <optional>
#include <ostream>
#include <string_view>
#include <tuple>
#include <unordered_set>
#include <utility>
#include <vector>

#include <unistd.h>

#include "core/free_aside.hpp"
#include "core/interrupt.hpp"
#include "mpi/error_bytes.hpp"
#include "physics/critical_step.hpp"
#include "physics/narrow_phase.hpp"
#include "sim/behavior_modules.hpp"
#include "sim/contact_stiffness.hpp"
#include "sim/contacts.hpp"
#include "sim/convert.hpp"
#include "sim/detection.hpp"
#include "sim/distribution.hpp"
#include "sim/integrator.hpp"
#include "sim/law_models.hpp"
#include "sim/module_table.hpp"
#include "sim/rigid_body.hpp"
#include "sim/shape_contacts.hpp"
#include "sim/simulation_manager.hpp"
#include "sim/touch.hpp"
#include "sim/watchdog.hpp"

namespace demlab::sim {

// ---- the loop ------------------------------------------------------------------------------

template <int D>
std::vector<std::unique_ptr<SimModule<D>>> SimulationManager<D>::makeModules(
    const SceneUse& u) const {
  ModuleList<D> m = buildModules(s_, u);
  for (auto& o : outputModules()) m.push_back(std::move(o));
  return m;
}

template <int D>
std::vector<std::string> SimulationManager<D>::listModules() const {
  SimLoop<D> loop;
  loop.setModules(makeModules(sceneUse(s_)));
  return loop.names();
}

template <int D>
void SimulationManager<D>::prepare() {
  if (configDirty_) {
    if (s_.dist) decideWhole();
    const SceneUse f = sceneUse(s_);
    if (f.shapes) checkShapeRoutines(s_);
    // A distributed scene's ranks hold parts of it: its skin and static step survey were
    // taken from the whole when it was distributed.
    const double skin = s_.dist ? s_.dist->skin : skinInUse();
    if (s_.periodic.any()) checkPeriodic(skin);
    // The static estimate is a pass over the elements: taken once for both.
    StepSurvey survey;
    if (s_.dist) {
      survey = {s_.dist->critical, s_.dist->linearDuration, s_.dist->hertzDuration};
    } else {
      staticCriticalStep(true, &survey);  // may throw StepAbandoned, changing nothing
    }
    const double dt = timeStepFrom(survey);
    survey_ = survey;
    const size_t nm = s_.nMat();
    s_.pairParams.resize(nm * nm);
    s_.pairLawFn.resize(nm * nm);
    for (size_t m = 0; m < nm; ++m) {
      for (size_t k = 0; k < nm; ++k) {
        const int8_t o = s_.pairLawOverride[m * nm + k];
        const LawKind law = o < 0 ? s_.defaultLaw : static_cast<LawKind>(o);
        const auto [ma, mk] = modelMaterials(s_, m, k);
        s_.pairParams[m * nm + k] = physics::mixPair(law, ma, mk, s_.hertzDamping);
        s_.pairParams[m * nm + k].coulomb = s_.coulomb;
        s_.pairLawFn[m * nm + k] = physics::contactLawFor<D>(law);
      }
    }
    s_.anyFriction = f.anyFriction;
    if (f.anyFriction != s_.keepHistory) {
      // Springs appear or go: the next search sizes (or drops) the per-candidate arrays.
      s_.histories.clear();
      s_.pairSprings.clear();
      s_.wallSprings.clear();
      s_.needRebuild = true;
    }
    s_.keepHistory = f.anyFriction;
    if (f.shapes != s_.anyShapes) {
      s_.anyShapes = f.shapes;
      s_.needRebuild = true;
    }
    if (f.rotating && !s_.rotating) {
      // Torques were not accumulated while rotation was off: start from none.
      for (auto& t : s_.elements.a.t) t = ElementArrays<D>::zeroAngular();
      for (auto& t : s_.elements.a.tPrev) t = ElementArrays<D>::zeroAngular();
    }
    s_.rotating = f.rotating;
    s_.stepDt = dt;
    if (skin != s_.skin) {
      s_.skin = skin;
      s_.needRebuild = true;
    }
    stepLimit_ = s_.dist ? s_.dist->stepLimit : watchdogStepLimit(s_);
    loop_.setModules(makeModules(f));
    configDirty_ = false;
  }
  if (!s_.forcesReady) {
    // The forces at the current time, with a zero step: springs take no increment, nothing
    // is dissipated, walls and loads are evaluated now. Energy the edits put into contact
    // springs (a grain placed overlapping) is the user's, not the run's: the ledger rebases.
    const double before = ledgerSum();
    const double dt = s_.stepDt;
    s_.stepDt = 0;
    ElementArrays<D>& a = s_.elements.a;
    for (auto& f : a.f) f.setZero();
    for (auto& t : a.t) t = ElementArrays<D>::zeroAngular();
    s_.contacts.clear();
    s_.ledger.elastic = 0;
    loop_.forcesOnly(s_);
    s_.stepDt = dt;
    s_.forcesReady = true;
    if (s_.ledger.started) s_.ledger.reference += ledgerSum() - before;
  }
  if (!s_.ledger.started) {
    s_.ledger.reference = ledgerSum();
    const double u = potential();
    s_.ledger.gravityReference = s_.dist && !s_.dist->initial ? s_.dist->comm->sum(u) : u;
    s_.ledger.started = true;
  }
}

template <int D>
double SimulationManager<D>::skinInUse() const {
  if (s_.skinOption >= 0) return s_.skinOption;
  // Summed in sorted order: the value must not depend on the dense order, which spatial
  // reordering changes; a one-ulp change here would force an extra search after a load and
  // break bit-identical continuation from a checkpoint.
  std::vector<Real> radii = s_.elements.a.r;
  std::sort(radii.begin(), radii.end());
  double sum = 0;
  for (Real r : radii) sum += r;
  return radii.empty() ? 0 : 0.2 * sum / static_cast<double>(radii.size());
}

template <int D>
void SimulationManager<D>::checkFinite() const {
  const ElementArrays<D>& a = s_.elements.a;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!a.x[i].allFinite() || !a.v[i].allFinite()) {
      throw Error("grain " + toString(s_.elements.pool().handleAt(static_cast<uint32_t>(i))) +
                      " has a non-finite state at step " + std::to_string(s_.steps) +
                      ": the time step is too large for the contacts",
                  {"INTEGRATION", "NAN"});
    }
  }
}

namespace {

// Clears a scene's abandonOn when the scope ends, however it ends: outside a run or a relax
// nothing may abandon the scene's work.
struct AbandonOff {
  const std::atomic<bool>*& flag;
  ~AbandonOff() { flag = nullptr; }
};

// Puts the scene `copy` holds in place of s and empties copy. The replaced scene's arrays of
// candidates and contacts are freed aside: a step stopped part way in a large scene holds
// hundreds of megabytes of them, whose return to the system would delay the stop by tenths of
// a second. The rest is freed here: it may hold Tcl callbacks (scripted behaviors and wall
// motions), which belong to the interpreter's thread. Changes s and copy.
template <int D>
void replaceScene(Scene<D>& s, std::optional<Scene<D>>& copy) {
  Scene<D> dropped = std::exchange(s, std::move(*copy));
  copy.reset();
  freeAside(std::make_tuple(std::move(dropped.candidates), std::move(dropped.contactGroups),
                            std::move(dropped.contacts), std::move(dropped.touchNow),
                            std::move(dropped.touchPrev), std::move(dropped.pairSprings)));
}

}  // namespace

template <int D>
RunReport SimulationManager<D>::run(const RunOptions& options) {
  // The run stops through options.stop, at step boundaries or back to a copy: nothing inside
  // a step (a search's sorting, elements a source adds, an output's file) may throw
  // {INTERRUPTED} from the process-wide flag half way.
  const InterruptScope unpolled(nullptr);
  // A distributed run's last messages are taken by the other ranks before it returns
  // (GhostPlan sends a step's messages without waiting): none stays in flight between runs.
  // (Not while an error unwinds it: the other ranks may never take them.)
  struct EndSends {
    const Scene<D>& s;
    ~EndSends() {
      if (s.dist && std::uncaught_exceptions() == 0) s.dist->plan.finishSends();
    }
  } endSends{s_};
  // What an undo goes back to. A check that fires before the first step must leave the scene
  // as it was, but after edits the force pass below changes it (forces, contacts, ledger); a
  // scene with script callbacks is undone when one fails. Other runs keep no copy.
  const bool scripted =
      options.failed && (std::any_of(s_.behaviors.items().begin(), s_.behaviors.items().end(),
                                     [](const auto& b) { return b->hasCallbacks(); }) ||
                         anyScripted(s_.walls.items));
  std::optional<Scene<D>> before;
  if ((s_.watchdog.enabled && (!s_.forcesReady || configDirty_)) || scripted) {
    // The copy polls the run's stop flag as it serializes (a scene of hundreds of megabytes
    // takes a second to copy): stopped there, the run has done nothing. (A distributed run's
    // ranks would not stop alike: they copy to the end.)
    before = copySceneUnlessStopped(s_.dist ? nullptr : options.stop);
    if (!before) {
      RunReport rep;
      rep.interrupted = true;
      rep.time = s_.time;
      return rep;
    }
  }
  const uint64_t searchedBefore = s_.rebuilds;
  // With the copy taken above, the first force pass of an edited scene (a second on a very
  // large one) and the steps until the run keeps a copy of its own can be abandoned too (not
  // in a distributed run: its ranks stop together at step boundaries, none abandoning alone
  // a pass whose exchanges the others wait in).
  s_.abandonOn = before && !s_.dist ? options.stop : nullptr;
  const AbandonOff unset{s_.abandonOn};
  // Stopped in the run's first force pass, or in the contacts' step taken after it: the
  // scene as it was before the run.
  const auto abandonedBeforeFirstStep = [&] {
    replaceScene(s_, before);
    configDirty_ = true;
    RunReport rep;
    rep.interrupted = rep.abandoned = true;
    rep.time = s_.time;
    return rep;
  };
  try {
    prepare();
  } catch (const StepAbandoned&) {
    return abandonedBeforeFirstStep();
  }
  RunReport rep;
  const uint64_t steps0 = s_.steps, rebuilds0 = s_.rebuilds;
  const double time0 = s_.time;
  loop_.resetTimers();
  const auto t0 = std::chrono::steady_clock::now();
  uint64_t total = options.steps;
  // The automatic step follows the contacts: every kContactStepEvery steps of the scene's step
  // count (and at the counts checksContactsEarly names, where the step is found unstable), and
  // when the run's first force pass searched (an edited scene), it is taken again
  // from their overlaps (sim/contact_stiffness.hpp) for the steps after, with the static part
  // as the last configuration (prepare, also within the run) made it. The count alone says
  // when, so a run continued from a checkpoint goes on with the same steps.
  // The motion bound is taken with the contacts' step, and in between only when the fastest
  // element (the watchdog's speed, or a pass of its own) would move more than the bound's share
  // of the step limit: each change of the step within a contact breaks the symmetry that makes
  // an elastic impact's errors cancel (a pusher's ledger 8e-5 at a fixed step, 2e-3 with the
  // step taken again as the struck grain sped up). A function of the scene and its count, so a
  // continued run takes it at the same steps too.
  const bool adaptive = s_.autoFraction > 0;
  bool watched = s_.watchdog.enabled;
  // changed: the step's deferred changes were applied after the watchdog looked.
  const auto followContacts = [&](uint64_t k, bool now, bool changed) {
    if (!adaptive) return;
    bool measure = now || s_.steps % kContactStepEvery == 0;
    const bool early = !measure && checksContactsEarly(s_.steps);
    double contacts = measure || early ? contactCriticalStep(s_, [&] { pollStep(s_); })
                                       : std::numeric_limits<double>::infinity();
    // (The branches above are the same on every rank: a function of the step count.)
    if (s_.dist && (measure || early)) contacts = s_.dist->comm->min(contacts);
    // Early, taken only where the step is beyond the contacts' stability limit: each change of
    // the step within a contact costs an elastic impact its symmetry (above).
    if (early) measure = s_.stepDt > contacts;
    double speed =
        std::sqrt(k > 0 && watched && !changed ? s_.fastestSpeed2 : fastestSpeed2(s_));
    if (s_.dist) speed = s_.dist->comm->max(speed);
    // Early, the motion bound is taken again for an element faster than it was made for (a
    // scene starting at rest under gravity: its first impacts come at the speed it gained).
    const bool faster = early && speed > s_.motionSpeed;
    if (!retakesMotion(measure || faster, speed, s_.stepDt, stepLimit_)) return;
    if (measure) s_.contactStep = contacts;
    // A non-finite speed (a blown-up state the watchdog, or the run's finiteness check,
    // reports) leaves the bound as it was: a checkpoint holds only finite ones.
    if (std::isfinite(kSpeedHeadroom * speed)) {
      s_.motionSpeed = kSpeedHeadroom * speed;
      s_.motionStep = motionBound(s_.motionSpeed, survey_, stepLimit_);
    }
    const double dt = autoStep(survey_, s_.motionStep);
    if (dt == s_.stepDt) return;
    s_.stepDt = dt;
    // A run to a simulated time: the steps left at the new step (k steps done).
    if (!std::isnan(options.endTime)) {
      const double left = std::ceil((options.endTime - s_.time) / dt * (1 - 1e-12));
      total = k + static_cast<uint64_t>(std::clamp(left, 0.0, 1e15));
    }
  };
  try {
    followContacts(0, s_.rebuilds != searchedBefore, false);
  } catch (const StepAbandoned&) {
    return abandonedBeforeFirstStep();
  }
  const uint64_t every =
      options.progressEvery ? options.progressEvery : std::max<uint64_t>(1, total / 100);
  // The contact records of a step are only seen after the run's last step unless an output,
  // the progress callback, a stop or a module that reads them looks in between. The
  // watchdog's overlap check looks at every step (a blow-up's deep overlaps can come and go
  // within a few steps) but needs no records: the passes keep the step's deepest contact.
  // Outputs that read contacts get records at the steps they are due at.
  bool seen = options.progress || options.stop || loop_.readsContactRecords();
  struct Restore {
    bool& flag;
    bool& deep;
    ~Restore() {
      flag = true;
      deep = false;
    }
  } restore{s_.recordContacts, s_.trackDeepest};
  // The copy a long step goes back to when Ctrl-C comes part way (RunOptions::longStep):
  // rollback_, once this run has refreshed it.
  using Clock = std::chrono::steady_clock;
  bool kept = false;
  auto keptAt = t0;
  // At a step boundary (`now`), after a step that took stepSeconds, stepsLeft to go: copies
  // the scene into rollback_ when the run needs one (long steps), the last is old enough and
  // the steps left are worth a copy, and lets the run's steps be abandoned (Scene::abandonOn)
  // while a copy of this run exists. Returns false if Ctrl-C stopped a first copy (then none
  // is kept). Changes rollback_ and the scene's mark.
  const auto keepCopy = [&](double stepSeconds, Clock::time_point now, uint64_t stepsLeft) {
    // (A distributed run stops at step boundaries only: its ranks abandon no step alone.)
    if (!options.stop || (!kept && stepSeconds <= options.longStep) || !rollbackFits() ||
        s_.dist) {
      if (!kept) s_.abandonOn = nullptr;  // short steps: stopped at their boundaries, no copy
      return true;
    }
    const double wait = kCopyEvery * rollbackSeconds_;
    if (kept ? std::chrono::duration<double>(now - keptAt).count() < wait
             : static_cast<double>(stepsLeft) * stepSeconds < wait) {
      return true;  // a few long steps (sim step 1 in a loop) pay no copy: each answers at its end
    }
    if (!refreshRollback(options.stop)) return false;  // stopped: the run ends at this boundary
    keptAt = Clock::now();
    kept = true;
    s_.abandonOn = options.stop;
    return true;
  };
  std::optional<WatchdogTrip> trip;
  bool untouched = false;  // back to the scene before the run: nothing below may change it
  // Puts back the scene as it was before the run (the copy `before`, which must be there).
  const auto backToBefore = [&] {
    replaceScene(s_, before);
    configDirty_ = true;
    untouched = true;
  };
  try {
    // The scene as set up (placed overlaps, initial speeds) before the first step.
    if (watched) {
      watchTogether(s_, [&] {
        watchdogCheck(s_, s_.dist ? s_.dist->stepLimit : watchdogStepLimit(s_),
                      s_.steps == 0 ? CheckPoint::BeforeFirstStep : CheckPoint::BeforeRun);
      });
    }
    // Stopped before its first step: the scene as it was before the run, when the run has it
    // (the force pass above changed forces, candidates and springs, not the motion).
    const auto stoppedBeforeFirstStep = [&] {
      rep.interrupted = true;
      if (before) backToBefore();
    };
    // Steps that were long in the last run: the copy before the first (its arrays are kept).
    if (total > 0 && lastStepSeconds_ > options.longStep &&
        !keepCopy(lastStepSeconds_, Clock::now(), total)) {
      stoppedBeforeFirstStep();
      total = 0;
    }
    for (uint64_t k = 0; k < total; ++k) {
      bool stop = options.stop && options.stop->load(std::memory_order_relaxed);
      // The ranks of a distributed run stop at the same boundary: one that stopped alone would
      // leave the others waiting in the step's exchanges. They agree every kStopEvery steps.
      if (s_.dist) stop = k % kStopEvery == 0 && s_.dist->comm->max(stop ? 1.0 : 0.0) > 0;
      if (stop) {
        if (k == 0) {
          stoppedBeforeFirstStep();
        } else {
          rep.interrupted = true;
        }
        break;
      }
      s_.recordContacts = seen || k + 1 == total || outputsReadNextStep();
      s_.trackDeepest = !s_.recordContacts && watched && s_.watchdog.overlap > 0;
      const auto stepStart = Clock::now();
      Clock::time_point stepEnd;
      try {
        loop_.step(s_);
        stepEnd = Clock::now();
        // The step's deferred creations and removals end it (their force pass polls too).
        // The step then follows the scene as a checkpoint at this boundary holds it.
        bool changed = false;
        if (!s_.deferred.empty() && applyDeferred()) {
          seen = seen || loop_.readsContactRecords();
          watched = s_.watchdog.enabled;
          changed = true;
        }
        followContacts(k + 1, false, changed);
      } catch (const StepAbandoned&) {
        // Back to the copy: the run's own, or the scene as it was before the run, which a run
        // stopped in its first step takes when it has it (its own copy holds the run's force
        // pass: the same motion, but not the scene the command was given).
        const bool toBefore = !kept || (before && k == 0);
        std::optional<Scene<D>>& back = toBefore ? before : rollback_;
        rep.dropped = s_.steps - back->steps;
        rep.abandoned = true;
        if (!toBefore) {
          // The copy was prepared as the scene is: only the modules' scratch, left half
          // written, is made anew. The dropped scene's arrays serve the next copy.
          std::swap(s_, *rollback_);
          loop_.setModules(makeModules(sceneUse(s_)));
        } else {
          backToBefore();
        }
        rep.interrupted = true;
        break;
      }
      if (!watched && (k & 1023) == 1023) checkFinite();
      if (options.progress && (k + 1) % every == 0 && k + 1 < total) options.progress(k + 1, total);
      lastStepSeconds_ = std::chrono::duration<double>(stepEnd - stepStart).count();
      if (k + 1 < total && !keepCopy(lastStepSeconds_, stepEnd, total - k - 1)) {
        rep.interrupted = true;
        break;
      }
    }
  } catch (const WatchdogHit& h) {
    trip = describeTrip(h, s_.steps == steps0);
  }
  if (!untouched) {
    s_.placedElements.clear();
    s_.placedWalls.clear();
    if (s_.dist) s_.dist->placed.clear();
  }
  if (!watched) checkFinite();
  rep.steps = s_.steps - steps0;
  if (options.progress && !trip) options.progress(rep.steps, total);
  rep.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rep.simulatedTime = s_.time - time0;
  rep.time = s_.time;
  const auto names = loop_.names();
  for (size_t k = 0; k < names.size(); ++k) rep.modules.push_back({names[k], loop_.seconds()[k]});
  rep.contacts = s_.contacts.size();
  if (s_.dist) rep.contacts = static_cast<uint64_t>(s_.dist->comm->sum(static_cast<int64_t>(rep.contacts)));
  rep.neighborRebuilds = s_.rebuilds - rebuilds0;
  const EnergyLedger e = energy();
  if (!trip && !untouched) s_.ledger.scale = e.scale;
  rep.energyResidual = e.residual;
  const bool failed = !trip && options.failed && options.failed();
  if (before && ((trip && s_.steps == steps0) || failed)) {
    replaceScene(s_, before);
    configDirty_ = true;
    rep.undone = failed;
    rep.time = s_.time;
  }
  if (trip) throw RunStopped(std::move(*trip), rep);
  return rep;
}

template <int D>
bool SimulationManager<D>::refreshRollback(const std::atomic<bool>* stop) {
  s_.abandonOn = nullptr;  // not in the copy
  if (!rollback_) {
    // The first copy faults its pages in (a second at half a million grains): made by the
    // serializing copy, which polls Ctrl-C. It holds only what a checkpoint holds; the
    // assignment below makes it exact.
    rollback_ = copySceneUnlessStopped(stop);
    if (!rollback_) return false;
  }
  const auto t0 = std::chrono::steady_clock::now();
  *rollback_ = s_;  // into the arrays of the last copy: no new pages to fault in
  rollbackSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return true;
}

template <int D>
bool SimulationManager<D>::rollbackFits() const {
  if (rollback_) return true;  // its arrays are there already
  const long pages = sysconf(_SC_AVPHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || pageSize <= 0) return false;
  const double bytes = static_cast<double>(memory().total()) +
                       static_cast<double>(s_.bonds.bonds.capacity() * sizeof(Bond<D>));
  return 2 * bytes <= static_cast<double>(pages) * static_cast<double>(pageSize);
}

template <int D>
bool SimulationManager<D>::applyDeferred() {
  DeferredChanges changes = std::move(s_.deferred);
  s_.deferred = {};
  std::vector<ElementId> gone;
  std::unordered_set<uint64_t> seenIds;
  for (ElementId id : changes.destroy) {
    if (s_.elements.pool().valid(id) && seenIds.insert(id.bits()).second) gone.push_back(id);
  }
  const bool broke = applyBondBreaks(changes.breakBonds);
  if (gone.empty() && changes.create.empty()) {
    if (broke) prepare();
    return broke;
  }
  // Shapes the changes bring in need their contact routines: checked before anything changes.
  std::vector<TypeId> extra;
  for (const ElementDef& d : changes.create) {
    if (d.shape.empty()) continue;
    if (const auto id = ShapeTable<D>::get().id(d.shape)) {
      extra.push_back(*id);
      for (TypeId m : ShapeTable<D>::get().type(*id).memberTypes(d.shapeParams)) extra.push_back(m);
    }
  }
  if (!extra.empty()) checkShapeRoutines(s_, extra);
  if (!gone.empty()) removeElementSet(gone);
  if (!changes.create.empty()) addElements(changes.create);
  prepare();
  return true;
}

template <int D>
RunReport SimulationManager<D>::step() {
  RunOptions o;
  o.steps = 1;
  return run(o);
}

// ---- the watchdog ---------------------------------------------------------------------------

namespace {

std::string num(double x, const char* f = "%.3g") {
  char b[48];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

std::string percent(double x) {
  return num(100 * x, "%.3g") + "%";
}

}  // namespace

std::string WatchdogTrip::message(const std::function<std::string(ElementId)>& grainName,
                                  const std::function<std::string(WallId)>& wallName) const {
  std::string who;
  if (grains.size() == 1 && wall.isNull()) {
    who = "element " + grainName(grains[0]);
  } else if (grains.size() == 2) {
    who = "elements " + grainName(grains[0]) + " and " + grainName(grains[1]);
  } else if (grains.size() == 1) {
    who = "element " + grainName(grains[0]) + " and wall " + wallName(wall);
  }
  return "run stopped at step " + std::to_string(step) + " (t = " + physics::formatReal(time) +
         " s) by the watchdog" + (atStart ? ", before the first step: " : ": ") + who + " " + what +
         "; likely cause: " + cause + "; fix: " + fix;
}

RunStopped::RunStopped(WatchdogTrip trip, RunReport report)
    : Error(
          trip.message([](ElementId g) { return toString(g); }, [](WallId w) { return toString(w); }),
          {"WATCHDOG", trip.check}),
      trip_(std::move(trip)),
      report_(std::move(report)) {}

namespace {

// Returns the words of trip t that the rank describing it knows alone (the check, the elements
// and the wall, the finding, the cause and the fix), each ended by a NUL.
std::vector<char> tripBytes(const WatchdogTrip& t) {
  std::vector<char> out;
  const auto add = [&](const std::string& w) { mpi::appendWord(w, out); };
  add(t.check);
  add(std::to_string(t.wall.bits()));
  for (const std::string* w : {&t.what, &t.cause, &t.fix}) add(*w);
  for (const ElementId g : t.grains) add(std::to_string(g.bits()));
  return out;
}

// Sets t's words from tripBytes' form b. Changes t.
void tripFromBytes(const std::vector<char>& b, WatchdogTrip& t) {
  const std::vector<std::string> words = mpi::wordsFromBytes(b);
  t.check = words.at(0);
  t.wall = WallId::fromBits(std::stoull(words.at(1)));
  t.what = words.at(2);
  t.cause = words.at(3);
  t.fix = words.at(4);
  t.grains.clear();
  for (size_t k = 5; k < words.size(); ++k)
    t.grains.push_back(ElementId::fromBits(std::stoull(words[k])));
}

}  // namespace

template <int D>
WatchdogTrip SimulationManager<D>::describeTrip(const WatchdogHit& h, bool atStart) const {
  WatchdogTrip t;
  if (h.rank < 0) t = describeOwnTrip(h);
  t.step = s_.steps;
  t.time = s_.time;
  t.atStart = atStart;
  // A distributed run: the rank holding the element describes it, and every rank raises that
  // description, so that a script reading the message does the same on every rank.
  if (s_.dist) {
    const mpi::Communicator& comm = *s_.dist->comm;
    const int owner = h.rank >= 0 ? h.rank : comm.rank();
    const auto all = comm.gatherBytes(h.rank < 0 ? tripBytes(t) : std::vector<char>{});
    if (owner != comm.rank()) tripFromBytes(all.at(static_cast<size_t>(owner)), t);
  }
  return t;
}

template <int D>
WatchdogTrip SimulationManager<D>::describeOwnTrip(const WatchdogHit& h) const {
  WatchdogTrip t;
  // The handles scripts hold (in a distributed scene not this rank's own).
  const auto grainId = [&](uint32_t i) { return elementHandleAt(i); };
  t.grains.push_back(grainId(h.a));
  if (h.hasB) {
    if (h.wall) {
      t.wall = s_.walls.pool().handleAt(h.b);
    } else {
      t.grains.push_back(grainId(h.b));
    }
  }
  const double dt = s_.stepDt;
  const double crit = criticalTimeStep();
  const bool fixed = s_.autoFraction == 0;
  const std::string stepText = "dt = " + num(dt) + " s, critical estimate " + num(crit) + " s";
  const bool tooLarge = std::isfinite(crit) && dt > crit;
  const std::string autoFix =
      "use sim timestep auto (0.2 of the critical estimate), or a smaller fixed step";
  switch (h.kind) {
    case WatchdogHit::Nan:
      t.check = "NAN";
      t.what = "has a non-finite position or velocity";
      t.cause = tooLarge ? "the time step is too large for the contacts (" + stepText + ")"
                         : "the integration blew up (" + stepText +
                               "), or a load or a wall motion gave a non-finite value";
      // Under the automatic step, advising it would name the setting in force.
      t.fix = fixed ? autoFix + "; check the loads"
                    : "check the loads and the walls' motions for a non-finite value; if the "
                      "contacts blew up, a smaller fraction (sim timestep auto -fraction " +
                          num(0.5 * s_.autoFraction) + ")";
      break;
    case WatchdogHit::Speed:
      t.check = "SPEED";
      t.what = "moves " + num(h.value) + " m in one step (|v| = " + num(h.extra) +
               " m/s, dt = " + num(dt) + " s), more than " +
               (h.limit > 0.5 * s_.skin ? "half the smallest radius" : "half the skin") + " (" +
               num(h.limit) + " m)";
      if (tooLarge) {
        t.cause = "the time step is too large for the stiffness (" + stepText +
                  "): contacts blow up and throw elements out";
      } else if (fixed) {
        t.cause =
            "the element is too fast for the time step: a contact can begin already deep, or "
            "the element cross a thin wall, within a step";
      } else {
        // The automatic step follows the fastest speed (motionBound): only a jump within one
        // step outruns it.
        t.cause = "the element's speed jumped within one step beyond what the automatic step "
                  "followed (made for " + num(s_.motionSpeed) +
                  " m/s): an impulse from a load, a wall's motion or a contact that blew up";
      }
      t.fix = (tooLarge || fixed ? autoFix
                                 : std::string("check the loads, the walls' motions and the "
                                               "contacts' stiffness")) +
              "; module watchdog -speed 0 turns this check off";
      break;
    case WatchdogHit::Overlap:
      t.check = "OVERLAP";
      t.what = std::string("overlap by ") + percent(h.value) + " of the " +
               (h.wall ? "element's radius" : "smaller radius") + " (limit " + percent(h.limit) +
               ")";
      if (h.placed) {
        t.cause = "the elements were placed overlapping";
        t.fix =
            "place them apart, or relax the scene first (sim relax); module watchdog "
            "-placed sets the limit";
      } else if (tooLarge) {
        t.cause = "the time step is too large for the stiffness (" + stepText + ")";
        t.fix = autoFix;
      } else {
        t.cause = "the contact is too soft for the impact speed or the load (" + stepText + ")";
        t.fix =
            "a stiffer material (larger young or normalstiffness), slower impacts or "
            "smaller loads, or a higher limit (module watchdog -overlap)";
      }
      break;
    case WatchdogHit::Energy:
      t.check = "ENERGY";
      t.what = "is the fastest element while the energy balance grew by " + num(h.value) + " J, " +
               percent(h.value / h.extra) + " of the energy scale " + num(h.extra) + " J (limit " +
               percent(s_.watchdog.energy) + ")";
    {
      // The contacts at the overlaps the run reached (a loaded bed stiffens): what a step of
      // theirs would be, and a fix that is not the setting in force.
      const double now = contactCriticalStep(s_);
      t.cause = "the integration creates energy: the time step is too large (" + stepText +
                (std::isfinite(now) ? "; the contacts at their overlaps now allow " + num(now) + " s"
                                    : std::string()) +
                ")";
      t.fix = (fixed ? "use sim timestep auto (it follows the contacts' stiffness), or a smaller "
                       "fixed step"
                     : "a smaller fraction (sim timestep auto -fraction " +
                           num(0.5 * s_.autoFraction) + "), or a fixed step below " +
                           num(0.5 * std::min(crit, now)) + " s") +
              "; module watchdog -energy sets the bound";
    }
      break;
  }
  return t;
}

template <int D>
double SimulationManager<D>::worstOverlap(double fraction, bool push, std::vector<bool>* moved) {
  ElementArrays<D>& a = s_.elements.a;
  const WallNarrowPhase<D>& np = WallNarrowPhase<D>::get();
  std::vector<bool> pinned;
  if (push && !s_.blocked.empty()) {
    pinned.assign(a.size(), false);
    for (const BlockedElement& b : s_.blocked) {
      const uint32_t i = s_.elements.pool().findDense(b.id);
      if (i != HandlePool<ElementKind>::kNpos && (b.dofs & (dof::X | dof::Y | dof::Z)) != 0)
        pinned[i] = true;
    }
  }
  double worst = 0;
  for (const ContactRecord<D>& c : s_.contacts) {
    // Relaxing pushes balls apart along their centre line; a shape's records are left out.
    if (a.geometry[c.a] != 0 || (!c.wall && a.geometry[c.b] != 0)) continue;
    const physics::SphereShape<D> sa{a.x[c.a], a.r[c.a]};
    std::optional<physics::ContactGeometry<D>> g;
    Real rmin = a.r[c.a];
    if (c.wall) {
      const Wall<D>& w = s_.walls.items[c.b];
      const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, w.shape);
      g = np.table.get(np.sphere, np.byShape[static_cast<int>(w.kind)]).fn.one(&sa, shape);
    } else {
      rmin = std::min(rmin, a.r[c.b]);
      g = physics::intersect<D>(sa, physics::SphereShape<D>{partnerPosition(s_, c.a, c.b), a.r[c.b]});
    }
    if (!g) continue;
    worst = std::max(worst, g->overlap / rmin);
    if (!push || g->overlap <= fraction * rmin) continue;
    // Back to half the allowed overlap, shared by inverse mass; the normal points from a to b.
    // A grain with a blocked translation stays where it is: the other one takes it all.
    const Real excess = g->overlap - 0.5 * fraction * rmin;
    const Real ma = pinned.empty() || !pinned[c.a] ? a.invMass[c.a] : 0;
    if (c.wall) {
      if (ma == 0) continue;
      a.x[c.a] -= excess * g->normal;
    } else {
      const Real mb = pinned.empty() || !pinned[c.b] ? a.invMass[c.b] : 0;
      if (ma + mb == 0) continue;
      const Real wa = ma / (ma + mb);
      a.x[c.a] -= (excess * wa) * g->normal;
      a.x[c.b] += (excess * (1 - wa)) * g->normal;
      if (moved && mb != 0) (*moved)[c.b] = true;
    }
    if (moved && ma != 0) (*moved)[c.a] = true;
  }
  return worst;
}

template <int D>
RelaxReport SimulationManager<D>::relax(double fraction, uint64_t maxIterations,
                                        const std::atomic<bool>* stop, double longPass) {
  if (!(fraction > 0 && fraction <= 1)) {
    throw Error("bad fraction \"" + physics::formatReal(fraction) + "\": must be in (0, 1]",
                {"VALUE", "FRACTION"});
  }
  if (maxIterations < 1) {
    throw Error("bad iterations \"0\": must be at least 1", {"VALUE", "ITERATIONS"});
  }
  RelaxReport rep;
  if (s_.elements.size() == 0) return rep;
  const InterruptScope unpolled(nullptr);  // as in run: stopped through stop alone
  if (stop && stop->load(std::memory_order_relaxed)) {  // before any work: nothing changed
    rep.interrupted = true;
    return rep;
  }
  // A pass (the moves, then a neighbour search and a force pass of the moved scene) of a
  // large scene takes a second. Before a pass that may be long (the last one was, or, for the
  // first, a force pass of a large scene is due), the scene is copied into rollback_ as a run
  // with long steps copies it; Ctrl-C then abandons the pass part way, back to the copy: the
  // scene as the last whole pass (or the call) left it.
  using Clock = std::chrono::steady_clock;
  constexpr size_t kLargeScene = 100000;  // about where a search and force pass take 50 ms
  std::vector<bool> moved(s_.elements.size(), false), movedAtCopy;
  const AbandonOff unset{s_.abandonOn};
  // Keeps the copy before a pass when lastSeconds says it may be long; returns false if Ctrl-C
  // stopped the process's first copy (then the scene is as it was). Changes rollback_.
  const auto keepCopy = [&](double lastSeconds) {
    s_.abandonOn = nullptr;
    if (!stop || lastSeconds <= longPass || !rollbackFits()) return true;
    if (!refreshRollback(stop)) return false;
    movedAtCopy = moved;
    s_.abandonOn = stop;
    return true;
  };
  // A pass's time until one is measured: long for a large scene.
  double passSeconds = s_.elements.size() >= kLargeScene ? HUGE_VAL : 0;
  if (!keepCopy(configDirty_ || !s_.forcesReady ? passSeconds : 0)) {
    rep.interrupted = true;
    return rep;
  }
  try {
    prepare();  // the contacts at the current positions
    rep.before = rep.after = worstOverlap(fraction, false);
    while (rep.after > fraction && rep.iterations < maxIterations) {
      if (stop && stop->load(std::memory_order_relaxed)) {
        rep.interrupted = true;
        break;
      }
      if (!keepCopy(passSeconds)) {
        rep.interrupted = true;
        break;
      }
      const auto t0 = Clock::now();
      const double before = ledgerSum();
      worstOverlap(fraction, true, &moved);
      // An edit: the potential energy the moves changed is the user's, and the next force
      // pass (in prepare) rebases the elastic energy the same way.
      s_.ledger.reference += ledgerSum() - before;
      s_.needRebuild = true;
      s_.forcesReady = false;
      if (stop && stop->load(std::memory_order_relaxed)) {  // the next run's prepare catches up
        rep.iterations += 1;
        rep.interrupted = true;
        break;
      }
      prepare();
      rep.after = worstOverlap(fraction, false);
      rep.iterations += 1;
      passSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    }
  } catch (const StepAbandoned&) {
    // Back to the copy; the modules' scratch, left half written, is made anew.
    std::swap(s_, *rollback_);
    moved = std::move(movedAtCopy);
    configDirty_ = true;
    rep.interrupted = true;
  }
  rep.moved = static_cast<uint64_t>(std::count(moved.begin(), moved.end(), true));
  return rep;
}

// ---- the energy ledger ---------------------------------------------------------------------

template <int D>
double SimulationManager<D>::potential() const {
  const VecD<D> g = s_.behaviors.gravity();
  if (g.squaredNorm() == 0) return 0;
  const ElementArrays<D>& a = s_.elements.a;
  double u = 0;
  for (size_t i = 0; i < s_.ownedCount(); ++i) u -= g.dot(a.x[i]) / a.invMass[i];
  return u;
}

template <int D>
double SimulationManager<D>::ledgerSum() const {
  const ElementArrays<D>& a = s_.elements.a;
  double k = 0;
  for (size_t i = 0; i < s_.ownedCount(); ++i) {
    k += 0.5 * a.v[i].squaredNorm() / a.invMass[i] + 0.5 * twiceRotationalEnergy(s_, i);
  }
  double u = potential();
  LedgerSums l = s_.ledger;
  if (s_.dist) reduceLedger(*s_.dist->comm, k, u, l, nullptr, s_.dist->initial);
  return l.balanceSum(k, u);
}

template <int D>
EnergyLedger SimulationManager<D>::energy() const {
  EnergyLedger e;
  const ElementArrays<D>& a = s_.elements.a;
  for (size_t i = 0; i < s_.ownedCount(); ++i) {
    e.kineticTranslational += 0.5 * a.v[i].squaredNorm() / a.invMass[i];
    e.kineticRotational += 0.5 * twiceRotationalEnergy(s_, i);
  }
  LedgerSums l = s_.ledger;
  e.gravitational = potential();
  if (s_.dist) {
    // The ranks' parts added: the kinetic energies as two terms, the potential, the sums.
    double kinetic = e.kineticTranslational;
    reduceLedger(*s_.dist->comm, kinetic, e.gravitational, l, &e.kineticRotational,
                 s_.dist->initial);
    e.kineticTranslational = kinetic;
  }
  e.elastic = l.elastic;
  e.dampingLoss = l.dampingLoss;
  e.frictionLoss = l.frictionLoss;
  e.wallWork = l.wallWork;
  e.behaviorWork = l.behaviorWork;
  e.springWork = l.springWork;
  e.bondReleased = l.bondReleased;
  const double kinetic = e.kineticTranslational + e.kineticRotational;
  e.balance = l.started ? l.balanceSum(kinetic, e.gravitational) - l.reference : 0;
  e.scale = l.scaleWith(kinetic, e.gravitational, l.started);
  e.residual = e.scale > 0 ? std::abs(e.balance) / e.scale : 0;
  return e;
}

// ---- queries -------------------------------------------------------------------------------

template <int D>
MemoryReport SimulationManager<D>::memory() const {
  // Returns the bytes a vector's capacity holds.
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  MemoryReport m;
  m.grains = s_.elements.a.heapBytes() + s_.elements.pool().heapBytes();
  m.detection = bytes(s_.candidates) + bytes(s_.wallCandidates) + bytes(s_.xAtBuild) +
                bytes(s_.marginWeight) +
                s_.contactGroups.heapBytes();
  for (const auto& list : s_.wallCandidates) m.detection += bytes(list);
  m.search = loop_.workingBytes(SimLevel::Detection);
  m.passes = loop_.workingBytes() - m.search;
  m.springs = s_.pairSprings.heapBytes() + bytes(s_.wallSprings) + s_.histories.heapBytes();
  for (const auto& list : s_.wallSprings) m.springs += bytes(list);
  m.contacts = bytes(s_.contacts);
  return m;
}

template <int D>
std::vector<ContactInfo> SimulationManager<D>::contacts() const {
  std::vector<ContactInfo> out;
  out.reserve(s_.contacts.size());
  const ElementArrays<D>& a = s_.elements.a;
  const WallNarrowPhase<D>& np = WallNarrowPhase<D>::get();
  // A pair with a shape has one record per contact point, in a row, in the order of its
  // routine's points: they are recomputed once per pair and handed out in that order.
  ContactPoint<D> pts[kMaxContactPoints];
  int nPts = 0, next = 0;
  const ContactRecord<D>* pairOf = nullptr;
  InterruptPoll poll("contacts");  // a query's: a run's outputs read them with nothing to poll
  for (const ContactRecord<D>& c : s_.contacts) {
    poll();
    ContactInfo ci;
    ci.a = elementHandleAt(c.a);
    ci.centreA = fromVec<D>(a.x[c.a]);
    const physics::SphereShape<D> sa{a.x[c.a], a.r[c.a]};
    std::optional<physics::ContactGeometry<D>> g;
    if (a.geometry[c.a] != 0 || (!c.wall && a.geometry[c.b] != 0)) {
      if (pairOf == nullptr || pairOf->a != c.a || pairOf->b != c.b || pairOf->wall != c.wall ||
          next >= nPts) {
        nPts = c.wall ? elementWallPoints(s_, c.a, s_.walls.items[c.b], pts)
                      : elementPairPoints(s_, c.a, c.b, pts);
        next = 0;
        pairOf = &c;
      }
      if (next < nPts) g = pts[next++].g;
      if (c.wall) {
        ci.wall = s_.walls.pool().handleAt(c.b);
      } else {
        ci.b = elementHandleAt(c.b);
        ci.centreB = fromVec<D>(a.x[c.b]);
      }
    } else if (c.wall) {
      const Wall<D>& w = s_.walls.items[c.b];
      ci.wall = s_.walls.pool().handleAt(c.b);
      const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, w.shape);
      g = np.table.get(np.sphere, np.byShape[static_cast<int>(w.kind)]).fn.one(&sa, shape);
    } else {
      ci.b = elementHandleAt(c.b);
      ci.centreB = fromVec<D>(a.x[c.b]);
      g = physics::intersect<D>(sa, physics::SphereShape<D>{partnerPosition(s_, c.a, c.b), a.r[c.b]});
    }
    if (g) {
      ci.point = fromVec<D>(g->point);
      ci.normal = fromVec<D>(g->normal);
      ci.overlap = g->overlap;
    }
    ci.force = fromVec<D>(c.force);
    out.push_back(ci);
  }
  return out;
}

template <int D>
std::array<Vec3d, 2> SimulationManager<D>::bounds() const {
  const Real inf = std::numeric_limits<Real>::infinity();
  Vec3d lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  bool any = false;
  auto grow = [&](int k, Real l, Real h) {
    lo[k] = std::min(lo[k], l);
    hi[k] = std::max(hi[k], h);
  };
  const ElementArrays<D>& a = s_.elements.a;
  for (size_t i = 0; i < a.size(); ++i) {
    any = true;
    for (int k = 0; k < D; ++k) grow(k, a.x[i][k] - a.r[i], a.x[i][k] + a.r[i]);
  }
  for (const Wall<D>& w : s_.walls.items) {
    if (w.kind == WallShape::Plane) continue;
    const physics::Bounds<D> b =
        std::visit([](const auto& sh) { return physics::bounds(sh); }, w.shape);
    bool finite = true;
    for (int k = 0; k < D; ++k) finite = finite && std::isfinite(b.lo[k]) && std::isfinite(b.hi[k]);
    if (!finite) continue;
    any = true;
    for (int k = 0; k < D; ++k) grow(k, b.lo[k], b.hi[k]);
  }
  if (s_.dist) {
    // Collective: the box of every rank's elements (the walls are every rank's alike).
    std::vector<double> v{lo[0], lo[1], lo[2], -hi[0], -hi[1], -hi[2]};
    s_.dist->comm->min(v);
    lo = Vec3d{v[0], v[1], v[2]};
    hi = Vec3d{-v[3], -v[4], -v[5]};
    any = lo[0] <= hi[0];
  }
  if (!any) return {Vec3d{0, 0, 0}, Vec3d{0, 0, 0}};
  for (int k = D; k < 3; ++k) lo[k] = hi[k] = 0;
  return {lo, hi};
}

template <int D>
std::vector<ElementId> SimulationManager<D>::elementIds() const {
  const auto h = s_.elements.pool().handles();
  return {h.begin(), h.end()};
}

namespace {

template <int D>
void appendVec(std::vector<double>& out, const VecD<D>& v) {
  for (int k = 0; k < D; ++k) out.push_back(v[k]);
}
inline void appendAngular(std::vector<double>& out, Real w) {
  out.push_back(w);
}
inline void appendAngular(std::vector<double>& out, const Vec3& w) {
  appendVec<3>(out, w);
}

}  // namespace

template <int D>
std::vector<double> SimulationManager<D>::positions() const {
  std::vector<double> out;
  out.reserve(D * s_.elements.size());
  for (const auto& x : s_.elements.a.x) appendVec<D>(out, x);
  return out;
}

template <int D>
std::vector<double> SimulationManager<D>::velocities() const {
  std::vector<double> out;
  out.reserve(D * s_.elements.size());
  for (const auto& x : s_.elements.a.v) appendVec<D>(out, x);
  return out;
}

template <int D>
std::vector<double> SimulationManager<D>::forces() const {
  std::vector<double> out;
  out.reserve(D * s_.elements.size());
  for (const auto& x : s_.elements.a.f) appendVec<D>(out, x);
  return out;
}

template <int D>
std::vector<double> SimulationManager<D>::angularVelocities() const {
  std::vector<double> out;
  for (const auto& w : s_.elements.a.w) appendAngular(out, w);
  return out;
}

template <int D>
std::vector<double> SimulationManager<D>::orientations() const {
  std::vector<double> out;
  for (const auto& q : s_.elements.a.q) {
    const auto o = fromRotation(q);
    for (int k = 0; k < (D == 2 ? 1 : 4); ++k) out.push_back(o[k]);
  }
  return out;
}

template <int D>
std::vector<double> SimulationManager<D>::radii() const {
  return s_.elements.a.r;
}

template <int D>
ElementTable SimulationManager<D>::elementTable() const {
  const ElementArrays<D>& a = s_.elements.a;
  const size_t n = s_.ownedCount();  // a distributed scene's ghosts are other ranks' to show
  ElementTable t;
  t.ids = elementIds();
  InterruptPoll poll("reading the elements");
  auto three = [n, &poll](auto&& get) {
    std::vector<double> out;
    out.reserve(3 * n);
    for (size_t i = 0; i < n; ++i) {
      poll();
      const Vec3d v = get(i);
      out.insert(out.end(), v.begin(), v.end());
    }
    return out;
  };
  t.position = three([&](size_t i) { return fromVec<D>(a.x[i]); });
  t.velocity = three([&](size_t i) { return fromVec<D>(a.v[i]); });
  t.force = three([&](size_t i) { return fromVec<D>(a.f[i]); });
  t.angularVelocity = three([&](size_t i) { return fromAngular(a.w[i]); });
  t.torque = three([&](size_t i) { return fromAngular(a.t[i]); });
  t.orientation.reserve(4 * n);
  for (size_t i = 0; i < n; ++i) {
    poll();
    std::array<double, 4> o = fromRotation(a.q[i]);
    // A 2D angle as the quaternion of the same turn about z, so one glyph filter serves both.
    if constexpr (D == 2) o = {std::cos(0.5 * o[0]), 0, 0, std::sin(0.5 * o[0])};
    t.orientation.insert(t.orientation.end(), o.begin(), o.end());
  }
  t.radius.assign(a.r.begin(), a.r.begin() + static_cast<std::ptrdiff_t>(n));
  t.mass.resize(n);
  for (size_t i = 0; i < n; ++i) {
    poll();
    t.mass[i] = 1 / a.invMass[i];
  }
  t.material.assign(a.material.begin(), a.material.begin() + static_cast<std::ptrdiff_t>(n));
  t.materialNames = s_.materialNames;
  // Shapes: the ball first, then the types in the order elements use them.
  const ShapeTable<D>& table = ShapeTable<D>::get();
  std::vector<int64_t> indexOfType;
  auto shapeIndex = [&](TypeId id) {
    if (indexOfType.size() <= id.value) indexOfType.resize(id.value + 1, -1);
    if (indexOfType[id.value] < 0) {
      indexOfType[id.value] = int64_t(t.shapeNames.size());
      t.shapeNames.emplace_back(table.type(id).name());
    }
    return uint32_t(indexOfType[id.value]);
  };
  shapeIndex(ShapeTable<D>::ball());
  for (const auto& g : s_.geometries) t.shapeParamCount = std::max(t.shapeParamCount, g->params.size());
  t.shape.resize(n);
  t.shapeParams.assign(n * t.shapeParamCount, 0.0);
  for (size_t i = 0; i < n; ++i) {
    poll();
    const Geometry<D>& g = *s_.geometries[a.geometry[i]];
    t.shape[i] = shapeIndex(g.shape);
    std::copy(g.params.begin(), g.params.end(), t.shapeParams.begin() + i * t.shapeParamCount);
  }
  for (std::string_view tag : elementTagTable().tags()) {
    t.tagNames.emplace_back(tag);
    std::vector<uint8_t>& on = t.tagged.emplace_back(n, 0);
    for (uint32_t i : taggedIndices(std::string(tag))) on[i] = 1;
  }
  return t;
}

// ---- whole scene ---------------------------------------------------------------------------

template <int D>
std::string SimulationManager<D>::serialize(IoMode mode, const BehaviorManager<D>* behaviors) const {
  Writer w;
  const FreeAsideOnThrow aside(w.bytes);  // stopped half way: hundreds of megabytes to free
  // Room for about all of it at once (more than it needs costs only address space): grown by
  // doubling, a scene of hundreds of megabytes was copied whole in one call, twice.
  w.bytes.reserve(4096 + s_.elements.size() * 320 + s_.candidates.size() * 48 +
                  s_.contacts.size() * 48 + s_.xAtBuild.size() * 24 + s_.histories.size() * 40 +
                  s_.bonds.bonds.size() * 192 + s_.bonds.breaks.size() * 96);
  writeScene(w, s_, mode, behaviors);
  return std::move(w.bytes);
}


template <int D>
double SimulationManager<D>::contactCriticalTimeStep() const {
  return contactCriticalStep(s_);
}

template <int D>
uint64_t SimulationManager<D>::stateDigest() const {
  return hashBytes(serialize(IoMode::Digest));
}

template <int D>
Scene<D> SimulationManager<D>::copyScene() const {
  if (s_.dist) {
    // A distributed scene's part (its elements and ghosts) is copied as it is, with a
    // Distribution of its own: a checkpoint's bytes hold whole scenes only.
    Scene<D> c = s_;
    c.dist = std::make_shared<Distribution<D>>(*s_.dist);
    return c;
  }
  std::string b = serialize(IoMode::Clone);
  const FreeAsideOnThrow asideBytes(b);
  Scene<D> c;
  const FreeAsideOnThrow asideCopy(c);
  Reader r(b);
  readScene(r, c);
  c.behaviors = s_.behaviors;  // deep copies, sharing the TimeFunctions
  // The walls' TimeFunctions and the angle a scripted wall turned since the last search: not
  // in the bytes (a checkpoint cannot hold them); the dense order is the same.
  for (size_t k = 0; k < c.walls.items.size(); ++k) {
    c.walls.items[k].velocityFn = s_.walls.items[k].velocityFn;
    c.walls.items[k].omegaFn = s_.walls.items[k].omegaFn;
    c.walls.items[k].scriptedAngle = s_.walls.items[k].scriptedAngle;
  }
  return c;
}

template <int D>
std::optional<Scene<D>> SimulationManager<D>::copySceneUnlessStopped(
    const std::atomic<bool>* stop) const {
  const InterruptScope polled(stop);
  try {
    return copyScene();
  } catch (const Error& e) {
    if (std::find(e.code().begin(), e.code().end(), "INTERRUPTED") == e.code().end()) throw;
    return std::nullopt;
  }
}

template <int D>
std::unique_ptr<Simulation> SimulationManager<D>::clone() const {
  auto m = std::make_unique<SimulationManager<D>>();
  m->s_ = copyScene();
  return m;
}

template <int D>
std::vector<std::string> SimulationManager<D>::save(std::ostream& out, bool skipCallbacks) const {
  std::vector<std::string> skipped;
  const std::string file = saveBytes(skipCallbacks, &skipped);
  out.write(file.data(), static_cast<std::streamsize>(file.size()));
  if (!out) throw Error("can't write the checkpoint: the stream failed", {"SAVE", "IO"});
  return skipped;
}

template <int D>
std::string SimulationManager<D>::saveBytes(bool skipCallbacks,
                                            std::vector<std::string>* skippedOut) const {
  std::vector<std::string> skipped;
  std::vector<BehaviorId> drop;
  const auto& items = s_.behaviors.items();
  for (size_t k = 0; k < items.size(); ++k) {
    if (!items[k]->hasCallbacks()) continue;
    const BehaviorId id = s_.behaviors.pool().handleAt(static_cast<uint32_t>(k));
    skipped.push_back("behavior " + toString(id) + " (" + items[k]->describe() + ")");
    drop.push_back(id);
  }
  // A scripted wall is saved moving on at its last step's rates (writeScene).
  for (size_t k = 0; k < s_.walls.items.size(); ++k) {
    if (!s_.walls.items[k].scripted()) continue;
    const WallId id = s_.walls.pool().handleAt(static_cast<uint32_t>(k));
    skipped.push_back("wall " + toString(id) + " (a scripted motion)");
  }
  if (!skipped.empty() && !skipCallbacks) {
    std::string list;
    for (const std::string& s : skipped) list += (list.empty() ? "" : ", ") + s;
    throw Error("can't save the scene: " + list +
                    " uses a script callback, which a checkpoint cannot hold; remove it or "
                    "save with callbacks skipped",
                {"SAVE", "CALLBACK"});
  }
  if (s_.dist) {
    // Every rank gives its part, rank 0 serializes the whole scene; the others return nothing.
    SimulationManager<D> whole;
    whole.s_ = gatheredScene();
    if (s_.dist->comm->rank() != 0) {
      if (skippedOut != nullptr) *skippedOut = std::move(skipped);
      return {};
    }
    return whole.saveBytes(skipCallbacks, skippedOut);
  }
  std::string bytes;
  if (drop.empty()) {
    bytes = serialize(IoMode::Checkpoint);
  } else {
    BehaviorManager<D> kept = s_.behaviors;
    for (BehaviorId id : drop) kept.remove(id);
    bytes = serialize(IoMode::Checkpoint, &kept);
  }
  if (skippedOut != nullptr) *skippedOut = std::move(skipped);
  return sealCheckpoint(std::move(bytes));
}

template <int D>
void SimulationManager<D>::load(std::istream& in) {
  std::string bytes;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) bytes.append(chunk, size_t(in.gcount()));
  loadBytes(std::move(bytes));
}

template <int D>
void SimulationManager<D>::loadBytes(std::string fileBytes) {
  std::string b = unsealCheckpoint(std::move(fileBytes));
  const FreeAsideOnThrow asideBytes(b);
  Scene<D> fresh;
  const FreeAsideOnThrow asideScene(fresh);
  Reader r(b);
  readScene(r, fresh);
  s_ = std::move(fresh);
  configDirty_ = true;
}

template class SimulationManager<2>;
template class SimulationManager<3>;

}  // namespace demlab::sim
