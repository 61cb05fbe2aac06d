// SimulationManager<D>: scene editing (materials, grains, tags, behaviors, options), each
// call checking its whole input first. Walls are in simulation_walls.cpp; running, queries and
// whole-scene operations in simulation_run.cpp.
#include "sim/simulation_manager.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>

#include "core/interrupt.hpp"
#include "core/name_lookup.hpp"
#include "physics/critical_step.hpp"
#include "sim/behaviors/gravity.hpp"
#include "sim/behaviors/load.hpp"
#include "sim/convert.hpp"
#include "sim/history_store.hpp"
#include "sim/rigid_body.hpp"
#include "sim/option_table.hpp"
#include "sim/watchdog.hpp"

namespace demlab::sim {

std::string dofNames(unsigned mask) {
  static const char* const kNames[] = {"x", "y", "z", "rx", "ry", "rz"};
  std::string out;
  for (unsigned k = 0; k < 32; ++k) {
    if (!(mask & (1u << k))) continue;
    if (!out.empty()) out.push_back(' ');
    if (k < 6) {
      out.append(kNames[k]);
    } else {
      out.append("bit").append(std::to_string(k));
    }
  }
  return out;
}

unsigned dofFromName(std::string_view name) {
  static const char* const kNames[] = {"x", "y", "z", "rx", "ry", "rz"};
  for (unsigned k = 0; k < 6; ++k) {
    if (name == kNames[k]) return 1u << k;
  }
  throw Error("bad degree of freedom \"" + std::string(name) + "\": must be x, y, z, rx, ry or rz",
              {"VALUE", "DOF"});
}

LawKind lawFromName(std::string_view name) {
  for (LawKind k : {LawKind::Linear, LawKind::HertzMindlin}) {
    if (physics::lawName(k) == name) return k;
  }
  throw Error("bad law \"" + std::string(name) + "\": must be linear or hertz_mindlin",
              {"VALUE", "LAW"});
}

std::unique_ptr<Simulation> makeSimulation(int dim) {
  if (dim == 2) return std::make_unique<SimulationManager<2>>();
  if (dim == 3) return std::make_unique<SimulationManager<3>>();
  throw Error("bad dimension \"" + std::to_string(dim) + "\": must be 2 or 3",
              {"VALUE", "DIMENSION"});
}

// ---- time --------------------------------------------------------------------------------

template <int D>
void SimulationManager<D>::setTimeStep(double dt) {
  checkPositive(dt, "time step");
  s_.dt = dt;
  s_.autoFraction = 0;
  touchConfig();
}

template <int D>
void SimulationManager<D>::setAutoTimeStep(double fraction, double stepsPerContact) {
  if (!(fraction > 0 && fraction <= 1)) {
    throwBad("fraction", physics::formatReal(fraction), "must be in (0, 1]");
  }
  if (!(stepsPerContact >= 0 && stepsPerContact <= 1e6)) {
    throwBad("stepspercontact", physics::formatReal(stepsPerContact), "must be in [0, 1e6]");
  }
  s_.autoFraction = fraction;
  if (stepsPerContact != s_.stepsPerContact) {
    s_.stepsPerContact = stepsPerContact;
    s_.motionStep = std::numeric_limits<double>::infinity();  // taken again at the next run
    s_.motionSpeed = 0;
  }
  touchConfig();
}

template <int D>
double SimulationManager<D>::timeStep() const {
  StepSurvey survey;
  if (s_.autoFraction == 0) return timeStepFrom(survey);
  // (Distributed: the whole scene's, over the ranks: collective.)
  staticCriticalStep(false, &survey, true);
  const double dt = timeStepFrom(survey);  // throws when there is none
  // What the run's start will take: the motion bound again if the fastest element outran it.
  double speed = std::sqrt(fastestSpeed2(s_));
  if (s_.dist) speed = s_.dist->comm->max(speed);
  const double limit = s_.dist ? s_.dist->stepLimit : watchdogStepLimit(s_, skinInUse());
  if (!retakesMotion(s_.steps % kContactStepEvery == 0, speed, dt, limit)) return dt;
  return autoStep(survey, motionBound(kSpeedHeadroom * speed, survey, limit));
}

template <int D>
bool SimulationManager<D>::retakesMotion(bool measure, double speed, double dt,
                                         double stepLimit) const {
  return measure || (speed > s_.motionSpeed && speed * dt > kMoveShare * stepLimit);
}

template <int D>
double SimulationManager<D>::timeStepFrom(const StepSurvey& survey) const {
  if (s_.autoFraction > 0) {
    const double dt = autoStep(survey, s_.motionStep);
    if (!std::isfinite(dt)) {
      throw Error("no time step: it is automatic and the scene has no grains and no sources",
                  {"VALUE", "TIMESTEP"});
    }
    return dt;
  }
  if (!(s_.dt > 0)) throw Error("no time step: set one", {"VALUE", "TIMESTEP"});
  return s_.dt;
}

template <int D>
double SimulationManager<D>::criticalTimeStep() const {
  // (Distributed: the whole scene's, as the ranks last decided it together.)
  return std::min(s_.dist ? s_.dist->critical : staticCriticalStep(), s_.contactStep);
}

template <int D>
double SimulationManager<D>::autoStep(const StepSurvey& survey, double motionStep) const {
  // The fraction scales the static estimate, which for Hertz-Mindlin (the Rayleigh step) is
  // a scale for accuracy (LIGGGHTS advises at most 0.2 of it), and the contacts' estimate,
  // which is a stability limit, 2.5 times as far: at the default 0.2 the step stays within half
  // the limit the contacts' overlaps set (an oedometric compression of a soft Hertz bed to 30 %
  // strain then closes its energy balance to 1e-4; doc/design.md, "The time step").
  constexpr double kContactOverStatic = 2.5;
  const double stable =
      s_.autoFraction * std::min(survey.critical, kContactOverStatic * s_.contactStep);
  const double accurate =
      s_.stepsPerContact > 0 ? survey.linearDuration / s_.stepsPerContact
                             : std::numeric_limits<double>::infinity();
  return std::min({stable, accurate, motionStep});
}

template <int D>
double SimulationManager<D>::motionBound(double speed, const StepSurvey& survey,
                                         double stepLimit) const {
  // A non-finite speed bounds nothing: the watchdog's NAN check (or the run's finiteness
  // check) reports the state, and a zero step would make a run of -time endless.
  if (!(speed > 0 && std::isfinite(speed))) return std::numeric_limits<double>::infinity();
  double bound = kMoveShare * stepLimit / speed;
  if (s_.stepsPerContact > 0) {
    // Two elements at the fastest speed, head on: tc scales as v^(-1/5).
    bound = std::min(bound,
                     survey.hertzDuration * std::pow(2 * speed, -0.2) / s_.stepsPerContact);
  }
  return bound;
}

template <int D>
double SimulationManager<D>::staticCriticalStep(bool polled, StepSurvey* survey,
                                               bool acrossRanks) const {
  // Per material: the smallest grain, which is also the lightest and has the least inertia
  // (mass ~ density r^D). Each pair of materials in use (walls included) is then taken with
  // the smallest grain of either side against it: the stiffest contact (the pair's constants)
  // against the smallest mass and inertia, and the damping's reduction of the stable step
  // (physics::criticalTimeStep). For Hertz-Mindlin pairs the Rayleigh step of each grain's own
  // material counts too (a light grain against a heavy, stiff one).
  const size_t nm = s_.nMat();
  const Real inf = std::numeric_limits<Real>::infinity();
  std::vector<Real> rmin(nm, inf);
  std::vector<bool> used(nm, false);
  const ElementArrays<D>& a = s_.elements.a;
  // Elements of other shapes: per material their least mass along a contact normal and least
  // volume-equivalent radius (the ball's formulas below take a mass and a radius). The mass
  // along a normal at a point at lever arm r is at least 1 / (1/m + R^2 / I_min) with R the
  // bounding radius (sim/shape_contacts.hpp's effective mass): a corner contact is stiffer for
  // its mass than the centre line.
  std::vector<Real> shapeMass(nm, inf), shapeR(nm, inf);
  for (size_t i = 0; i < a.size(); ++i) {
    const uint32_t m = a.material[i];
    used[m] = true;
    if (a.geometry[i] == 0) {
      rmin[m] = std::min(rmin[m], a.r[i]);
      continue;
    }
    const Geometry<D>& g = *s_.geometries[a.geometry[i]];
    const Real rho = s_.materials[m].density;
    const Real iMin = D == 2 ? rho * g.principalMoments[2] : rho * g.principalMoments.minCoeff();
    const Real lever = s_.rotationEnabled ? g.boundRadius * g.boundRadius / iMin : 0;
    shapeMass[m] = std::min(shapeMass[m], 1 / (a.invMass[i] + lever));
    const Real req = D == 3 ? std::cbrt(g.volume * 3 / (4 * std::numbers::pi))
                            : std::sqrt(g.volume / std::numbers::pi);
    shapeR[m] = std::min(shapeR[m], req);
  }
  for (const Wall<D>& w : s_.walls.items) used[w.material] = true;
  // What the sources will insert counts as if it were there: a source into an empty scene runs.
  for (const SourceState& src : s_.sources) {
    used[src.material] = true;
    rmin[src.material] = std::min(rmin[src.material], Real(src.def.size.minRadius()));
  }
  if (acrossRanks && s_.dist) {
    // A distributed part: the whole scene's smallest grains, over the ranks (collective).
    const mpi::Communicator& comm = *s_.dist->comm;
    comm.min(rmin);
    comm.min(shapeMass);
    comm.min(shapeR);
    std::vector<double> u(used.begin(), used.end());
    comm.max(u);
    for (size_t m = 0; m < nm; ++m) used[m] = u[m] > 0;
  }
  Real best = inf, linearDuration = inf, hertzDuration = inf;
  // A grain of material `side` (mass, radius) in a contact of pair p: the stable step, the
  // Rayleigh step (the sphere of a disc's radius and mass in 2D) and how long its contacts last.
  const bool synchronized = s_.integrator == IntegratorKind::Synchronized;
  const auto take = [&](const physics::PairParams& p, size_t side, Real mass, Real r) {
    const Real rayleigh = physics::rayleighDimensionFactor<D>(r);
    if (p.law == LawKind::HertzMindlin) {
      best = std::min(best, rayleigh * physics::criticalTimeStep(p, mass, r, synchronized));
      best = std::min(best, rayleigh * physics::rayleighTimeStep(s_.materials[side], r));
      hertzDuration = std::min(hertzDuration, physics::contactDuration(p, mass, r, 1));
    } else {
      best = std::min(best, physics::criticalTimeStep(p, mass, r, synchronized));
      linearDuration = std::min(linearDuration, physics::contactDuration(p, mass, r, 1));
    }
  };
  for (size_t m = 0; m < nm; ++m) {
    if (!std::isfinite(rmin[m]) && !std::isfinite(shapeR[m])) continue;
    for (size_t k = 0; k < nm; ++k) {
      if (!used[k]) continue;
      const int8_t o = s_.pairLawOverride[m * nm + k];
      const LawKind law = o < 0 ? s_.defaultLaw : static_cast<LawKind>(o);
      // The pair as the run mixes it: its own coefficients (a stiffer pair, a lower
      // restitution) change the stable step.
      const auto [ma, mk] = s_.pairMaterials(m, k);
      const physics::PairParams p = physics::mixPair(law, ma, mk, s_.hertzDamping);
      for (const size_t side : {m, k}) {
        if (std::isfinite(rmin[side])) {  // else a wall's material, or shapes only
          const Real r = rmin[side];
          take(p, side, ballMass<D>(s_.materials[side].density, r), r);
        }
        if (std::isfinite(shapeR[side])) take(p, side, shapeMass[side], shapeR[side]);
      }
    }
  }
  const double critical = std::min(best, bondCriticalStep(polled));
  if (survey) *survey = {critical, linearDuration, hertzDuration};
  return critical;
}

// ---- materials and laws --------------------------------------------------------------------

template <int D>
uint32_t SimulationManager<D>::materialIndex(const std::string& name) const {
  for (size_t m = 0; m < s_.materialNames.size(); ++m) {
    if (s_.materialNames[m] == name) return static_cast<uint32_t>(m);
  }
  throw Error("no material named \"" + name + "\"", {"LOOKUP", "MATERIAL"});
}

template <int D>
void SimulationManager<D>::addMaterial(const std::string& name, const MaterialDef& def) {
  checkObjectName("material", name);
  for (const std::string& n : s_.materialNames) {
    if (n == name) {
      throw Error("material \"" + name + "\" already exists", {"EXISTS", "MATERIAL"});
    }
  }
  def.check();
  const size_t n = s_.nMat();
  std::vector<int8_t> table((n + 1) * (n + 1), -1);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) table[i * (n + 1) + j] = s_.pairLawOverride[i * n + j];
  }
  s_.materialNames.push_back(name);
  s_.materials.push_back(def);
  s_.pairLawOverride = std::move(table);
  touchConfig();
}

