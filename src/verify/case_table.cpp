// The case table: one row per verification case, with its stated tolerance.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "verify/case_list.hpp"
#include "verify/verify.hpp"

namespace demlab::verify {

double Quantity::error() const {
  const double s = scale > 0 ? scale : std::abs(reference);
  const double diff = std::abs(measured - reference);
  if (!std::isfinite(measured)) return std::numeric_limits<double>::infinity();
  return s > 0 ? diff / s : diff;
}

double CaseResult::error() const {
  double e = 0;
  for (const Quantity& q : quantities) e = std::max(e, q.error());
  return e;
}

bool CaseDef::knownToFail(int dim) const {
  if (knownFailure.empty()) return false;
  return knownFailureDims.empty() ||
         std::find(knownFailureDims.begin(), knownFailureDims.end(), dim) != knownFailureDims.end();
}

bool CaseDef::knownToFail(int dim, const std::string& integrator) const {
  return knownToFail(dim) && !(touchFixes && !integrator.ends_with("-notouch"));
}

bool assertedIntegrator(const std::string& integrator) {
  return integrator == integrators()[0] || integrator == integrators()[2];
}

const std::vector<std::string>& integrators() {
  static const std::vector<std::string> names{"synchronized", "verlet", "synchronized-notouch",
                                              "verlet-notouch"};
  return names;
}

namespace {

CaseDef row(std::string name, std::string title, std::string description, double tolerance,
            double checkSteps, double minOrder, std::string timeScale,
            CaseResult (*run)(const RunSpec&)) {
  CaseDef c;
  c.name = std::move(name);
  c.title = std::move(title);
  c.description = std::move(description);
  c.dims = {2, 3};
  c.tolerance = tolerance;
  c.checkSteps = checkSteps;
  c.minOrder = minOrder;
  c.timeScaleName = std::move(timeScale);
  c.run = run;
  return c;
}

// The known failures (verify.hpp CaseDef::knownFailure), reported in doc/verification.md.
const char* kTouchPhase =
    "the damped laws' normal force jumps to cn v0 at the touch, which the fixed step resolves "
    "only to first order, with a sign set by where in its step the touch falls: at tc/50 a "
    "touch at 0.1 or 0.9 of a step errs 1.0-1.2 % in restitution, peak overlap and peak force "
    "(0.1 % at mid-step). Reproduce: demlab_verify --cases impact-linear-plane --dims 3 "
    "--integrators synchronized-notouch (quantities.csv, phase=0.9). The touch correction "
    "(module touch on, the default: the synchronized rows) removes it: 0.12 % at tc/50 at "
    "every phase, converging at order 2.0 (finding 3)";
const char* kGasDrift =
    "the energy between contacts wanders more than issue 3 allows: 16 grains, 2000 contact "
    "times, at tc/50 the drift is 2.3e-3 (discs) and 1.9e-4 (spheres), falling at about "
    "second order (2.4e-5 and 4.5e-6 at tc/800); the sim's ledger residual agrees. Each "
    "collision's touch and release (kinks in the force) leave an O(dt^2) energy error of "
    "random sign, which adds up over collisions. Reproduce: demlab_verify --cases "
    "elastic-gas --integrators synchronized-notouch. The touch correction (module touch on, "
    "the default: the synchronized rows) meets issue 3: 1.5e-5 (discs) and 7.0e-7 (spheres) "
    "at tc/50, falling at order 3 (finding 7)";

std::vector<CaseDef> makeTable() {
  std::vector<CaseDef> t;
  t.push_back(
      row("impact-linear-plane", "Normal impact, linear law, grain on a floor",
          "A grain (r = 0.01 m, rho = 2500, E = 1e8 Pa, nu = 0.3) meets a floor at 1 m/s, linear "
          "law (kn = E* R*), restitution 0.5. Contact time 2 acos(zeta)/omega_d, peak overlap "
          "(v0/omega) exp(-zeta acos(zeta)/sqrt(1-zeta^2)) and restitution e (the cut-off law, "
          "Schwager and Poeschel 2007) are closed forms; the peak force is the RK4 reference. "
          "Each run makes three impacts, touching at 0.1, 0.5 and 0.9 of a step.",
          0.01, 50, 0, "tc", impactLinearPlane));
  t.back().knownFailure = kTouchPhase;
  t.back().touchFixes = true;
  t.push_back(
      row("impact-linear-sphere", "Normal impact, linear law, grain on grain (radius ratio 2)",
          "As impact-linear-plane between grains of radii 0.01 and 0.02 m (m* and R* mixed), "
          "approaching at 1 m/s.",
          0.01, 50, 0, "tc", impactLinearSphere));
  t.back().knownFailure = kTouchPhase;
  t.back().touchFixes = true;
  t.push_back(
      row("impact-hertz-plane", "Normal impact, Hertz-Mindlin, grain on a floor",
          "The same grain and floor under Hertz-Mindlin: an elastic impact (e = 1) against Hertz's "
          "closed forms (peak overlap (15 m* v0^2/(16 E* sqrt(R*)))^(2/5), duration 2.9432 "
          "delta_max/v0, peak force 4/3 E* sqrt(R*) delta_max^(3/2)), and a damped one (material e "
          "= 0.5) against the RK4 reference of the damped law (no closed form) with the default, "
          "calibrated damping, whose rebound is the material's e.",
          0.01, 50, 0, "tc", impactHertzPlane));
  t.push_back(row("impact-hertz-sphere",
                  "Normal impact, Hertz-Mindlin, grain on grain (radius ratio 2)",
                  "As impact-hertz-plane between grains of radii 0.01 and 0.02 m.", 0.01, 50, 0,
                  "tc", impactHertzSphere));
  t.push_back(row(
      "oblique-sliding", "Oblique impact with friction, gross sliding",
      "A grain hits a floor at v_n = 1 m/s with v_t = psi v_n (psi = 3 and 6: incidence 71.6 "
      "and 80.5 degrees), no spin, linear law, e = 0.5, mu = 0.3, sliding throughout (above psi "
      "= mu (1+e)(1+1/k): 1.575 sphere, 1.35 disc). The reference is the compliant model in "
      "continuous time (the normal law, the shear spring with its Coulomb cap and the spin "
      "integrated by RK4, reference_oblique.hpp): the rigid-body impulses (v_t'/v_t = 1 - "
      "mu(1+e)/psi, w'r/v_t = mu(1+e)/(k psi), given in the note) leave out the shear spring's "
      "stretching after the touch (1 % of the tangential impulse at psi = 3) and the torque arm "
      "r - delta/2 (3.5 % of the disc's spin), which no time step removes. Errors relative to "
      "v_t.",
      0.01, 50, 0, "tc", obliqueSliding));
  t.push_back(
      row("oblique-sweep", "Oblique impact with friction across incidence angles",
          "As oblique-sliding at psi = 0.1 ... 2.5 times the sliding threshold, against the same "
          "compliant reference, which also covers the sticking and mixed regimes of Maw, Barber "
          "and Fawcett (the shear spring's stored energy comes back as reverse slip, so the "
          "answer depends on kt/kn and damping; the rigid-body values, rolling 1/(1+k) below "
          "the threshold, are given in the note). The observed order is not asked: the 3D "
          "spin at psi = 1.181 settles 0.5-0.7 % from the reference (down to tc/3200, "
          "--finest 6), where the reference chatters between sticking and sliding on the cap "
          "(finding 8).",
          0.02, 50, 0, "tc", obliqueSweep));
  t.push_back(
      row("incline-rolling", "Rolling down an incline",
          "A grain resting on a floor with gravity tilted by 20 degrees, mu = 0.5 (rolling "
          "without slip): a = g sin(theta)/(1+k) (5/7 sphere, 2/3 disc), w r = v. Acceleration "
          "fitted over t = 0.05..0.15 s; both laws. tc: half period of the resting contact.",
          0.002, 50, 0, "tc", inclineRolling));
  t.push_back(
      row("incline-sliding", "Sliding down an incline",
          "As incline-rolling at 30 degrees with mu = 0.1 (sliding): a = g(sin - mu cos), spin "
          "accelerating at w'r = mu g cos(theta)/k.",
          0.002, 50, 0, "tc", inclineSliding));
  t.push_back(
      row("slide-to-roll", "A sliding grain turning to rolling",
          "A grain launched at v0 = 1 m/s without spin on a floor, mu = 0.3: rolls after "
          "t = k v0/((1+k) mu g) (2 v0/(7 mu g) sphere, v0/(3 mu g) disc) at v0/(1+k) (5/7, 2/3 "
          "v0), having dissipated (1/2) m v0^2 k/(1+k) (the ledger's friction plus damping "
          "losses). Both laws.",
          0.005, 50, 0, "tc", slideToRoll));
  t.push_back(
      row("bounce", "A grain bouncing under gravity",
          "Dropped from 0.05 m onto a floor, linear law, e = 0.8, E = 1e7 Pa: the ratios of three "
          "successive apex heights (e^2 = 0.64 for instantaneous impacts) against the same law "
          "with gravity integrated by the RK4 reference.",
          0.01, 50, 0, "tc", bounce));
  t.push_back(
      row("elastic-gas", "Energy conservation of an elastic, frictionless gas",
          "16 grains (a lattice of pitch 5 r, jittered) in a box of planes, linear law "
          "kn = 1e4 N/m, e = 1, mu = 0, random velocities up to 0.5 m/s, 2000 contact times (300 "
          "short), sampled once per contact time: the drift, the largest relative deviation of "
          "kinetic plus spring energy (computed from the contacts' overlaps) from its start over "
          "the samples with no contact open (inside contacts Verlet's energy oscillates by "
          "O(dt^2) about its shadow energy: that deviation is in the note). Issue 3 asks below "
          "1e-4 at tc/50, falling as dt^2.",
          1e-4, 50, 1.8, "tc", elasticGas));
  t.back().knownFailure = kGasDrift;
  t.back().touchFixes = true;
  return t;
}

}  // namespace

const std::vector<CaseDef>& caseTable() {
  static const std::vector<CaseDef> table = makeTable();
  return table;
}

const CaseDef& findCase(const std::string& name) {
  for (const CaseDef& c : caseTable()) {
    if (c.name == name) return c;
  }
  std::string all;
  const auto& t = caseTable();
  for (size_t k = 0; k < t.size(); ++k) {
    all += (k == 0 ? "" : (k + 1 == t.size() ? ", or " : ", ")) + t[k].name;
  }
  throw Error("bad case \"" + name + "\": must be " + all, {"LOOKUP", "CASE"});
}

}  // namespace demlab::verify
