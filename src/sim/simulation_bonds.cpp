// SimulationManager<D>: bonds (models, making, removing, breaking, querying, their time-step
// bound). The force pass is sim/bond_module.hpp; the models are sim/bond_models/.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "core/free_aside.hpp"
#include "core/interrupt.hpp"
#include "core/name_lookup.hpp"
#include "search/cgrid.hpp"
#include "sim/bond_module.hpp"
#include "sim/convert.hpp"
#include "sim/simulation_manager.hpp"

namespace demlab::sim {

namespace {

// Returns a standard normal deviate that depends on seed and k alone (splitmix64 and
// Box-Muller): a bond's strengths do not depend on the order bonds are made in.
double normalDeviate(uint64_t seed, uint64_t k) {
  auto mix = [](uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  };
  const uint64_t h1 = mix(seed * 0x9e3779b97f4a7c15ull + k);
  const uint64_t h2 = mix(h1 + 0x9e3779b97f4a7c15ull);
  const double u1 = (static_cast<double>(h1 >> 11) + 0.5) / 9007199254740992.0;
  const double u2 = static_cast<double>(h2 >> 11) / 9007199254740992.0;
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * std::numbers::pi * u2);
}

// Calls pair(i, j) once for every pair of overlapping boxes (in no set order), searching with
// CGrid in slabs along the first axis of about kSlabBoxes boxes each, Ctrl-C polled between
// them: one search over a million boxes takes half a second, and a slab of 2^15 boxes a few
// hundredths (page faults included) on a slow machine. A pair is reported by the slab
// where its boxes' overlap begins along the axis, which holds both boxes. Throws
// demlab::Error {INTERRUPTED} between slabs.
template <int D, class Pair>
void searchInSlabs(const std::vector<search::Box<D, double>>& boxes, const Pair& pair) {
  constexpr size_t kSlabBoxes = size_t(1) << 15;
  const size_t n = boxes.size();
  const size_t slabs = std::max<size_t>(1, n / kSlabBoxes);
  std::vector<double> cut(slabs + 1);
  {
    std::vector<double> lo(n);
    for (size_t k = 0; k < n; ++k) lo[k] = boxes[k].lo[0];
    std::sort(lo.begin(), lo.end());
    for (size_t s = 1; s < slabs; ++s) cut[s] = lo[s * n / slabs];
  }
  cut[0] = -std::numeric_limits<double>::infinity();
  cut[slabs] = std::numeric_limits<double>::infinity();
  std::vector<search::Box<D, double>> sub;
  std::vector<uint32_t> which;
  std::vector<search::IndexPair> found;
  search::CGrid<D, double> grid;
  for (size_t s = 0; s < slabs; ++s) {
    pollInterrupt("bond add");
    if (!(cut[s] < cut[s + 1])) continue;  // between two equal cuts: no overlap begins here
    sub.clear();
    which.clear();
    for (size_t k = 0; k < n; ++k) {
      if (boxes[k].hi[0] >= cut[s] && boxes[k].lo[0] < cut[s + 1]) {
        sub.push_back(boxes[k]);
        which.push_back(uint32_t(k));
      }
    }
    grid.findPairs(sub, found);
    for (const search::IndexPair& p : found) {
      const uint32_t i = which[p.first], j = which[p.second];
      const double begins = std::max(boxes[i].lo[0], boxes[j].lo[0]);
      if (begins >= cut[s] && begins < cut[s + 1]) pair(i, j);
    }
  }
}

const char* modeName(BondBreakMode m) {
  return m == BondBreakMode::Tension ? "tension" : "shear";
}

}  // namespace

template <int D>
uint32_t SimulationManager<D>::bondModelIndex(const std::string& name) const {
  const auto& ms = s_.bonds.models;
  for (size_t k = 0; k < ms.size(); ++k) {
    if (ms[k].name == name) return static_cast<uint32_t>(k);
  }
  throw Error("no bond model named \"" + name + "\"", {"LOOKUP", "BONDMODEL"});
}

