// PairParams: the constants of one contact law for one pair of materials, mixed once when a
// run starts (mixPair), so the force loop reads a few numbers and never mixes anything.
//
// Mixing rules (documented choices; all symmetric in a and b):
//   E* (Yeff) = 1 / ((1 - nu_a^2)/E_a + (1 - nu_b^2)/E_b)            Hertz; LIGGGHTS createYeff
//   G* (Geff) = 1 / (2(2 - nu_a)(1 + nu_a)/E_a + 2(2 - nu_b)(1 + nu_b)/E_b)   LIGGGHTS createGeff
//   restitution e = sqrt(e_a e_b) (geometric mean: one material's e for a pair of that material)
//   friction mu = min(mu_a, mu_b) (the slipperier surface governs, as in YADE's FrictPhys)
// and the dampers from the pair's e: so that a head-on impact rebounds with e under either law
// (Hertz-Mindlin optionally with LIGGGHTS's coefficient instead: HertzDamping).
// LIGGGHTS itself takes e and mu per pair of atom types from the user; for one material, or
// for a pair table written with these rules, the constants here equal its constants.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string_view>

#include "core/math.hpp"
#include "physics/material.hpp"

namespace demlab::physics {

enum class LawKind : uint8_t { Linear, HertzMindlin };

// What the Coulomb limit mu Fn caps (tangential.hpp): the whole tangential force, spring and
// dashpot (Total, the default), or the spring force alone (Spring: LIGGGHTS's convention).
enum class CoulombCriterion : uint8_t { Total, Spring };

// Returns the criterion's name as the scripts spell it: "total", "spring".
std::string_view coulombCriterionName(CoulombCriterion c);

// How Hertz-Mindlin's restitution e becomes its dampers' beta (law_hertz_mindlin.hpp):
// Calibrated (the default) takes the beta whose cut-off impact rebounds with e
// (hertzDampingFactor); Liggghts takes LIGGGHTS's beta = ln e / sqrt(ln^2 e + pi^2), whose
// rebound is not e (0.25 for e = 0.1, 0.55 for e = 0.5), kept to reproduce LIGGGHTS runs.
enum class HertzDamping : uint8_t { Calibrated, Liggghts };

// Returns the form's name as the scripts spell it: "calibrated", "liggghts".
std::string_view hertzDampingName(HertzDamping d);

// Returns the law's name as the scripts spell it: "linear", "hertz_mindlin".
std::string_view lawName(LawKind law);

struct PairParams {
  LawKind law = LawKind::Linear;
  Real friction = 0;                                   // Coulomb mu of the pair
  CoulombCriterion coulomb = CoulombCriterion::Total;  // the scene's choice, set at run start
  Real restitution = 1;                                // e of the pair
  Real youngEff = 0;                                   // E* (Pa)
  Real shearEff = 0;                                   // G* (Pa)

  // ---- linear law (law_linear.hpp) ----
  // Normal stiffness of a contact: kn = knFixed + knPerRadius * R*, one of the two being 0.
  // Explicit stiffnesses give knFixed (harmonic mean 2 ka kb / (ka + kb) of the two materials'
  // values, so a pair of one material has that material's value; a material without an
  // explicit value takes its partner's). Otherwise knPerRadius = E*: kn = E* R*, the Hertz
  // contact stiffness 2 E* a at a contact radius a = R*/2.
  Real knFixed = 0;      // N/m
  Real knPerRadius = 0;  // Pa
  // kt = shearRatio * kn: explicit (harmonic mean of the shear stiffnesses over kn) or the
  // Mindlin ratio 4 G* / E*, i.e. 2(1 - nu)/(2 - nu) for one material (0.8235 at nu = 0.3).
  Real shearRatio = 0;
  // Damping ratio zeta of the normal oscillator (c_n / (2 sqrt(m* kn))), chosen so that a
  // head-on impact rebounds with the pair's e: zeta = linearDampingRatio(e). Damping is
  // stiffness proportional (the thesis's beta): c = beta k with beta = 2 zeta sqrt(m*/kn), so
  // cn = 2 zeta sqrt(m* kn) and ct = beta kt.
  Real dampingRatio = 0;

  // ---- Hertz-Mindlin (law_hertz_mindlin.hpp), LIGGGHTS's hertz + tangential history.
  // With a = sqrt(R* delta): kn = 4/3 E* a, kt = 8 G* a,
  // gamma_n = -2 sqrt(5/6) beta sqrt(2 E* a m*), gamma_t = -2 sqrt(5/6) beta sqrt(8 G* a m*),
  // beta <= 0: -hertzDampingFactor(e) / sqrt(5) (HertzDamping::Calibrated) or LIGGGHTS's
  // ln e / sqrt(ln^2 e + pi^2) (Liggghts). Precomputed factors:
  Real hertzKn = 0;      // 4/3 E*
  Real hertzKt = 0;      // 8 G*
  Real hertzGammaN = 0;  // -2 sqrt(5/6) beta sqrt(2 E*): gamma_n = hertzGammaN sqrt(a m*)
  Real hertzGammaT = 0;  // -2 sqrt(5/6) beta sqrt(8 G*): gamma_t = hertzGammaT sqrt(a m*)

