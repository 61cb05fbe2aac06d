// Contact force modules: grain-grain ("contacts") and grain-wall ("wall-contacts").
//
// The loops are templates over what the scene uses, chosen once when the loop is built:
// whether pair histories are kept (some material has friction), whether grains rotate, and
// the contact law (inline when every material pair of the scene uses one law; otherwise the
// law's function pointer from a per-material-pair table, so the law is resolved once per
// material pair, never by a switch per contact). The walls' narrow phase is looked up once per
// wall in the physics TypeInteractionManager table and run as one batch per wall.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <type_traits>
#include <utility>

#include "core/thread_pool.hpp"
#include "core/type_interaction.hpp"
#include "physics/law_hertz_mindlin.hpp"
#include "physics/law_linear.hpp"
#include "physics/mesh_contact.hpp"
#include "physics/narrow_phase.hpp"
#include "sim/contact_kernel.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// The law a contact loop calls. Law = -1: per-pair function pointer table.
template <int D, int Law>
struct LawCall {
  [[gnu::always_inline]] static physics::ContactForce<D> call(
      const Scene<D>& s, size_t pair, const physics::ContactGeometry<D>& g,
      const physics::ContactKinematics<D>& k, physics::TangentialHistory<D>* h, Real dt) {
    return call(s, s.pairParams[pair], pair, g, k, h, dt);
  }
  // The same with the pair's parameters given (p = s.pairParams[pair]).
  [[gnu::always_inline]] static physics::ContactForce<D> call(
      const Scene<D>& s, const physics::PairParams& p, size_t pair,
      const physics::ContactGeometry<D>& g, const physics::ContactKinematics<D>& k,
      physics::TangentialHistory<D>* h, Real dt) {
    if constexpr (Law == static_cast<int>(physics::LawKind::Linear)) {
      return physics::linearContact<D>(p, g, k, h, dt);
    } else if constexpr (Law == static_cast<int>(physics::LawKind::HertzMindlin)) {
      return physics::hertzMindlinContact<D>(p, g, k, h, dt);
    } else {
      return s.pairLawFn[pair](p, g, k, h, dt);
    }
  }

  // The law's square roots that depend on the overlap and the effective mass and radius only
  // (none for the function pointer table), and the law given them.
  struct NoRoots {};
  using Roots =
      std::conditional_t<Law == static_cast<int>(physics::LawKind::Linear), physics::LinearRoots,
                         std::conditional_t<Law == static_cast<int>(physics::LawKind::HertzMindlin),
                                            physics::HertzMindlinRoots, NoRoots>>;
  [[gnu::always_inline]] static Roots roots(const physics::PairParams& p, Real overlap,
                                            Real effMass, Real effRadius) {
    if constexpr (Law == static_cast<int>(physics::LawKind::Linear)) {
      return physics::linearRoots(p, effMass, effRadius);
    } else if constexpr (Law == static_cast<int>(physics::LawKind::HertzMindlin)) {
      return physics::hertzMindlinRoots(overlap, effMass, effRadius);
    } else {
      return {};
    }
  }
  [[gnu::always_inline]] static physics::ContactForce<D> call(
      const Scene<D>& s, const physics::PairParams& p, size_t pair,
      const physics::ContactGeometry<D>& g, const physics::ContactKinematics<D>& k,
      physics::TangentialHistory<D>* h, Real dt, const Roots& roots) {
    if constexpr (Law == static_cast<int>(physics::LawKind::Linear)) {
      return physics::linearContactWith<D>(p, g, k, h, dt, roots);
    } else if constexpr (Law == static_cast<int>(physics::LawKind::HertzMindlin)) {
      return physics::hertzMindlinContactWith<D>(p, g, k, h, dt, roots);
    } else {
      return s.pairLawFn[pair](p, g, k, h, dt);
    }
  }
};

// Returns how far behind the positions the velocities the laws see are, in steps: 0.5 for
// plain Verlet's half-step velocities, 0 when synchronized (physics/contact.hpp).
template <int D>
Real velocityLag(const Scene<D>& s) {
  return s.integrator == IntegratorKind::Verlet ? 0.5 : 0.0;
}

// Energy sums of one contact pass.
struct PassEnergy {
  double elastic = 0, damping = 0, friction = 0, springWork = 0, wallWork = 0;
  template <int D>
  void add(const physics::ContactForce<D>& f) {
    elastic += f.elasticEnergy;
    damping += f.dampingLoss;
    friction += f.frictionLoss;
    springWork += f.springWork;
  }
  // Adds another part's sums (a group's, a chunk's). Changes *this.
  void merge(const PassEnergy& o) {
    elastic += o.elastic;
    damping += o.damping;
    friction += o.friction;
    springWork += o.springWork;
    wallWork += o.wallWork;
  }
  // Books the contact energies (not the wall work) to the ledger. Changes l.
  void bookTo(LedgerSums& l) const {
    l.elastic += elastic;
    l.dampingLoss += damping;
    l.frictionLoss += friction;
    l.springWork += springWork;
  }
};

// Returns the candidates in a round of a phase of forEachContactGroup: a few milliseconds of
// contacts. A test sets a handful, so that a small bed runs many rounds.
inline size_t& contactRoundCandidates() {
  static size_t n = size_t(1) << 18;
  return n;
}

// Returns the number of groups forEachContactGroup runs: the scene's groups when they cover
// its candidates, else 1 (all candidates as one group). Changes nothing.
template <int D>
size_t contactGroupCount(const Scene<D>& s) {
  return s.contactGroups.cover(s.candidates.size()) ? s.contactGroups.groups.size() : 1;
}

