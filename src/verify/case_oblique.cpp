// Oblique impacts with Coulomb friction of a grain on a floor, linear law (e = 0.5, mu = 0.3),
// no initial spin, at tangential-to-normal speed ratios psi = v_t / v_n (incidence angle
// atan(psi) from the normal).
//
// Rigid-body impulses (Walton; Maw, Barber and Fawcett 1976 in the rigid limit): with
// k = I / (m r^2) (2/5 sphere, 1/2 disc), the contact slides throughout when
// psi >= mu (1 + e) (1 + 1/k), and then
//   v_t' / v_t = 1 - mu (1 + e) / psi,  (w' r) / v_t = mu (1 + e) / (k psi);
// below that threshold the rigid answer is rolling at exit, v_t' / v_t = 1 / (1 + k).
// The compliant contact departs from both, at every dt: its shear spring must stretch to
// mu Fn / kt before the force reaches the Coulomb limit (1 % less tangential impulse at
// psi = 3), its torque acts at the contact point r - delta/2 from the centre (0.4 delta_max / r
// less spin: 3.5 % for the soft disc here), and below the threshold the spring's stored energy
// comes back as reverse slip. So the reference is the compliant model itself in continuous
// time, integrated by RK4 (reference_oblique.hpp), at every psi; the rigid values are reported
// in the note.
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>

#include "physics/pair_params.hpp"
#include "verify/case_impact.hpp"
#include "verify/case_list.hpp"
#include "verify/reference_oblique.hpp"

namespace demlab::verify {

namespace {

constexpr double kE = 0.5, kMu = 0.3;

// Returns psi at which gross sliding starts for a grain of dimension dim.
double slidingThreshold(int dim) {
  return kMu * (1 + kE) * (1 + 1 / inertiaFactor(dim));
}

std::string fmt(const char* f, double x) {
  char b[48];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

// Returns the continuous-time model of the impact of m (the linear law's shear spring and
// dashpot mixed as the simulation mixes them: kt = shearRatio kn, ct = beta kt).
ObliqueLaw obliqueLaw(const ImpactMeasure& m, int dim) {
  const physics::PairParams p =
      physics::mixPair(sim::LawKind::Linear, material(1e8, kE, kMu), material(1e8, kE, kMu));
  ObliqueLaw law;
  law.normal = m.law;
  law.kt = p.shearRatio * m.law.kn;
  law.ct = m.law.cn / m.law.kn * law.kt;
  law.friction = kMu;
  law.inertia = inertiaFactor(dim) * m.law.mass * m.law.radius * m.law.radius;
  return law;
}

// Runs one oblique impact at psi and adds its quantities (relative to the incoming tangential
// speed) to out, named with prefix, against the compliant reference; appends the rigid-body
// values to rigid. Returns false if no whole contact was recorded.
bool oblique(const RunSpec& spec, double psi, const std::string& prefix, CaseResult& out,
             std::string& rigid) {
  ImpactSetup setup;
  setup.law = sim::LawKind::Linear;
  setup.restitution = kE;
  setup.friction = kMu;
  setup.tangentialRatio = psi;
  const ImpactMeasure m = measureImpact(setup, spec, out);
  if (!m.valid) return false;
  out.timeScale = m.tc;
  const double k = inertiaFactor(spec.dim), vt = psi;  // v_n = 1 m/s
  const ObliqueAnswer ref = solveOblique(obliqueLaw(m, spec.dim), 1.0, vt);
  out.quantities.push_back(
      quantity(prefix + "tangential_ratio", m.tangential / vt, ref.tangential / vt, "ode", 1));
  out.quantities.push_back(quantity(prefix + "spin_ratio", m.spin / vt, ref.spin / vt, "ode", 1));
  out.quantities.push_back(quantity(prefix + "restitution", m.restitution, kE, "analytic"));
  const bool sliding = psi >= slidingThreshold(spec.dim);
  const double tRigid = sliding ? 1 - kMu * (1 + kE) / psi : 1 / (1 + k);
  const double wRigid = sliding ? kMu * (1 + kE) / (k * psi) : 1 / (1 + k);
  rigid += (rigid.empty() ? "" : "; ") + prefix + " " + fmt("%.4f", tRigid) + " / " +
           fmt("%.4f", wRigid) + " (model " + fmt("%.4f", ref.tangential / vt) + " / " +
           fmt("%.4f", ref.spin / vt) + ")";
  return true;
}

// Returns the case's result, or its failure note if no whole contact was recorded.
CaseResult obliqueAt(const RunSpec& spec, std::initializer_list<double> psis, const char* f) {
  CaseResult out;
  std::string rigid;
  for (double psi : psis) {
    if (!oblique(spec, psi, "psi=" + fmt(f, psi) + "/", out, rigid)) {
      out.quantities.push_back(quantity("contact", 0, 1, "analytic"));
      out.note = "no complete contact was recorded";
      return out;
    }
  }
  out.note = "rigid-body tangential_ratio / spin_ratio (Walton): " + rigid;
  return out;
}

}  // namespace

CaseResult obliqueSliding(const RunSpec& spec) {
  return obliqueAt(spec, {3.0, 6.0}, "%.1f");
}

CaseResult obliqueSweep(const RunSpec& spec) {
  const double th = slidingThreshold(spec.dim);
  return obliqueAt(spec, {0.1 * th, 0.25 * th, 0.5 * th, 0.75 * th, th, 1.5 * th, 2.5 * th},
                   "%.3f");
}

}  // namespace demlab::verify
