// The point-to-point cohesive spring (MIMES's bonded samples): a normal and a shear spring
// joining the two elements at the bond's centre, with strengths given as forces. The normal
// spring is total (kn times the change of centre distance since bonding: a function of the
// positions, so it stores energy exactly); the shear spring is incremental (ks times the
// relative displacement at the centre, carried into the current bond plane), as a contact's
// tangential spring is. No moment: the pair resists bending only through the shear force's
// lever arms. It breaks in tension when the normal force exceeds the tensile strength, in
// shear when the shear force exceeds the shear strength (tension first).
#pragma once

#include "sim/bond_model.hpp"

namespace demlab::sim {

struct PointSpringBond {
  // The option order of the row: values[k] is options()[k].
  enum { kKn, kKs, kTensile, kShear, kScatter, kSeed };

  static std::vector<BondOption> options() {
    const double required = std::numeric_limits<double>::quiet_NaN();
    return {{"kn", "N/m", "normal stiffness", required, 0, true},
            {"ks", "N/m", "shear stiffness", required, 0, false},
            {"tensile", "N", "tensile strength: the largest normal pull", required, 0, false},
            {"shear", "N", "shear strength: the largest shear force", required, 0, false},
            {"scatter", "", "relative standard deviation of the strengths (normal, cut at 0)", 0, 0,
             false},
            {"seed", "", "seed of the strengths' scatter", 1, 0, false}};
  }

  // Returns the force on the second element; updates state (shear force, measures, energy).
  template <int D>
  static BondResponse<D> step(const std::vector<double>& v, const Bond<D>& bond,
                              const BondKinematics<D>& k, BondState<D>& state) {
    BondResponse<D> out;
    const Real kn = v[kKn], ks = v[kKs];
    state.normalForce = kn * (k.length - bond.restLength);
    state.shearForce -= ks * k.dShear;
    out.force = state.shearForce - state.normalForce * k.n;
    state.sigma = state.normalForce;
    state.tau = state.shearForce.norm();
    state.energy = 0.5 * state.normalForce * state.normalForce / kn +
                   (ks > 0 ? 0.5 * state.shearForce.squaredNorm() / ks : 0);
    if (state.sigma > bond.tensile) {
      out.breaks = BondBreakMode::Tension;
    } else if (state.tau > bond.shear) {
      out.breaks = BondBreakMode::Shear;
    }
    return out;
  }

  static BondStiffness stiffness(const std::vector<double>& v, Real ra, Real rb, int) {
    // The shear spring at the centre turns each element about its own centre (lever arm r).
    const Real r = std::max(ra, rb);
    return {std::max(v[kKn], v[kKs]), v[kKs] * r * r};
  }
};

}  // namespace demlab::sim
