// Contact detection module: CGrid (search/cgrid.hpp) over the grains' and walls' bounding boxes,
// grown by half a Verlet skin, so the candidate pairs stay valid until some grain has moved
// more than half the skin (or a grain plus a wall more than the whole skin). Then no contact
// is ever missed: two grains that were more than a skin apart at the search cannot touch
// before one of them has moved half a skin, and the check runs every step, fast movers
// included (a grain crossing half a skin per step simply triggers a search every step).
//
// A grain's box is grown by its own margin: half the skin, or more for the few grains much
// faster than the rest (chooseMargins), so that one fast grain (poured in, thrown out, falling
// through an orifice) does not force a search of the whole scene every few steps. The test
// stays exact: a pair not found had a gap over m_i + m_j, and is safe while every grain has
// moved less than its margin; a weight (half skin / m_i)^2 per grain makes the largest weighted
// squared displacement comparable with half the skin as before, walls included.
//
// Infinite planes are clipped to the domain (the grains' box grown by the skin) for the grid;
// a drum's box is its whole box. Wall candidates are kept per wall, so the narrow phase runs
// one batch per wall.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "physics/shapes.hpp"
#include "search/cgrid.hpp"
#include "sim/distribution.hpp"
#include "sim/history_store.hpp"
#include "sim/reorder.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Returns the largest float at most v (below) or the smallest at least v (above). The grid's
// boxes are floats, half the memory of doubles (CGrid keeps a sorted copy of them: 48 bytes a
// grain less at a search, the peak of a falling bed), rounded outward so that each holds its
// double box (to within the double subtraction of the domain's corner, 1e-16 of the extent)
// and the grid reports every pair whose double boxes overlap; the detection module then keeps
// the pairs within the skin by their double positions, so the candidates are those of double
// boxes.
// (The step to the neighbouring float is taken on the bits, not by a call to nextafterf.)
inline float floatBelow(double v) {
  const float f = static_cast<float>(v);
  if (!(f > v)) return f;  // also NaN, which the grid rejects
  if (f == 0) return -std::numeric_limits<float>::denorm_min();
  const uint32_t b = std::bit_cast<uint32_t>(f);
  return std::bit_cast<float>(f > 0 ? b - 1 : b + 1);
}
inline float floatAbove(double v) {
  return -floatBelow(-v);
}

template <int D>
class DetectionModule final : public SimModule<D> {
 public:
  explicit DetectionModule(double cellFactor)
      : cellFactor_(cellFactor), grid_(search::SearchOptions{cellFactor}) {}

  std::string_view name() const override { return "detection"; }
  SimLevel level() const override { return SimLevel::Detection; }

  void run(Scene<D>& s) override {
    s.periodic.advance(s.stepDt);
    bool need = s.needRebuild || stale(s);
    // A distributed run searches on every rank when one rank needs it.
    if (s.dist) need = s.dist->comm->max(need ? 1.0 : 0.0) > 0;
    if (!need) return;
    rebuild(s);
  }

  // Returns true if the candidates may miss a contact now.
  static bool stale(const Scene<D>& s) {
    const Real half = 0.5 * s.skin;
    // A Lees-Edwards offset moves the images of a pair apart as a displacement of one side.
    const Real g = std::sqrt(s.maxDisp2) + 0.5 * s.periodic.offsetTravel;
    if (g > half) return true;
    const double now = s.time + s.stepDt;
    Real wallMove = 0;
    for (const Wall<D>& w : s.walls.items)
      wallMove = std::max(wallMove, w.displacementSinceBuild(now));
    return g + wallMove > s.skin;
  }

