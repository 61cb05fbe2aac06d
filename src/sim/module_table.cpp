// The rows of the module table (sim/module_table.hpp) and what a scene uses.
#include "sim/module_table.hpp"

#include <algorithm>

#include "sim/behavior_modules.hpp"
#include "sim/bond_module.hpp"
#include "sim/cohesion.hpp"
#include "sim/constraints.hpp"
#include "sim/contacts.hpp"
#include "sim/detection.hpp"
#include "sim/distribution.hpp"
#include "sim/integrator.hpp"
#include "sim/law_models.hpp"
#include "sim/rigid_body.hpp"
#include "sim/rolling_resistance.hpp"
#include "sim/shape_contacts.hpp"
#include "sim/sink.hpp"
#include "sim/source.hpp"
#include "sim/touch.hpp"
#include "sim/watchdog.hpp"

namespace demlab::sim {

template <int D>
ElementUse elementUse(const Scene<D>& s) {
  ElementUse e;
  e.grainMaterials.assign(s.nMat(), false);
  const ElementArrays<D>& a = s.elements.a;
  for (size_t i = 0; i < s.ownedCount(); ++i) {
    e.grainMaterials[a.material[i]] = true;
    if (squaredNorm(a.w[i]) != 0) e.spinning = true;
  }
  for (size_t i = 0; i < a.size() && s.geometries.size() > 1; ++i) {
    if (a.geometry[i] == 0) continue;
    e.shapes = true;
    if (a.invInertia[i] == 0) e.rigid = true;
  }
  return e;
}

template <int D>
SceneUse sceneUse(const Scene<D>& s) {
  // A distributed run's ranks hold parts of the scene: what the whole uses was decided from
  // every part (SimulationManager::prepare), but for the walls, which every rank holds alike
  // (a wall set in motion).
  if (s.dist) {
    SceneUse u = s.dist->use;
    u.walls = s.walls.size() > 0;
    u.movingWalls = s.walls.anyMoving();
    return u;
  }
  return sceneUseWith(s, elementUse(s));
}

template <int D>
SceneUse sceneUseWith(const Scene<D>& s, const ElementUse& e) {
  SceneUse f;
  f.shapes = e.shapes;
  f.rigid = e.rigid;
  const size_t nm = s.nMat();
  const std::vector<bool>& grainMat = e.grainMaterials;
  std::vector<bool> anyMat = grainMat;
  for (const Wall<D>& w : s.walls.items) {
    anyMat[w.material] = true;
    if (w.kind == WallShape::Mesh) f.shapes = true;  // every element meets it in the shape pass
  }
  int law = -2;
  for (size_t m = 0; m < nm; ++m) {
    if (!grainMat[m]) continue;
    for (size_t k = 0; k < nm; ++k) {
      if (!anyMat[k]) continue;
      const auto [ma, mk] = modelMaterials(s, m, k);
      if (ma.friction > 0 && mk.friction > 0) f.anyFriction = true;
      const int8_t o = s.pairLawOverride[m * nm + k];
      const int l = o < 0 ? static_cast<int>(s.defaultLaw) : o;
      law = law == -2 ? l : (law == l ? law : -1);
    }
  }
  f.law = law == -2 ? static_cast<int>(s.defaultLaw) : law;
  if (std::count(grainMat.begin(), grainMat.end(), true) == 1) {
    const auto m =
        static_cast<long>(std::find(grainMat.begin(), grainMat.end(), true) - grainMat.begin());
    f.grainPair = m * static_cast<long>(nm) + m;
  }
  // A shape's normal forces act off its centre: it turns with or without friction; so do
  // bonded elements (a bond's shear force and moment).
  f.rotating = s.rotationEnabled && (f.anyFriction || s.behaviors.hasTorqueLoads() || e.spinning ||
                                     f.shapes || s.bonds.intact() > 0);
  f.walls = s.walls.size() > 0;
  f.movingWalls = s.walls.anyMoving();
  return f;
}

namespace {

template <int D>
bool always(const Scene<D>&, const SceneUse&) {
  return true;
}

// make for a module built without arguments.
template <int D, template <int> class M>
void plain(const Scene<D>&, const SceneUse&, ModuleList<D>& out) {
  out.push_back(std::make_unique<M<D>>());
}

template <int D>
struct Rows {
  static constexpr ModuleRow<D> rows[] = {
      {"integrate", always<D>, plain<D, PredictModule>},
      {"rotation", [](const Scene<D>&, const SceneUse& u) { return u.rotating; },
       [](const Scene<D>&, const SceneUse& u, ModuleList<D>& out) {
         out.push_back(std::make_unique<PredictRotationModule<D>>(u.rigid));
       }},
      {"rigid-rotation", [](const Scene<D>&, const SceneUse& u) { return u.rotating && u.rigid; },
       plain<D, PredictRigidRotationModule>},
      {"walls", [](const Scene<D>&, const SceneUse& u) { return u.movingWalls; },
       plain<D, WallMotionModule>},
      // A distributed run: the owned elements' states to the ranks holding their ghosts.
      {"ghosts", [](const Scene<D>& s, const SceneUse&) { return s.dist != nullptr; },
       plain<D, GhostModule>},
      {"detection", always<D>,
       [](const Scene<D>& s, const SceneUse&, ModuleList<D>& out) {
         out.push_back(std::make_unique<DetectionModule<D>>(s.cellFactor));
       }},
      {"contacts", always<D>,
       [](const Scene<D>&, const SceneUse& u, ModuleList<D>& out) {
         for (auto& c :
              makeContactModules<D>(u.law, u.anyFriction, u.rotating, u.walls, u.grainPair)) {
           out.push_back(std::move(c));
         }
       }},
      {"shape-contacts", [](const Scene<D>&, const SceneUse& u) { return u.shapes; },
       plain<D, ShapeContactModule>},
      {"rolling",
       [](const Scene<D>& s, const SceneUse& u) {
         return u.rotating && subModelRuns(s.rollingModel, anyRollingFriction(s));
       },
       [](const Scene<D>& s, const SceneUse&, ModuleList<D>& out) {
         out.push_back(std::make_unique<RollingResistanceModule<D>>(s));
       }},
      {"cohesion",
       [](const Scene<D>& s, const SceneUse&) {
         return subModelRuns(s.cohesionModel, anyCohesion(s));
       },
       [](const Scene<D>& s, const SceneUse&, ModuleList<D>& out) {
         out.push_back(std::make_unique<CohesionModule<D>>(s));
       }},
      {"bonds", [](const Scene<D>& s, const SceneUse&) { return s.bonds.intact() > 0; },
       plain<D, BondModule>},
      // Gravity, then one module per behavior type present (sim/behavior_registry.hpp).
      {"behaviors", [](const Scene<D>& s, const SceneUse&) { return s.behaviors.size() > 0; },
       [](const Scene<D>& s, const SceneUse&, ModuleList<D>& out) {
         appendBehaviorModules(s, out);
       }},
      // Last of the force stages but the constraints: it reads the velocities the forces and
      // loads were computed with.
      {"touch", [](const Scene<D>& s, const SceneUse&) { return s.touchCorrection; },
       plain<D, TouchModule>},
      // A distributed run: the ghosts' forces of the pairs above back to their owners.
      // (Its "ghost-forces-out" is moved back by buildModules: placeGhostForceSend.)
      {"ghost-forces", [](const Scene<D>& s, const SceneUse&) { return s.dist != nullptr; },
       [](const Scene<D>&, const SceneUse&, ModuleList<D>& out) {
         out.push_back(std::make_unique<GhostForceSendModule<D>>(SimLevel::Behaviors));
         out.push_back(std::make_unique<GhostForceModule<D>>());
       }},
      // After every force: it cancels what acts along a blocked degree of freedom.
      {"constraints", [](const Scene<D>& s, const SceneUse&) { return !s.blocked.empty(); },
       plain<D, ConstraintModule>},
      {"rigid-correct", [](const Scene<D>&, const SceneUse& u) { return u.rotating && u.rigid; },
       plain<D, CorrectRigidRotationModule>},
      {"integrate-correct", always<D>, plain<D, CorrectModule>},
      // Removals, then insertions, asked for at the end of the step (Scene::deferred).
      {"sinks", [](const Scene<D>& s, const SceneUse&) { return !s.sinks.empty(); },
       plain<D, SinkModule>},
      {"sources", [](const Scene<D>& s, const SceneUse&) { return !s.sources.empty(); },
       plain<D, SourceModule>},
      {"watchdog", [](const Scene<D>& s, const SceneUse&) { return s.watchdog.enabled; },
       [](const Scene<D>& s, const SceneUse&, ModuleList<D>& out) {
         out.push_back(std::make_unique<WatchdogModule<D>>(watchdogStepLimit(s)));
       }},
  };
};

}  // namespace

template <int D>
std::span<const ModuleRow<D>> moduleTable() {
  return Rows<D>::rows;
}

namespace {

template <int D>
std::vector<ModuleRow<D>>& addedRows() {
  static std::vector<ModuleRow<D>> rows;
  return rows;
}

}  // namespace

template <int D>
void addModuleRow(const ModuleRow<D>& row) {
  addedRows<D>().push_back(row);
}

template <int D>
ModuleList<D> buildModules(const Scene<D>& s, const SceneUse& u) {
  ModuleList<D> out;
  for (const ModuleRow<D>& row : moduleTable<D>()) {
    if (row.wanted(s, u)) row.make(s, u, out);
  }
  for (const ModuleRow<D>& row : addedRows<D>()) {
    if (row.wanted(s, u)) row.make(s, u, out);
  }
  if (s.dist) {
    std::stable_sort(out.begin(), out.end(),
                     [](const auto& a, const auto& b) { return a->level() < b->level(); });
    placeGhostForceSend(out);
  }
  return out;
}

template SceneUse sceneUse<2>(const Scene<2>&);
template SceneUse sceneUse<3>(const Scene<3>&);
template ElementUse elementUse<2>(const Scene<2>&);
template ElementUse elementUse<3>(const Scene<3>&);
template SceneUse sceneUseWith<2>(const Scene<2>&, const ElementUse&);
template SceneUse sceneUseWith<3>(const Scene<3>&, const ElementUse&);
template std::span<const ModuleRow<2>> moduleTable<2>();
template std::span<const ModuleRow<3>> moduleTable<3>();
template void addModuleRow<2>(const ModuleRow<2>&);
template void addModuleRow<3>(const ModuleRow<3>&);
template ModuleList<2> buildModules<2>(const Scene<2>&, const SceneUse&);
template ModuleList<3> buildModules<3>(const Scene<3>&, const SceneUse&);

}  // namespace demlab::sim
