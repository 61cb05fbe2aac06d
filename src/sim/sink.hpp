// Sinks (SinkDef, sim/boundaries.hpp): the "sinks" module asks, at the end of each step (of
// every `every`-th step), for the removal of every element whose centre is in the sink's region (or outside it) or beyond its
// plane, through the scene's deferred changes; the manager removes them after the step and the
// ledger is rebased for the energy they take away (sim/simulation_run.cpp, applyDeferred). The
// elements are visited in dense order and the sinks in creation order; an element two sinks
// would take is counted by the first only, so the counters add up to the elements removed.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Returns true if sink k takes an element with its centre at x. Changes nothing.
template <int D>
bool sinkTakes(const SinkDef& k, const VecD<D>& x) {
  Vec3d p{0, 0, 0};
  for (int c = 0; c < D; ++c) p[c] = x[c];
  if (k.kind == SinkDef::Plane) {
    double side = 0;
    for (int c = 0; c < D; ++c) side += (p[c] - k.point[c]) * k.normal[c];
    return side < 0;
  }
  // A centre is in the region when a ball of radius 0 there is.
  return k.region.holds(p, 0, D) != k.outside;
}

template <int D>
class SinkModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "sinks"; }
  SimLevel level() const override { return SimLevel::Cleanup; }
  // Changes the sinks' counters and s.deferred.destroy.
  void run(Scene<D>& s) override {
    const ElementArrays<D>& a = s.elements.a;
    bool any = false;
    for (const SinkState& k : s.sinks) any = any || boundaryActs(k.def.every, s.steps);
    if (!any) return;
    for (size_t i = 0; i < a.size(); ++i) {
      for (SinkState& k : s.sinks) {
        if (!boundaryActs(k.def.every, s.steps) || !sinkTakes<D>(k.def, a.x[i])) continue;
        k.count += 1;
        k.mass += 1 / a.invMass[i];
        s.deferred.destroy.push_back(s.elements.pool().handleAt(static_cast<uint32_t>(i)));
        break;
      }
    }
  }
};

}  // namespace demlab::sim