template <int D>
void SimulationManager<D>::addBondModel(const std::string& name, const std::string& type,
                                        const std::vector<std::pair<std::string, double>>& values) {
  checkObjectName("bond model", name);
  for (const BondModel& m : s_.bonds.models) {
    if (m.name == name) {
      throw Error("bond model \"" + name + "\" already exists", {"EXISTS", "BONDMODEL"});
    }
  }
  BondModel m;
  m.name = name;
  m.type = bondModelType(type);
  const BondModelType& t = bondModelTypes()[m.type];
  m.values.resize(t.options.size());
  for (size_t k = 0; k < t.options.size(); ++k) m.values[k] = t.options[k].fallback;
  for (const auto& [key, x] : values) {
    size_t k = 0;
    while (k < t.options.size() && t.options[k].name != key) ++k;
    if (k == t.options.size()) {
      throw Error("bad option \"" + key + "\": a " + type + " bond has no such option",
                  {"VALUE", "OPTION"});
    }
    const BondOption& o = t.options[k];
    const bool ok = o.strict ? x > o.min : x >= o.min;
    if (std::isnan(x) || !ok || (std::isinf(x) && o.name != "tensile" && o.name != "shear")) {
      throwBad(o.name, physics::formatReal(x),
               std::string("must be ") + (o.strict ? "> " : ">= ") + physics::formatReal(o.min) +
                   " and finite");
    }
    m.values[k] = x;
  }
  for (size_t k = 0; k < t.options.size(); ++k) {
    if (std::isnan(m.values[k])) {
      throw Error("missing option \"-" + t.options[k].name + "\" of a " + type + " bond",
                  {"VALUE", "OPTION"});
    }
  }
  s_.bonds.models.push_back(std::move(m));
}

template <int D>
std::vector<BondModelInfo> SimulationManager<D>::bondModels() const {
  std::vector<BondModelInfo> out;
  for (const BondModel& m : s_.bonds.models) {
    const BondModelType& t = bondModelTypes()[m.type];
    BondModelInfo i{m.name, t.name, {}};
    for (size_t k = 0; k < t.options.size(); ++k)
      i.values.emplace_back(t.options[k].name, m.values[k]);
    out.push_back(std::move(i));
  }
  return out;
}

template <int D>
std::vector<uint32_t> SimulationManager<D>::makeBonds(
    const std::vector<std::pair<uint32_t, uint32_t>>& pairs, uint32_t m) {
  const BondModel& model = s_.bonds.models[m];
  const BondModelType& t = bondModelTypes()[model.type];
  const double tensile = bondOption(t, model.values, "tensile");
  const double shear = bondOption(t, model.values, "shear");
  const double scatter = bondOption(t, model.values, "scatter");
  const auto seed = static_cast<uint64_t>(bondOption(t, model.values, "seed"));
  const ElementArrays<D>& a = s_.elements.a;
  // Made aside, then appended: Ctrl-C while they are made leaves no bond.
  std::vector<Bond<D>> made;
  made.reserve(pairs.size());
  InterruptPoll poll("bond add");
  uint32_t next = s_.bonds.nextId;
  for (const auto& [i, j] : pairs) {
    poll();
    Bond<D> b;
    b.id = next++;
    b.a = s_.elements.pool().handleAt(i);
    b.b = s_.elements.pool().handleAt(j);
    b.model = m;
    b.restLength = (a.x[j] - a.x[i]).norm();
    b.tensile = tensile;
    b.shear = shear;
    if (scatter > 0) {
      // Two independent draws per bond: tensile and shear strengths scatter independently.
      b.tensile = std::max(0.0, tensile * (1 + scatter * normalDeviate(seed, 2ull * b.id)));
      b.shear = std::max(0.0, shear * (1 + scatter * normalDeviate(seed, 2ull * b.id + 1)));
    }
    made.push_back(b);
  }
  std::vector<uint32_t> ids;
  ids.reserve(made.size());
  for (const Bond<D>& b : made) {
    poll();
    ids.push_back(b.id);
  }
  // The room first touched while Ctrl-C is polled: the append below cannot stop half way.
  const size_t total = s_.bonds.bonds.size() + made.size();
  s_.bonds.bonds.reserve(total);
  touchRoom(s_.bonds.bonds, total, Bond<D>{}, "bond add");
  s_.bonds.bonds.insert(s_.bonds.bonds.end(), made.begin(), made.end());
  s_.bonds.nextId = next;
  if (!ids.empty()) touchConfig();
  return ids;
}