// Runs body(begin, end, group) for every group of candidates of s (ContactGroups): phase after
// phase, the groups of a phase at once on the thread pool, or all candidates as group 0 when
// the groups do not cover them. The body may write the forces and torques of its group's
// elements and what it keeps per candidate or per group, nothing shared. Changes what body
// changes. Polls Ctrl-C between rounds of contactRoundCandidates() candidates (pollStep).
template <int D, class Body>
void forEachContactGroup(const Scene<D>& s, Body&& body) {
  const size_t nc = s.candidates.size();
  const ContactGroups& g = s.contactGroups;
  if (!g.cover(nc)) {
    body(size_t{0}, nc, size_t{0});
    return;
  }
  ThreadPool& pool = ThreadPool::global();
  // Four parts a thread: the pool gives thread t parts 4t .. 4t+3 first, and a thread done
  // early takes parts of a slower one.
  const size_t parts = pool.threads() == 1 ? 1 : 4 * pool.threads();
  std::vector<uint32_t> cut(parts + 1);
  for (const ContactGroups::Range& phase : g.phases) {
    // A phase goes in rounds of whole groups of about contactRoundCandidates(), with a
    // poll for Ctrl-C between them (pollStep): a phase of a bed of millions of grains is tens
    // of milliseconds. The groups of a phase share no element, so their order is free.
    const size_t round = contactRoundCandidates();
    for (uint32_t from = phase.begin; from < phase.end;) {
      if (from > phase.begin) pollStep(s);
      uint32_t to = from + 1;
      const size_t roundStart = g.groups[from].begin;
      while (to < phase.end && g.groups[to].end - roundStart <= round) ++to;
      // Part t is the t-th share of the round's candidates, whole groups in order: groups
      // differ tenfold in size, so equal counts of groups would leave a thread idle.
      const size_t all = g.groups[to - 1].end - roundStart;
      uint32_t k = from;
      for (size_t t = 0; t <= parts; ++t) {
        const size_t want = roundStart + all * t / parts;
        while (k < to && g.groups[k].begin < want) ++k;
        cut[t] = t == parts ? to : k;
      }
      pool.forEach(parts, [&](size_t t, unsigned) {
        for (uint32_t j = cut[t]; j < cut[t + 1]; ++j) {
          body(size_t{g.groups[j].begin}, size_t{g.groups[j].end}, size_t{j});
        }
      });
      from = to;
    }
  }
}

// Appends the records of parts 0 .. parts - 1 (partOf(k): a group's or a chunk's record array,
// kept by a threaded pass) to the scene's in part order, copying the parts at once on the
// thread pool. Changes s.contacts and empties the parts.
template <int D, class PartOf>
void gatherRecords(Scene<D>& s, size_t parts, PartOf&& partOf) {
  const size_t start = s.contacts.size();
  size_t total = start;
  for (size_t k = 0; k < parts; ++k) total += partOf(k).size();
  if (total > s.contacts.capacity()) s.contacts.reserve(total + total / 8);
  s.contacts.resize(total);
  std::vector<size_t> at(parts);
  for (size_t k = 0, o = start; k < parts; o += partOf(k).size(), ++k) at[k] = o;
  ThreadPool::global().forEach(parts, [&](size_t k, unsigned) {
    std::vector<ContactRecord<D>>& part = partOf(k);
    std::copy(part.begin(), part.end(), s.contacts.begin() + static_cast<std::ptrdiff_t>(at[k]));
    part.clear();
  });
}

// Returns true when grainPair (makeContactModules: the pair index of the grains' one material,
// or -1) names a pair of the scene's mixed table. Changes nothing.
template <int D>
bool isOnePair(long grainPair, const Scene<D>& s) {
  return grainPair >= 0 && static_cast<size_t>(grainPair) < s.pairParams.size();
}

// Returns the Hertz-Mindlin constants the SIMD kernels take for a material pair.
inline kernel::HertzPair hertzPairOf(const physics::PairParams& p) {
  return {p.hertzKn, p.hertzKt, p.hertzGammaN, p.hertzGammaT, p.friction};
}

// Returns nothing; points the kernel arguments k (kernel::HertzPassArgs or WallPassArgs) at the
// grain arrays a (Eigen's fixed-size vectors are their D doubles, so they are plain doubles);
// the spin and torque arrays only when grains rotate.
template <bool Rotation, class Args, int D>
void bindGrainArrays(Args& k, ElementArrays<D>& a) {
  k.x = reinterpret_cast<const double*>(a.x.data());
  k.v = reinterpret_cast<const double*>(a.v.data());
  k.f = reinterpret_cast<double*>(a.f.data());
  if constexpr (Rotation) {
    k.w = reinterpret_cast<const double*>(a.w.data());
    k.t = reinterpret_cast<double*>(a.t.data());
  }
  k.r = a.r.data();
  k.invMass = a.invMass.data();
  k.material = a.material.data();
}

// The narrow-phase table for walls: one lookup per wall per step.
template <int D>
struct WallNarrowPhase {
  TypeRegistry types{"shape type"};
  TypeInteractionManager<physics::NarrowPhaseEntry<D>> table{types, "narrow phase"};
  TypeId sphere, byShape[5];  // none for meshes: balls meet them in the shape pass
  WallNarrowPhase() {
    physics::registerNarrowPhase<D>(types, table);
    sphere = types.get("sphere");
    byShape[static_cast<int>(WallShape::Plane)] = types.get("plane");
    byShape[static_cast<int>(WallShape::Finite)] = types.get("flatwall");
    byShape[static_cast<int>(WallShape::Box)] = types.get("box");
    byShape[static_cast<int>(WallShape::Drum)] = types.get("drum");
  }
  static const WallNarrowPhase& get() {
    static const WallNarrowPhase instance;
    return instance;
  }
};

