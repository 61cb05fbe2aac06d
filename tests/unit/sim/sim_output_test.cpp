// Output modules (Simulation::addOutput): when they fire, that they are absent from the loop
// when there are none, and that they change nothing a run computes.
#include <sstream>

#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_output_test {

using testing::addBox;
using testing::latticeGrains;
using testing::material;

// A small box of moving, colliding grains with gravity and friction: every kind of module runs.
std::unique_ptr<Simulation> bed(int dim) {
  auto s = makeSimulation(dim);
  s->addMaterial("glass", material(1e7, 0.8, 0.3));
  addBox(*s, 0.1, "glass");
  s->addElements(latticeGrains(dim, 40, 0.004, 0.1, 0.5, "glass", 7));
  s->addGravity(dim == 2 ? Vec3d{0, -9.81, 0} : Vec3d{0, 0, -9.81});
  s->setTimeStep(1e-4);
  return s;
}

struct Recorder {
  std::vector<uint64_t> steps;
  std::vector<double> times;
  OutputDef def(uint64_t everySteps, double everyTime = 0) {
    OutputDef d;
    d.name = "recorder";
    d.everySteps = everySteps;
    d.everyTime = everyTime;
    d.callback = [this](const Simulation& s) {
      steps.push_back(s.stepCount());
      times.push_back(s.time());
    };
    return d;
  }
};

bool hasModule(const Simulation& s, const std::string& name) {
  const auto m = s.listModules();
  return std::find(m.begin(), m.end(), name) != m.end();
}

TEST(SimOutput, FiresEveryNSteps) {
  for (int dim : {2, 3}) {
    auto s = bed(dim);
    s->runSteps(3);  // the loop is built: the output is plugged into it
    Recorder r;
    s->addOutput(r.def(10));
    s->runSteps(35);
    EXPECT_EQ(r.steps, (std::vector<uint64_t>{10, 20, 30}));
    s->runSteps(2);
    EXPECT_EQ(r.steps.back(), 40u);
  }
}

TEST(SimOutput, FiresAtTheStepNearestEachMultipleOfTheInterval) {
  auto s = bed(2);
  Recorder r;
  s->addOutput(r.def(0, 3.4e-4));  // dt = 1e-4: multiples 3.4, 6.8, 10.2, 13.6 steps
  s->runSteps(15);
  EXPECT_EQ(r.steps, (std::vector<uint64_t>{3, 7, 10, 14}));
  // An interval shorter than the step fires at most once per step.
  Recorder every;
  s->addOutput(every.def(0, 1e-5));
  s->runSteps(4);
  EXPECT_EQ(every.steps, (std::vector<uint64_t>{16, 17, 18, 19}));
}

TEST(SimOutput, NoOutputNoModule) {
  auto s = bed(3);
  EXPECT_FALSE(hasModule(*s, "outputs"));
  RunReport rep = s->runSteps(5);
  for (const ModuleTime& m : rep.modules) EXPECT_NE(m.module, "outputs");
  Recorder r;
  const OutputId id = s->addOutput(r.def(1));
  ASSERT_TRUE(hasModule(*s, "outputs"));
  EXPECT_EQ(s->listModules().back(), "outputs");  // after the step is complete
  rep = s->runSteps(5);
  EXPECT_EQ(rep.modules.back().module, "outputs");
  EXPECT_EQ(r.steps.size(), 5u);
  ASSERT_EQ(s->outputs().size(), 1u);
  EXPECT_EQ(s->outputs()[0].id, id);
  EXPECT_EQ(s->outputs()[0].everySteps, 1u);
  s->removeOutput(id);
  EXPECT_FALSE(hasModule(*s, "outputs"));
  rep = s->runSteps(5);
  EXPECT_EQ(r.steps.size(), 5u);
  for (const ModuleTime& m : rep.modules) EXPECT_NE(m.module, "outputs");
  EXPECT_TRUE(s->outputs().empty());
}

