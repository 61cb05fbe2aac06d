// The public Simulation API: Defs rejected with the right error code and nothing changed,
// modules a scene runs, tags and removal, determinism, clone, save/load continuation.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_api_test {

using testing::addBox;
using testing::codeOf;
using testing::grain;
using testing::latticeGrains;
using testing::material;
using testing::plane;
using testing::setWatchdog;

class SimApi : public ::testing::TestWithParam<int> {};

TEST_P(SimApi, BadDefsAreRejectedAndChangeNothing) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("glass", material(1e8, 0.5, 0.5));
  s->addWall(plane({0, 0, 0}, d == 3 ? Vec3d{0, 0, 1} : Vec3d{0, 1, 0}, "glass"));
  const ElementId g = s->addElement(grain({0.5, 0.5, d == 3 ? 0.5 : 0.0}, 0.01, "glass"));
  s->addGravity({0, d == 2 ? -9.81 : 0, d == 3 ? -9.81 : 0});
  s->setAutoTimeStep(0.2);
  s->runSteps(10);
  const uint64_t digest = s->stateDigest();

  using Code = std::vector<std::string>;
  const double z = d == 3 ? 0.5 : 0.0;
  EXPECT_EQ(codeOf([&] { s->addElement(grain({0, 0, z}, -1, "glass")); }), (Code{"VALUE", "RADIUS"}));
  EXPECT_EQ(codeOf([&] {
              s->addElement(grain({0, 0, z}, NAN, "glass"));
            }),
            (Code{"VALUE", "RADIUS"}));
  EXPECT_EQ(codeOf([&] {
              s->addElement(grain({0, 0, z}, 0.01, "steel"));
            }),
            (Code{"LOOKUP", "MATERIAL"}));
  EXPECT_EQ(codeOf([&] {
              s->addElement(grain({INFINITY, 0, z}, 0.01, "glass"));
            }),
            (Code{"VALUE", "POSITION"}));
  ElementDef tagged = grain({0, 0, z}, 0.01, "glass");
  tagged.tags = {"ok", "9bad"};
  EXPECT_EQ(codeOf([&] { s->addElement(tagged); }), (Code{"VALUE", "TAG"}));
  // A batch with one bad Def adds nothing.
  std::vector<ElementDef> batch = {grain({0, 0, z}, 0.01, "glass"), grain({0, 0, z}, 0, "glass")};
  EXPECT_EQ(codeOf([&] { s->addElements(batch); }), (Code{"VALUE", "RADIUS"}));
  ElementDef named = grain({0, 0, z}, 0.01, "glass");
  named.name = "a";
  EXPECT_EQ(codeOf([&] { s->addElements({named, named}); }), (Code{"EXISTS", "NAME"}));
  EXPECT_EQ(codeOf([&] { s->addMaterial("glass", material(1e8, 0.5, 0.5)); }),
            (Code{"EXISTS", "MATERIAL"}));
  EXPECT_EQ(codeOf([&] { s->addMaterial("rubber", material(-1, 0.5, 0.5)); }),
            (Code{"VALUE", "YOUNG"}));
  EXPECT_EQ(codeOf([&] { s->setTimeStep(0); }), (Code{"VALUE", "TIMESTEP"}));
  EXPECT_EQ(codeOf([&] { s->setAutoTimeStep(2); }), (Code{"VALUE", "FRACTION"}));
  EXPECT_EQ(codeOf([&] {
              s->addWall(plane({0, 0, 0}, {0, 0, 0}, "glass"));
            }),
            (Code{"VALUE", "NORMAL"}));
  WallDef drum;
  drum.shape = WallShape::Drum;
  drum.material = "glass";
  drum.radius = -2;
  EXPECT_EQ(codeOf([&] { s->addWall(drum); }), (Code{"VALUE", "RADIUS"}));
  WallDef shaken = plane({0, 0, 0}, {0, 1, 0}, "glass");
  shaken.motion = WallMotion{.amplitude = {0, 0.01, 0}, .frequency = 0};
  EXPECT_EQ(codeOf([&] { s->addWall(shaken); }), (Code{"VALUE", "FREQUENCY"}));
  EXPECT_EQ(codeOf([&] { s->addLoad(LoadDef{}); }), (Code{"VALUE", "TARGET"}));
  EXPECT_EQ(codeOf([&] { s->setOption("integrator", "name", std::string("euler")); }),
            (Code{"VALUE", "NAME"}));
  EXPECT_EQ(codeOf([&] { s->setOption("detection", "cellfactor", -1.0); }),
            (Code{"VALUE", "CELLFACTOR"}));
  EXPECT_EQ(codeOf([&] { s->setOption("detection", "spacing", 1.0); }), (Code{"VALUE", "OPTION"}));
  EXPECT_EQ(codeOf([&] { s->setOption("integrate", "name", 1.0); }), (Code{"LOOKUP", "MODULE"}));
  EXPECT_EQ(codeOf([&] { s->setElementVelocity(g, {NAN, 0, 0}); }), (Code{"VALUE", "VELOCITY"}));
  if (d == 2) {
    EXPECT_EQ(codeOf([&] {
                s->addElement(grain({0, 0, 1}, 0.01, "glass"));
              }),
              (Code{"VALUE", "POSITION"}));
    ElementDef spin = grain({0, 0, 0}, 0.01, "glass");
    spin.angularVelocity = {1, 0, 0};
    EXPECT_EQ(codeOf([&] { s->addElement(spin); }), (Code{"VALUE", "ANGULARVELOCITY"}));
  }
  EXPECT_EQ(codeOf([&] { (void)lawFromName("hooke"); }), (Code{"VALUE", "LAW"}));
  EXPECT_EQ(codeOf([&] { (void)makeSimulation(4); }), (Code{"VALUE", "DIMENSION"}));
  // Stale handles.
  s->removeElement(g);
  const uint64_t afterRemove = s->stateDigest();
  EXPECT_NE(afterRemove, digest);
  EXPECT_EQ(codeOf([&] { s->removeElement(g); }), (Code{"LOOKUP", "HANDLE"}));
  EXPECT_EQ(codeOf([&] { (void)s->element(g); }), (Code{"LOOKUP", "HANDLE"}));
  EXPECT_EQ(codeOf([&] { s->tagElement(g, "x"); }), (Code{"LOOKUP", "HANDLE"}));
  std::istringstream junk("not a checkpoint");
  EXPECT_EQ(codeOf([&] { s->load(junk); }), (Code{"LOAD", "FORMAT"}));
  auto other = makeSimulation(d == 2 ? 3 : 2);
  std::stringstream ck;
  other->save(ck);
  EXPECT_EQ(codeOf([&] { s->load(ck); }), (Code{"LOAD", "DIMENSION"}));
  EXPECT_EQ(s->stateDigest(), afterRemove);
}