template <int D>
void SimulationManager<D>::setMaterial(const std::string& name, const MaterialDef& def) {
  const uint32_t m = materialIndex(name);
  def.check();
  const auto& mats = s_.elements.a.material;
  int64_t taking = std::count(mats.begin(), mats.begin() + s_.ownedCount(), m);
  if (s_.dist) taking = s_.dist->comm->sum(taking);  // (every rank's elements: collective)
  if (def.isRigid() && taking > 0) {
    throw Error("material \"" + name + "\" can't be made rigid: elements take it (only walls may)",
                {"VALUE", "MATERIAL"});
  }
  const double before = ledgerSum();
  s_.materials[m] = def;
  ElementArrays<D>& a = s_.elements.a;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a.material[i] != m) continue;
    const auto [invMass, invInertia] =
        inverseMassAndInertia(*s_.geometries[a.geometry[i]], def.density, a.r[i]);
    a.invMass[i] = invMass;
    a.invInertia[i] = invInertia;
  }
  s_.ledger.reference += ledgerSum() - before;
  // (Distributed: the ghosts' masses are their owners' from the next search on.)
  s_.needRebuild = s_.needRebuild || s_.dist != nullptr;
  touchConfig();
}

template <int D>
MaterialDef SimulationManager<D>::material(const std::string& name) const {
  return s_.materials[materialIndex(name)];
}