  // Searches anew: fills s.candidates and s.wallCandidates, resets the skin bookkeeping; at
  // every s.elements.reorderEvery-th search (counting from the first) first sorts the grains'
  // dense order spatially (sim/reorder.hpp), which renumbers every dense index. Changes
  // s.contacts' capacity (sized for the coming steps); of its scratch keeps only the grid's
  // arrays, and those only when searches are frequent.
  void rebuild(Scene<D>& s) {
    using Box = search::Box<D, Real>;
    using GridBox = search::Box<D, float>;
    springs_.collect(s);
    // The old candidates, the positions at the last search and the contact records' room are
    // not needed through the search: freed, the search's scratch reuses their memory instead
    // of adding to the run's peak.
    std::vector<CandidatePair>().swap(s.candidates);
    // (The touch states describe the old candidates: springs_ carries them to the new.)
    s.touchNowValid = s.wallTouchNowValid = false;
    std::vector<ContactRecord<D>>().swap(s.contacts);
    std::vector<VecD<D>>().swap(s.xAtBuild);
    std::vector<Real>().swap(s.marginWeight);
    // A distributed run's elements move to their ranks first, and its ghosts come after the
    // owned elements are sorted (sim/distribution.hpp).
    if (s.dist) migrate(s, springs_);
    const uint32_t every = s.elements.reorderEvery;
    if (every > 0 && s.rebuilds % every == 0) reorderGrains(s);
    if (s.dist) makeGhosts(s);
    if (s.periodic.any()) wrapIntoCell(s);
    // Ctrl-C is polled between the search's stages (pollStep): a search of a bed of millions
    // of grains takes a large part of a second. Abandoned, the module is made anew.
    pollStep(s);
    const ElementArrays<D>& a = s.elements.a;
    const size_t n = a.size(), owned = s.ownedCount();
    const Real half = 0.5 * s.skin;
    const bool wide = chooseMargins(s);
    const auto margin = [&](size_t i) { return wide ? margin_[i] : half; };
    // Room for the walls too: growing past n would double the largest array of the search.
    boxes_.reserve(n + s.walls.size());
    boxes_.resize(n);
    Box domain;
    domain.lo.fill(std::numeric_limits<Real>::infinity());
    domain.hi.fill(-std::numeric_limits<Real>::infinity());
    for (size_t i = 0; i < n; ++i) {
      const Real e = a.r[i] + margin(i);
      for (int k = 0; k < D; ++k) {
        domain.lo[k] = std::min(domain.lo[k], a.x[i][k] - e);
        domain.hi[k] = std::max(domain.hi[k], a.x[i][k] + e);
      }
    }
    const Real widest = wide ? *std::max_element(margin_.begin(), margin_.end()) : half;
    for (int k = 0; k < D; ++k) {
      domain.lo[k] -= half + widest;
      domain.hi[k] += half + widest;
    }
    if (s.periodic.any() && n > 0) {
      // The images reach up to two radii and the skin beyond the cell.
      const Real rMax = *std::max_element(a.r.begin(), a.r.end());
      const Real reach = 2 * rMax + 2 * s.skin;
      for (int k = 0; k < D; ++k) {
        if (!s.periodic.periodic(k)) continue;
        domain.lo[k] = std::min(domain.lo[k], s.periodic.lo[k] - reach);
        domain.hi[k] = std::max(domain.hi[k], s.periodic.hi[k] + reach);
      }
    }
    // The grid's boxes are taken from the domain's corner, so their precision is a float's
    // over the domain's extent, wherever the scene sits (a bed 4 km from the origin would
    // otherwise get boxes a quarter of a millimetre coarse).
    const auto corner = domain.lo;
    for (size_t i = 0; i < n; ++i) {
      const Real e = a.r[i] + margin(i);
      for (int k = 0; k < D; ++k) {
        boxes_[i].lo[k] = floatBelow(a.x[i][k] - e - corner[k]);
        boxes_[i].hi[k] = floatAbove(a.x[i][k] + e - corner[k]);
      }
    }
    const size_t nw = s.walls.size();
    wallOfBox_.clear();
    if (n > 0) {
      for (size_t w = 0; w < nw; ++w) {
        Box b = std::visit(
            [&](const auto& shape) -> Box {
              using S = std::decay_t<decltype(shape)>;
              if constexpr (std::is_same_v<S, physics::PlaneShape<D>>) {
                return physics::boundsWithin(shape, domain);
              } else {
                return physics::bounds(shape);
              }
            },
            s.walls.items[w].shape);
        bool empty = false;
        for (int k = 0; k < D; ++k) {
          b.lo[k] = std::max(b.lo[k] - half, domain.lo[k]);
          b.hi[k] = std::min(b.hi[k] + half, domain.hi[k]);
          if (!(b.lo[k] <= b.hi[k])) empty = true;
        }
        if (empty) continue;
        GridBox g;
        for (int k = 0; k < D; ++k) {
          g.lo[k] = floatBelow(b.lo[k] - corner[k]);
          g.hi[k] = floatAbove(b.hi[k] - corner[k]);
        }
        boxes_.push_back(g);
        wallOfBox_.push_back(static_cast<uint32_t>(w));
      }
    }
    const size_t firstImage = boxes_.size();
    if (s.periodic.any()) addImageBoxes(s, corner, half);
    pairs_.reserve(lastPairs_ + lastPairs_ / 8);
    pollStep(s);
    // The search stops part way when Ctrl-C comes and the step may be abandoned.
    grid_.setStop(s.abandonOn);
    grid_.findPairs(boxes_, pairs_);
    pollStep(s);
    lastPairs_ = pairs_.size();
    // The search's scratch goes back to the heap between searches, the grid's and the boxes'
    // before the pairs are sorted out; the next search reserves room for about as many pairs
    // as this one found. The grid's arrays are the largest after the grains', but grown again
    // from empty they cost about another search (page faults): they are kept when the searches
    // come at least every kKeepGridSteps steps, where the search's moment is the run's peak
    // anyway, and freed when searches are rare, as in a settled bed, where the records and
    // springs of the steps between set the peak.
    std::vector<search::Box<D, float>>().swap(boxes_);
    const bool frequent = searchedBefore_ && s.steps - lastSearchStep_ <= kKeepGridSteps;
    if (!frequent) grid_ = search::CGrid<D, float>(search::SearchOptions{cellFactor_});
    searchedBefore_ = true;
    lastSearchStep_ = s.steps;
    s.wallCandidates.assign(nw, {});
    // Ctrl-C between slices of the passes over the pairs, tens of millions with a wide skin.
    const auto poll = [&s] { pollStep(s); };
    // The grain pairs kept are compacted to the front of pairs_ and then copied once into a
    // candidate array of exactly their number (grown by doubling it would hold up to twice).
    size_t kept = 0, touching = 0, wallPairs = 0;
    // Pairs with an element that is not a ball go to the shape contact pass (its bounding
    // sphere made them candidates); a scene of balls only never looks.
    s.shapeCandidates.clear();
    s.shapeWallCandidates.clear();
    const bool shapes = s.anyShapes;
    const auto isShape = [&](uint32_t i) { return a.geometry[i] != 0; };
    polledFor(pairs_.size(), poll, [&](size_t at) {
      search::IndexPair p = pairs_[at];
      if (p.second >= firstImage) {
        // An element and another's image: the pair of the two elements, measured through
        // the boundary (the nearest image) from here on. Walls and images do not meet.
        if (p.first >= n && p.first < firstImage) return;
        if (p.first >= firstImage) return;
        p.second = imageOwner_[p.second - firstImage];
        if (p.second == p.first) return;
      }
      if (p.second < n) {
        // Boxes overlap for pairs up to sqrt(D) times farther apart than spheres can come
        // within their margins: keep only the pairs whose gap is at most the two margins.
        const Real rs = a.r[p.first] + a.r[p.second],
                   reach = rs + (wide ? margin_[p.first] + margin_[p.second] : s.skin);
        const VecD<D> raw = a.x[p.second] - a.x[p.first];
        const Real d2 = (s.periodic.any() ? s.periodic.nearest(raw) : raw).squaredNorm();
        if (d2 > reach * reach) return;
        // The lower global id first: the contact loop keeps each spring in that orientation,
        // and two ranks computing the same pair orient it alike.
        const search::IndexPair q = a.globalId[p.first] < a.globalId[p.second]
                                        ? p
                                        : search::IndexPair{p.second, p.first};
        // A pair is computed by the rank owning its A (with no ghosts, every rank).
        if (q.first >= owned) return;
        if (d2 < rs * rs) touching += 1;
        if (shapes && (isShape(q.first) || isShape(q.second))) {
          s.shapeCandidates.push_back({q.first, q.second});
          return;
        }
        pairs_[kept++] = q;
      } else if (shapes && p.first < n &&
                 (isShape(p.first) || s.walls.items[wallOfBox_[p.second - n]].kind == WallShape::Mesh)) {
        // Elements of every shape meet a mesh wall in the shape pass (several points a pair).
        s.shapeWallCandidates.emplace_back(p.first, wallOfBox_[p.second - n]);
      } else if (p.first < owned) {
        s.wallCandidates[wallOfBox_[p.second - n]].push_back(p.first);
        wallPairs += 1;
      }
    });
    s.candidates.reserve(kept);
    polledFor(kept, poll, [&](size_t k) { s.candidates.push_back({pairs_[k].first, pairs_[k].second}); });
    groupCandidates(s.candidates, &s.contactGroups, nullptr, poll);
    pollStep(s);
    for (auto& list : s.wallCandidates) std::sort(list.begin(), list.end());
    std::vector<search::IndexPair>().swap(pairs_);
    std::vector<uint32_t>().swap(wallOfBox_);
    // Room for the contact records of the coming steps: as many as the last recorded step
    // had (contacts change little within a skin), else an estimate from the pairs touching
    // now; more grow the array by an eighth (appendRecord). Grown by doubling from empty
    // instead, the records' array would leave its smaller copies resident (a tenth of a dense
    // bed's peak memory); sized by the estimate, it held a fifth more than the records.
    const size_t expect =
        s.lastRecorded > 0 ? s.lastRecorded : touching + touching / 16 + wallPairs;
    s.contacts.reserve(expect + expect / 32 + 16);
    springs_.give(s, touching);
    s.xAtBuild = a.x;
    if (wide) {
      s.marginWeight.resize(n);
      for (size_t i = 0; i < n; ++i) {
        const Real q = half / margin_[i];
        s.marginWeight[i] = q * q;
      }
    }
    std::vector<Real>().swap(margin_);
    s.maxDisp2 = 0;
    s.periodic.offsetTravel = 0;
    std::vector<uint32_t>().swap(imageOwner_);
    const double now = s.time + s.stepDt;
    for (Wall<D>& w : s.walls.items) {
      w.pointAtBuild = w.point;
      w.timeAtBuild = now;
      w.scriptedAngle = 0;
    }
    s.needRebuild = false;
    s.rebuilds += 1;
  }

