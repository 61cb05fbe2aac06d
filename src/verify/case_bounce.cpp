// A grain dropped on a floor under gravity, bouncing three times (linear law, e = 0.8): the
// ratios of successive apex heights. For an instantaneous impact they would be e^2 = 0.64; the
// contact's duration under gravity changes them slightly (the weight presses during the contact
// and the clamped force ends before the overlap does), so the reference is the same law with
// gravity integrated by the RK4 reference (reference_ode.hpp), impact by impact. Free flight
// under constant gravity is integrated exactly by velocity Verlet, so an apex height is read
// exactly from any free-flight state: gap + v^2 / (2 g).
#include <cmath>
#include <cstdio>
#include <string>

#include "physics/pair_params.hpp"
#include "verify/case_common.hpp"
#include "verify/case_list.hpp"
#include "verify/reference_ode.hpp"

namespace demlab::verify {

CaseResult bounce(const RunSpec& spec) {
  CaseResult out;
  const int d = spec.dim, up = upAxis(d);
  const double r = 0.01, h0 = 0.05, e = 0.8;
  auto s = sim::makeSimulation(d);
  setIntegrator(*s, spec.integrator);
  const sim::MaterialDef mat = material(1e7, e, 0);
  s->addMaterial("m", mat);
  s->setContactLaw(sim::LawKind::Linear);
  s->addWall(planeWall({0, 0, 0}, axisVec(up, 1), "m"));
  const sim::ElementId id = s->addElement(grainDef(axisVec(up, r + h0), r, "m"));
  s->addGravity(axisVec(up, -kGravity));
  ImpactLaw law;
  law.mass = s->element(id).mass;
  law.radius = r;
  law.kn = youngEff(mat) * r;
  law.cn = 2 * physics::linearDampingRatio(e) * std::sqrt(law.mass * law.kn);
  law.gravity = kGravity;
  const double tc = linearDamped(law, 1).duration;
  const double dt = tc / spec.stepsPerTime;
  s->setTimeStep(dt);
  out.timeScale = tc;
  Runner run(*s, out);
  double hPrev = h0, hRef = h0;
  std::string textbook;
  for (int b = 1; b <= 3; ++b) {
    // Fly to just before the touch in one run, then step through the contact.
    sim::ElementState g = s->element(id);
    const double gap = g.position[up] - r, v = g.velocity[up];
    const double tHit = (v + std::sqrt(v * v + 2 * kGravity * gap)) / kGravity;
    const double ahead = std::floor(tHit / dt) - 2;
    if (ahead > 0) run.run(static_cast<uint64_t>(ahead));
    bool touched = false;
    for (int k = 0; k < 100000; ++k) {
      run.step();
      g = s->element(id);
      const double overlap = r - g.position[up];
      if (overlap > 0) touched = true;
      if (touched && overlap < 0 && g.velocity[up] > 0) break;
    }
    const double h = g.position[up] - r + g.velocity[up] * g.velocity[up] / (2 * kGravity);
    const ImpactAnswer a = solveImpact(law, std::sqrt(2 * kGravity * hRef));
    const double hNext = a.exitSpeed * a.exitSpeed / (2 * kGravity) - a.endOverlap;
    char name[32];
    std::snprintf(name, sizeof name, "apex_ratio_%d", b);
    out.quantities.push_back(quantity(name, h / hPrev, hNext / hRef, "ode"));
    char t[64];
    std::snprintf(t, sizeof t, "%s%.5f", b > 1 ? ", " : "", hNext / hRef);
    textbook += t;
    hPrev = h;
    hRef = hNext;
  }
  out.note = "reference apex ratios " + textbook + " against e^2 = 0.64 for instantaneous impacts";
  return out;
}

}  // namespace demlab::verify