template <int D>
void SimulationManager<D>::setContactLaw(LawKind law) {
  if (law != LawKind::Linear && law != LawKind::HertzMindlin) {
    throw Error("bad law: must be linear or hertz_mindlin", {"VALUE", "LAW"});
  }
  s_.defaultLaw = law;
  touchConfig();
}

template <int D>
void SimulationManager<D>::setCoulombCriterion(physics::CoulombCriterion c) {
  if (c != physics::CoulombCriterion::Total && c != physics::CoulombCriterion::Spring) {
    throw Error("bad coulomb criterion: must be total or spring", {"VALUE", "COULOMB"});
  }
  s_.coulomb = c;
  touchConfig();
}

template <int D>
void SimulationManager<D>::setHertzDamping(physics::HertzDamping d) {
  if (d != physics::HertzDamping::Calibrated && d != physics::HertzDamping::Liggghts) {
    throw Error("bad damping: must be calibrated or liggghts", {"VALUE", "DAMPING"});
  }
  s_.hertzDamping = d;
  touchConfig();
}

template <int D>
void SimulationManager<D>::setPairLaw(const std::string& a, const std::string& b, LawKind law) {
  const uint32_t i = materialIndex(a), j = materialIndex(b);
  if (law != LawKind::Linear && law != LawKind::HertzMindlin) {
    throw Error("bad law: must be linear or hertz_mindlin", {"VALUE", "LAW"});
  }
  const size_t n = s_.nMat();
  s_.pairLawOverride[i * n + j] = static_cast<int8_t>(law);
  s_.pairLawOverride[j * n + i] = static_cast<int8_t>(law);
  touchConfig();
}

template <int D>
LawKind SimulationManager<D>::pairLaw(const std::string& a, const std::string& b) const {
  const uint32_t i = materialIndex(a), j = materialIndex(b);
  const int8_t o = s_.pairLawOverride[i * s_.nMat() + j];
  return o < 0 ? s_.defaultLaw : static_cast<LawKind>(o);
}