TEST_P(SimApi, ModulesFollowTheScene) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("slick", material(1e8, 0.9, 0.0));
  s->addElements(latticeGrains(d, 8, 0.01, 0.1, 0.1, "slick", 1));
  s->setTimeStep(1e-5);
  using Names = std::vector<std::string>;
  EXPECT_EQ(s->listModules(), (Names{"integrate", "detection", "contacts", "touch",
                                     "integrate-correct", "watchdog"}));
  s->addMaterial("rough", material(1e8, 0.5, 0.5));
  s->addElement(grain({0.5, 0.5, d == 3 ? 0.5 : 0.0}, 0.01, "rough"));
  // "rough" against "slick" has no friction (min rule), but rough against rough has.
  EXPECT_EQ(s->listModules(), (Names{"integrate", "rotation", "detection", "contacts-friction",
                                     "touch", "integrate-correct", "watchdog"}));
  s->setOption("rotation", "on", false);
  EXPECT_EQ(s->listModules(), (Names{"integrate", "detection", "contacts-friction", "touch",
                                     "integrate-correct", "watchdog"}));
  addBox(*s, 1.0, "slick");
  s->addGravity({0, -9.81, 0});
  EXPECT_EQ(s->listModules(),
            (Names{"integrate", "detection", "contacts-friction", "wall-contacts-friction",
                   "gravity", "touch", "integrate-correct", "watchdog"}));
  WallDef piston = plane({0, 2, 0}, {0, -1, 0}, "slick");
  piston.motion = WallMotion{.velocity = {0, -0.1, 0}};
  s->addWall(piston);
  const RunReport rep = s->runSteps(20);
  EXPECT_EQ(rep.steps, 20u);
  Names ran;
  for (const ModuleTime& m : rep.modules) ran.push_back(m.module);
  EXPECT_EQ(ran, (Names{"integrate", "walls", "detection", "contacts-friction",
                        "wall-contacts-friction", "gravity", "touch", "integrate-correct",
                        "watchdog"}));
  EXPECT_EQ(ran, s->listModules());
  // The watchdog is on by default and can be turned off.
  WatchdogOptions off;
  off.enabled = false;
  setWatchdog(*s, off);
  EXPECT_EQ(s->listModules().back(), "integrate-correct");
}

