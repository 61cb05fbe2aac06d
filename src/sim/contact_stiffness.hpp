// The critical time step the scene's contacts give as they are now.
//
// The static estimate (SimulationManager::criticalTimeStep: the Rayleigh step for Hertz-Mindlin,
// the pair's fixed frequency for the linear law) takes a grain's contacts as they are at a
// small overlap. A Hertz contact stiffens with its overlap (the normal tangent stiffness is
// 2 E* sqrt(R* delta), the tangential 8 G* sqrt(R* delta)), so a bed under load (an oedometer,
// a triaxial cell, heavy grains on soft ones) can outgrow it: at 0.2 of the Rayleigh step a
// Hertz bed compressed past about 15 % strain pumps energy into its contacts until the watchdog
// stops it. This estimate reads the overlaps instead.
//
// Each touching pair of balls, and each ball on a wall, has two modes: the normal one,
// omega^2 = kn (1/m_i + 1/m_j), and with friction the tangential-rotational one,
// omega^2 = kt (1/m_i + 1/m_j + l_i^2/I_i + l_j^2/I_j) (l the lever arm; the wall's terms are
// zero), each made faster by its damping to omega / dampedStepFactor(zeta) (the stability limit
// of a damped oscillator under the scene's integrator, physics/critical_step.hpp). An
// element's rate is the sum of its contacts' fastest modes (for equal masses the Gershgorin
// bound of the stiffness matrix, exact for one pair), and the estimate is 2 / sqrt of the
// largest.
//
// Elements of other shapes touch at several points at once (a box's corners, a level set's
// nodes), each a contact of its own whose force turns the body about a lever arm: their points
// are found as the shape pass finds them, and each point's modes take the inverse masses along
// its normal and its tangent with the lever arms' terms, (r x n).I^-1 (r x n) (in 3D the
// tangent's worst case, |r|^2 over the least principal moment). The points of one pair act in
// parallel, so their stiffnesses and their dampers add before the damping factor is taken
// (nine equal dampers in parallel triple zeta); the pairs then add as the balls' do. Nine
// nodes of a level-set disc resting on a floor make its rocking mode 27 times stiffer than one
// node's normal mode: at the static estimate's step it was unstable, held only by the Coulomb
// cap, and fed the ledger energy the motion never had.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "physics/mesh_contact.hpp"
#include "sim/contacts.hpp"
#include "sim/rigid_body.hpp"
#include "sim/scene.hpp"
#include "sim/shape_contacts.hpp"

