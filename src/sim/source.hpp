// Sources (SourceDef, sim/boundaries.hpp): the "sources" module inserts elements at the end of
// each step, through the scene's deferred changes, so nothing is created while a pass holds a
// dense index. A source owes rate x (time since it started) of mass (or elements); it places
// elements while it owes more than it gave, so what it inserted trails what it owes by less
// than one element. Each element's radius is drawn once and kept until it is placed (a radius
// that found no room this step is tried again at the next), so the inserted sizes follow the
// distribution whatever the crowding; its position is drawn uniformly in the region and kept
// only if it overlaps no element and no wall by more than the tolerance.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

#include "sim/contacts.hpp"
#include "sim/scene.hpp"
#include "sim/shape.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Sebastiano Vigna's SplitMix64 over a state kept in the scene: one word to checkpoint.
struct SplitMix64 {
  using result_type = uint64_t;
  uint64_t& state;
  static constexpr uint64_t min() { return 0; }
  static constexpr uint64_t max() { return ~uint64_t(0); }
  // Returns the next 64 random bits. Changes state.
  uint64_t operator()() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Returns a uniform number in [0, 1). Changes state.
  double unit() { return double((*this)() >> 11) * 0x1.0p-53; }
};

// Returns true once the source has given all it must (its target count or mass).
inline bool sourceDone(const SourceState& src) {
  const SourceDef& d = src.def;
  return (d.targetCount > 0 && src.count >= d.targetCount) ||
         (d.targetMass > 0 && src.mass >= d.targetMass);
}

// Returns true if the source owes an element at time t (it has given less than it owes).
inline bool sourceOwes(const SourceState& src, double t) {
  if (sourceDone(src)) return false;
  const double elapsed = t - src.start;
  if (src.def.massRate > 0) return src.mass < src.def.massRate * elapsed;
  return static_cast<double>(src.count) < std::floor(src.def.countRate * elapsed);
}

// The balls near a source's region, for the overlap test of its placements: the elements
// present and those placed earlier in the step.
template <int D>
struct NearBalls {
  std::vector<VecD<D>> x;
  std::vector<Real> r;
};

// Returns true if a ball of radius r at p overlaps none of near's balls and no wall of s by more
// than tol x the smaller radius. Changes nothing.
template <int D>
bool placeFree(const Scene<D>& s, const NearBalls<D>& near, const VecD<D>& p, Real r, Real tol) {
  for (size_t k = 0; k < near.x.size(); ++k) {
    const Real reach = r + near.r[k] - tol * std::min(r, near.r[k]);
    if ((p - near.x[k]).squaredNorm() < reach * reach) return false;
  }
  const WallNarrowPhase<D>& np = WallNarrowPhase<D>::get();
  const physics::SphereShape<D> ball{p, r};
  for (const Wall<D>& w : s.walls.items) {
    const void* shape = std::visit([](const auto& sh) -> const void* { return &sh; }, w.shape);
    const auto g =
        np.table.get(np.sphere, np.byShape[static_cast<int>(w.kind)]).fn.one(&ball, shape);
    if (g && g->overlap > tol * r) return false;
  }
  return true;
}

// Appends to s.deferred.create the elements source src owes at the scene's time, as many as
// find room in src.def.tries attempts each. Changes src (counts, mass, generator, pending
// radius) and s.deferred.
template <int D>
void runSource(Scene<D>& s, SourceState& src) {
  if (!sourceOwes(src, s.time)) return;
  const SourceDef& d = src.def;
  SplitMix64 rng{src.rng};
  Vec3d lo3, hi3;
  d.region.bounds(D, lo3, hi3);
  const Real rMax = d.size.maxRadius();
  // The elements that can touch a ball placed in the region's box.
  NearBalls<D> near;
  const ElementArrays<D>& a = s.elements.a;
  Real rAll = 0;
  for (Real r : a.r) rAll = std::max(rAll, r);
  for (size_t i = 0; i < a.size(); ++i) {
    bool in = true;
    for (int k = 0; k < D && in; ++k) {
      in = a.x[i][k] >= lo3[k] - rMax - rAll && a.x[i][k] <= hi3[k] + rMax + rAll;
    }
    if (!in) continue;
    near.x.push_back(a.x[i]);
    near.r.push_back(a.r[i]);
  }
  const double density = s.materials[src.material].density;
  // A shape other than the ball: its reference Geometry, scaled for each element (made at the
  // first element this call places, not on the steps that place none).
  std::optional<Geometry<D>> shape;
  while (sourceOwes(src, s.time)) {
    if (src.pendingRadius == 0) src.pendingRadius = d.size.draw(rng);
    const Real r = src.pendingRadius;
    bool placed = false;
    VecD<D> p;
    for (uint32_t t = 0; t < d.tries && !placed; ++t) {
      Vec3d q{0, 0, 0};
      for (int k = 0; k < D; ++k) q[k] = lo3[k] + r + (hi3[k] - lo3[k] - 2 * r) * rng.unit();
      if (!d.region.holds(q, r, D)) continue;
      for (int k = 0; k < D; ++k) p[k] = q[k];
      placed = placeFree(s, near, p, r, d.tolerance);
    }
    if (!placed) return;  // the region is full for now: the debt carries to the next step
    ElementDef e;
    for (int k = 0; k < D; ++k) {
      e.position[k] = p[k];
      e.velocity[k] = d.velocity[k] + d.jitter * (2 * rng.unit() - 1);
    }
    if (d.randomOrientation) e.orientation = randomOrientation<D>(rng);
    Real mass = ballMass<D>(density, r);
    if (!d.shape.empty()) {
      if (!shape) shape = ShapeTable<D>::get().makeGeometry(d.shape, d.shapeParams);
      const Real f = r / shape->boundRadius;
      e.shape = d.shape;
      e.shapeParams = *ShapeTable<D>::get().type(shape->shape).scaled(d.shapeParams, f);
      mass = density * shape->volume * (D == 3 ? f * f * f : f * f);
    } else {
      e.radius = r;
    }
    e.material = s.materialNames[src.material];
    e.tags = d.tags;
    s.deferred.create.push_back(std::move(e));
    near.x.push_back(p);
    near.r.push_back(r);
    src.count += 1;
    src.mass += mass;
    src.pendingRadius = 0;
  }
}

// Returns an orientation uniform over the rotations, as ElementDef::orientation: 3D the unit
// quaternion {w x y z} of Shoemake's method (three uniform draws), 2D {angle} uniform in
// [-pi, pi). Changes rng.
template <int D>
std::vector<double> randomOrientation(SplitMix64& rng) {
  const double twoPi = 2 * std::numbers::pi;
  if constexpr (D == 2) {
    return {twoPi * rng.unit() - std::numbers::pi};
  } else {
    const double u1 = rng.unit(), u2 = rng.unit(), u3 = rng.unit();
    const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
    return {b * std::cos(twoPi * u3), a * std::sin(twoPi * u2), a * std::cos(twoPi * u2),
            b * std::sin(twoPi * u3)};
  }
}

template <int D>
class SourceModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "sources"; }
  SimLevel level() const override { return SimLevel::Cleanup; }
  void run(Scene<D>& s) override {
    for (SourceState& src : s.sources) {
      if (boundaryActs(src.def.every, s.steps)) runSource(s, src);
    }
  }
};

}  // namespace demlab::sim