// Returns record c's overlap as a fraction of the smaller radius (a wall's: of the grain's) when
// it is above f, else -1; the watchdog's measure. A ball pair's test needs no square root:
// overlap > f min(ra, rb) <=> distance < ra + rb - f min(ra, rb). Changes nothing.
template <int D>
Real recordOverlapRatio(const Scene<D>& s, const ContactRecord<D>& c, Real f) {
  const ElementArrays<D>& a = s.elements.a;
  if (!c.wall) {
    const Real ra = a.r[c.a], rb = a.r[c.b];
    const Real t = ra + rb - f * std::min(ra, rb);
    if (t <= 0) return -1;  // no distance is that small (equal radii at the default limit 2)
    const Real d2 = (partnerPosition(s, c.a, c.b) - a.x[c.a]).squaredNorm();
    if (d2 >= t * t) return -1;
    return (ra + rb - std::sqrt(d2)) / std::min(ra, rb);
  }
  const Wall<D>& w = s.walls.items[c.b];
  if (const auto* plane = std::get_if<physics::PlaneShape<D>>(&w.shape)) {
    // A plane: the overlap is r minus the signed distance of the centre.
    const Real ratio = 1 - (a.x[c.a] - plane->point).dot(plane->normal) / a.r[c.a];
    return ratio > f ? ratio : -1;
  }
  const physics::SphereShape<D> sa{a.x[c.a], a.r[c.a]};
  if (const auto* mesh = std::get_if<physics::MeshShape<D>>(&w.shape)) {
    // The deepest of the ball's points on the mesh.
    physics::MeshContact<D> mc[16];
    const int n = physics::sphereMeshContacts<D>(sa, *mesh, mc, 16);
    Real ratio = -1;
    for (int k = 0; k < n; ++k) ratio = std::max(ratio, mc[k].g.overlap / a.r[c.a]);
    return ratio > f ? ratio : -1;
  }
  const WallNarrowPhase<D>& np = WallNarrowPhase<D>::get();
  const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, w.shape);
  const auto geo = np.table.get(np.sphere, np.byShape[static_cast<int>(w.kind)]).fn.one(&sa, shape);
  if (!geo) return -1;
  const Real ratio = geo->overlap / a.r[c.a];
  return ratio > f ? ratio : -1;
}

// Where a pass hands a contact: its record to *records (when recording) or, tracking only the
// deepest contact, to *deepest. Changes what it points at.
template <int D>
struct ContactSink {
  std::vector<ContactRecord<D>>* records = nullptr;
  DeepestContact<D>* deepest = nullptr;
  const Scene<D>* s = nullptr;
  bool any() const { return records != nullptr || deepest != nullptr; }
  void put(const ContactRecord<D>& c) const {
    if (records != nullptr) {
      appendRecord<D>(*records, c);
    } else {
      deepest->consider(recordOverlapRatio(*s, c, s->watchdog.overlap), c);
    }
  }
};

template <int D, int Law, bool History, bool Rotation>
class BallContactModule final : public SimModule<D> {
 public:
  // grainPair: the index into s.pairParams of every pair when all grains have one material
  // (makeContactModules), else -1.
  explicit BallContactModule(long grainPair = -1) : grainPair_(grainPair) {}
  std::string_view name() const override { return History ? "contacts-friction" : "contacts"; }
  SimLevel level() const override { return SimLevel::Contacts; }

  void run(Scene<D>& s) override {
    const size_t groups = contactGroupCount(s);
    if (out_.size() < groups) out_.resize(groups);
    // One thread appends the records straight to the scene's, in candidate order; several
    // keep each group's and append them in group order (candidate order) after the pass.
    const bool threaded = ThreadPool::global().threads() > 1 && groups > 1;
    const bool record = s.recordContacts;
    const bool deep = !record && s.trackDeepest;
    for (size_t g = 0; g < groups; ++g) {
      out_[g].energy = {};
      out_[g].contacts = 0;
      out_[g].records.clear();
      out_[g].deepest = {};
    }
    if constexpr (History) {
      if (threaded) s.pairSprings.prepareConcurrent();
    }
    if (s.touchCorrection) {
      // The last step's states become the previous ones; this pass writes every byte of now.
      s.touchPrevValid = s.touchNowCurrent();
      std::swap(s.touchNow, s.touchPrev);
      s.touchNow.resize(s.candidates.size());
    }
    bool ran = false;
    // Periodic scenes measure each pair to the nearest image (sim/periodic.hpp), in both.
    const bool periodic = s.periodic.any();
    if constexpr (kKernel) ran = kernelPass(s, record, deep, threaded);
    if (!ran) {
      forEachContactGroup(s, [&](size_t begin, size_t end, size_t g) {
        const ContactSink<D> sink = sinkOf(s, g, record, deep, threaded);
        const bool one = isOnePair(grainPair_, s);
        if (periodic) {
          one ? pass<true, true>(s, begin, end, out_[g].energy, sink)
              : pass<false, true>(s, begin, end, out_[g].energy, sink);
        } else {
          one ? pass<true, false>(s, begin, end, out_[g].energy, sink)
              : pass<false, false>(s, begin, end, out_[g].energy, sink);
        }
      });
    }
    s.touchNowValid = s.touchCorrection;
    PassEnergy e;
    for (size_t g = 0; g < groups; ++g) e.merge(out_[g].energy);
    // The work of Lees-Edwards images (zero otherwise).
    if (periodic) s.ledger.wallWork += e.wallWork;
    if (record && threaded) {
      gatherRecords(s, groups, [&](size_t g) -> std::vector<ContactRecord<D>>& {
        return out_[g].records;
      });
      // Freed: between steps the records are held once, in the scene.
      for (size_t g = 0; g < groups; ++g) std::vector<ContactRecord<D>>().swap(out_[g].records);
    }
    if (deep) {
      for (size_t g = 0; g < groups; ++g) s.deepest.consider(out_[g].deepest.ratio, out_[g].deepest.record);
    }
    e.bookTo(s.ledger);
  }

  size_t workingBytes() const override {
    size_t bytes = out_.capacity() * sizeof(GroupOut);
    for (const GroupOut& o : out_) bytes += o.records.capacity() * sizeof(ContactRecord<D>);
    return bytes;
  }