  // ---- time step: the larger of the two materials' sqrt(rho/G) / (0.1631 nu + 0.8766), so
  // the Rayleigh step of a grain of radius R is pi R rayleighSlowness (critical_step.hpp).
  Real rayleighSlowness = 0;  // s/m
};

// The linear spring-dashpot with its normal force cut off at zero (contact.hpp): a head-on
// impact ends when the force vanishes, before the overlap does, so its restitution is not the
// textbook e = exp(-pi zeta / sqrt(1 - zeta^2)) of the full damped oscillator (which includes
// an attractive tail) but (Schwager and Poeschel, Granular Matter 9 (2007) 465):
//   zeta < 1: e = exp(-2 zeta acos(zeta) / sqrt(1 - zeta^2)), force duration 2 acos(zeta)/omega_d
//   zeta = 1: e = exp(-2), duration 2/omega_n
//   zeta > 1: with W = sqrt(zeta^2 - 1), u = zeta + W: omega_n t* = 2 ln(u)/W and
//             e = exp(-zeta omega_n t*) |cosh(W omega_n t*) - (zeta/W) sinh(W omega_n t*)|
// with omega_n = sqrt(kn/m*), omega_d = omega_n sqrt(1 - zeta^2). e falls from 1 (zeta = 0)
// through 0.55 at the textbook zeta of e = 0.5 to 0 as zeta grows. For e near 1 the two
// agree (e = 0.9: 0.2 % apart); for e = 0.5 they differ by 10 %, which is why demlab inverts
// the exact relation: the rebound of the implemented law has the material's e.

// Returns the restitution of a head-on impact under the cut-off linear law with damping ratio
// zeta >= 0. Changes nothing.
Real linearRestitution(Real zeta);

// Returns the damping ratio zeta >= 0 with linearRestitution(zeta) = e, for e in (0, 1], to
// rounding (bisection); zeta is capped near 1e100 (e below ~1e-200 behaves as that e).
// Changes nothing.
Real linearDampingRatio(Real e);

// Returns the time from first touch until the normal force vanishes, in units of 1/omega_n,
// for the cut-off linear law with damping ratio zeta (pi for zeta = 0). Changes nothing.
Real linearForceDuration(Real zeta);

// Hertz-Mindlin's normal impact in units where the approach speed is 1 (length delta0 and time
// t0 with m* delta0 / t0^2 = 4/3 E* sqrt(R*) delta0^(3/2), delta0 = v0 t0):
//   x'' = -x^(3/2) - c x^(1/4) x',  x(0) = 0, x'(0) = 1,  c = -sqrt(5) beta,
// the same equation for every v0, E*, R* and m*: the damping form makes e depend on c alone.
// The force (the right side) is cut off at 0 (contact.hpp). Once it reaches 0 while the grains
// part (x' < 0), it stays 0 until they separate: x^(5/4) + c x' only falls as x does at the
// now constant x'. So the velocity when the force vanishes is the separation velocity, and
// e is -x' at that moment: the same definition as linearRestitution's.
// LIGGGHTS's beta gives c = sqrt(5) |ln e| / sqrt(ln^2 e + pi^2), whose rebound is well above
// e for small e (doc/verification.md has the table).

// Returns the restitution of the cut-off Hertz impact with damping factor c >= 0 (1 for c = 0),
// integrated (adaptive RK4, series start) to about 1e-10. Changes nothing.
Real hertzRestitution(Real c);

// Returns c >= 0 with hertzRestitution(c) = e, for e in (0, 1], to about 1e-10 in e (bisection;
// each distinct e is solved once and remembered, thread-safe); e below hertzRestitution of
// c = 1e4 (1.25e-8: e falls as 1.25 / c^2 there) gets that c. Changes nothing visible.
Real hertzDampingFactor(Real e);

// Returns LIGGGHTS's beta = ln e / sqrt(ln^2 e + pi^2) (<= 0) for e in (0, 1]. Changes nothing.
Real liggghtsBeta(Real e);

// Return the pair's restitution sqrt(e_a e_b) and friction min(mu_a, mu_b), the mixing rules
// above (mixPair's, and those of a query that needs no law constants). Change nothing.
inline Real mixRestitution(const MaterialDef& a, const MaterialDef& b) {
  // sqrt(e e) rounds to e exactly for the common one-material pair (sqrt is correctly rounded).
  return std::sqrt(a.restitution * b.restitution);
}
inline Real mixFriction(const MaterialDef& a, const MaterialDef& b) {
  return std::min(a.friction, b.friction);
}

// Returns the constants of `law` for the pair (a, b), Hertz-Mindlin's dampers by `damping`;
// symmetric: mixPair(l, a, b) and mixPair(l, b, a) are equal. Changes nothing. Throws
// demlab::Error as a.check() and b.check() do (the materials are checked first, so a bad
// material never yields a PairParams).
PairParams mixPair(LawKind law, const MaterialDef& a, const MaterialDef& b,
                   HertzDamping damping = HertzDamping::Calibrated);

}  // namespace demlab::physics
