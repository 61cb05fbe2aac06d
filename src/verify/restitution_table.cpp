// restitutionSection: one impact per cell, each a fresh Simulation.
#include "verify/restitution_table.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "physics/pair_params.hpp"
#include "sim/simulation.hpp"

namespace demlab::verify {
namespace {

using physics::HertzDamping;
using sim::LawKind;

constexpr double kR = 1e-3, kV0 = 1, kYoung = 5e6, kPoisson = 0.3, kSteps = 1000;

// Returns the rebound -(normal relative velocity after) / (before) of one head-on impact at
// kV0 in 3D with the default integrator and dt = tc / kSteps (tc: the elastic Hertz contact
// time, or pi / omega_n for the linear law): two equal grains of radius kR, or one on a floor.
double rebound(LawKind law, HertzDamping damping, double e, bool wall) {
  auto s = sim::makeSimulation(3);
  sim::MaterialDef m;
  m.density = 2500;
  m.young = kYoung;
  m.poisson = kPoisson;
  m.restitution = e;
  m.friction = 0;
  s->addMaterial("m", m);
  s->setContactLaw(law);
  s->setHertzDamping(damping);
  sim::ElementDef a;
  a.radius = kR;
  a.material = "m";
  a.position = {0, 0, 2 * kR + 1e-9};
  a.velocity = {0, 0, wall ? -kV0 : -0.5 * kV0};
  const sim::ElementId ga = s->addElement(a);
  sim::ElementId gb;
  if (wall) {
    sim::WallDef w;
    w.shape = sim::WallShape::Plane;
    w.point = {0, 0, kR};
    w.normal = {0, 0, 1};
    w.material = "m";
    s->addWall(w);
  } else {
    sim::ElementDef b = a;
    b.position = {0, 0, 0};
    b.velocity = {0, 0, 0.5 * kV0};
    gb = s->addElement(b);
  }
  const double mass = s->element(ga).mass;
  const double mstar = wall ? mass : 0.5 * mass, rstar = wall ? kR : 0.5 * kR;
  const double es = kYoung / (2 * (1 - kPoisson * kPoisson));  // E* of one material
  const double tc = law == LawKind::Linear
                        ? std::numbers::pi / std::sqrt(es * rstar / mstar)
                        : 2.868 * std::pow(mstar * mstar / (rstar * es * es * kV0), 0.2);
  s->setTimeStep(tc / kSteps);
  s->runSteps(static_cast<uint64_t>(4 * kSteps));
  const double va = s->element(ga).velocity[2], vb = wall ? 0 : s->element(gb).velocity[2];
  return (va - vb) / kV0;
}

}  // namespace

std::string restitutionSection() {
  std::string out =
      "## Restitution\n\n"
      "**Restitution means what it says.** A head-on impact at 1 m/s through the Simulation "
      "API (3D, the default integrator, dt = tc/1000 with tc the elastic contact time, "
      "E = 5 MPa, nu = 0.3, radius 1 mm, 2500 kg/m^3): two equal grains (\"pair\") and one "
      "grain on a plane wall (\"wall\"); e_out is the normal relative velocity after over the "
      "one before. The normal force is cut off at 0, so the restitution is the velocity when "
      "it vanishes, which is also the separation velocity (src/physics/pair_params.hpp). The "
      "linear law's damping inverts the cut-off oscillator's exact relation; Hertz-Mindlin's "
      "calibrated damping (`law damping calibrated`, the default) solves the dimensionless "
      "cut-off Hertz impact for its damping factor; `law damping liggghts` is LIGGGHTS's "
      "beta = ln e / sqrt(ln^2 e + pi^2), whose rebound is well above e for small e (the "
      "column \"ODE\" is that rebound from the dimensionless law, hertzRestitution). The "
      "other columns differ from e_in by the time step's error, first order in dt: ~1e-4 "
      "for Hertz, up to 5e-4 for the linear law, whose damping force jumps at the touch; the "
      "unit tests assert 1e-3 at this step (tests/unit/physics/"
      "physics_restitution_test.cpp). Written by src/verify/restitution_table.cpp into the "
      "report; `demlab_verify --restitution` prints it, and the verify test checks that this "
      "file holds it.\n\n"
      "| e_in | linear pair | linear wall | hertz calibrated pair | hertz calibrated wall | "
      "hertz liggghts pair | hertz liggghts ODE |\n"
      "|---|---|---|---|---|---|---|\n";
  for (int k = 1; k <= 19; ++k) {
    const double e = 0.05 * k;
    const double c = -std::sqrt(5.0) * physics::liggghtsBeta(e);
    char row[256];
    std::snprintf(row, sizeof row, "| %.2f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f |\n", e,
                  rebound(LawKind::Linear, HertzDamping::Calibrated, e, false),
                  rebound(LawKind::Linear, HertzDamping::Calibrated, e, true),
                  rebound(LawKind::HertzMindlin, HertzDamping::Calibrated, e, false),
                  rebound(LawKind::HertzMindlin, HertzDamping::Calibrated, e, true),
                  rebound(LawKind::HertzMindlin, HertzDamping::Liggghts, e, false),
                  physics::hertzRestitution(c));
    out += row;
  }
  return out + "\n";
}

}  // namespace demlab::verify