template <int D>
std::vector<uint32_t> SimulationManager<D>::addBonds(
    const std::vector<std::pair<ElementId, ElementId>>& pairs, const std::string& model) {
  const uint32_t m = bondModelIndex(model);
  std::set<std::pair<uint32_t, uint32_t>> seen;
  for (const Bond<D>& b : s_.bonds.bonds) {
    seen.insert(std::minmax(b.a.index, b.b.index));
  }
  std::vector<std::pair<uint32_t, uint32_t>> dense;
  for (const auto& [p, q] : pairs) {
    const uint32_t i = s_.elements.index(p), j = s_.elements.index(q);
    if (i == j) {
      throw Error("bad pair \"" + toString(p) + " " + toString(q) +
                      "\": an element can't be bonded to itself",
                  {"VALUE", "PAIR"});
    }
    if (!seen.insert(std::minmax(p.index, q.index)).second) {
      throw Error("bad pair \"" + toString(p) + " " + toString(q) + "\": already bonded",
                  {"VALUE", "PAIR"});
    }
    dense.emplace_back(i, j);
  }
  return makeBonds(dense, m);
}

template <int D>
std::vector<uint32_t> SimulationManager<D>::addBondsWithin(const std::vector<ElementId>& among,
                                                           double gap, const std::string& model) {
  if (!(gap >= 0) || !std::isfinite(gap)) {
    throwBad("gap", physics::formatReal(gap), "must be >= 0 and finite");
  }
  const uint32_t m = bondModelIndex(model);
  // Every loop polls, from the first: before the search, half a million elements' indices,
  // radii and boxes were a tenth of a second deaf.
  InterruptPoll poll("bond add");  // before any bond is made
  std::vector<uint32_t> idx;
  if (among.empty()) {
    idx.reserve(s_.elements.size());
    for (uint32_t i = 0; i < s_.elements.size(); ++i) {
      poll();
      idx.push_back(i);
    }
  } else {
    for (ElementId id : among) {
      poll();
      idx.push_back(s_.elements.index(id));
    }
    polledSort(idx, "bond add");
    idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
  }
  const ElementArrays<D>& a = s_.elements.a;
  // A bond joins near neighbours: across a gap of at most one element's width. Wider, a bond
  // would pass through the elements between and every pair of a crowd would be bonded (a gap
  // of 1e308 m made 4.5 million bonds of 3000 elements before failing for lack of time).
  Real rmax = 0;
  for (uint32_t i : idx) {
    poll();
    rmax = std::max(rmax, a.r[i]);
  }
  if (gap > 2 * rmax) {
    throwBad("gap", physics::formatReal(gap),
             "must be at most the largest diameter of the elements bonded (" +
                 physics::formatReal(2 * rmax) + " m): a bond joins near neighbours");
  }
  // The pairs bonded already, as sorted keys (a std::set of a million pairs took half a
  // second to build).
  const auto key = [](uint32_t p, uint32_t q) {
    return uint64_t(std::min(p, q)) << 32 | std::max(p, q);
  };
  std::vector<uint64_t> bonded;
  bonded.reserve(s_.bonds.bonds.size());
  for (const Bond<D>& b : s_.bonds.bonds) {
    poll();
    bonded.push_back(key(b.a.index, b.b.index));
  }
  polledSort(bonded, "bond add");
  // Candidates from CGrid over each element's box grown by half the gap: a pair within the
  // gap has overlapping boxes. (A sweep along x alone met n^(2/3) elements per element in a
  // dense block: minutes for 10^6.)
  std::vector<search::Box<D, double>> boxes;
  boxes.reserve(idx.size());
  for (size_t k = 0; k < idx.size(); ++k) {
    poll();
    boxes.emplace_back();
    const uint32_t i = idx[k];
    const double reach = a.r[i] + gap / 2;
    for (int c = 0; c < D; ++c) {
      boxes[k].lo[c] = a.x[i][c] - reach;
      boxes[k].hi[c] = a.x[i][c] + reach;
    }
  }
  std::vector<std::pair<uint32_t, uint32_t>> pairs;
  searchInSlabs<D>(boxes, [&](uint32_t fi, uint32_t fj) {
    poll();
    const uint32_t i = idx[fi], j = idx[fj];
    const Real surface = (a.x[j] - a.x[i]).norm() - a.r[i] - a.r[j];
    if (surface > gap) return;
    if (std::binary_search(bonded.begin(), bonded.end(), key(a.slot[i], a.slot[j]))) return;
    pairs.emplace_back(std::min(i, j), std::max(i, j));
  });
  polledSort(pairs, "bond add");
  return makeBonds(pairs, m);
}