  // Returns the bytes this module holds between searches (the grid's scratch when searches are
  // frequent, else none).
  size_t workingBytes() const override {
    return grid_.workingBytes() + boxes_.capacity() * sizeof(search::Box<D, float>) +
           imageOwner_.capacity() * sizeof(uint32_t) +
           wallOfBox_.capacity() * sizeof(uint32_t) +
           pairs_.capacity() * sizeof(search::IndexPair) + springs_.workingBytes();
  }

 private:
  static constexpr uint64_t kKeepGridSteps = 1000;

  // Wraps every element into the periodic cell (sim/periodic.hpp), booking the kinetic energy
  // of Lees-Edwards velocity jumps as wall work. Changes positions, velocities, unwrap offsets
  // and the ledger.
  static void wrapIntoCell(Scene<D>& s) {
    ElementArrays<D>& a = s.elements.a;
    double work = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      work += s.periodic.wrap(a.x[i], a.v[i], a.invMass[i],
                              s.elements.pool().handleAt(static_cast<uint32_t>(i)));
    }
    s.ledger.wallWork += work;
  }

  // Appends the grid boxes of the elements' images that come within reach of the cell (each
  // pair through the boundary once: PeriodicBox::forEachImage), their owners in imageOwner_.
  // Changes boxes_ and imageOwner_.
  void addImageBoxes(const Scene<D>& s, const std::array<Real, D>& corner, Real half) {
    const ElementArrays<D>& a = s.elements.a;
    Real rMax = 0;
    for (Real r : a.r) rMax = std::max(rMax, r);
    imageOwner_.clear();
    for (size_t i = 0; i < a.size(); ++i) {
      const Real e = a.r[i] + half;
      s.periodic.forEachImage(a.x[i], a.r[i] + rMax + s.skin, [&](const VecD<D>& p) {
        search::Box<D, float> b;
        for (int k = 0; k < D; ++k) {
          b.lo[k] = floatBelow(p[k] - e - corner[k]);
          b.hi[k] = floatAbove(p[k] + e - corner[k]);
        }
        boxes_.push_back(b);
        imageOwner_.push_back(static_cast<uint32_t>(i));
      });
    }
  }

  // The margins' rule. A grain's margin is its speed times the time the bulk takes to move
  // half a skin (half the skin over the kMarginQuantile-th quantile of the speeds), at least
  // half the skin and at most kMaxMarginFactor times it: with the bulk at rest or slow, the
  // fastest grains reach their margins about when the bulk reaches its own. A margin k times
  // wider finds a few more candidates for that grain only.
  static constexpr double kMarginQuantile = 0.99;
  static constexpr Real kMaxMarginFactor = 8;

  // Fills margin_ for the search (sizes as the elements) and returns true when some margin
  // exceeds half the skin; returns false, margin_ empty, when every grain gets half the skin:
  // when the detection's margins option is off, in periodic scenes (the cell's size check allows for half skins), scenes of fewer than 100
  // grains (one search costs little) and when no grain is much faster than the quantile.
  // The speeds are those of the state at the search, so the choice is deterministic.
  bool chooseMargins(const Scene<D>& s) {
    const ElementArrays<D>& a = s.elements.a;
    const size_t n = a.size();
    margin_.clear();
    // (A distributed run's ghosts reach half the skin from every side.)
    if (!s.wideMargins || s.periodic.any() || s.dist || n < 100) return false;
    const Real half = 0.5 * s.skin;
    std::vector<Real> speed2(n);
    Real top = 0;
    for (size_t i = 0; i < n; ++i) {
      speed2[i] = a.v[i].squaredNorm();
      top = std::max(top, speed2[i]);
    }
    const size_t q = std::min(n - 1, static_cast<size_t>(kMarginQuantile * double(n)));
    std::nth_element(speed2.begin(), speed2.begin() + q, speed2.end());
    const Real vRef = std::sqrt(speed2[q]);
    // Nothing much faster than the bulk: the uniform margins.
    if (!(top > 4 * vRef * vRef) || !std::isfinite(top)) return false;
    // The time the bulk takes to move half a skin (infinite for a bulk at rest).
    const Real tau = vRef > 0 ? half / vRef : std::numeric_limits<Real>::infinity();
    margin_.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const Real v = std::sqrt(a.v[i].squaredNorm());
      const Real m = v > 0 ? v * tau : 0;
      margin_[i] = std::clamp(m, half, kMaxMarginFactor * half);
    }
    return true;
  }

  double cellFactor_;
  std::vector<Real> margin_;  // per grain at a search (chooseMargins); empty between searches
  bool searchedBefore_ = false;
  uint64_t lastSearchStep_ = 0;  // s.steps at the last search
  search::CGrid<D, float> grid_;
  std::vector<search::Box<D, float>> boxes_;
  std::vector<uint32_t> wallOfBox_;
  std::vector<uint32_t> imageOwner_;  // per image box (after the walls'): its element
  std::vector<search::IndexPair> pairs_;
  size_t lastPairs_ = 0;  // pairs found by the last search
  SpringTransfer<D> springs_;
};

}  // namespace demlab::sim
