// The module table (sim/module_table.hpp): the built-in rows have distinct names, a scene's loop
// is what its rows want, and a module from outside src/sim (here the test's own linear drag,
// F = -c m v) joins every loop through addModuleRow alone and runs in it: a free grain's speed
// decays as exp(-c t) and the ledger, with the drag's work, balances.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "sim/integrator.hpp"
#include "sim/module_table.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_module_table_test {

using testing::grain;
using testing::material;

constexpr double kDrag = 5.0;  // 1/s

// The test's module: linear drag on every grain of a scene that has a material named "syrup".
template <int D>
class DragModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "toy-drag"; }
  SimLevel level() const override { return SimLevel::Behaviors; }
  void run(Scene<D>& s) override {
    ElementArrays<D>& a = s.elements.a;
    double work = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      const VecD<D> f = (-kDrag / a.invMass[i]) * a.v[i];
      a.f[i] += f;
      work += f.dot(halfStepVelocity(s, i)) * s.stepDt;
    }
    s.ledger.behaviorWork += work;
  }
};

template <int D>
bool wantsDrag(const Scene<D>& s, const SceneUse&) {
  return std::find(s.materialNames.begin(), s.materialNames.end(), "syrup") !=
         s.materialNames.end();
}

template <int D>
void makeDrag(const Scene<D>&, const SceneUse&, ModuleList<D>& out) {
  out.push_back(std::make_unique<DragModule<D>>());
}

// Registers the drag once per dimension for the whole test program.
void registerDrag() {
  static const bool done = [] {
    addModuleRow<2>({"toy-drag", wantsDrag<2>, makeDrag<2>});
    addModuleRow<3>({"toy-drag", wantsDrag<3>, makeDrag<3>});
    return true;
  }();
  (void)done;
}

TEST(SimModuleTable, BuiltInRowsHaveDistinctNames) {
  std::set<std::string_view> names;
  for (const ModuleRow<3>& row : moduleTable<3>()) EXPECT_TRUE(names.insert(row.name).second);
  EXPECT_GE(names.size(), 10u);
}

class SimModuleTableDim : public ::testing::TestWithParam<int> {};

TEST_P(SimModuleTableDim, ModuleFromOutsideJoinsAndRuns) {
  registerDrag();
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("glass", material(1e7, 0.5, 0.0));
  const ElementId plain = s->addElement(grain({0, 0, 0}, 0.01, "glass", {1, 0, 0}));
  auto modules = s->listModules();
  EXPECT_EQ(std::find(modules.begin(), modules.end(), "toy-drag"), modules.end());
  s->addMaterial("syrup", material(1e7, 0.5, 0.0));
  modules = s->listModules();
  ASSERT_NE(std::find(modules.begin(), modules.end(), "toy-drag"), modules.end());
  // After the force stages, before the second kick: in level order.
  EXPECT_LT(std::find(modules.begin(), modules.end(), "toy-drag"),
            std::find(modules.begin(), modules.end(), "integrate-correct"));
  s->setTimeStep(1e-4);
  s->runSteps(2000);
  const double t = s->time();
  EXPECT_NEAR(s->element(plain).velocity[0], std::exp(-kDrag * t), 1e-6);
  // The drag's work is booked with the half-step velocity, first order in the step: the
  // residual is about c dt / 2 of the energy moved.
  EXPECT_LT(s->energy().residual, kDrag * 1e-4);
  EXPECT_GT(s->energy().behaviorWork, -0.6 * s->element(plain).mass);
}

INSTANTIATE_TEST_SUITE_P(Dims, SimModuleTableDim, ::testing::Values(2, 3),
                         [](const auto& info) { return std::to_string(info.param) + "D"; });

}  // namespace sim_module_table_test
}  // namespace demlab::sim