 private:
  long grainPair_;
  // Per group: the energy sums, the contacts found, the records (threaded and recording); a
  // cache line each, since the groups of a phase write theirs from different threads.
  struct alignas(64) GroupOut {
    PassEnergy energy;
    size_t contacts = 0;
    std::vector<ContactRecord<D>> records;
    DeepestContact<D> deepest;
  };
  std::vector<GroupOut> out_;

  // Returns the candidates' touch states to write (Scene::touchNow), or null when the touch
  // correction is off. Changes nothing.
  static uint8_t* touchStateOf(Scene<D>& s) {
    return s.touchCorrection ? s.touchNow.data() : nullptr;
  }

  // Returns where group g's contacts go: the scene's records (one thread), the group's (several),
  // the group's deepest contact, or nowhere.
  ContactSink<D> sinkOf(Scene<D>& s, size_t g, bool record, bool deep, bool threaded) {
    ContactSink<D> k;
    k.s = &s;
    if (record) k.records = threaded ? &out_[g].records : &s.contacts;
    if (deep) k.deepest = &out_[g].deepest;
    return k;
  }

  // 3D Hertz-Mindlin beds go through the SIMD contact kernel (contact_kernel.hpp) when the
  // platform has one: the same arithmetic in the same order as pass() below, several contacts
  // per register. $DEMLAB_KERNEL=eigen (or kernel::setActive) keeps pass().
  static constexpr bool kKernel = D == 3 && Law == static_cast<int>(physics::LawKind::HertzMindlin);
  kernel::HertzPassFn kernelFn_ = nullptr;
  kernel::Isa kernelIsa_{};
  std::vector<kernel::HertzPair> kernelPairs_;
  // Prefetching pays on beds whose grain arrays outgrow the shared cache (mono_100k_dense: a
  // quarter off the pass) and costs a few percent below it (10^4 and 2 10^4 grains); the grain
  // state's lines only where most candidates touch (mono_100k, a falling lattice, pays 24
  // instructions per candidate for them and gains nothing).
  static constexpr size_t kPrefetchGrains = 65536;
  size_t lastContacts_ = 0;

  // Where a group's kernel contacts go: the group's first candidate and its sink; in a
  // Lees-Edwards scene, the images' work of its contacts through the sliding boundary.
  struct RecordSink {
    const Scene<D>* s;
    size_t base;
    ContactSink<D> sink;
    double imageWork = 0;
  };
  // Hands the kernel's contacts to the sink (kernel::HertzPassArgs::record).
  static void appendRecords(void* sink, const uint32_t* cand, const double* force, size_t n) {
    RecordSink& k = *static_cast<RecordSink*>(sink);
    if (k.s->periodic.sheared()) addImageWork(k, cand, force, n);
    if (!k.sink.any()) return;
    for (size_t c = 0; c < n; ++c) {
      const CandidatePair p = k.s->candidates[k.base + cand[c]];
      k.sink.put({p.i, p.j, false, VecD<D>(force + 3 * c)});
    }
  }
  // Adds the images' work of the contacts through the sliding boundary (as pass() books it,
  // contact by contact in candidate order). Changes k.imageWork.
  static void addImageWork(RecordSink& k, const uint32_t* cand, const double* force, size_t n) {
    const PeriodicBox<D>& box = k.s->periodic;
    const VecD<D>* x = k.s->elements.a.x.data();
    for (size_t c = 0; c < n; ++c) {
      const CandidatePair p = k.s->candidates[k.base + cand[c]];
      const int crossed = box.gradientCrossings(x[p.j] - x[p.i]);
      if (crossed != 0) k.imageWork += box.imageWork(crossed, force[3 * c + box.flow], k.s->stepDt);
    }
  }

