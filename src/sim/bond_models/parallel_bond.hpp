// The parallel bond of Potyondy and Cundall (Int. J. Rock Mech. Min. Sci. 41 (2004) 1329): a
// cemented cylinder (3D) or a slab of unit thickness (2D) of radius R = lambda min(ra, rb)
// between the two elements, centred on their axis, carrying force and moment:
//   area A = pi R^2, I = pi R^4 / 4, J = pi R^4 / 2 (3D); A = 2R, I = 2R^3 / 3 (2D);
//   normal force  Fn = kn A (L - L0)              (tension > 0)
//   shear force   dFs = -ks A dUs                 (incremental, in the current bond plane)
//   twist         dMt = -ks J dtheta_n            (3D)
//   bending       dMb = -kn I dtheta_s
// with kn, ks stiffnesses per area (Pa/m). The normal force is written in total form (kn A
// times the length change since bonding): for the small strains a bond reaches before it breaks
// it equals the sum of Potyondy and Cundall's increments, and it stores energy exactly. The
// largest stresses on the bond's rim are
//   sigma = Fn / A + |Mb| R / I,    tau = |Fs| / A + |Mt| R / J
// and the bond breaks in tension when sigma exceeds the tensile strength, else in shear when tau
// exceeds the shear strength. A straight chain of such bonds of spacing L is an Euler-Bernoulli
// beam of E = kn L and G = ks L (tests/unit/sim/sim_bond_test.cpp).
#pragma once

#include <numbers>

#include "sim/bond_model.hpp"

namespace demlab::sim {

struct ParallelBond {
  enum { kKn, kKs, kTensile, kShear, kRadius, kScatter, kSeed };

  static std::vector<BondOption> options() {
    const double required = std::numeric_limits<double>::quiet_NaN();
    return {{"kn", "Pa/m", "normal stiffness per area", required, 0, true},
            {"ks", "Pa/m", "shear stiffness per area", required, 0, false},
            {"tensile", "Pa", "tensile strength (largest normal stress on the rim)", required, 0,
             false},
            {"shear", "Pa", "shear strength (largest shear stress on the rim)", required, 0, false},
            {"radius", "", "the bond's radius as a fraction lambda of the smaller element's", 1, 0,
             true},
            {"scatter", "", "relative standard deviation of the strengths (normal, cut at 0)", 0, 0,
             false},
            {"seed", "", "seed of the strengths' scatter", 1, 0, false}};
  }

  // The cross-section of the bond between radii ra and rb: radius, area, I and J.
  struct Section {
    Real r, area, inertia, polar;
  };
  static Section section(const std::vector<double>& v, Real ra, Real rb, int dim) {
    const Real r = v[kRadius] * std::min(ra, rb);
    if (dim == 2) return {r, 2 * r, 2 * r * r * r / 3, 0};
    const Real r2 = r * r;
    return {r, std::numbers::pi * r2, std::numbers::pi * r2 * r2 / 4,
            std::numbers::pi * r2 * r2 / 2};
  }

  // Returns the force and moment on the second element; updates state.
  template <int D>
  static BondResponse<D> step(const std::vector<double>& v, const Bond<D>& bond,
                              const BondKinematics<D>& k, BondState<D>& state) {
    BondResponse<D> out;
    const Section s = section(v, k.ra, k.rb, D);
    const Real kn = v[kKn], ks = v[kKs];
    state.normalForce = kn * s.area * (k.length - bond.restLength);
    state.shearForce -= (ks * s.area) * k.dShear;
    Real twistTerm = 0, twistEnergy = 0;
    if constexpr (D == 3) {
      const Real twistAngle = k.dRot.dot(k.n);
      state.twistMoment -= ks * s.polar * twistAngle;
      state.bendMoment -= (kn * s.inertia) * (k.dRot - twistAngle * k.n);
      out.moment = state.bendMoment + state.twistMoment * k.n;
      twistTerm = std::abs(state.twistMoment) * s.r / s.polar;
      if (ks > 0) twistEnergy = 0.5 * state.twistMoment * state.twistMoment / (ks * s.polar);
    } else {
      state.bendMoment -= kn * s.inertia * k.dRot;
      out.moment = state.bendMoment;
    }
    out.force = state.shearForce - state.normalForce * k.n;
    const Real bend = angularNorm(state.bendMoment);
    state.sigma = state.normalForce / s.area + bend * s.r / s.inertia;
    state.tau = state.shearForce.norm() / s.area + twistTerm;
    state.energy = 0.5 * state.normalForce * state.normalForce / (kn * s.area) +
                   0.5 * bend * bend / (kn * s.inertia) + twistEnergy +
                   (ks > 0 ? 0.5 * state.shearForce.squaredNorm() / (ks * s.area) : 0);
    if (state.sigma > bond.tensile) {
      out.breaks = BondBreakMode::Tension;
    } else if (state.tau > bond.shear) {
      out.breaks = BondBreakMode::Shear;
    }
    return out;
  }

  static BondStiffness stiffness(const std::vector<double>& v, Real ra, Real rb, int dim) {
    const Section s = section(v, ra, rb, dim);
    const Real r = std::max(ra, rb);
    const Real kt = std::max(v[kKn], v[kKs]) * s.area;
    return {kt, std::max(v[kKn] * s.inertia, v[kKs] * s.polar) + v[kKs] * s.area * r * r};
  }
};

}  // namespace demlab::sim