TEST_P(SimApi, TagsRemovalAndQueries) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("glass", material(1e8, 0.5, 0.3));
  auto defs = latticeGrains(d, 20, 0.01, 0.2, 0.0, "glass", 2);
  for (size_t k = 0; k < defs.size(); ++k) defs[k].tags = {k % 2 ? "odd" : "even"};
  defs[3].name = "third";
  const auto ids = s->addElements(defs);
  EXPECT_EQ(s->elementCount(), 20u);
  EXPECT_EQ(s->findElement("third"), ids[3]);
  EXPECT_EQ(s->elementsTagged("odd").size(), 10u);
  const ElementState g3 = s->element(ids[3]);
  EXPECT_EQ(g3.name, "third");
  EXPECT_EQ(g3.tags, std::vector<std::string>{"odd"});
  EXPECT_DOUBLE_EQ(g3.radius, 0.01);
  const double m =
      d == 3 ? 2500 * 4.0 / 3 * std::numbers::pi * 1e-6 : 2500 * std::numbers::pi * 1e-4;
  EXPECT_NEAR(g3.mass, m, 1e-12 * m);
  EXPECT_EQ(s->removeElements("odd"), 10u);
  EXPECT_EQ(s->elementCount(), 10u);
  EXPECT_THROW(s->findElement("third"), Error);
  EXPECT_EQ(s->positions().size(), 10u * d);
  EXPECT_EQ(s->orientations().size(), 10u * (d == 3 ? 4 : 1));
  EXPECT_EQ(s->angularVelocities().size(), 10u * (d == 3 ? 3 : 1));
  const auto live = s->elementIds();
  for (ElementId id : live) EXPECT_EQ(s->element(id).tags, std::vector<std::string>{"even"});
  const auto b = s->bounds();
  EXPECT_LT(b[0][0], b[1][0]);
}

// Builds a scene that uses every part that has state: friction histories, rotation, a moving
// wall, a drum, gravity and a constant load, grains in contact.
std::unique_ptr<Simulation> busyScene(int d) {
  auto s = makeSimulation(d);
  s->addMaterial("glass", material(1e7, 0.6, 0.4));
  s->addMaterial("steel", material(2e7, 0.8, 0.2, 7800));
  s->setPairLaw("glass", "steel", LawKind::Linear);
  auto defs = latticeGrains(d, 60, 0.004, 0.08, 0.2, "glass", 3);
  for (size_t k = 0; k < defs.size(); k += 3) defs[k].material = "steel";
  for (size_t k = 0; k < defs.size(); k += 5) defs[k].tags = {"loaded"};
  s->addElements(defs);
  addBox(*s, 0.08, "steel");
  WallDef lid = plane({0, 0.073, 0}, {0, -1, 0}, "glass");
  lid.motion = WallMotion{.velocity = {0, -0.05, 0}, .amplitude = {0, 0.002, 0}, .frequency = 40};
  s->addWall(lid);
  s->addGravity({0, -9.81, 0});
  LoadDef load;
  load.tag = "loaded";
  load.force = {1e-4, 0, 0};
  load.torque = {0, 0, 1e-7};
  s->addLoad(load);
  s->setAutoTimeStep(0.2);
  return s;
}

TEST_P(SimApi, SameSceneTwiceIsBitIdentical) {
  const int d = GetParam();
  auto a = busyScene(d), b = busyScene(d);
  EXPECT_EQ(a->stateDigest(), b->stateDigest());
  a->runSteps(1500);
  for (int k = 0; k < 3; ++k) b->runSteps(500);
  EXPECT_GT(a->contactCount(), 0u);
  EXPECT_EQ(a->positions(), b->positions());
  EXPECT_EQ(a->velocities(), b->velocities());
  EXPECT_EQ(a->stateDigest(), b->stateDigest());
  // The digest sees a one-ulp change.
  const ElementId g = b->elementIds()[7];
  Vec3d v = b->element(g).velocity;
  v[0] = std::nextafter(v[0], 1.0);
  b->setElementVelocity(g, v);
  EXPECT_NE(a->stateDigest(), b->stateDigest());
}

TEST_P(SimApi, SaveLoadAndCloneContinueBitIdentically) {
  const int d = GetParam();
  auto a = busyScene(d);
  a->runSteps(700);
  std::stringstream ck;
  EXPECT_TRUE(a->save(ck).empty());
  auto copy = a->clone();
  EXPECT_EQ(copy->stateDigest(), a->stateDigest());
  a->runSteps(700);
  auto b = makeSimulation(d);
  b->load(ck);
  b->runSteps(700);
  copy->runSteps(700);
  EXPECT_EQ(b->positions(), a->positions());
  EXPECT_EQ(b->stateDigest(), a->stateDigest());
  EXPECT_EQ(copy->stateDigest(), a->stateDigest());
  EXPECT_EQ(b->energy().dampingLoss, a->energy().dampingLoss);
}

