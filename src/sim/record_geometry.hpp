// The geometry of one contact record (Scene::contacts) recomputed from the positions, for the
// modules that act on the contacts the force passes found (rolling resistance, cohesion): the
// records keep only the pair and the force, which is what queries and checkpoints need.
#pragma once

#include <optional>
#include <variant>

#include "sim/contacts.hpp"
#include "sim/scene.hpp"

namespace demlab::sim {

template <int D>
struct RecordGeometry {
  physics::ContactGeometry<D> g;  // normal from the grain a towards b (or the wall)
  Real radiusA = 0;               // a's radius
  Real radiusB = 0;               // b's radius; 0 for a wall (flat: infinite radius)
  uint32_t materialB = 0;         // b's material, or the wall's
};

// Returns the geometry of record c of scene s, or nothing when the pair no longer overlaps
// (it always does within the step that recorded it) or when an element is not a ball. Changes
// nothing.
template <int D>
std::optional<RecordGeometry<D>> recordGeometry(const Scene<D>& s, const ContactRecord<D>& c) {
  const ElementArrays<D>& a = s.elements.a;
  // The modules that read records (rolling resistance, cohesion) are ball models.
  if (s.anyShapes && (a.geometry[c.a] != 0 || (!c.wall && a.geometry[c.b] != 0))) {
    return std::nullopt;
  }
  const physics::SphereShape<D> sa{a.x[c.a], a.r[c.a]};
  RecordGeometry<D> out;
  out.radiusA = a.r[c.a];
  std::optional<physics::ContactGeometry<D>> g;
  if (c.wall) {
    const WallNarrowPhase<D>& np = WallNarrowPhase<D>::get();
    const Wall<D>& w = s.walls.items[c.b];
    const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, w.shape);
    g = np.table.get(np.sphere, np.byShape[static_cast<int>(w.kind)]).fn.one(&sa, shape);
    out.materialB = w.material;
  } else {
    g = physics::intersect<D>(sa, physics::SphereShape<D>{partnerPosition(s, c.a, c.b), a.r[c.b]});
    out.radiusB = a.r[c.b];
    out.materialB = a.material[c.b];
  }
  if (!g) return std::nullopt;
  out.g = *g;
  return out;
}

}  // namespace demlab::sim