TEST(SimOutput, ChangesNothingARunComputes) {
  auto a = bed(3), b = bed(3);
  Recorder r;
  b->runSteps(7);
  b->addOutput(r.def(3));
  a->runSteps(7);
  EXPECT_EQ(a->stateDigest(), b->stateDigest());  // not part of the digest
  a->runSteps(200);
  b->runSteps(200);
  EXPECT_EQ(a->stateDigest(), b->stateDigest());
  EXPECT_EQ(a->positions(), b->positions());
  // Not cloned, and saved without complaint (not part of the scene); kept across load.
  EXPECT_TRUE(b->clone()->outputs().empty());
  std::stringstream out;
  EXPECT_TRUE(b->save(out).empty());
  b->load(out);
  ASSERT_EQ(b->outputs().size(), 1u);
  EXPECT_EQ(b->stateDigest(), a->stateDigest());
  const size_t before = r.steps.size();
  b->runSteps(6);
  EXPECT_EQ(r.steps.size(), before + 2);
  EXPECT_EQ(r.steps.back(), 213u);
}

TEST(SimOutput, BadDefsChangeNothing) {
  auto s = bed(2);
  const uint64_t digest = s->stateDigest();
  auto code = [&](const OutputDef& d) {
    try {
      s->addOutput(d);
    } catch (const Error& e) {
      return e.code();
    }
    return std::vector<std::string>{};
  };
  Recorder r;
  EXPECT_EQ(code(r.def(0, 0)), (std::vector<std::string>{"DEMLAB", "VALUE", "OUTPUT"}));
  EXPECT_EQ(code(r.def(2, 0.1)), (std::vector<std::string>{"DEMLAB", "VALUE", "OUTPUT"}));
  EXPECT_EQ(code(r.def(0, -1)), (std::vector<std::string>{"DEMLAB", "VALUE", "OUTPUT"}));
  EXPECT_EQ(code(r.def(0, std::nan(""))), (std::vector<std::string>{"DEMLAB", "VALUE", "OUTPUT"}));
  OutputDef none = r.def(1);
  none.callback = nullptr;
  EXPECT_EQ(code(none), (std::vector<std::string>{"DEMLAB", "VALUE", "CALLBACK"}));
  EXPECT_TRUE(s->outputs().empty());
  EXPECT_FALSE(hasModule(*s, "outputs"));
  EXPECT_EQ(s->stateDigest(), digest);
  const OutputId id = s->addOutput(r.def(1));
  s->removeOutput(id);
  try {
    s->removeOutput(id);
    ADD_FAILURE() << "a removed output was removed again";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "LOOKUP", "HANDLE"}));
  }
}

TEST(SimOutput, CallbackErrorEndsTheRunAfterACompleteStep) {
  auto s = bed(2);
  OutputDef d;
  d.everySteps = 4;
  Simulation* self = s.get();
  d.callback = [self](const Simulation&) {
    self->removeOutput(OutputId{});  // not allowed while firing: STATE BUSY
  };
  s->addOutput(d);
  try {
    s->runSteps(10);
    ADD_FAILURE() << "the callback's error was lost";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "STATE", "BUSY"}));
  }
  EXPECT_EQ(s->stepCount(), 4u);
  // The scene goes on exactly as one that never had the output (the ledger's running scale,
  // which only a completed run() updates, aside).
  auto ref = bed(2);
  ref->runSteps(4);
  EXPECT_EQ(s->positions(), ref->positions());
  EXPECT_EQ(s->velocities(), ref->velocities());
  s->removeOutput(s->outputs()[0].id);
  s->runSteps(10);
  ref->runSteps(10);
  EXPECT_EQ(s->positions(), ref->positions());
  EXPECT_EQ(s->angularVelocities(), ref->angularVelocities());
}

}  // namespace sim_output_test
}  // namespace demlab::sim
