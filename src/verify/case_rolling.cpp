// A grain on a floor under gravity, for both contact laws: rolling down an incline (gravity
// tilted by theta: a = g sin(theta) / (1 + k), k = I / (m r^2), i.e. 5/7 g sin(theta) for a
// sphere, 2/3 for a disc), sliding down a steeper one (a = g (sin(theta) - mu cos(theta)), spin
// accelerating at w' r = mu g cos(theta) / k), and a grain launched sliding without spin turning
// to rolling (after t = k v0 / ((1 + k) mu g): 2 v0 / (7 mu g) for a sphere, at the speed
// v0 / (1 + k): 5/7 v0; having dissipated (1/2) m v0^2 k / (1 + k)).
//
// The grain starts at the static overlap of its weight, so the normal contact does not ring.
// Density 2500 kg/m^3 (spheres), 25 kg/m^2 (discs: about the same weight at r = 0.01 m).
// The time scale is the resting contact's half period, tc = pi sqrt(m / k_eff), k_eff = dF/d
// delta at the static overlap. These are rigid-body answers: the contact's compliance leaves an
// error floor (the tangential spring's oscillation) that a smaller dt does not remove.
#include <cmath>
#include <numeric>
#include <vector>

#include "verify/case_common.hpp"
#include "verify/case_list.hpp"

namespace demlab::verify {

namespace {

constexpr double kRadius = 0.01, kYoung = 1e8;

struct Resting {
  std::unique_ptr<sim::Simulation> s;
  sim::ElementId id;
  double tc = 0, dt = 0, mass = 0;
};

// Returns a grain of radius kRadius resting at its static overlap on a floor (normal = up),
// gravity of magnitude g tilted by theta towards +x, law, friction mu, initial velocity v0
// along x, dt = tc / spec.stepsPerTime.
Resting resting(const RunSpec& spec, sim::LawKind law, double theta, double mu, double v0) {
  Resting r;
  const int d = spec.dim, up = upAxis(d);
  r.s = sim::makeSimulation(d);
  setIntegrator(*r.s, spec.integrator);
  // Discs of 25 kg/m^2 weigh about what spheres of 2500 kg/m^3 do at this radius, so the
  // static overlap (the compliance error against the rigid answer) is alike in 2D and 3D.
  const sim::MaterialDef m = material(kYoung, 0.5, mu, d == 2 ? 25 : 2500);
  r.s->addMaterial("m", m);
  r.s->setContactLaw(law);
  r.s->addWall(planeWall({0, 0, 0}, axisVec(up, 1), "m"));
  r.id = r.s->addElement(grainDef(axisVec(up, 2 * kRadius), kRadius, "m"));
  r.mass = r.s->element(r.id).mass;
  const double fn = r.mass * kGravity * std::cos(theta), es = youngEff(m);
  double delta, keff;
  if (law == sim::LawKind::Linear) {
    keff = es * kRadius;
    delta = fn / keff;
  } else {
    delta = std::pow(fn / (4.0 / 3.0 * es * std::sqrt(kRadius)), 2.0 / 3.0);
    keff = 1.5 * fn / delta;
  }
  r.tc = std::numbers::pi * std::sqrt(r.mass / keff);
  r.dt = r.tc / spec.stepsPerTime;
  r.s->setTimeStep(r.dt);
  r.s->setElementPosition(r.id, axisVec(up, kRadius - delta));
  r.s->setElementVelocity(r.id, {v0, 0, 0});
  Vec3d g = axisVec(up, -kGravity * std::cos(theta));
  g[0] = kGravity * std::sin(theta);
  r.s->addGravity(g);
  return r;
}

// Returns the spin of the grain as the surface speed w r of rolling along +x (2D: about -z;
// 3D, z up: about +y).
double spinSpeed(int d, const sim::ElementState& g) {
  return (d == 2 ? -g.angularVelocity[2] : g.angularVelocity[1]) * g.radius;
}

// Returns the least-squares slope of y against x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  const double mx = std::accumulate(x.begin(), x.end(), 0.0) / n;
  const double my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxy = 0, sxx = 0;
  for (size_t k = 0; k < x.size(); ++k) {
    sxy += (x[k] - mx) * (y[k] - my);
    sxx += (x[k] - mx) * (x[k] - mx);
  }
  return sxy / sxx;
}

const char* lawPrefix(sim::LawKind law) {
  return law == sim::LawKind::Linear ? "linear/" : "hertz/";
}

// The incline: samples the velocity and spin every tc/2 over [0.05 s, 0.15 s] and fits the
// accelerations. Adds acceleration (and roll_ratio or spin_acceleration) to out.
void incline(const RunSpec& spec, sim::LawKind law, double theta, double mu, bool rolling,
             CaseResult& out) {
  Resting r = resting(spec, law, theta, mu, 0);
  Runner run(*r.s, out);
  const uint64_t chunk = std::max<uint64_t>(1, static_cast<uint64_t>(spec.stepsPerTime / 2));
  std::vector<double> t, v, w;
  while (r.s->time() < 0.15) {
    run.run(chunk);
    if (r.s->time() < 0.05) continue;
    const sim::ElementState g = r.s->element(r.id);
    t.push_back(r.s->time());
    v.push_back(g.velocity[0]);
    w.push_back(spinSpeed(spec.dim, g));
  }
  const double k = inertiaFactor(spec.dim);
  const std::string pre = lawPrefix(law);
  if (rolling) {
    const double a = kGravity * std::sin(theta) / (1 + k);
    out.quantities.push_back(quantity(pre + "acceleration", slope(t, v), a, "analytic"));
    out.quantities.push_back(quantity(pre + "roll_ratio", w.back() / v.back(), 1, "analytic"));
  } else {
    const double a = kGravity * (std::sin(theta) - mu * std::cos(theta));
    const double alpha = mu * kGravity * std::cos(theta) / k;
    out.quantities.push_back(quantity(pre + "acceleration", slope(t, v), a, "analytic"));
    out.quantities.push_back(quantity(pre + "spin_acceleration", slope(t, w), alpha, "analytic"));
  }
  if (out.timeScale == 0) out.timeScale = r.tc;  // the first law's (Hertz) tc
}

}  // namespace

