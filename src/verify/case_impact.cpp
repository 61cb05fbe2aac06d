// Normal (head-on) impacts, sphere-plane and sphere-sphere, for the linear law and for Hertz:
// contact time, peak overlap, peak force and restitution against closed forms (and the RK4
// reference where there is none). Also the impact recorder used by the oblique cases.
#include "verify/case_impact.hpp"

#include <cmath>
#include <vector>

#include "physics/pair_params.hpp"
#include "verify/reference_ode.hpp"

namespace demlab::verify {

namespace {

constexpr double kRadius = 0.01, kSpeed = 1.0, kYoung = 1e8;

}  // namespace

ImpactLaw impactLaw(const ImpactSetup& setup, double massA, double massB) {
  const sim::MaterialDef m = material(kYoung, setup.restitution, setup.friction);
  const double rA = kRadius, rB = setup.sphere ? setup.radiusRatio * kRadius : 0;
  ImpactLaw law;
  law.hertz = setup.law == sim::LawKind::HertzMindlin;
  law.mass = setup.sphere ? massA * massB / (massA + massB) : massA;
  law.radius = setup.sphere ? rA * rB / (rA + rB) : rA;
  law.youngEff = youngEff(m);
  law.restitution = setup.restitution;
  // Linear law: kn = E* R* and zeta from the cut-off restitution relation (pair_params.hpp).
  law.kn = law.youngEff * law.radius;
  law.cn = 2 * physics::linearDampingRatio(setup.restitution) * std::sqrt(law.mass * law.kn);
  return law;
}

ImpactMeasure measureImpact(const ImpactSetup& setup, const RunSpec& spec, CaseResult& out) {
  const int d = spec.dim, up = upAxis(d);
  auto s = sim::makeSimulation(d);
  setIntegrator(*s, spec.integrator);
  s->addMaterial("m", material(kYoung, setup.restitution, setup.friction));
  s->setContactLaw(setup.law);
  const double rA = kRadius, rB = setup.radiusRatio * kRadius;
  // Direction of approach: A moves along -up onto the floor, or A (left) and B (right) meet
  // along x. The tangential velocity (oblique impacts) is along x for the floor, y for spheres.
  const int tAxis = setup.sphere ? 1 : 0;
  sim::ElementId a, b;
  if (setup.sphere) {
    a = s->addElement(grainDef({0, 0, 0}, rA, "m"));
    b = s->addElement(grainDef({rA + rB + 1, 0, 0}, rB, "m"));
  } else {
    s->addWall(planeWall({0, 0, 0}, axisVec(up, 1), "m"));
    a = s->addElement(grainDef(axisVec(up, rA + 1), rA, "m"));
  }
  const double mA = s->element(a).mass, mB = setup.sphere ? s->element(b).mass : 0;
  const ImpactLaw law = impactLaw(setup, mA, mB);
  const double tc =
      law.hertz ? hertzElastic(law, kSpeed).duration : linearDamped(law, kSpeed).duration;
  const double dt = tc / spec.stepsPerTime;
  s->setTimeStep(dt);
  // The touch falls at the same phase of step k0 + 1 for every dt, so the runs of a
  // convergence study differ only in dt.
  const int k0 = 4;
  const double gap = kSpeed * (k0 + setup.touchPhase) * dt;
  const double vt = setup.tangentialRatio * kSpeed;
  if (setup.sphere) {
    // Relative velocity of B against A: -v0 along x (approach) and +vt along y; split by
    // momentum so the centre of mass stays at rest.
    const double fa = mB / (mA + mB), fb = mA / (mA + mB);
    s->setElementPosition(b, {rA + rB + gap, 0, 0});
    Vec3d va{fa * kSpeed, 0, 0}, vb{-fb * kSpeed, 0, 0};
    va[tAxis] -= fa * vt;
    vb[tAxis] += fb * vt;
    s->setElementVelocity(a, va);
    s->setElementVelocity(b, vb);
  } else {
    s->setElementPosition(a, axisVec(up, rA + gap));
    Vec3d v = axisVec(up, -kSpeed);
    v[tAxis] = vt;
    s->setElementVelocity(a, v);
  }
  Runner run(*s, out);
  // Samples per step: overlap, normal force.
  std::vector<double> delta, force;
  auto overlapNow = [&]() {
    if (!setup.sphere) return rA - s->element(a).position[up];
    const Vec3d xa = s->element(a).position, xb = s->element(b).position;
    const double dx = xb[0] - xa[0], dy = xb[1] - xa[1], dz = xb[2] - xa[2];
    return rA + rB - std::sqrt(dx * dx + dy * dy + dz * dz);
  };
  auto forceNow = [&]() {
    double f = 0;
    for (const sim::ContactInfo& c : s->contacts()) f += dot(c.force, c.normal);
    return f;
  };
  delta.push_back(overlapNow());
  force.push_back(0);
  const size_t maxSteps = static_cast<size_t>(20 * spec.stepsPerTime) + 100;
  size_t end = 0;  // first sample with zero force after the touch
  bool touched = false;
  for (size_t k = 1; k < maxSteps; ++k) {
    run.step();
    delta.push_back(overlapNow());
    force.push_back(forceNow());
    if (delta.back() > 0) touched = true;
    if (touched && force.back() <= 0 && end == 0) end = k;
    // Free flight again: no overlap, the force ended.
    if (end && delta.back() < 0) break;
  }
  ImpactMeasure m;
  m.law = law;
  m.tc = tc;
  if (!touched || end < 4) {
    m.valid = false;
    return m;
  }
  size_t first = 1;
  while (delta[first] <= 0) ++first;
  // Touch: delta is linear in free flight (exact to rounding).
  const double t0 = (first - 1 + -delta[first - 1] / (delta[first] - delta[first - 1])) * dt;
  // End: elastic laws end with the overlap (delta linear there); damped ones when the force
  // crosses zero (smooth there), extrapolated from the last three positive samples by the
  // parabola through them (a line through two left the measure an O(dt^2) error of its own,
  // with a sign set by where the zero falls between samples, larger than the run's).
  double t1;
  if (setup.restitution == 1) {
    size_t k = end;
    while (delta[k] > 0) ++k;
    t1 = (k - 1 + delta[k - 1] / (delta[k - 1] - delta[k])) * dt;
  } else {
    t1 = (end - 1 + forceZeroAfter(force[end - 3], force[end - 2], force[end - 1])) * dt;
  }
  m.duration = t1 - t0;
  size_t kd = first, kf = first;
  for (size_t k = first; k < end; ++k) {
    if (delta[k] > delta[kd]) kd = k;
    if (force[k] > force[kf]) kf = k;
  }
  m.peakOverlap = parabolicPeak(delta[kd - 1], delta[kd], delta[kd + 1]);
  m.peakForce = kf > first && force[kf + 1] > 0
                    ? parabolicPeak(force[kf - 1], force[kf], force[kf + 1])
                    : force[kf];
  // Velocities after the impact (free flight): normal rebound and tangential velocity and spin
  // of the contact point.
  const sim::ElementState ga = s->element(a);
  if (setup.sphere) {
    const sim::ElementState gb = s->element(b);
    m.restitution = (gb.velocity[0] - ga.velocity[0]) / kSpeed;
    m.tangential = gb.velocity[tAxis] - ga.velocity[tAxis];
    // Surface speed of the contact points from spin (about z for tangential motion along y).
    m.spin = -(gb.angularVelocity[2] * rB + ga.angularVelocity[2] * rA);
  } else {
    m.restitution = ga.velocity[up] / kSpeed;
    m.tangential = ga.velocity[tAxis];
    // Rolling along +x on the floor: 2D spin about -z, 3D (z up) about +y.
    m.spin = (d == 2 ? -ga.angularVelocity[2] : ga.angularVelocity[1]) * rA;
  }
  m.valid = true;
  return m;
}

namespace {

// Adds the four normal-impact quantities of one impact to out, prefixed.
void addImpactQuantities(const ImpactSetup& setup, const ImpactMeasure& m, CaseResult& out,
                         const std::string& prefix) {
  const ImpactAnswer ode = solveImpact(m.law, kSpeed);
  ImpactAnswer closed;
  std::string src = "analytic", srcForce = "analytic", srcE = "analytic";
  double e = setup.restitution;
  if (!m.law.hertz) {
    closed = linearDamped(m.law, kSpeed);
    closed.peakForce = ode.peakForce;
    srcForce = "ode";
  } else if (setup.restitution == 1) {
    closed = hertzElastic(m.law, kSpeed);
  } else {
    closed = ode;
    src = srcForce = srcE = "ode";
    e = ode.exitSpeed / kSpeed;
  }
  out.quantities.push_back(quantity(prefix + "contact_time", m.duration, closed.duration, src));
  out.quantities.push_back(
      quantity(prefix + "peak_overlap", m.peakOverlap, closed.peakOverlap, src));
  out.quantities.push_back(
      quantity(prefix + "peak_force", m.peakForce, closed.peakForce, srcForce));
  out.quantities.push_back(quantity(prefix + "restitution", m.restitution, e, srcE));
}

CaseResult runImpact(sim::LawKind law, bool sphere, const RunSpec& spec) {
  CaseResult out;
  std::vector<double> restitutions =
      law == sim::LawKind::Linear ? std::vector<double>{0.5} : std::vector<double>{1.0, 0.5};
  for (double e : restitutions)
    for (double phase : {0.1, 0.5, 0.9}) {
      ImpactSetup setup;
      setup.touchPhase = phase;
      setup.law = law;
      setup.sphere = sphere;
      setup.radiusRatio = 2;
      setup.restitution = e;
      const ImpactMeasure m = measureImpact(setup, spec, out);
      if (!m.valid) {
        out.note = "no complete contact was recorded";
        out.quantities.push_back(quantity("contact", 0, 1, "analytic"));
        return out;
      }
      std::string prefix = restitutions.size() > 1 ? (e == 1 ? "elastic/" : "e=0.5/") : "";
      prefix += "phase=" + std::to_string(phase).substr(0, 3) + "/";
      addImpactQuantities(setup, m, out, prefix);
      if (e != 1 && law == sim::LawKind::HertzMindlin) {
        ImpactLaw liggghts = m.law;
        liggghts.liggghtsDamping = true;
        const double eModel = solveImpact(m.law, kSpeed).exitSpeed / kSpeed;
        const double eLiggghts = solveImpact(liggghts, kSpeed).exitSpeed / kSpeed;
        out.note = "Hertz-Mindlin with material restitution 0.5 rebounds at e = " +
                   std::to_string(eModel) + " in the reference (calibrated damping; with " +
                   "LIGGGHTS's coefficient, `law damping liggghts`: " + std::to_string(eLiggghts) +
                   ")";
      }
      if (out.timeScale == 0) out.timeScale = m.tc;
    }
  return out;
}

}  // namespace

CaseResult impactLinearPlane(const RunSpec& spec) {
  return runImpact(sim::LawKind::Linear, false, spec);
}
CaseResult impactLinearSphere(const RunSpec& spec) {
  return runImpact(sim::LawKind::Linear, true, spec);
}
CaseResult impactHertzPlane(const RunSpec& spec) {
  return runImpact(sim::LawKind::HertzMindlin, false, spec);
}
CaseResult impactHertzSphere(const RunSpec& spec) {
  return runImpact(sim::LawKind::HertzMindlin, true, spec);
}

}  // namespace demlab::verify
