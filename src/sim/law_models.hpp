// The contact law's sub-model choices (`law model`, in the spirit of LAMMPS's `pair granular`):
// the tangential model (history spring with Coulomb's limit, or none) and whether rolling
// resistance and cohesion run (on, off, or auto: when a coefficient is non-zero, the behaviour
// before the choice existed). The normal law and its damping are the scene's law and Hertz
// damping (Scene::defaultLaw, Scene::hertzDamping).
//
// A choice acts where the pairs' coefficients are read: a sub-model switched off sees a zero
// coefficient (modelMaterials), so the loop builder leaves its module out and the mixers give
// nothing to it, with no test in any contact kernel.
#pragma once

#include <cstdint>
#include <utility>

#include "sim/scene.hpp"

namespace demlab::sim {

// The values of Scene::tangentialModel (indices into the option's choices, option_table.cpp).
namespace tangential {
inline constexpr uint8_t kHistory = 0, kNone = 1;
}
// The values of Scene::rollingModel and Scene::cohesionModel.
namespace submodel {
inline constexpr uint8_t kOn = 0, kOff = 1, kAuto = 2;
}

// Returns materials m and k of s as the pair's contact sees them: Scene::pairMaterials (the
// pair's own coefficients put in both) with the friction zero when the tangential model is
// none, the rolling friction zero when rolling is off, the cohesion zero when it is off.
// Changes nothing.
template <int D>
std::pair<physics::MaterialDef, physics::MaterialDef> modelMaterials(const Scene<D>& s, size_t m,
                                                                     size_t k) {
  auto out = s.pairMaterials(m, k);
  for (physics::MaterialDef* d : {&out.first, &out.second}) {
    if (s.tangentialModel == tangential::kNone) d->friction = 0;
    if (s.rollingModel == submodel::kOff) d->rollingFriction = 0;
    if (s.cohesionModel == submodel::kOff) d->cohesion = 0;
  }
  return out;
}

// Returns true if a sub-model whose choice is model runs: on always, off never, auto when some
// pair has a coefficient for it (present).
inline bool subModelRuns(uint8_t model, bool present) {
  return model == submodel::kOn || (model == submodel::kAuto && present);
}

}  // namespace demlab::sim