template <int D>
void SimulationManager<D>::setPairCoefficients(const std::string& a, const std::string& b,
                                               const PairCoefficients& c) {
  const uint32_t i = materialIndex(a), j = materialIndex(b);
  // Each test is written so that a NaN (unset) passes and nothing else outside the range does.
  const auto check = [](double x, bool ok, const char* what, const char* range, const char* code) {
    if (std::isnan(x) || ok) return;
    throw Error(
        std::string("bad ") + what + " \"" + physics::formatReal(x) + "\": must be " + range,
        {"VALUE", code});
  };
  check(c.restitution, c.restitution > 0 && c.restitution <= 1, "restitution",
        "a number greater than 0 and at most 1", "RESTITUTION");
  check(c.friction, c.friction >= 0 && std::isfinite(c.friction), "friction",
        "a non-negative number", "FRICTION");
  check(c.rolling, c.rolling >= 0 && std::isfinite(c.rolling), "rolling friction",
        "a non-negative number", "ROLLINGFRICTION");
  check(c.cohesion, c.cohesion >= 0 && std::isfinite(c.cohesion), "cohesion",
        "a non-negative number", "COHESION");
  check(c.young, c.young > 0 && std::isfinite(c.young), "young", "a positive number", "YOUNG");
  const uint32_t lo = std::min(i, j), hi = std::max(i, j);
  std::erase_if(s_.pairOverrides, [&](const PairOverride& o) { return o.a == lo && o.b == hi; });
  const bool any = !std::isnan(c.restitution) || !std::isnan(c.friction) ||
                   !std::isnan(c.rolling) || !std::isnan(c.cohesion) || !std::isnan(c.young);
  if (any) s_.pairOverrides.push_back({lo, hi, c});
  touchConfig();
}

template <int D>
PairCoefficients SimulationManager<D>::pairOverrides(const std::string& a,
                                                     const std::string& b) const {
  const uint32_t i = materialIndex(a), j = materialIndex(b);
  for (const PairOverride& o : s_.pairOverrides) {
    if (o.a == std::min(i, j) && o.b == std::max(i, j)) return o.c;
  }
  return {};
}

template <int D>
PairCoefficients SimulationManager<D>::pairCoefficients(const std::string& a,
                                                        const std::string& b) const {
  const uint32_t i = materialIndex(a), j = materialIndex(b);
  const auto [ma, mb] = s_.pairMaterials(i, j);
  PairCoefficients c;
  // The mixing rules (physics/pair_params.hpp, sim/pair_table.hpp), without the law's
  // constants (mixPair would solve Hertz's damping calibration for a query).
  c.restitution = physics::mixRestitution(ma, mb);
  c.friction = physics::mixFriction(ma, mb);
  c.rolling = std::min(ma.rollingFriction, mb.rollingFriction);
  c.cohesion = std::min(ma.cohesion, mb.cohesion);
  // The pair's own modulus as given (the copies' mixing gives it back to rounding).
  const double own = pairOverrides(a, b).young;
  c.young = !std::isnan(own) ? own
                             : 1 / ((1 - ma.poisson * ma.poisson) / ma.young +
                                    (1 - mb.poisson * mb.poisson) / mb.young);
  return c;
}

// ---- grains --------------------------------------------------------------------------------

template <int D>
typename Simulation::ElementMeshes SimulationManager<D>::elementMeshes() const {
  ElementMeshes out;
  if (s_.geometries.size() < 2) return out;
  const ShapeTable<D>& t = ShapeTable<D>::get();
  std::vector<int32_t> meshOfGeometry(s_.geometries.size(), -1);
  for (size_t k = 1; k < s_.geometries.size(); ++k) {
    const Geometry<D>& g = *s_.geometries[k];
    const std::vector<Vec3> tri = t.type(g.shape).renderTriangles(g.params);
    if (tri.empty()) continue;
    meshOfGeometry[k] = static_cast<int32_t>(out.meshes.size());
    out.meshes.emplace_back();
    for (const Vec3& p : tri) out.meshes.back().push_back({p.x(), p.y(), p.z()});
  }
  if (out.meshes.empty()) return out;
  for (uint32_t g : s_.elements.a.geometry) out.meshOf.push_back(meshOfGeometry[g]);
  return out;
}

template <int D>
uint32_t SimulationManager<D>::geometryIndex(const Geometry<D>& g) {
  if (g.shape == ShapeTable<D>::ball()) return 0;
  const auto [it, added] = s_.geometryLookup.emplace(std::make_pair(g.shape.value, g.params),
                                                     static_cast<uint32_t>(s_.geometries.size()));
  if (added) s_.geometries.push_back(Shareable<Geometry<D>>::make(g));
  return it->second;
}

template <int D>
typename SimulationManager<D>::CheckedElement SimulationManager<D>::checkElement(
    const ElementDef& def, const Geometry<D>* same) const {
  CheckedElement c;
  const ShapeTable<D>& table = ShapeTable<D>::get();
  const std::string_view shape =
      def.shape.empty() ? table.type(ShapeTable<D>::ball()).name() : std::string_view(def.shape);
  // The ball's Geometry is the scene's first; any other is the scene's own if it has one of the
  // same type and parameters (made deterministically from them: a packing of equal clumps or
  // level sets makes one, not one an element), else made (and checked) from the table.
  const auto id = table.id(shape);
  const auto known = id ? s_.geometryLookup.find(std::make_pair(id->value, def.shapeParams))
                        : s_.geometryLookup.end();
  c.geometry = def.shape.empty() && def.shapeParams.empty() ? *s_.geometries[0]
               : same != nullptr                           ? *same
               : known != s_.geometryLookup.end()          ? *s_.geometries[known->second]
                                                           : table.makeGeometry(shape, def.shapeParams);
  if (c.geometry.boundRadius == 0) {
    checkPositive(def.radius, "radius");
    c.r = def.radius;
  } else {
    if (def.radius != 0) {
      throw Error("bad radius: a " + std::string(shape) +
                      " takes no radius (its size is in its parameters)",
                  {"VALUE", "RADIUS"});
    }
    c.r = c.geometry.boundRadius;
  }
  checkRadiusRange(c.r, c.geometry.boundRadius == 0 ? "radius" : "size");
  c.q = toRotation<D>(def.orientation);
  c.x = toVec<D>(def.position, "position");
  c.v = toVec<D>(def.velocity, "velocity");
  c.w = toAngular<D>(def.angularVelocity, "angular velocity");
  checkPositionRange<D>(c.x, c.r);
  checkVelocityRange<D>(c.v);
  checkAngularRange(c.w, c.r, D);
  c.material = materialIndex(def.material);
  for (const std::string& t : def.tags) checkTagName(t);
  if (!def.name.empty()) {
    checkObjectName("grain", def.name);
    if (elementNameTable().find(def.name)) throwNameExists("grain", def.name);
  }
  if (s_.materials[c.material].isRigid()) {
    throw Error("material \"" + def.material + "\" is rigid: only walls take it",
                {"VALUE", "MATERIAL"});
  }
  checkDofMask(def.blocked);
  c.blocked = static_cast<uint8_t>(def.blocked);
  std::tie(c.invMass, c.invInertia) =
      inverseMassAndInertia(c.geometry, s_.materials[c.material].density, c.r);
  checkMassRange(c.invMass, c.r);
  return c;
}

