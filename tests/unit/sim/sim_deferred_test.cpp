// Deferred creation and destruction (Scene::deferred, applied at the end of the step): a toy
// source and a toy sink, modules of this test added through addModuleRow, feed grains into a
// falling stream and take them out below a plane during one run. The counts add up, the
// ledger follows the energy that enters and leaves with the grains, and the run is
// deterministic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "sim/module_table.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_deferred_test {

using testing::material;
using testing::up;

int created = 0, destroyed = 0;  // over the whole program, by the toy modules

// Every 50 steps, while fewer than 8 grains are there, asks for one more at the top.
template <int D>
class ToySource final : public SimModule<D> {
 public:
  std::string_view name() const override { return "toy-source"; }
  SimLevel level() const override { return SimLevel::Cleanup; }
  void run(Scene<D>& s) override {
    if (s.steps % 50 != 0 || s.elements.size() >= 8) return;
    ElementDef g;
    g.radius = 0.005;
    g.material = "hopper";
    g.position[static_cast<size_t>(up(D))] = 0.1;
    g.position[0] = 0.02 * (created % 9);  // a column each: they never touch
    g.velocity[static_cast<size_t>(up(D))] = -0.5;
    s.deferred.create.push_back(g);
    ++created;
  }
};

// Asks for the removal of every grain below the plane up = -0.05 (twice, to check that a
// handle asked for twice goes once).
template <int D>
class ToySink final : public SimModule<D> {
 public:
  std::string_view name() const override { return "toy-sink"; }
  SimLevel level() const override { return SimLevel::Cleanup; }
  void run(Scene<D>& s) override {
    const ElementArrays<D>& a = s.elements.a;
    for (size_t i = 0; i < a.size(); ++i) {
      if (a.x[i][up(D)] >= -0.05) continue;
      const ElementId id = s.elements.pool().handleAt(static_cast<uint32_t>(i));
      s.deferred.destroy.push_back(id);
      s.deferred.destroy.push_back(id);
      ++destroyed;
    }
  }
};

template <int D>
bool inHopper(const Scene<D>& s, const SceneUse&) {
  return std::find(s.materialNames.begin(), s.materialNames.end(), "hopper") !=
         s.materialNames.end();
}

void registerToys() {
  static const bool done = [] {
    addModuleRow<2>(
        {"toy-source", inHopper<2>, [](const Scene<2>&, const SceneUse&, ModuleList<2>& out) {
           out.push_back(std::make_unique<ToySource<2>>());
         }});
    addModuleRow<3>(
        {"toy-source", inHopper<3>, [](const Scene<3>&, const SceneUse&, ModuleList<3>& out) {
           out.push_back(std::make_unique<ToySource<3>>());
         }});
    addModuleRow<2>(
        {"toy-sink", inHopper<2>, [](const Scene<2>&, const SceneUse&, ModuleList<2>& out) {
           out.push_back(std::make_unique<ToySink<2>>());
         }});
    addModuleRow<3>(
        {"toy-sink", inHopper<3>, [](const Scene<3>&, const SceneUse&, ModuleList<3>& out) {
           out.push_back(std::make_unique<ToySink<3>>());
         }});
    return true;
  }();
  (void)done;
}

class SimDeferred : public ::testing::TestWithParam<int> {};

TEST_P(SimDeferred, SourceAndSinkDuringOneRun) {
  registerToys();
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("hopper", material(1e7, 0.5, 0.3));
  Vec3d g{0, 0, 0};
  g[static_cast<size_t>(up(d))] = -9.81;
  s->addGravity(g);
  s->setTimeStep(1e-4);
  auto twin = s->clone();
  created = destroyed = 0;
  const RunReport r = s->runSteps(3000);
  EXPECT_EQ(r.steps, 3000u);
  const int made = created, gone = destroyed;
  // Each grain falls from 0.1 past -0.05 in about 0.13 s (1300 steps): many come and go.
  EXPECT_GT(made, 8);
  EXPECT_GT(gone, 2);
  EXPECT_EQ(static_cast<int>(s->elementCount()), made - gone);
  EXPECT_LE(s->elementCount(), 8u);
  for (double z : s->positions()) EXPECT_TRUE(std::isfinite(z));
  // What entered and left took its energy with it: the balance of the rest still closes.
  EXPECT_LT(s->energy().residual, 1e-6);
  // The same run again: the same scene, bit for bit.
  created = destroyed = 0;
  twin->runSteps(3000);
  EXPECT_EQ(twin->stateDigest(), s->stateDigest());
  EXPECT_EQ(created, made);
}

INSTANTIATE_TEST_SUITE_P(Dims, SimDeferred, ::testing::Values(2, 3),
                         [](const auto& info) { return std::to_string(info.param) + "D"; });

}  // namespace sim_deferred_test
}  // namespace demlab::sim
