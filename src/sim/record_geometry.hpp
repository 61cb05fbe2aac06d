// The geometry of one contact record (Scene::contacts) recomputed from the positions, for the
// modules that act on the contacts the force passes found (rolling resistance, cohesion): the
// records keep only the pair and the force, which is what queries and checkpoints need.
#pragma once

#include <array>
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

// Returns true if record c of scene s is a shape's (an element not a ball, or a mesh wall):
// its geometry is then one of its pair's points (sim/shape_contacts.hpp).
template <int D>
bool isShapeRecord(const Scene<D>& s, const ContactRecord<D>& c) {
  const ElementArrays<D>& a = s.elements.a;
  return s.anyShapes && (a.geometry[c.a] != 0 || (!c.wall && a.geometry[c.b] != 0) ||
                         (c.wall && s.walls.items[c.b].kind == WallShape::Mesh));
}

// Returns the geometry of record c of scene s, a ball's (against a ball or a wall), or nothing
// when the pair no longer overlaps (it always does within the step that recorded it) or c is a
// shape's (cohesion is a ball model; RecordGeometryReader serves shapes). Changes nothing.
template <int D>
std::optional<RecordGeometry<D>> recordGeometry(const Scene<D>& s, const ContactRecord<D>& c) {
  if (isShapeRecord(s, c)) return std::nullopt;
  const ElementArrays<D>& a = s.elements.a;
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

// Serves the geometry of a step's records read in list order, shapes' too. A pair of shapes
// touching at several points has one record per point, consecutive and in its row's order
// (sim/shape_contacts.hpp), so the k-th record of a run of the same pair is its row's point k;
// the row is computed once per run (recomputing it per record made the rolling resistance of
// a shape on a mesh cost several times its contact pass).
template <int D>
class RecordGeometryReader {
 public:
  // Returns the geometry of record c of s, the record following the previous call's, or
  // nothing when its pair no longer overlaps there. Changes only the reader.
  std::optional<RecordGeometry<D>> next(const Scene<D>& s, const ContactRecord<D>& c) {
    const bool same = c.a == a_ && c.b == b_ && c.wall == wall_;
    a_ = c.a, b_ = c.b, wall_ = c.wall;
    k_ = same ? k_ + 1 : 0;
    if (!same) points_ = -1;
    if (!isShapeRecord(s, c)) return recordGeometry(s, c);
    if (points_ < 0) {
      points_ = c.wall ? elementWallPoints(s, c.a, s.walls.items[c.b], pts_.data())
                       : elementPairPoints(s, c.a, c.b, pts_.data());
    }
    if (k_ >= points_) return std::nullopt;
    const ContactPoint<D>& p = pts_[k_];
    RecordGeometry<D> out;
    out.g = p.g;
    out.radiusA = c.wall ? p.effRadius : 2 * p.effRadius;
    out.radiusB = c.wall ? 0 : 2 * p.effRadius;
    out.materialB = c.wall ? s.walls.items[c.b].material : s.elements.a.material[c.b];
    return out;
  }

 private:
  uint32_t a_ = ~0u, b_ = ~0u;
  bool wall_ = false;
  int k_ = 0;
  int points_ = -1;  // the current run's row, computed at its first shape record
  std::array<ContactPoint<D>, kMaxContactPoints> pts_;
};

}  // namespace demlab::sim