template <int D>
double SimulationManager<D>::elementEnergy(uint32_t i) const {
  const ElementArrays<D>& a = s_.elements.a;
  return 0.5 * a.v[i].squaredNorm() / a.invMass[i] + 0.5 * twiceRotationalEnergy(s_, i) -
         s_.behaviors.gravity().dot(a.x[i]) / a.invMass[i];
}

template <int D>
ElementId SimulationManager<D>::addElement(const ElementDef& def) {
  if (s_.dist) return addElementOnRanks(def);
  const CheckedElement c = checkElement(def);
  const ElementId id = s_.elements.add(c.x, c.v, c.w, c.r, c.invMass, c.invInertia, c.material,
                                   def.name, def.tags, geometryIndex(c.geometry));
  s_.elements.a.q.back() = c.q;
  if (c.blocked != 0) s_.blocked.push_back({id, c.blocked});
  s_.ledger.reference += elementEnergy(static_cast<uint32_t>(s_.elements.size() - 1));
  markPlaced(id);
  s_.needRebuild = true;
  touchConfig();
  return id;
}

template <int D>
std::vector<ElementId> SimulationManager<D>::addElements(const std::vector<ElementDef>& defs) {
  refuseIfDistributed("add elements");
  std::vector<CheckedElement> checked;
  checked.reserve(defs.size());
  std::unordered_set<std::string> names;
  InterruptPoll poll("adding elements");  // before anything is added
  for (size_t k = 0; k < defs.size(); ++k) {
    const ElementDef& d = defs[k];
    poll();
    // A packing's elements of one shape: its Geometry made once (mass properties integrated
    // over a grid for overlapping clumps), not once an element.
    const bool asBefore = k > 0 && !d.shapeParams.empty() && d.shape == defs[k - 1].shape &&
                          d.shapeParams == defs[k - 1].shapeParams;
    try {
      checked.push_back(checkElement(d, asBefore ? &checked.back().geometry : nullptr));
    } catch (const Error& e) {
      if (d.origin.empty()) throw;
      throw e.within(d.origin);
    }
    if (!d.name.empty() && !names.insert(d.name).second) throwNameExists("grain", d.name);
  }
  std::vector<ElementId> ids;
  ids.reserve(defs.size());
  ElementArrays<D>& a = s_.elements.a;
  const size_t n0 = a.size();
  const size_t n1 = n0 + defs.size();
  // Batches after the first grow the arrays by half (not to exactly n1: a reallocation per
  // batch would copy every grain each time); reserveElements() sizes them exactly.
  if (a.x.capacity() < n1) reserveElements(n0 == 0 ? n1 : std::max(n1, n0 + n0 / 2));
  // The room's pages first touched while Ctrl-C is still polled: the commit below, which
  // cannot stop half way, then takes no page fault (most of its time where faults are slow).
  a.touchRoom(n1, "adding elements");
  s_.elements.pool().touchRoom(static_cast<uint32_t>(std::min<size_t>(n1, UINT32_MAX)),
                               "adding elements");
  touchRoom(ids, defs.size(), ElementId{}, "adding elements");
  for (size_t k = 0; k < defs.size(); ++k) {
    const CheckedElement& c = checked[k];
    ids.push_back(s_.elements.add(c.x, c.v, c.w, c.r, c.invMass, c.invInertia, c.material,
                                defs[k].name, defs[k].tags, geometryIndex(c.geometry)));
    a.q.back() = c.q;
    if (c.blocked != 0) s_.blocked.push_back({ids.back(), c.blocked});
    s_.ledger.reference += elementEnergy(static_cast<uint32_t>(n0 + k));
    markPlaced(ids.back());
  }
  s_.needRebuild = true;
  touchConfig();
  return ids;
}

template <int D>
void SimulationManager<D>::reserveElements(size_t n) {
  s_.elements.a.reserve(n);
  s_.elements.pool().reserve(static_cast<uint32_t>(std::min<size_t>(n, UINT32_MAX)));
}

template <int D>
void SimulationManager<D>::removeElement(ElementId id) {
  refuseIfDistributed("remove an element");
  const uint32_t i = s_.elements.index(id);
  s_.ledger.reference -= elementEnergy(i);
  forgetCandidates();
  dropBlocked([&](ElementId g) { return g == id; });
  std::erase(s_.placedElements, id);
  const uint32_t slot = s_.elements.remove(id);
  dropBonds({slot});
  if (s_.keepHistory) s_.histories.removeId(slot);
  s_.shapeSprings.eraseIf([&](const ShapeSpringKey& k) { return k.a == slot || k.b == slot; });
  s_.needRebuild = true;
  touchConfig();
}