  // Returns false, changing nothing, when no kernel is active; else runs the pass through it,
  // group by group (threaded: see run()), each group's energy sums into energy_.
  bool kernelPass(Scene<D>& s, bool record, bool deep, bool threaded) {
    kernel::Isa isa;
    if (!kernel::activeIsa(&isa)) return false;
    if (kernelFn_ == nullptr || isa != kernelIsa_) {
      kernelFn_ = kernel::hertzPass(isa, History, Rotation);
      kernelIsa_ = isa;
      if (kernelFn_ == nullptr) return false;
    }
    static_assert(sizeof(VecD<D>) == D * sizeof(double) &&
                  sizeof(AngularD<D>) == D * sizeof(double));
    static_assert(sizeof(CandidatePair) == 2 * sizeof(uint32_t));
    ElementArrays<D>& a = s.elements.a;
    const bool one = isOnePair(grainPair_, s);
    const size_t nPairs = one ? 1 : s.pairParams.size();
    kernelPairs_.resize(nPairs);
    for (size_t k = 0; k < nPairs; ++k) {
      kernelPairs_[k] = hertzPairOf(s.pairParams[one ? static_cast<size_t>(grainPair_) : k]);
    }
    kernel::HertzPassArgs base;
    bindGrainArrays<Rotation>(base, a);
    base.pairs = kernelPairs_.data();
    base.nMat = s.nMat();
    base.onePair = one;
    base.dt = s.stepDt;
    base.lag = velocityLag(s);
    base.springCriterion = s.coulomb == physics::CoulombCriterion::Spring;
    // Dense: the last pass found contacts for more than a quarter of its candidates.
    const bool dense = 4 * lastContacts_ > s.candidates.size();
    base.prefetch = a.size() > kPrefetchGrains ? (dense ? 2 : 1) : 0;
    // $DEMLAB_PREFETCH (0, 1, 2) overrides the choice, for measuring it.
    static const int forced = [] {
      const char* pf = std::getenv("DEMLAB_PREFETCH");
      return pf != nullptr && pf[0] >= '0' && pf[0] <= '2' ? pf[0] - '0' : -1;
    }();
    if (forced >= 0) base.prefetch = forced;
    base.touchState = touchStateOf(s);
    const uint32_t* cand = reinterpret_cast<const uint32_t*>(s.candidates.data());
    kernel::PeriodicCell cell;
    if (s.periodic.any()) {
      const PeriodicBox<D>& box = s.periodic;
      for (int k = 0; k < D; ++k) cell.length[k] = box.periodic(k) ? box.length(k) : 0.0;
      if (box.sheared()) {
        cell.speed = box.shearSpeed();
        cell.offset = box.offset;
        cell.flow = box.flow;
        cell.gradient = box.gradient;
      }
      base.periodic = &cell;
    }
    forEachContactGroup(s, [&](size_t begin, size_t end, size_t g) {
      if (end == begin) return;
      kernel::HertzPassArgs k = base;
      k.cand = cand + 2 * begin;
      k.nCand = end - begin;
      if (base.touchState != nullptr) k.touchState = base.touchState + begin;
      kernel::SpringSlots slots;
      if constexpr (History) {
        slots = s.pairSprings.slots(begin);
        k.springs = &slots;
      }
      // The deepest contact the watchdog reads between records: kept by the kernel itself.
      if (deep) k.deepLimit = s.watchdog.overlap;
      RecordSink sink{&s, begin, sinkOf(s, g, record, false, threaded)};
      if (sink.sink.any() || s.periodic.sheared()) {
        k.record = &appendRecords;
        k.recordContext = &sink;
      }
      kernelFn_(k);
      if (k.deepRatio > out_[g].deepest.ratio) {
        const CandidatePair p = s.candidates[begin + k.deepCand];
        out_[g].deepest.consider(k.deepRatio, {p.i, p.j, false, VecD<D>::Zero()});
      }
      out_[g].contacts = k.contacts;
      out_[g].energy = {k.elastic, k.damping, k.friction, k.springWork, sink.imageWork};
    });
    lastContacts_ = 0;
    for (size_t g = 0; g < contactGroupCount(s); ++g) lastContacts_ += out_[g].contacts;
    return true;
  }

  // The sphere-sphere narrow phase is inline here (physics::intersect's geometry, without the
  // optional and the contact point): one sqrt and one division per contact, the division
  // shared by the normal, the effective mass and the effective radius. For spheres the lever
  // arms are along the normal, (r_i - overlap/2) n from A's centre and -(r_j - overlap/2) n from
  // B's, so the relative velocity and both torques take one cross product each.
  //
  // The candidates go in batches of kBatch, in three passes: the first finds the touching pairs
  // of the batch, the second takes their geometry and the law's square roots (LawCall::roots),
  // the third runs the law on them in candidate order. The square roots and the division of one
  // contact depend on each other; taken for many contacts in a row their latencies overlap, where
  // in one pass over each contact they set its pace. The arithmetic and its order are those of one
  // pass: the results are the same to the bit.
  static constexpr size_t kBatch = 64;