template <int D>
void SimulationManager<D>::removeBonds(const std::vector<uint32_t>& ids) {
  std::set<uint32_t> drop(ids.begin(), ids.end());
  // Every id checked against the ids there in one pass (a scan of the bonds per id was
  // quadratic).
  std::unordered_set<uint32_t> there;
  there.reserve(s_.bonds.bonds.size());
  for (const Bond<D>& b : s_.bonds.bonds) there.insert(b.id);
  for (uint32_t id : drop) {
    if (!there.contains(id)) throw Error("no bond " + std::to_string(id), {"LOOKUP", "BOND"});
  }
  std::erase_if(s_.bonds.bonds, [&](const Bond<D>& b) { return drop.contains(b.id); });
  touchConfig();
}

template <int D>
void SimulationManager<D>::dropBonds(const std::unordered_set<uint32_t>& slots) {
  const size_t before = s_.bonds.bonds.size();
  std::erase_if(s_.bonds.bonds, [&](const Bond<D>& b) {
    return slots.contains(b.a.index) || slots.contains(b.b.index);
  });
  if (s_.bonds.bonds.size() != before) touchConfig();
}

template <int D>
bool SimulationManager<D>::applyBondBreaks(const std::vector<PendingBreak>& breaks) {
  bool any = false;
  for (const PendingBreak& p : breaks) {
    Bond<D>& b = s_.bonds.bonds[p.index];
    if (!b.intact) continue;
    b.intact = false;
    any = true;
    const uint32_t i = s_.elements.pool().findDense(b.a);
    const uint32_t j = s_.elements.pool().findDense(b.b);
    BondBreak<D> r;
    r.bond = b.id;
    r.a = b.a;
    r.b = b.b;
    r.mode = p.mode;
    r.time = s_.time;
    r.step = s_.steps;
    r.point = bondFrame(s_.elements.a, i, j).centre;
    r.energy = b.state.energy;
    r.measure = p.mode == BondBreakMode::Tension ? b.state.sigma : b.state.tau;
    // The energy the bond held leaves the elastic term for the released one: the balance is
    // unchanged by the break itself.
    s_.ledger.elastic -= r.energy;
    s_.ledger.bondReleased += r.energy;
    s_.bonds.breaks.push_back(r);
  }
  if (any) touchConfig();
  return any;
}

template <int D>
BondInfo SimulationManager<D>::bondInfo(const Bond<D>& b, const BondBreak<D>* broke) const {
  const ElementArrays<D>& a = s_.elements.a;
  BondInfo info;
  info.id = b.id;
  info.a = b.a;
  info.b = b.b;
  info.model = s_.bonds.models[b.model].name;
  info.intact = b.intact;
  info.restLength = b.restLength;
  const BondFrame<D> f =
      bondFrame(a, s_.elements.pool().findDense(b.a), s_.elements.pool().findDense(b.b));
  info.length = f.length;
  info.strain = (f.length - b.restLength) / b.restLength;
  info.tensile = b.tensile;
  info.shear = b.shear;
  if (b.intact) {
    const BondState<D>& st = b.state;
    info.force = fromVec<D>(VecD<D>(st.shearForce - st.normalForce * f.n));
    if constexpr (D == 3) {
      info.moment = fromAngular(AngularD<D>(st.bendMoment + st.twistMoment * f.n));
    } else {
      info.moment = fromAngular(st.bendMoment);
    }
    info.normalForce = st.normalForce;
    info.sigma = st.sigma;
    info.tau = st.tau;
    info.energy = st.energy;
  } else if (broke) {
    info.breakMode = modeName(broke->mode);
    info.breakTime = broke->time;
  }
  return info;
}

