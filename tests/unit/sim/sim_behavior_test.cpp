// The behavior registry and its torque ramp (sim/behaviors/torque_ramp.hpp): the analytic spin
// of a free grain, the energy ledger, the cap, tag groups, removal, checkpoints, and the
// registry's errors.
#include <sstream>

#include "sim/behavior_registry.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_behavior_test {

using testing::codeOf;
using testing::grain;
using testing::material;
using Code = std::vector<std::string>;

// Returns a scene with one free grain (no contact, no gravity) and dt = 1e-4.
std::unique_ptr<Simulation> oneGrain(int d, ElementId* id) {
  auto s = makeSimulation(d);
  s->addMaterial("m", material(1e7, 0.5, 0.5));
  *id = s->addElement(grain({0, 0, 0}, 0.01, "m"));
  s->setTimeStep(1e-4);
  return s;
}

std::vector<BehaviorParam> ramp(ElementId g, const Vec3d& t0, const Vec3d& rate) {
  return {{"element", {}, {}, g}, vecParam("torque", t0), vecParam("rate", rate)};
}

// Returns the inertia of the grain (2/5 m r^2 in 3D, 1/2 m r^2 in 2D).
double inertia(const Simulation& s, ElementId g) { return s.element(g).inertia; }

class TorqueRamp : public ::testing::TestWithParam<int> {};

// Returns the ledger's (behavior work - rotational energy gained) / energy gained after a
// ramp's first 0.2 s at time step dt; checks the spin against the analytic answer.
double rampLedgerError(int d, double dt) {
  ElementId g;
  auto s = oneGrain(d, &g);
  s->setTimeStep(dt);
  const double T0 = 2e-4, rate = 0.05;
  s->addBehavior("torque-ramp", ramp(g, {0, 0, T0}, {0, 0, rate}));
  s->runSteps(static_cast<uint64_t>(std::llround(0.2 / dt)));
  const double t = s->time(), I = inertia(*s, g);
  const double expected = (T0 * t + rate * t * t / 2) / I;
  const std::vector<double> w = s->angularVelocities();
  // The trapezoidal kick integrates a linear torque exactly: the spin is right to rounding.
  EXPECT_NEAR(d == 2 ? w[0] : w[2], expected, 1e-9 * expected);
  const EnergyLedger e = s->energy();
  EXPECT_NEAR(e.kineticRotational, I * expected * expected / 2, 1e-9 * e.kineticRotational);
  EXPECT_NEAR(e.residual, (e.behaviorWork - e.kineticRotational) / e.scale, 1e-12);
  return (e.behaviorWork - e.kineticRotational) / e.kineticRotational;
}

// The spin follows omega(t) = (T0 t + rate t^2/2) / I; the ledger's work, T at the step's end
// times the half-step spin, is first order in dt for a torque that changes: its error is below
// 1/steps and halves with dt.
TEST_P(TorqueRamp, FreeGrainFollowsTheAnalyticSpin) {
  const int d = GetParam();
  const double coarse = rampLedgerError(d, 1e-4), fine = rampLedgerError(d, 5e-5);
  EXPECT_LT(std::abs(coarse), 1.0 / 2000);
  EXPECT_NEAR(coarse / fine, 2.0, 0.1);
}

TEST_P(TorqueRamp, CapHoldsTheMagnitude) {
  const int d = GetParam();
  ElementId g;
  auto s = oneGrain(d, &g);
  auto p = ramp(g, {0, 0, 0}, {0, 0, -1.0});
  p.push_back(numberParam("max", 0.01));
  s->addBehavior("torque-ramp", p);
  s->runSteps(1000);  // capped from t = 0.01 to 0.1: omega = -(0.01^2/2 + 0.01 * 0.09) / I
  const double I = inertia(*s, g), t = s->time();
  const double expected = -(0.01 * 0.01 / 2 + 0.01 * (t - 0.01)) / I;
  const std::vector<double> w = s->angularVelocities();
  EXPECT_NEAR(d == 2 ? w[0] : w[2], expected, 1e-6 * std::abs(expected));
}

TEST_P(TorqueRamp, TagGroupAndRemoval) {
  const int d = GetParam();
  ElementId a;
  auto s = oneGrain(d, &a);
  ElementDef other = grain({1, 0, 0}, 0.01, "m");
  other.tags = {"spun"};
  const ElementId b = s->addElement(other);
  s->tagElement(a, "spun");
  const ElementId c = s->addElement(grain({2, 0, 0}, 0.01, "m"));
  std::vector<BehaviorParam> p{{"tag", {}, "spun", {}}, vecParam("rate", {0, 0, 1})};
  const BehaviorId id = s->addBehavior("torque-ramp", p);
  ASSERT_EQ(s->behaviors().size(), 1u);
  EXPECT_EQ(s->behaviors()[0].kind, "torque-ramp");
  s->runSteps(10);
  const int n = d == 2 ? 1 : 3;
  std::vector<double> w = s->angularVelocities();
  EXPECT_GT(w[n - 1], 0);      // a
  EXPECT_GT(w[2 * n - 1], 0);  // b
  EXPECT_EQ(w[3 * n - 1], 0);  // c, untagged
  (void)b;
  (void)c;
  s->removeBehavior(id);
  EXPECT_TRUE(s->behaviors().empty());
  const double before = s->angularVelocities()[n - 1];
  s->runSteps(10);
  EXPECT_EQ(s->angularVelocities()[n - 1], before);
  EXPECT_EQ(codeOf([&] { s->removeBehavior(id); }), (Code{"LOOKUP", "HANDLE"}));
}