  // Runs candidates begin .. end - 1, adding their energies to e and handing their contacts to
  // the sink.
  template <bool OnePair, bool Periodic>
  void pass(Scene<D>& s, size_t begin, size_t end, PassEnergy& e, const ContactSink<D>& sink) {
    using Call = LawCall<D, Law>;
    ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt;
    const size_t nMat = s.nMat();
    const Real lag = velocityLag(s);
    const VecD<D>* __restrict x = a.x.data();
    const VecD<D>* __restrict v = a.v.data();
    const AngularD<D>* __restrict w = a.w.data();
    VecD<D>* __restrict force = a.f.data();
    AngularD<D>* __restrict torque = a.t.data();
    const Real* __restrict r = a.r.data();
    const Real* __restrict invMass = a.invMass.data();
    const uint32_t* __restrict material = a.material.data();
    const CandidatePair* __restrict cand = s.candidates.data();
    PairSprings<D>& springs = s.pairSprings;
    uint8_t* state = touchStateOf(s);
    const size_t nc = end;
    physics::PairParams one;
    if constexpr (OnePair) one = s.pairParams[static_cast<size_t>(grainPair_)];
    // The batch: candidate index, pair index, geometry, effective mass and radius, roots.
    uint32_t bk[kBatch];
    size_t bp[kBatch];
    physics::ContactGeometry<D> bg[kBatch];
    Real bm[kBatch], br[kBatch];
    typename Call::Roots broots[kBatch];
    // Periodic: the vector to the nearest image, and the Lees-Edwards cells crossed.
    const PeriodicBox<D>& box = s.periodic;
    int bn[kBatch];
    const auto between = [&](uint32_t i, uint32_t j, int* n) -> VecD<D> {
      if constexpr (Periodic) {
        return box.nearest(x[j] - x[i], n);
      } else {
        *n = 0;
        return x[j] - x[i];
      }
    };
    for (size_t k0 = begin; k0 < nc; k0 += kBatch) {
      const size_t kEnd = std::min(nc, k0 + kBatch);
      // The touching candidates of the batch, without a branch on each (about half touch, in
      // no order a predictor could learn); a pair that stopped touching gives its spring's
      // slot back (sim/pair_springs.hpp).
      size_t m = 0;
      for (size_t kc = k0; kc < kEnd; ++kc) {
        const uint32_t i = cand[kc].i, j = cand[kc].j;
        const Real rs = r[i] + r[j];
        int crossed;
        const bool touch = between(i, j, &crossed).squaredNorm() < rs * rs;
        bk[m] = static_cast<uint32_t>(kc);
        m += touch;
        if constexpr (History) {
          if (!touch) springs.release(kc);
        }
      }
      if (state != nullptr) {
        std::memset(state + k0, 0, kEnd - k0);
        for (size_t c = 0; c < m; ++c) state[bk[c]] = kernel::kTouching;
      }
      for (size_t c = 0; c < m; ++c) {
        const uint32_t i = cand[bk[c]].i, j = cand[bk[c]].j;
        const VecD<D> d = between(i, j, &bn[c]);
        const Real ri = r[i], rj = r[j];
        const Real rs = ri + rj;
        const Real d2 = d.squaredNorm();
        const Real sumInvMass = invMass[i] + invMass[j];
        physics::ContactGeometry<D>& g = bg[c];
        Real effMass, effRadius;
        if (d2 > 0) [[likely]] {
          const Real dist = std::sqrt(d2);
          const Real srs = sumInvMass * rs;
          const Real q = 1 / (dist * srs);
          g.normal = d * (q * srs);
          g.overlap = rs - dist;
          effMass = q * dist * rs;
          effRadius = ri * rj * sumInvMass * dist * q;
        } else {
          // Coincident centres: the first axis, as physics::intersect.
          g.normal = VecD<D>::Unit(0);
          g.overlap = rs;
          effMass = 1 / sumInvMass;
          effRadius = ri * rj / rs;
        }
        const size_t pair = OnePair ? 0 : material[i] * nMat + material[j];
        broots[c] = Call::roots(OnePair ? one : s.pairParams[pair], g.overlap, effMass, effRadius);
        bp[c] = pair;
        bm[c] = effMass;
        br[c] = effRadius;
      }
      for (size_t c = 0; c < m; ++c) {
        const size_t k0 = bk[c];
        // A (i) is the grain with the lower global id (the search orders each pair so), so a pair's
        // spring keeps one orientation.
        const uint32_t i = cand[k0].i, j = cand[k0].j;
        const physics::ContactGeometry<D>& g = bg[c];
        const Real armA = r[i] - 0.5 * g.overlap, armB = r[j] - 0.5 * g.overlap;
        VecD<D> vrel = v[j] - v[i];
        if constexpr (Periodic) {
          // Through the sliding boundary the other's image moves with -n U along the flow.
          if (bn[c] != 0) vrel[box.flow] -= bn[c] * box.shearSpeed();
        }
        if constexpr (Rotation) vrel -= cross(armA * w[i] + armB * w[j], g.normal);
        const physics::ContactKinematics<D> k{vrel, bm[c], br[c], lag};
        physics::TangentialHistory<D>* h = nullptr;
        if constexpr (History) h = springs.at(k0);
        physics::ContactForce<D> f;
        if constexpr (OnePair) {
          f = Call::call(s, one, static_cast<size_t>(grainPair_), g, k, h, dt, broots[c]);
        } else {
          f = Call::call(s, s.pairParams[bp[c]], bp[c], g, k, h, dt, broots[c]);
        }
        force[j] += f.force;
        force[i] -= f.force;
        if constexpr (Rotation) {
          const AngularD<D> cn = cross(g.normal, f.force);
          torque[i] -= armA * cn;
          torque[j] -= armB * cn;
        }
        e.add(f);
        if (state != nullptr && f.cutOff) state[k0] |= kernel::kCutOff;
        if constexpr (Periodic) {
          if (bn[c] != 0) e.wallWork += box.imageWork(bn[c], f.force[box.flow], dt);
        }
        if (sink.any()) sink.put({i, j, false, f.force});
      }
    }
  }
};

template <int D, int Law, bool History, bool Rotation>
class WallContactModule final : public SimModule<D> {
 public:
  std::string_view name() const override {
    return History ? "wall-contacts-friction" : "wall-contacts";
  }
  SimLevel level() const override { return SimLevel::Contacts; }
  // (A distributed run's wall candidates are its owned elements': sim/detection.hpp.)
  bool ownedOnly() const override { return true; }

  // grainPair: as BallContactModule's (the one grain material m's pair m * nMat + m, or -1).
  explicit WallContactModule(long grainPair = -1) : grainPair_(grainPair) {}

  // The walls run one after another (a grain may touch several); each wall's candidates, in
  // chunks of kChunk, at once on the thread pool: a wall lists a grain once, so its chunks
  // write different grains. Each chunk sums its wall force and energies from zero and the
  // chunks' sums are added in chunk order: the chunks are fixed by the candidates alone, so
  // the bits are the same for any number of threads.
  void run(Scene<D>& s) override {
    const bool threaded = ThreadPool::global().threads() > 1;
    if (s.touchCorrection) {
      // As the grain pass's touch states (BallContactModule::run), per wall.
      s.wallTouchPrevValid = s.wallTouchNowCurrent();
      std::swap(s.wallTouchNow, s.wallTouchPrev);
      s.wallTouchNow.resize(s.walls.size());
      for (size_t w = 0; w < s.walls.size(); ++w) {
        s.wallTouchNow[w].resize(w < s.wallCandidates.size() ? s.wallCandidates[w].size() : 0);
      }
    }
    PassEnergy e;
    for (size_t w = 0; w < s.walls.size(); ++w) {
      Wall<D>& wall = s.walls.items[w];
      wall.force.setZero();
      if (w >= s.wallCandidates.size()) continue;
      const size_t nw = s.wallCandidates[w].size();
      if (nw == 0) continue;
      const size_t chunks = (nw + kChunk - 1) / kChunk;
      if (chunks_.size() < chunks) chunks_.resize(chunks);
      ThreadPool::global().forEach(chunks, [&](size_t c, unsigned) {
        Chunk& k = chunks_[c];
        k.force.setZero();
        k.energy = {};
        k.records.clear();
        k.deepest = {};
        const size_t begin = c * kChunk, end = std::min(nw, begin + kChunk);
        ContactSink<D> sink;
        sink.s = &s;
        if (s.recordContacts) sink.records = threaded ? &k.records : &s.contacts;
        if (!s.recordContacts && s.trackDeepest) sink.deepest = &k.deepest;
        if (isOnePair(grainPair_, s)) {
          pass<true>(s, w, begin, end, k, sink);
        } else {
          pass<false>(s, w, begin, end, k, sink);
        }
      });
      double work = 0;  // this wall's, in chunk order as the ledger's
      for (size_t c = 0; c < chunks; ++c) {
        Chunk& k = chunks_[c];
        wall.force += k.force;
        work += k.energy.wallWork;
        e.merge(k.energy);
        s.deepest.consider(k.deepest.ratio, k.deepest.record);
      }
      wall.work += work;
      if (threaded && s.recordContacts) {
        gatherRecords(s, chunks, [&](size_t c) -> std::vector<ContactRecord<D>>& {
          return chunks_[c].records;
        });
        for (size_t c = 0; c < chunks; ++c) std::vector<ContactRecord<D>>().swap(chunks_[c].records);
      }
    }
    s.wallTouchNowValid = s.touchCorrection;
    e.bookTo(s.ledger);
    s.ledger.wallWork += e.wallWork;
  }