template <int D>
size_t SimulationManager<D>::removeElementList(const std::vector<ElementId>& ids) {
  std::vector<ElementId> unique;
  std::unordered_set<uint64_t> seen;
  for (ElementId g : ids) {
    if (seen.insert(g.bits()).second) unique.push_back(g);
  }
  if (s_.dist) return removeElementsOnRanks(unique);
  for (ElementId g : unique) s_.elements.index(g);  // (all or none: LOOKUP HANDLE first)
  for (ElementId g : unique) removeElement(g);
  return unique.size();
}

template <int D>
size_t SimulationManager<D>::removeElements(const std::string& tag) {
  const std::vector<ElementId> ids = elementTagTable().objects(tag);
  if (ids.empty()) return 0;
  if (s_.dist) return removeElementsOnRanks(ids);
  removeElementSet(ids);
  return ids.size();
}

template <int D>
void SimulationManager<D>::removeElementSet(const std::vector<ElementId>& ids) {
  forgetCandidates();
  std::unordered_set<uint32_t> slots;
  for (ElementId id : ids) {
    // The element takes its energy out of the scene: the ledger's reference goes with it.
    s_.ledger.reference -= elementEnergy(s_.elements.index(id));
    slots.insert(s_.elements.remove(id));
  }
  dropBlocked([&](ElementId g) { return slots.contains(g.index); });
  std::erase_if(s_.placedElements, [&](ElementId g) { return slots.contains(g.index); });
  dropBonds(slots);
  s_.shapeSprings.eraseIf([&](const ShapeSpringKey& k) { return slots.contains(k.a) || slots.contains(k.b); });
  if (s_.keepHistory) {
    std::vector<std::pair<uint32_t, uint32_t>> drop;
    s_.histories.forEach([&](const auto& p, auto&) {
      if (slots.contains(p.first) || slots.contains(p.second)) drop.emplace_back(p.first, p.second);
    });
    for (const auto& [p, q] : drop) s_.histories.erase(p, q);
  }
  s_.needRebuild = true;
  touchConfig();
}

template <int D>
ElementState SimulationManager<D>::element(ElementId id) const {
  const uint32_t i = s_.elements.index(id);
  const ElementArrays<D>& a = s_.elements.a;
  ElementState g;
  g.id = id;
  // (The names, tags and blocked list hold the scripts' handles; a distributed scene's id is
  // this rank's handle.)
  const ElementId listed = s_.dist ? s_.dist->handleOf(a.globalId[i]) : id;
  if (auto n = elementNameTable().nameOf(listed)) g.name = std::string(*n);
  for (std::string_view t : elementTagTable().tagsOf(listed)) g.tags.emplace_back(t);
  g.material = s_.materialNames[a.material[i]];
  g.radius = a.r[i];
  g.mass = 1 / a.invMass[i];
  const Geometry<D>& geom = *s_.geometries[a.geometry[i]];
  const Vec3 moments =
      geom.boundRadius == 0 ? Vec3::Constant(1 / a.invInertia[i])
                            : Vec3(s_.materials[a.material[i]].density * geom.principalMoments);
  g.inertia = moments.maxCoeff();
  g.principalInertia = {moments.x(), moments.y(), moments.z()};
  g.position = fromVec<D>(a.x[i]);
  g.unwrapped = fromVec<D>(VecD<D>(a.x[i] + s_.periodic.unwrapOffset(id)));
  g.velocity = fromVec<D>(a.v[i]);
  g.angularVelocity = fromAngular(a.w[i]);
  g.force = fromVec<D>(a.f[i]);
  g.torque = fromAngular(a.t[i]);
  g.orientation = fromRotation(a.q[i]);
  g.shape = ShapeTable<D>::get().type(geom.shape).name();
  g.shapeParams = geom.params;
  for (const BlockedElement& b : s_.blocked) {
    if (b.id == listed) g.blocked = b.dofs;
  }
  return g;
}

template <int D>
ElementId SimulationManager<D>::findElement(const std::string& name) const {
  return elementNameTable().get(name);
}

// The kinematic setters change one element wherever it is (editElement, after which a
// distributed scene's every rank searches again), move the ledger's reference alike and have
// the forces computed anew.
template <int D>
void SimulationManager<D>::setElementPosition(ElementId id, const Vec3d& p) {
  const VecD<D> x = toVec<D>(p, "position");
  const ElementEdit e = editElement(id, [&](uint32_t i) {
    checkPositionRange<D>(x, s_.elements.a.r[i]);
    s_.elements.a.x[i] = x;
  });
  s_.ledger.reference += e.energy;
  markPlacedEdit(id, e);
  s_.needRebuild = true;
  s_.forcesReady = false;
}

template <int D>
void SimulationManager<D>::setElementVelocity(ElementId id, const Vec3d& v) {
  const VecD<D> x = toVec<D>(v, "velocity");
  checkVelocityRange<D>(x);
  const ElementEdit e = editElement(id, [&](uint32_t i) { s_.elements.a.v[i] = x; });
  s_.ledger.reference += e.energy;
  s_.forcesReady = false;
}

template <int D>
void SimulationManager<D>::setElementAngularVelocity(ElementId id, const Vec3d& w) {
  const AngularD<D> x = toAngular<D>(w, "angular velocity");
  const ElementEdit e = editElement(id, [&](uint32_t i) {
    checkAngularRange(x, s_.elements.a.r[i], D);
    s_.elements.a.w[i] = x;
  });
  s_.ledger.reference += e.energy;
  // (Distributed: the next run decides again for the whole scene whether it turns.)
  touchConfig();
}

template <int D>
void SimulationManager<D>::setElementOrientation(ElementId id, const std::vector<double>& o) {
  const RotationD<D> q = toRotation<D>(o);
  // A shape's rotational energy (w . I_world w) depends on its orientation: the ledger rebases.
  const ElementEdit e = editElement(id, [&](uint32_t i) { s_.elements.a.q[i] = q; });
  s_.ledger.reference += e.energy;
  markPlacedEdit(id, e);
  s_.forcesReady = false;
}

