// The module table (LAMMPS's style table, thesis chapter 9's SimModules): one row per module
// kind, in loop order within each level. A row says when a scene wants the module and makes
// it; buildModules() is the whole loop builder, so adding a module is one class and one row
// (module_table.cpp), with no edit to the manager. A scene runs only the rows it wants
// (`module list`): one without friction runs no history code, one without walls no wall code.
#pragma once

#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// What a scene uses, read from it once when its loop is built: the rows' wants read these
// (and the scene's options) rather than scanning the scene each.
struct SceneUse {
  bool anyFriction = false, rotating = false, walls = false, movingWalls = false;
  // Some element is not a ball; some element's inertia is not isotropic (sim/rigid_body.hpp).
  bool shapes = false, rigid = false;
  int law = 0;  // the one law of every pair in use, or -1 when they differ
  // The material pair (index into Scene::pairParams) of every grain-grain contact when all
  // grains have one material, else -1.
  long grainPair = -1;
};

// Returns what the scene s uses. Changes nothing.
template <int D>
SceneUse sceneUse(const Scene<D>& s);

// What the elements bring to SceneUse: the materials they take (by index), whether one spins,
// is not a ball, has no rotational inertia. A distributed run takes each rank's and ORs them
// (SimulationManager::prepare), so that the whole scene's choice follows from them.
struct ElementUse {
  std::vector<bool> grainMaterials;
  bool spinning = false, shapes = false, rigid = false;
};
// Returns what s's own elements bring (a distributed part's: its owned elements). Changes
// nothing.
template <int D>
ElementUse elementUse(const Scene<D>& s);
// Returns what the scene s uses with elements that bring e. Changes nothing.
template <int D>
SceneUse sceneUseWith(const Scene<D>& s, const ElementUse& e);

template <int D>
using ModuleList = std::vector<std::unique_ptr<SimModule<D>>>;

template <int D>
struct ModuleRow {
  // The row's name as `module list` shows it (a row may make several modules, as the contact
  // row makes the grain and wall passes of the scene's law).
  std::string_view name;
  // Returns true if scene s (using u) runs this row's modules.
  bool (*wanted)(const Scene<D>& s, const SceneUse& u);
  // Appends this row's modules for scene s to out.
  void (*make)(const Scene<D>& s, const SceneUse& u, ModuleList<D>& out);
};

// Returns the built-in rows, in loop order. Changes nothing.
template <int D>
std::span<const ModuleRow<D>> moduleTable();

// Adds a row after the built-in ones (and those added before), for modules that live outside
// src/sim (a plug-in, a test's own module): every loop built afterwards asks it, in every scene.
// Not thread-safe; call before building scenes. Changes the process's table.
template <int D>
void addModuleRow(const ModuleRow<D>& row);

// Returns the modules of every row that s wants, in table order (built-in, then added) (the loop
// then sorts them by level, keeping this order within a level). Changes nothing.
template <int D>
ModuleList<D> buildModules(const Scene<D>& s, const SceneUse& u);

}  // namespace demlab::sim