TEST_P(SimApi, CallbacksAreReportedBySave) {
  const int d = GetParam();
  auto a = busyScene(d);
  LoadDef pulse;
  pulse.tag = "loaded";
  pulse.forceFn[0] = [](double t) { return 1e-4 * std::sin(100 * t); };
  const BehaviorId id = a->addLoad(pulse);
  a->runSteps(50);
  std::stringstream ck;
  try {
    a->save(ck);
    ADD_FAILURE() << "save accepted a callback";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "SAVE", "CALLBACK"}));
    EXPECT_NE(std::string(e.what()).find("script callback"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ck.str().size(), 0u);
  const auto skipped = a->save(ck, true);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_NE(skipped[0].find(toString(id)), std::string::npos);
  auto b = makeSimulation(d);
  b->load(ck);
  EXPECT_EQ(b->behaviors().size(), a->behaviors().size() - 1);
  // A clone keeps the callback, and runs as the original.
  auto c = a->clone();
  a->runSteps(100);
  c->runSteps(100);
  EXPECT_EQ(a->stateDigest(), c->stateDigest());
}

TEST_P(SimApi, LedgerClosesWithLoadsWallsAndFriction) {
  const int d = GetParam();
  auto s = busyScene(d);
  const EnergyLedger e0 = s->energy();
  s->runSteps(1500);
  const EnergyLedger e = s->energy();
  std::cout << "[ figures  ] " << d << "D busy scene ledger: residual " << e.residual
            << ", damping " << e.dampingLoss << " J, friction " << e.frictionLoss
            << " J, wall work " << e.wallWork << " J, load work " << e.behaviorWork << " J\n";
  EXPECT_EQ(e0.dampingLoss, 0);
  EXPECT_GT(e.dampingLoss, 0);
  EXPECT_GT(e.frictionLoss, 0);
  EXPECT_NE(e.wallWork, 0);                      // the lid moves
  EXPECT_GT(e.behaviorWork, 0);                  // the loads push the grains along +x
  EXPECT_LT(e.gravitational, e0.gravitational);  // the grains settle
  EXPECT_LT(e.residual, 2e-2);
}

TEST_P(SimApi, RemovalDuringARunKeepsTheRestConsistent) {
  const int d = GetParam();
  auto s = busyScene(d);
  s->runSteps(300);
  const size_t loaded = s->elementsTagged("loaded").size();
  const size_t n = s->elementCount();
  EXPECT_EQ(s->removeElements("loaded"), loaded);
  s->removeWall(s->wallIds().front());
  s->removeElement(s->elementIds()[3]);
  EXPECT_EQ(s->elementCount(), n - loaded - 1);
  EXPECT_EQ(s->wallCount(), static_cast<size_t>(2 * d));
  s->runSteps(300);
  // Every reported contact names live objects.
  for (const ContactInfo& c : s->contacts()) {
    EXPECT_NO_THROW(s->element(c.a));
    if (!c.b.isNull()) {
      EXPECT_NO_THROW(s->element(c.b));
    }
  }
  // And the edited scene still checkpoints and continues bit-identically.
  std::stringstream ck;
  s->save(ck);
  auto t = makeSimulation(d);
  t->load(ck);
  s->runSteps(200);
  t->runSteps(200);
  EXPECT_EQ(s->stateDigest(), t->stateDigest());
}

TEST_P(SimApi, StopFlagAndProgress) {
  const int d = GetParam();
  auto s = busyScene(d);
  std::atomic<bool> stop{false};
  uint64_t calls = 0, last = 0;
  RunOptions o;
  o.steps = 1000;
  o.stop = &stop;
  o.progressEvery = 100;
  o.progress = [&](uint64_t done, uint64_t total) {
    ++calls;
    last = done;
    EXPECT_EQ(total, 1000u);
    if (done >= 300) stop = true;
  };
  const RunReport r = s->run(o);
  EXPECT_TRUE(r.interrupted);
  EXPECT_EQ(r.steps, 300u);
  EXPECT_EQ(s->stepCount(), 300u);
  EXPECT_EQ(last, 300u);
  EXPECT_EQ(calls, 4u);
  EXPECT_GT(r.wallSeconds, 0);
  // The scene started at t = 0; the automatic step may have changed at a neighbour search.
  EXPECT_EQ(r.simulatedTime, s->time());
  EXPECT_GT(r.simulatedTime, 0);
}

INSTANTIATE_TEST_SUITE_P(Dims, SimApi, ::testing::Values(2, 3),
                         [](const auto& info) { return std::to_string(info.param) + "D"; });

}  // namespace sim_api_test
}  // namespace demlab::sim