TEST_P(TorqueRamp, SaveLoadAndCloneContinueBitIdentically) {
  const int d = GetParam();
  ElementId g;
  auto a = oneGrain(d, &g);
  auto p = ramp(g, {0, 0, 1e-4}, {0, 0, 0.02});
  p.push_back(numberParam("start", 0.005));
  p.push_back(numberParam("max", 1e-3));
  a->addGravity({0, 0, 0});
  a->addBehavior("torque-ramp", p);
  a->runSteps(300);
  std::stringstream ck;
  EXPECT_TRUE(a->save(ck).empty());
  auto copy = a->clone();
  EXPECT_EQ(copy->stateDigest(), a->stateDigest());
  auto b = makeSimulation(d);
  b->load(ck);
  EXPECT_EQ(b->stateDigest(), a->stateDigest());
  EXPECT_EQ(b->behaviors()[1].description, a->behaviors()[1].description);
  a->runSteps(300);
  b->runSteps(300);
  copy->runSteps(300);
  EXPECT_EQ(b->stateDigest(), a->stateDigest());
  EXPECT_EQ(copy->stateDigest(), a->stateDigest());
}

// A checkpoint naming a type this build does not know is refused with a clear error.
TEST_P(TorqueRamp, UnknownTypeInACheckpoint) {
  const int d = GetParam();
  ElementId g;
  auto a = oneGrain(d, &g);
  a->addBehavior("torque-ramp", ramp(g, {0, 0, 0}, {0, 0, 1}));
  std::stringstream ck;
  a->save(ck);
  std::string bytes = testing::editCheckpoint(ck.str(), [](std::string& b) {
    const size_t at = b.find("torque-ramp");
    ASSERT_NE(at, std::string::npos);
    b.replace(at, 11, "torque-ramq");
  });
  std::stringstream bad(bytes);
  auto b = makeSimulation(d);
  const uint64_t before = b->stateDigest();
  try {
    b->load(bad);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (Code{"DEMLAB", "LOAD", "FORMAT"}));
    EXPECT_NE(std::string(e.what()).find("unknown behavior type \"torque-ramq\""),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(b->stateDigest(), before);
}

TEST_P(TorqueRamp, BadParametersChangeNothing) {
  const int d = GetParam();
  ElementId g;
  auto s = oneGrain(d, &g);
  const uint64_t before = s->stateDigest();
  EXPECT_EQ(codeOf([&] { s->addBehavior("spring", {}); }), (Code{"LOOKUP", "BEHAVIORTYPE"}));
  EXPECT_EQ(codeOf([&] { s->addBehavior("torque-ramp", {{"element", {}, {}, g}}); }),
            (Code{"VALUE", "OPTION"}));
  EXPECT_EQ(codeOf([&] { s->addBehavior("torque-ramp", {vecParam("rate", {0, 0, 1})}); }),
            (Code{"VALUE", "TARGET"}));
  auto p = ramp(g, {0, 0, 0}, {0, 0, 1});
  p.push_back(numberParam("max", -1));
  EXPECT_EQ(codeOf([&] { s->addBehavior("torque-ramp", p); }), (Code{"VALUE", "MAX"}));
  p.back() = numberParam("color", 1);
  EXPECT_EQ(codeOf([&] { s->addBehavior("torque-ramp", p); }), (Code{"VALUE", "OPTION"}));
  if (d == 2) {
    EXPECT_EQ(codeOf([&] { s->addBehavior("torque-ramp", ramp(g, {1, 0, 0}, {0, 0, 1})); }),
              (Code{"VALUE", "TORQUE"}));
  }
  s->removeElement(g);
  EXPECT_EQ(codeOf([&] { s->addBehavior("torque-ramp", ramp(g, {0, 0, 0}, {0, 0, 1})); }),
            (Code{"LOOKUP", "HANDLE"}));
  EXPECT_TRUE(s->behaviors().empty());
  (void)before;
}

INSTANTIATE_TEST_SUITE_P(Dims, TorqueRamp, ::testing::Values(2, 3));

TEST(BehaviorRegistry, ListsTypesAndRefusesUnknownOnes) {
  std::vector<std::string> names;
  for (const BehaviorTypeInfo& t : behaviorTypes()) names.push_back(t.name);
  EXPECT_EQ(names, (std::vector<std::string>{"gravity", "load", "torque-ramp"}));
  try {
    findBehaviorRow("spring");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (Code{"DEMLAB", "LOOKUP", "BEHAVIORTYPE"}));
    EXPECT_STREQ(e.what(), "unknown behavior type \"spring\": must be gravity, load or torque-ramp");
  }
}

// The generic path builds the same gravity and load as addGravity and addLoad: equal digests.
TEST(BehaviorRegistry, GenericAddMatchesTheTypedCalls) {
  for (int d : {2, 3}) {
    ElementId g1, g2;
    auto a = oneGrain(d, &g1);
    auto b = oneGrain(d, &g2);
    const Vec3d gv = d == 2 ? Vec3d{0, -9.81, 0} : Vec3d{0, 0, -9.81};
    a->addGravity(gv);
    b->addBehavior("gravity", {vecParam("g", gv)});
    LoadDef l;
    l.grain = g1;
    l.force = {1e-3, 0, 0};
    a->addLoad(l);
    b->addBehavior("load", {{"element", {}, {}, g2}, vecParam("force", {1e-3, 0, 0})});
    EXPECT_EQ(a->stateDigest(), b->stateDigest());
    EXPECT_EQ(a->listModules(), b->listModules());
    a->runSteps(100);
    b->runSteps(100);
    EXPECT_EQ(a->stateDigest(), b->stateDigest());
  }
}

}  // namespace sim_behavior_test
}  // namespace demlab::sim