namespace demlab::sim {

namespace contact_stiffness_detail {

// A contact's two modes as sums over what acts in parallel (the points of one shape pair):
// stiffness times inverse mass (omega^2) and damping coefficient times inverse mass
// (2 zeta omega), normal and tangential.
struct ModeSums {
  Real kN = 0, cN = 0, kT = 0, cT = 0;
  void add(const ModeSums& o) { kN += o.kN, cN += o.cN, kT += o.kT, cT += o.cT; }
};

// Returns omega^2 / dampedStepFactor(zeta)^2 for the mode omega^2 = k, 2 zeta omega = c: the
// rate whose 2 / sqrt is the mode's stable step under the integrator.
inline Real dampedRate(Real k, Real c, bool synchronized) {
  if (!(k > 0)) return 0;
  const Real f = physics::dampedStepFactor(c / (2 * std::sqrt(k)), synchronized);
  return k / (f * f);
}

// Returns the faster mode's rate of s (dampedRate).
inline Real fastestRate(const ModeSums& s, bool synchronized) {
  return std::max(dampedRate(s.kN, s.cN, synchronized), dampedRate(s.kT, s.cT, synchronized));
}

// Returns the modes of a contact of pair p with overlap delta, radius rEff, the sides' inverse
// masses along the normal summed (muN) and along the tangent with their lever terms (muT);
// the tangential one only with friction (tangential).
inline ModeSums contactModes(const physics::PairParams& p, Real delta, Real rEff, Real muN,
                             Real muT, bool tangential) {
  Real kn, kt, gn, gt;
  const Real mEff = 1 / muN;
  if (p.law == physics::LawKind::HertzMindlin) {
    const Real a = std::sqrt(rEff * delta);
    kn = 1.5 * p.hertzKn * a;  // dF/d delta of 4/3 E* sqrt(R*) delta^1.5
    kt = p.hertzKt * a;
    gn = std::abs(p.hertzGammaN) * std::sqrt(a * mEff);
    gt = std::abs(p.hertzGammaT) * std::sqrt(a * mEff);
  } else {
    kn = p.knFixed + p.knPerRadius * rEff;
    kt = p.shearRatio * kn;
    gn = 2 * p.dampingRatio * std::sqrt(kn * mEff);
    gt = 2 * p.dampingRatio * std::sqrt(kt * mEff);
  }
  ModeSums m;
  if (muN > 0) m.kN = kn * muN, m.cN = gn * muN;
  if (tangential && p.friction > 0 && muT > 0) m.kT = kt * muT, m.cT = gt * muT;
  return m;
}

// Returns element i's inverse mass along unit direction u at lever arm r: 1/m + (r x u).I^-1
// (r x u), without the rotational term when the scene does not rotate; worst: the largest over
// the directions orthogonal to u (in 3D a bound: |r|^2 over the least principal moment).
template <int D>
Real inverseMassAt(const Scene<D>& s, uint32_t i, const VecD<D>& r, const VecD<D>& u, bool worst) {
  const ElementArrays<D>& a = s.elements.a;
  const Real mu = a.invMass[i];
  if (!s.rotating) return mu;
  if constexpr (D == 3) {
    if (worst) {
      const Real invI =
          a.invInertia[i] != 0 ? a.invInertia[i] : 1 / principalFrame(s, i).I.minCoeff();
      return mu + r.squaredNorm() * invI;
    }
    return mu + inverseInertiaAlong(s, i, AngularD<3>(r.cross(u)));
  } else {
    // In 2D the tangent is one direction: the normal turned a quarter.
    const VecD<2> t = worst ? VecD<2>(-u.y(), u.x()) : u;
    return mu + inverseInertiaAlong(s, i, cross(r, t));
  }
}

}  // namespace contact_stiffness_detail

// Returns the critical time step of s's ball contacts at their present overlaps (the
// candidates of the last search, the walls' candidates, mesh walls' among the shape
// candidates), +inf when none touches. Needs the
// pair table (s.pairParams) of a prepared scene. Calls poll() every 65 536 candidate pairs
// (a wide skin gives tens of millions: a second's pass); poll may throw, and this changes
// nothing.
template <int D, class Poll = void (*)()>
Real contactCriticalStep(
    const Scene<D>& s, Poll&& poll = [] {}) {
  using contact_stiffness_detail::contactModes;
  using contact_stiffness_detail::fastestRate;
  using contact_stiffness_detail::ModeSums;
  const ElementArrays<D>& a = s.elements.a;
  const size_t n = a.size(), nMat = s.nMat();
  if (n == 0 || s.pairParams.size() != nMat * nMat) return std::numeric_limits<Real>::infinity();
  const bool tangential = s.tangentialModel == 0;
  const bool rotating = s.rotating;
  const bool sync = s.integrator == IntegratorKind::Synchronized;
  std::vector<Real> rate(n, 0);
  for (size_t at = 0; at < s.candidates.size(); ++at) {
    if ((at & 0xffff) == 0) poll();
    const uint32_t i = s.candidates[at].i, j = s.candidates[at].j;
    if (a.geometry[i] != 0 || a.geometry[j] != 0) continue;
    const VecD<D> raw = a.x[j] - a.x[i];
    const Real d2 = (s.periodic.any() ? s.periodic.nearest(raw) : raw).squaredNorm();
    const Real rs = a.r[i] + a.r[j];
    if (!(d2 < rs * rs)) continue;
    const Real delta = rs - std::sqrt(d2);
    const Real muN = a.invMass[i] + a.invMass[j];
    Real muT = muN;
    if (rotating) {
      const Real li = a.r[i] - 0.5 * delta, lj = a.r[j] - 0.5 * delta;
      muT += li * li * a.invInertia[i] + lj * lj * a.invInertia[j];
    }
    const physics::PairParams& p = s.pairParams[a.material[i] * nMat + a.material[j]];
    const Real k =
        fastestRate(contactModes(p, delta, a.r[i] * a.r[j] / rs, muN, muT, tangential), sync);
    rate[i] += k;
    rate[j] += k;
  }
  // A ball i on a wall of material wallMat, overlap delta (the wall's mass infinite).
  const auto addWallContact = [&](uint32_t i, Real delta, uint32_t wallMat) {
    if (!(delta > 0)) return;
    const Real muN = a.invMass[i];
    Real muT = muN;
    if (rotating) {
      const Real l = a.r[i] - 0.5 * delta;
      muT += l * l * a.invInertia[i];
    }
    const physics::PairParams& p = s.pairParams[a.material[i] * nMat + wallMat];
    rate[i] += fastestRate(contactModes(p, delta, a.r[i], muN, muT, tangential), sync);
  };
  const WallNarrowPhase<D>& np = WallNarrowPhase<D>::get();
  std::vector<physics::ContactGeometry<D>> geoms;
  std::vector<uint32_t> touched, balls;
  for (size_t w = 0; w < s.walls.size() && w < s.wallCandidates.size(); ++w) {
    const Wall<D>& wall = s.walls.items[w];
    if (wall.kind == WallShape::Mesh) continue;
    balls.clear();
    for (uint32_t i : s.wallCandidates[w]) {
      if (a.geometry[i] == 0) balls.push_back(i);
    }
    if (balls.empty()) continue;
    geoms.resize(balls.size());
    touched.resize(balls.size());
    const auto& entry = np.table.get(np.sphere, np.byShape[static_cast<int>(wall.kind)]).fn;
    const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, wall.shape);
    const size_t m = entry.grains(shape, a.x.data(), a.r.data(), balls.data(), balls.size(),
                                  geoms.data(), touched.data());
    for (size_t c = 0; c < m; ++c) {
      addWallContact(touched[c], geoms[c].overlap, wall.material);
    }
  }
  // Balls on mesh walls (the shape pass meets them): each surface feature they touch.
  physics::MeshContact<D> mesh[8];
  for (const auto& [i, w] : s.shapeWallCandidates) {
    if (a.geometry[i] != 0) continue;
    const Wall<D>& wall = s.walls.items[w];
    const auto* shape = std::get_if<physics::MeshShape<D>>(&wall.shape);
    if (shape == nullptr) continue;
    const int m = physics::sphereMeshContacts<D>({a.x[i], a.r[i]}, *shape, mesh, 8);
    for (int c = 0; c < m; ++c) addWallContact(i, mesh[c].g.overlap, wall.material);
  }
  // Elements of other shapes: every contact point of their pairs and of their walls.
  if (!s.shapeCandidates.empty() || !s.shapeWallCandidates.empty()) {
    using contact_stiffness_detail::inverseMassAt;
    const ShapeTable<D>& table = ShapeTable<D>::get();
    std::vector<double> placedA, placedB;
    // Element i as the shape rows see it, in its placed form (into buf) when its type has one.
    const auto ref = [&](uint32_t i, std::vector<double>& buf) {
      ElementRef<D> e = elementRef(s, i);
      if (e.g->placedSize != 0) {
        buf.resize(e.g->placedSize);
        table.type(e.g->shape).place(e, buf.data());
        e.placed = buf.data();
      }
      return e;
    };
    const bool localCurvature = s.curvatureModel == 1;
    ContactPoint<D> pts[kMaxContactPoints];
    for (const CandidatePair& c : s.shapeCandidates) {
      const uint32_t i = c.i, j = c.j;
      const int m = shapePairPoints(ref(i, placedA), ref(j, placedB), pts);
      const physics::PairParams& p = s.pairParams[a.material[i] * nMat + a.material[j]];
      ModeSums pair;
      for (int k = 0; k < m; ++k) {
        const VecD<D>& nrm = pts[k].g.normal;
        const VecD<D> ra = pts[k].g.point - a.x[i], rb = pts[k].g.point - a.x[j];
        const Real muN = inverseMassAt(s, i, ra, nrm, false) + inverseMassAt(s, j, rb, nrm, false);
        const Real muT = inverseMassAt(s, i, ra, nrm, true) + inverseMassAt(s, j, rb, nrm, true);
        const Real radius = pts[k].hertzRadius(localCurvature);
        pair.add(contactModes(p, pts[k].g.overlap, radius, muN, muT, tangential));
      }
      const Real k2 = fastestRate(pair, sync);
      rate[i] += k2;
      rate[j] += k2;
    }
    for (const auto& [i, w] : s.shapeWallCandidates) {
      if (a.geometry[i] == 0) continue;  // a ball on a mesh: above
      const Wall<D>& wall = s.walls.items[w];
      const int m = elementWallPoints(ref(i, placedA), wall, pts);
      const physics::PairParams& p = s.pairParams[a.material[i] * nMat + wall.material];
      ModeSums pair;
      for (int k = 0; k < m; ++k) {
        const VecD<D>& nrm = pts[k].g.normal;
        const VecD<D> ra = pts[k].g.point - a.x[i];
        pair.add(contactModes(p, pts[k].g.overlap, pts[k].hertzRadius(localCurvature),
                              inverseMassAt(s, i, ra, nrm, false),
                              inverseMassAt(s, i, ra, nrm, true), tangential));
      }
      rate[i] += fastestRate(pair, sync);
    }
  }
  const Real top = *std::max_element(rate.begin(), rate.end());
  return top > 0 ? 2 / std::sqrt(top) : std::numeric_limits<Real>::infinity();
}

}  // namespace demlab::sim