template <int D>
void SimulationManager<D>::checkDofMask(unsigned mask) const {
  if ((mask & ~dof::all(D)) != 0) {
    throw Error("bad degrees of freedom \"" + dofNames(mask) + "\": a " + std::to_string(D) +
                    "D element has " + dofNames(dof::all(D)),
                {"VALUE", "DOF"});
  }
}

template <int D>
void SimulationManager<D>::setElementBlocked(ElementId id, unsigned mask) {
  // A distributed scene: its owner answers the lookup on every rank, and every rank keeps the
  // list alike (ownedBlockedOf finds the owner's part). Nothing moves: no search follows.
  requireElement(id);
  checkDofMask(mask);
  dropBlocked([&](ElementId g) { return g == id; });
  if (mask != 0) s_.blocked.push_back({id, static_cast<uint8_t>(mask)});
  touchConfig();
}

template <int D>
void SimulationManager<D>::scaleElementRadii(const std::vector<ElementId>& ids, double factor) {
  if (!(std::isfinite(factor) && factor > 0)) {
    throw Error("bad factor \"" + physics::formatReal(factor) + "\": must be a positive number",
                {"VALUE", "FACTOR"});
  }
  ElementArrays<D>& a = s_.elements.a;
  std::vector<uint32_t> slots;
  slots.reserve(ids.size());
  for (ElementId id : ids) {
    const uint32_t i = s_.elements.index(id);
    if (s_.geometries[a.geometry[i]]->shape != ShapeTable<D>::ball()) {
      throw Error("bad element " + std::to_string(id.scriptId()) +
                      ": only balls can be resized (a shape's size is in its parameters)",
                  {"VALUE", "SHAPE"});
    }
    const double r = a.r[i] * factor;
    checkRadiusRange(r);
    const auto inverses =
        inverseMassAndInertia(*s_.geometries[a.geometry[i]], s_.materials[a.material[i]].density, r);
    checkMassRange(inverses.first, r);
    slots.push_back(i);
  }
  const double before = ledgerSum();
  for (ElementId id : ids) markPlaced(id);
  for (uint32_t i : slots) {
    a.r[i] *= factor;
    std::tie(a.invMass[i], a.invInertia[i]) = inverseMassAndInertia(
        *s_.geometries[a.geometry[i]], s_.materials[a.material[i]].density, a.r[i]);
  }
  // An edit: the kinetic energy the masses changed and the elastic energy the overlaps changed
  // (rebased by the next force pass) are the user's, not the run's.
  s_.ledger.reference += ledgerSum() - before;
  s_.needRebuild = true;
  touchConfig();
}

template <int D>
template <class Pred>
void SimulationManager<D>::dropBlocked(Pred gone) {
  std::erase_if(s_.blocked, [&](const BlockedElement& b) { return gone(b.id); });
}

template <int D>
void SimulationManager<D>::forgetCandidates() {
  parkSprings(s_);
  s_.candidates.clear();
  s_.touchNowValid = s_.wallTouchNowValid = false;
  s_.contactGroups.clear();
  s_.wallCandidates.clear();
  s_.shapeCandidates.clear();
  s_.shapeWallCandidates.clear();
  s_.contacts.clear();
  s_.needRebuild = true;
}

// ---- tags ----------------------------------------------------------------------------------

template <int D>
NameLookup<ElementId>& SimulationManager<D>::elementNameTable() {
  return s_.dist ? s_.dist->names : s_.elements.names();
}

template <int D>
const NameLookup<ElementId>& SimulationManager<D>::elementNameTable() const {
  return s_.dist ? s_.dist->names : s_.elements.names();
}

template <int D>
TagTable<ElementKind>& SimulationManager<D>::elementTagTable() {
  return s_.dist ? s_.dist->tags : s_.elements.tags();
}

template <int D>
const TagTable<ElementKind>& SimulationManager<D>::elementTagTable() const {
  return s_.dist ? s_.dist->tags : s_.elements.tags();
}

template <int D>
void SimulationManager<D>::requireElement(ElementId id) const {
  if (!s_.dist) {
    s_.elements.index(id);
  } else if (s_.dist->comm->sum(ownedElement(id).isNull() ? 0.0 : 1.0) == 0) {
    throw Error("invalid element id \"" + toString(id) + "\": no such element",
                {"LOOKUP", "HANDLE"});
  }
}

template <int D>
void SimulationManager<D>::tagElement(ElementId id, const std::string& tag) {
  requireElement(id);
  elementTagTable().add(id, tag);
  if (s_.dist) ++s_.dist->tagEdits;
}

template <int D>
void SimulationManager<D>::untagElement(ElementId id, const std::string& tag) {
  requireElement(id);
  elementTagTable().remove(id, tag);
  if (s_.dist) ++s_.dist->tagEdits;
}

template <int D>
std::vector<ElementId> SimulationManager<D>::elementsTagged(const std::string& tag) const {
  return elementTagTable().objects(tag);
}

template <int D>
std::vector<uint32_t> SimulationManager<D>::taggedIndices(const std::string& tag) const {
  if (s_.ownedTagged != nullptr) return s_.ownedTagged(s_, tag);
  std::vector<uint32_t> out;
  s_.elements.tags().forEach(
      tag, [&](ElementId id) { out.push_back(s_.elements.pool().denseIndex(id)); });
  return out;
}

template <int D>
std::vector<std::string> SimulationManager<D>::elementNames() const {
  const auto names = elementNameTable().names();
  return {names.begin(), names.end()};
}

template <int D>
std::vector<std::string> SimulationManager<D>::wallNames() const {
  const auto names = s_.walls.names().names();
  return {names.begin(), names.end()};
}