  size_t workingBytes() const override {
    size_t bytes = chunks_.capacity() * sizeof(Chunk);
    for (const Chunk& k : chunks_) {
      bytes += k.geoms.capacity() * sizeof(physics::ContactGeometry<D>) +
               (k.touched.capacity() + k.slots.capacity()) * sizeof(uint32_t) +
               k.cut.capacity() +
               k.records.capacity() * sizeof(ContactRecord<D>) +
               k.pairs.capacity() * sizeof(kernel::HertzPair);
    }
    return bytes;
  }

 private:
  static constexpr size_t kChunk = 512;
  long grainPair_;

  // One chunk's scratch (the narrow phase's contacts and grains, the kernel's spring slots and
  // constants) and results (the force on the wall, the energies, the records when threaded);
  // cache lines of its own, since chunks run on different threads.
  struct alignas(64) Chunk {
    std::vector<physics::ContactGeometry<D>> geoms;
    std::vector<uint32_t> touched, slots;
    std::vector<uint8_t> cut;  // with touch states: the kernel's cut-offs, per contact
    std::vector<kernel::HertzPair> pairs;
    std::vector<ContactRecord<D>> records;
    VecD<D> force = VecD<D>::Zero();
    PassEnergy energy;
    DeepestContact<D> deepest;
  };
  std::vector<Chunk> chunks_;

