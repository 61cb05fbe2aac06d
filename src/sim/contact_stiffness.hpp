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
// zero), each made faster by its damping to omega / (sqrt(1 + zeta^2) - zeta) (the stability
// limit of a damped oscillator under central differences, physics/critical_step.hpp). An
// element's rate is the sum of its contacts' fastest modes (for equal masses the Gershgorin
// bound of the stiffness matrix, exact for one pair), and the estimate is 2 / sqrt of the
// largest. Elements of other shapes keep the static estimate (their contacts are several
// points and go through the shape pass).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "physics/mesh_contact.hpp"
#include "sim/contacts.hpp"
#include "sim/scene.hpp"

namespace demlab::sim {

namespace contact_stiffness_detail {

// Returns omega^2 / (sqrt(1 + zeta^2) - zeta)^2 for stiffness k, damping coefficient gamma and
// inverse mass mu: the rate of a damped mode with the stability limit's damping factor in it.
inline Real dampedRate(Real k, Real gamma, Real mu) {
  if (!(k > 0) || !(mu > 0)) return 0;
  const Real omega2 = k * mu;
  const Real zeta = gamma * std::sqrt(mu) / (2 * std::sqrt(k));
  const Real f = std::sqrt(1 + zeta * zeta) - zeta;
  return omega2 / (f * f);
}

// Returns the fastest mode's rate (dampedRate) of a contact of pair p with overlap delta,
// radius rEff, the sides' inverse masses summed (muN), and with their lever terms (muT).
inline Real contactRate(const physics::PairParams& p, Real delta, Real rEff, Real muN, Real muT,
                        bool tangential) {
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
  Real rate = dampedRate(kn, gn, muN);
  if (tangential && p.friction > 0) rate = std::max(rate, dampedRate(kt, gt, muT));
  return rate;
}

}  // namespace contact_stiffness_detail

// Returns the critical time step of s's ball contacts at their present overlaps (the
// candidates of the last search, the walls' candidates, mesh walls' among the shape
// candidates), +inf when none touches. Needs the
// pair table (s.pairParams) of a prepared scene. Changes nothing.
template <int D>
Real contactCriticalStep(const Scene<D>& s) {
  using contact_stiffness_detail::contactRate;
  const ElementArrays<D>& a = s.elements.a;
  const size_t n = a.size(), nMat = s.nMat();
  if (n == 0 || s.pairParams.size() != nMat * nMat) return std::numeric_limits<Real>::infinity();
  const bool tangential = s.tangentialModel == 0;
  const bool rotating = s.rotating;
  std::vector<Real> rate(n, 0);
  for (const CandidatePair& c : s.candidates) {
    const uint32_t i = c.i, j = c.j;
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
    const Real k = contactRate(p, delta, a.r[i] * a.r[j] / rs, muN, muT, tangential);
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
    rate[i] += contactRate(p, delta, a.r[i], muN, muT, tangential);
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
  const Real top = *std::max_element(rate.begin(), rate.end());
  return top > 0 ? 2 / std::sqrt(top) : std::numeric_limits<Real>::infinity();
}

}  // namespace demlab::sim