CaseResult inclineRolling(const RunSpec& spec) {
  CaseResult out;
  const double theta = 20 * std::numbers::pi / 180;  // tan 20 = 0.36 < (1 + 1/k) mu = 1.75
  for (sim::LawKind law : {sim::LawKind::HertzMindlin, sim::LawKind::Linear}) {
    incline(spec, law, theta, 0.5, true, out);
  }
  return out;
}

CaseResult inclineSliding(const RunSpec& spec) {
  CaseResult out;
  const double theta = 30 * std::numbers::pi / 180;  // tan 30 = 0.58 > (1 + 1/k) mu = 0.35
  for (sim::LawKind law : {sim::LawKind::HertzMindlin, sim::LawKind::Linear}) {
    incline(spec, law, theta, 0.1, false, out);
  }
  return out;
}

CaseResult slideToRoll(const RunSpec& spec) {
  CaseResult out;
  const double v0 = 1.0, mu = 0.3, k = inertiaFactor(spec.dim);
  const double tRoll = k * v0 / ((1 + k) * mu * kGravity);
  for (sim::LawKind law : {sim::LawKind::HertzMindlin, sim::LawKind::Linear}) {
    Resting r = resting(spec, law, 0, mu, v0);
    Runner run(*r.s, out);
    // Slip speed v - w r each step until it first crosses zero (linear interpolation).
    double slipPrev = v0, tPrev = 0, tCross = -1;
    const uint64_t maxSteps = static_cast<uint64_t>(2 * tRoll / r.dt) + 10;
    for (uint64_t n = 0; n < maxSteps && tCross < 0; ++n) {
      run.step();
      const sim::ElementState g = r.s->element(r.id);
      const double slip = g.velocity[0] - spinSpeed(spec.dim, g), t = r.s->time();
      if (slip <= 0) tCross = tPrev + (t - tPrev) * slipPrev / (slipPrev - slip);
      slipPrev = slip;
      tPrev = t;
    }
    // Final speed: the mean over [1.5, 2.5] t_roll, where the stuck contact's tangential
    // spring may still ring a little.
    const uint64_t chunk = std::max<uint64_t>(1, static_cast<uint64_t>(spec.stepsPerTime / 4));
    while (r.s->time() < 1.5 * tRoll) run.run(chunk);
    double sum = 0;
    int count = 0;
    while (r.s->time() < 2.5 * tRoll) {
      run.run(chunk);
      sum += r.s->element(r.id).velocity[0];
      ++count;
    }
    const sim::EnergyLedger e = r.s->energy();
    const std::string pre = lawPrefix(law);
    out.quantities.push_back(quantity(pre + "roll_time", tCross, tRoll, "analytic"));
    out.quantities.push_back(quantity(pre + "final_speed", sum / count, v0 / (1 + k), "analytic"));
    out.quantities.push_back(quantity(pre + "dissipated", e.frictionLoss + e.dampingLoss,
                                      0.5 * r.mass * v0 * v0 * k / (1 + k), "analytic"));
    if (out.timeScale == 0) out.timeScale = r.tc;
  }
  return out;
}

}  // namespace demlab::verify