  // Runs wall w's candidates begin .. end - 1 (OnePair: every grain has one material, so the
  // wall has one PairParams, read once): the grains' forces and torques, their springs, the
  // chunk's wall force and energies; records to *rec when rec is not null.
  template <bool OnePair>
  void pass(Scene<D>& s, size_t w, size_t begin, size_t end, Chunk& ch, const ContactSink<D>& sink) {
    ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt;
    const size_t nMat = s.nMat();
    const Real lag = velocityLag(s);
    const WallNarrowPhase<D>& np = WallNarrowPhase<D>::get();
    const VecD<D>* __restrict x = a.x.data();
    const VecD<D>* __restrict v = a.v.data();
    const AngularD<D>* __restrict wv = a.w.data();
    VecD<D>* __restrict force = a.f.data();
    AngularD<D>* __restrict torque = a.t.data();
    const Real* __restrict r = a.r.data();
    const Real* __restrict invMass = a.invMass.data();
    const uint32_t* __restrict material = a.material.data();
    // The grains' one material (grainPair_ = m nMat + m).
    const size_t grainMat = OnePair ? static_cast<size_t>(grainPair_) / (nMat + 1) : 0;
    PassEnergy& e = ch.energy;
    Wall<D>& wall = s.walls.items[w];
    const uint32_t* which = s.wallCandidates[w].data() + begin;
    const size_t nWhich = end - begin;
    ch.geoms.resize(nWhich);
    ch.touched.resize(nWhich);
    const auto& entry = np.table.get(np.sphere, np.byShape[static_cast<int>(wall.kind)]).fn;
    const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, wall.shape);
    const size_t m = entry.grains(shape, a.x.data(), a.r.data(), which, nWhich, ch.geoms.data(),
                                  ch.touched.data());
    const size_t wallPair = grainMat * nMat + wall.material;
    physics::PairParams one;
    if constexpr (OnePair) one = s.pairParams[wallPair];
    physics::TangentialHistory<D>* __restrict springs = nullptr;
    if constexpr (History) springs = s.wallSprings[w].data() + begin;
    // With the touch correction: the candidates' states, touching first (the laws add the
    // cut-offs); ch.slots maps each contact to its candidate.
    uint8_t* state = s.touchCorrection ? s.wallTouchNow[w].data() + begin : nullptr;
    if (state != nullptr) {
      std::memset(state, 0, nWhich);
      mapContacts(ch, which, m);
      for (size_t c = 0; c < m; ++c) state[ch.slots[c]] = kernel::kTouching;
    }
    if constexpr (kKernel) {
      if (!wall.moving && kernelWall(s, w, m, which, nWhich, springs, ch, sink, state)) return;
    }
    // touched lists the grains in contact in the order of `which`: walk both to find each
    // contact's candidate index (its spring slot), zeroing the springs of those not touched.
    size_t kc = 0;
    for (size_t c = 0; c < m; ++c) {
      const uint32_t i = ch.touched[c];
      if constexpr (History) {
        while (which[kc] != i) springs[kc++] = {};
      }
      const physics::ContactGeometry<D>& g = ch.geoms[c];
      const VecD<D> vWall = wall.surfaceVelocity(g.point);
      VecD<D> vrel = vWall - v[i];
      VecD<D> arm;
      if constexpr (Rotation) {
        arm = g.point - x[i];
        vrel -= cross(wv[i], arm);
      }
      const physics::ContactKinematics<D> k{vrel, 1.0 / invMass[i], r[i], lag};
      physics::TangentialHistory<D>* h = nullptr;
      if constexpr (History) h = &springs[kc++];
      physics::ContactForce<D> f;
      if constexpr (OnePair) {
        f = LawCall<D, Law>::call(s, one, wallPair, g, k, h, dt);
      } else {
        f = LawCall<D, Law>::call(s, material[i] * nMat + wall.material, g, k, h, dt);
      }
      force[i] -= f.force;
      if constexpr (Rotation) torque[i] -= cross(arm, f.force);
      ch.force += f.force;
      e.add(f);
      if (state != nullptr && f.cutOff) state[ch.slots[c]] |= kernel::kCutOff;
      // Work done by the moving wall on the grain over the step.
      if (wall.moving) e.wallWork -= f.force.dot(vWall) * dt;
      if (sink.any()) sink.put({i, static_cast<uint32_t>(w), true, f.force});
    }
    if constexpr (History) {
      while (kc < nWhich) springs[kc++] = {};
    }
  }

  // Static walls of 3D Hertz-Mindlin scenes go through the SIMD kernel (contact_kernel.hpp:
  // the same arithmetic in the same order as the loop in pass()), when the platform has one.
  static constexpr bool kKernel = D == 3 && Law == static_cast<int>(physics::LawKind::HertzMindlin);
  struct RecordSink {
    ContactSink<D> sink;
    const uint32_t* grain;
    uint32_t wall;
  };
  static void appendRecords(void* sink, const uint32_t* c, const double* force, size_t n) {
    const RecordSink& k = *static_cast<const RecordSink*>(sink);
    for (size_t j = 0; j < n; ++j) k.sink.put({k.grain[c[j]], k.wall, true, VecD<D>(force + 3 * j)});
  }

  // Sets ch.slots to the candidate index of each of the chunk's m contacts (ch.touched lists
  // the touching grains in the order of which). Changes ch.slots.
  static void mapContacts(Chunk& ch, const uint32_t* which, size_t m) {
    ch.slots.resize(m);
    size_t kc = 0;
    for (size_t c = 0; c < m; ++c) {
      while (which[kc] != ch.touched[c]) ++kc;
      ch.slots[c] = static_cast<uint32_t>(kc++);
    }
  }

  // Returns false, changing nothing, when no kernel is active; else runs the chunk's m
  // contacts (ch.geoms, ch.touched; candidates which[0 .. nWhich), springs from springs[0])
  // through it, adding the cut-offs to the candidates' touch states when state is not null
  // (ch.slots then mapped by the caller).
  bool kernelWall(Scene<D>& s, size_t w, size_t m, const uint32_t* which, size_t nWhich,
                  physics::TangentialHistory<D>* springs, Chunk& ch, const ContactSink<D>& sink,
                  uint8_t* state) {
    kernel::Isa isa;
    if (!kernel::activeIsa(&isa)) return false;
    const kernel::WallPassFn fn = kernel::wallPass(isa, History, Rotation);
    if (fn == nullptr) return false;
    static_assert(sizeof(physics::ContactGeometry<D>) == 7 * sizeof(double));
    ElementArrays<D>& a = s.elements.a;
    Wall<D>& wall = s.walls.items[w];
    const size_t nMat = s.nMat();
    const bool one = isOnePair(grainPair_, s);
    ch.pairs.resize(one ? 1 : nMat);
    for (size_t k = 0; k < ch.pairs.size(); ++k) {
      const size_t mat = one ? static_cast<size_t>(grainPair_) / (nMat + 1) : k;
      const physics::PairParams& p = s.pairParams[mat * nMat + wall.material];
      ch.pairs[k] = {p.hertzKn, p.hertzKt, p.hertzGammaN, p.hertzGammaT, p.friction};
    }
    kernel::WallPassArgs k;
    if constexpr (History) {
      // Each contact's candidate index (its spring slot; mapped already with touch states);
      // the springs of the others zeroed.
      if (state == nullptr) mapContacts(ch, which, m);
      size_t kc = 0;
      for (size_t c = 0; c < m; ++c) {
        while (kc < ch.slots[c]) springs[kc++] = {};
        ++kc;
      }
      while (kc < nWhich) springs[kc++] = {};
      k.slot = ch.slots.data();
      k.springs = reinterpret_cast<double*>(springs);
    }
    bindGrainArrays<Rotation>(k, a);
    k.geometry = reinterpret_cast<const double*>(ch.geoms.data());
    k.grain = ch.touched.data();
    k.n = m;
    k.pairs = ch.pairs.data();
    k.onePair = one;
    k.dt = s.stepDt;
    k.lag = velocityLag(s);
    k.springCriterion = s.coulomb == physics::CoulombCriterion::Spring;
    RecordSink rs{sink, ch.touched.data(), static_cast<uint32_t>(w)};
    if (sink.any()) {
      k.record = &appendRecords;
      k.recordContext = &rs;
    }
    if (state != nullptr) {
      ch.cut.assign(m, 0);
      k.cutOff = ch.cut.data();
    }
    if (m > 0) fn(k);
    if (state != nullptr) {
      // (ch.slots: the candidate of each contact, as above)
      for (size_t c = 0; c < m; ++c) {
        if (ch.cut[c] != 0) state[ch.slots[c]] |= kernel::kCutOff;
      }
    }
    for (int c = 0; c < D; ++c) ch.force[c] = k.wallForce[c];
    ch.energy = {k.elastic, k.damping, k.friction, k.springWork, 0};
    return true;
  }
};

// Returns the grain-grain and grain-wall contact modules for the scene's law set, history and
// rotation flags. law: the one law of every pair, or -1 for mixed laws; grainPair: the index
// into Scene::pairParams of every grain-grain pair when all grains have one material, or -1.
template <int D>
std::vector<std::unique_ptr<SimModule<D>>> makeContactModules(int law, bool history, bool rotation,
                                                              bool walls, long grainPair = -1);

}  // namespace demlab::sim