template <int D>
std::vector<std::string> SimulationManager<D>::tagNames() const {
  std::vector<std::string> out;
  for (auto t : elementTagTable().tags()) out.emplace_back(t);
  for (auto t : s_.walls.tags().tags()) out.emplace_back(t);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

template <int D>
void SimulationManager<D>::tagWall(WallId id, const std::string& tag) {
  s_.walls.pool().denseIndex(id);
  s_.walls.tags().add(id, tag);
}

template <int D>
void SimulationManager<D>::untagWall(WallId id, const std::string& tag) {
  s_.walls.pool().denseIndex(id);
  s_.walls.tags().remove(id, tag);
}

template <int D>
std::vector<WallId> SimulationManager<D>::wallsTagged(const std::string& tag) const {
  return s_.walls.tags().objects(tag);
}

// ---- behaviors -----------------------------------------------------------------------------

template <int D>
BehaviorId SimulationManager<D>::addGravity(const Vec3d& g) {
  const VecD<D> gv = toVec<D>(g, "gravity");
  if (!(gv.norm() <= validity::kMaxAcceleration)) {
    throwBad("gravity", formatVec(g, D), "must be at most 1e9 m/s^2 in magnitude");
  }
  auto b = std::make_unique<GravityBehavior<D>>(gv);
  const double before = ledgerSum();
  const BehaviorId id = s_.behaviors.add(std::move(b));
  s_.ledger.reference += ledgerSum() - before;
  touchConfig();
  return id;
}

template <int D>
BehaviorId SimulationManager<D>::addLoad(const LoadDef& def) {
  if (def.grain.isNull() == def.tag.empty()) {
    throw Error("bad target: give exactly one of a grain or a tag", {"VALUE", "TARGET"});
  }
  if (!def.grain.isNull()) requireElement(def.grain);
  if (!def.tag.empty()) checkTagName(def.tag);
  toVec<D>(def.force, "force");
  toAngular<D>(def.torque, "torque");
  checkLoadRange(def.force, "force", D, false);
  checkLoadRange(def.torque, "torque", D, true);
  if (D == 2) {
    if (def.forceFn[2]) throwBad("force", "z", "must have z = 0 in 2D");
    if (def.torqueFn[0] || def.torqueFn[1]) throwBad("torque", "x y", "must be about z only in 2D");
  }
  auto b = std::make_unique<LoadBehavior<D>>();
  b->grain = def.grain;
  b->tag = def.tag;
  b->force = def.force;
  b->torque = def.torque;
  b->forceFn = def.forceFn;
  b->torqueFn = def.torqueFn;
  const BehaviorId id = s_.behaviors.add(std::move(b));
  touchConfig();
  return id;
}

template <int D>
BehaviorId SimulationManager<D>::addBehavior(const std::string& type,
                                             const std::vector<BehaviorParam>& params) {
  // (The types a distributed step applies: each rank acts on the elements it owns.)
  if (s_.dist && type != "gravity" && type != "load" && type != "torque-ramp") {
    throw Error("can't add a " + type + " behavior to a distributed scene: distributed runs do "
                "not support it yet",
                {"MPI", "UNSUPPORTED"});
  }
  std::unique_ptr<Behavior<D>> b = makeBehavior<D>(type, params);
  for (const BehaviorParam& p : params) {
    if (!p.grain.isNull()) requireElement(p.grain);
    if (!p.text.empty()) checkTagName(p.text);
  }
  // A uniform field changes the potential: the ledger is rebased as for any edit.
  const double before = ledgerSum();
  const BehaviorId id = s_.behaviors.add(std::move(b));
  s_.ledger.reference += ledgerSum() - before;
  touchConfig();
  return id;
}

template <int D>
void SimulationManager<D>::removeBehavior(BehaviorId id) {
  s_.behaviors.pool().denseIndex(id);
  const double before = ledgerSum();
  s_.behaviors.remove(id);
  s_.ledger.reference += ledgerSum() - before;
  touchConfig();
}

template <int D>
std::vector<BehaviorInfo> SimulationManager<D>::behaviors() const {
  std::vector<BehaviorInfo> out;
  const auto& items = s_.behaviors.items();
  for (size_t k = 0; k < items.size(); ++k) {
    const Behavior<D>& b = *items[k];
    out.push_back({s_.behaviors.pool().handleAt(static_cast<uint32_t>(k)), std::string(b.type()),
                   b.describe(), !b.hasCallbacks(), b.params()});
  }
  return out;
}

// ---- options -------------------------------------------------------------------------------

template <int D>
void SimulationManager<D>::setOptions(const std::vector<OptionSetting>& settings) {
  // All checked before any is stored, so a bad one changes nothing.
  std::vector<std::pair<size_t, double>> raw;
  for (const OptionSetting& st : settings) {
    const auto [o, k] = findOption(st.group, st.name);
    raw.emplace_back(k, optionRaw(*o, st.value));
  }
  if (raw.empty()) return;
  OptionEffect effect = OptionEffect::Loop;
  for (const auto& [k, x] : raw) {
    const OptionRow<D>& row = optionTable<D>()[k];
    row.set(s_, x);
    effect = std::max(effect, row.spec.effect);
  }
  if (effect == OptionEffect::Search) s_.needRebuild = true;
  if (effect == OptionEffect::Loop) {
    // Only the loop is rebuilt (a module comes or goes): the forces of the last step stay, so
    // such an option (the watchdog's) never changes the trajectory.
    configDirty_ = true;
  } else {
    touchConfig();
  }
}

template <int D>
OptionValue SimulationManager<D>::option(std::string_view group, std::string_view name) const {
  const auto [o, k] = findOption(group, name);
  return optionFromRaw(*o, optionTable<D>()[k].get(s_));
}

template class SimulationManager<2>;
template class SimulationManager<3>;

}  // namespace demlab::sim
