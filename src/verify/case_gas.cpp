// An elastic, frictionless gas in a box of planes (linear law, e = 1, mu = 0, kn = 1e4 N/m):
// the total energy, kinetic plus the springs' (1/2) kn delta^2 computed here from the contacts'
// overlaps (not from the sim's ledger), must stay constant. Sampled once per contact time.
// The error is the drift: the largest |E(t) - E(0)| / E(0) over the samples at which no contact
// is open (there the integrator's energy is the true energy; inside a contact velocity Verlet's
// energy oscillates by O(dt^2) around a conserved shadow energy). The largest deviation over
// all samples, contacts open or not, is given in the note. The time scale is the grain-grain
// contact time pi sqrt(m* / kn), m* = m / 2.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "verify/case_common.hpp"
#include "verify/case_list.hpp"

namespace demlab::verify {

CaseResult elasticGas(const RunSpec& spec) {
  CaseResult out;
  const int d = spec.dim;
  const double r = 0.01, kn = 1e4, vmax = 0.5;
  // Few grains, far apart: many samples find no contact open, where the drift is read.
  const int n = 16;
  const double contactTimes = spec.shortRun ? 300 : 2000;
  auto s = sim::makeSimulation(d);
  setIntegrator(*s, spec.integrator);
  sim::MaterialDef m = material(1e8, 1.0, 0.0);
  m.normalStiffness = kn;
  s->addMaterial("m", m);
  s->setContactLaw(sim::LawKind::Linear);
  // A jittered lattice, perAxis^d sites of pitch 5 r, in a box with a free layer around it.
  int perAxis = 1;
  while (std::pow(perAxis, d) < n) ++perAxis;
  const double pitch = 5 * r, side = (perAxis + 1) * pitch;
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<sim::ElementDef> defs;
  for (int k = 0; k < n; ++k) {
    Vec3d x{0, 0, 0}, v{0, 0, 0};
    int c = k;
    for (int a = 0; a < d; ++a) {
      x[a] = pitch * (1 + c % perAxis) + 0.2 * r * u(rng);
      c /= perAxis;
      v[a] = vmax * u(rng);
    }
    defs.push_back(grainDef(x, r, "m", v));
  }
  s->addElements(defs);
  for (int a = 0; a < d; ++a) {
    s->addWall(planeWall({0, 0, 0}, axisVec(a, 1), "m"));
    s->addWall(planeWall(axisVec(a, side), axisVec(a, -1), "m"));
  }
  std::vector<double> mass;
  for (sim::ElementId id : s->elementIds()) mass.push_back(s->element(id).mass);
  const double tc = std::numbers::pi * std::sqrt(0.5 * mass[0] / kn);
  s->setTimeStep(tc / spec.stepsPerTime);
  out.timeScale = tc;
  auto energy = [&]() {
    const std::vector<double> v = s->velocities();
    double e = 0;
    for (size_t i = 0; i < mass.size(); ++i) {
      double v2 = 0;
      for (int a = 0; a < d; ++a) v2 += v[i * d + a] * v[i * d + a];
      e += 0.5 * mass[i] * v2;
    }
    for (const sim::ContactInfo& c : s->contacts()) e += 0.5 * kn * c.overlap * c.overlap;
    return e;
  };
  Runner run(*s, out);
  const double e0 = energy();
  const uint64_t chunk = static_cast<uint64_t>(spec.stepsPerTime);
  double drift = 0, deviation = 0;
  uint64_t contacts = 0, quiet = 0;
  for (double t = 0; t < contactTimes; t += 1) {
    run.run(chunk);
    const size_t open = s->contactCount();
    const double err = std::abs(energy() - e0) / e0;
    contacts += open;
    deviation = std::max(deviation, err);
    if (open == 0) {
      drift = std::max(drift, err);
      ++quiet;
    }
  }
  out.quantities.push_back(quantity("energy_drift", quiet ? drift : deviation, 0, "analytic", 1));
  char b[160];
  std::snprintf(b, sizeof b,
                "%d grains; %llu of %g samples without contacts; largest deviation with contacts "
                "open %.3g",
                n, static_cast<unsigned long long>(quiet), contactTimes, deviation);
  out.note = b;
  return out;
}

}  // namespace demlab::verify
