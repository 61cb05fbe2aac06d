// The geometry of one contact record (Scene::contacts) recomputed from the positions, for the
// modules that act on the contacts the force passes found (rolling resistance, cohesion): the
// records keep only the pair and the force, which is what queries and checkpoints need.
#pragma once

#include <optional>
#include <variant>

#include "sim/contacts.hpp"
#include "sim/scene.hpp"
#include "sim/shape_contacts.hpp"

namespace demlab::sim {

template <int D>
struct RecordGeometry {
  physics::ContactGeometry<D> g;  // normal from the grain a towards b (or the wall)
  Real radiusA = 0;               // a's radius
  Real radiusB = 0;               // b's radius; 0 for a wall (flat: infinite radius)
  uint32_t materialB = 0;         // b's material, or the wall's
};

// Numbers the records of a step's list in order: a pair of shapes touching at several points
// has one record per point, consecutive and in its row's order (sim/shape_contacts.hpp), so
// the k-th record of a run of the same pair is its row's point k.
template <int D>
class RecordPointCounter {
 public:
  // Returns the point index of c, the record following the previous call's.
  int next(const ContactRecord<D>& c) {
    const bool same = c.a == a_ && c.b == b_ && c.wall == wall_;
    a_ = c.a, b_ = c.b, wall_ = c.wall;
    k_ = same ? k_ + 1 : 0;
    return k_;
  }

 private:
  uint32_t a_ = ~0u, b_ = ~0u, wall_ = 0;
  int k_ = 0;
};

// Returns the geometry of record c of scene s, or nothing when the pair no longer overlaps
// (it always does within the step that recorded it). A record of a shape (an element not a
// ball) is served when point, its index from a RecordPointCounter, is given (its radii are
// then those that give the row's effective radius), and skipped otherwise: cohesion is a
// ball model. Changes nothing.
template <int D>
std::optional<RecordGeometry<D>> recordGeometry(const Scene<D>& s, const ContactRecord<D>& c,
                                                int point = -1) {
  const ElementArrays<D>& a = s.elements.a;
  if (s.anyShapes && (a.geometry[c.a] != 0 || (!c.wall && a.geometry[c.b] != 0) ||
                      (c.wall && s.walls.items[c.b].kind == WallShape::Mesh))) {
    if (point < 0) return std::nullopt;
    ContactPoint<D> pts[kMaxContactPoints];
    const int n = c.wall ? elementWallPoints(s, c.a, s.walls.items[c.b], pts)
                         : elementPairPoints(s, c.a, c.b, pts);
    if (point >= n) return std::nullopt;
    RecordGeometry<D> out;
    out.g = pts[point].g;
    out.radiusA = c.wall ? pts[point].effRadius : 2 * pts[point].effRadius;
    out.radiusB = c.wall ? 0 : 2 * pts[point].effRadius;
    out.materialB = c.wall ? s.walls.items[c.b].material : a.material[c.b];
    return out;
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