template <int D>
std::vector<BondInfo> SimulationManager<D>::bonds() const {
  // The breaks by bond, found once: a scan of them per broken bond was quadratic.
  std::unordered_map<uint32_t, const BondBreak<D>*> broke;
  for (const BondBreak<D>& r : s_.bonds.breaks) broke[r.bond] = &r;
  std::vector<BondInfo> out;
  const FreeAsideOnThrow aside(out);  // stopped: hundreds of megabytes to give back
  out.reserve(s_.bonds.bonds.size());
  InterruptPoll poll("bond");  // a query's: a run's outputs read them with nothing to poll
  for (const Bond<D>& b : s_.bonds.bonds) {
    poll();
    const auto at = b.intact ? broke.end() : broke.find(b.id);
    out.push_back(bondInfo(b, at == broke.end() ? nullptr : at->second));
  }
  return out;
}

template <int D>
std::optional<BondInfo> SimulationManager<D>::bond(uint32_t id) const {
  for (const Bond<D>& b : s_.bonds.bonds) {
    if (b.id != id) continue;
    const BondBreak<D>* broke = nullptr;
    if (!b.intact)
      for (const BondBreak<D>& r : s_.bonds.breaks)
        if (r.bond == id) broke = &r;
    return bondInfo(b, broke);
  }
  return std::nullopt;
}

template <int D>
BondCount SimulationManager<D>::bondCount() const {
  BondCount n;
  n.bonds = s_.bonds.bonds.size();
  for (const Bond<D>& b : s_.bonds.bonds) n.intact += b.intact ? 1 : 0;
  for (const BondBreak<D>& r : s_.bonds.breaks) (r.mode == BondBreakMode::Tension ? n.tension : n.shear)++;
  return n;
}

template <int D>
std::vector<BondBreakInfo> SimulationManager<D>::bondBreaks() const {
  std::vector<BondBreakInfo> out;
  for (const BondBreak<D>& r : s_.bonds.breaks) {
    out.push_back({r.bond, r.a, r.b, modeName(r.mode), r.time, r.step, fromVec<D>(r.point),
                   r.energy, r.measure});
  }
  return out;
}

template <int D>
double SimulationManager<D>::bondCriticalStep(bool polled) const {
  // Gershgorin's bound on the largest eigenvalue of M^-1/2 K M^-1/2 for the bonds' springs:
  // each row's sum k/m_i + sum k/sqrt(m_i m_j), for translation and (with inertia) rotation;
  // the step is 2 / omega_max. Exact for a pair of equal elements, an upper bound on omega
  // for a chain or a pack (the translation-rotation coupling of the shear spring is in the
  // rotational stiffness's lever-arm term).
  const ElementArrays<D>& a = s_.elements.a;
  std::vector<double> rowT, rowR;
  // A tenth of a second for a million bonds, at a run's start and in the checks of `sim run`:
  // it polls Ctrl-C, the process-wide flag (a command's: nothing is changed yet) and, in a run
  // (polled), the run's own (pollStep; a query from a script inside a run must not).
  size_t seen = 0;
  for (const Bond<D>& b : s_.bonds.bonds) {
    if ((++seen & 0xffff) == 0) {
      if (polled) pollStep(s_);
      pollInterrupt("the critical step estimate");
    }
    if (!b.intact) continue;
    if (rowT.empty()) {
      rowT.assign(a.size(), 0);
      rowR.assign(a.size(), 0);
    }
    const uint32_t i = s_.elements.pool().findDense(b.a);
    const uint32_t j = s_.elements.pool().findDense(b.b);
    const BondModel& m = s_.bonds.models[b.model];
    const BondStiffness k = bondModelTypes()[m.type].stiffness(m.values, a.r[i], a.r[j], D);
    const double cross = std::sqrt(a.invMass[i] * a.invMass[j]);
    rowT[i] += k.translation * (a.invMass[i] + cross);
    rowT[j] += k.translation * (a.invMass[j] + cross);
    const double crossR = std::sqrt(a.invInertia[i] * a.invInertia[j]);
    rowR[i] += k.rotation * (a.invInertia[i] + crossR);
    rowR[j] += k.rotation * (a.invInertia[j] + crossR);
  }
  double w2 = 0;
  for (size_t i = 0; i < rowT.size(); ++i)
    w2 = std::max({w2, rowT[i], s_.rotationEnabled ? rowR[i] : 0});
  return w2 > 0 ? 2 / std::sqrt(w2) : std::numeric_limits<double>::infinity();
}

template class SimulationManager<2>;
template class SimulationManager<3>;

}  // namespace demlab::sim
