// Simulation::distribute on one rank (this program runs without mpirun: the world is one rank),
// so the distributed step's machinery (the first search keeping each rank's part, the ghost
// modules, the reductions of the ledger and the watchdog) runs with no other rank: it must give
// the serial run's bits. What it refuses, and the edits refused after it. The runs on 2 and 3
// ranks are tests/mpi/sim_ranks_test.cpp's.
#include <gtest/gtest.h>

#include <algorithm>

#include "sim/behavior_registry.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_distribute_test {

using testing::addBox;
using testing::codeOf;
using testing::grain;
using testing::latticeGrains;
using testing::material;

// A frictional bed of n balls falling in a box: 0.2 m side, radius 6 mm, speeds up to 0.5 m/s.
std::unique_ptr<Simulation> bed(int n) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0.5));
  addBox(*s, 0.2, "glass");
  s->addGravity({0, 0, -9.81});
  for (const ElementDef& e : latticeGrains(3, n, 0.006, 0.2, 0.5, "glass", 7)) s->addElement(e);
  return s;
}

TEST(SimDistribute, OneRankIsTheSerialRun) {
  auto serial = bed(1500), dist = bed(1500);
  // (Distributed runs give every element half the skin: DetectionModule::chooseMargins.)
  serial->setOption("detection", "margins", false);
  dist->distribute();
  EXPECT_TRUE(dist->distributed());
  const std::vector<std::string> modules = dist->listModules();
  EXPECT_NE(std::find(modules.begin(), modules.end(), "ghosts"), modules.end());
  EXPECT_NE(std::find(modules.begin(), modules.end(), "ghost-forces"), modules.end());
  RunReport a, b;
  for (int k = 0; k < 4; ++k) {
    a = serial->runSteps(500);
    b = dist->runSteps(500);
  }
  EXPECT_GT(b.neighborRebuilds, 0u);
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_GT(a.contacts, 1000u);
  const auto x = serial->elementSnapshots(), y = dist->elementSnapshots();
  ASSERT_EQ(x.size(), y.size());
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_EQ(x[i].id, y[i].id);
    EXPECT_EQ(x[i].position, y[i].position) << i;
    EXPECT_EQ(x[i].velocity, y[i].velocity) << i;
  }
  EXPECT_EQ(serial->energy().residual, dist->energy().residual);
  const Simulation::DistributionReport r = dist->distribution();
  EXPECT_EQ(r.ranks, 1);
  EXPECT_EQ(r.owned, 1500u);
  EXPECT_EQ(r.ghosts, 0u);
  EXPECT_GT(r.searches, 1u);
}

// The ghosts' forces leave as soon as no module left in the step acts on a ghost: with the touch
// correction off, right after the pairs between grains, so that the walls' pass and gravity
// (owned elements only) run while they travel; with it on (it corrects ghosts' velocities too),
// just before they are added. The same bits either way on one rank.
TEST(SimDistribute, GhostForcesLeaveBeforeTheModulesOfOwnedElementsOnly) {
  const auto order = [](const Simulation& s) {
    std::vector<std::string> m = s.listModules();
    const auto at = [&](const std::string& name) {
      return std::find(m.begin(), m.end(), name) - m.begin();
    };
    return std::vector<long>{at("contacts-friction"), at("ghost-forces-out"),
                             at("wall-contacts-friction"), at("gravity"), at("ghost-forces")};
  };
  auto lean = bed(600), touch = bed(600);
  lean->setOption("touch", "on", false);
  lean->distribute();
  touch->distribute();
  const std::vector<long> o = order(*lean);
  EXPECT_EQ(o[1], o[0] + 1);  // right after the grains' pairs
  EXPECT_EQ(o[2], o[1] + 1);
  EXPECT_LT(o[2], o[3]);
  EXPECT_LT(o[3], o[4]);
  const std::vector<long> t = order(*touch);
  EXPECT_EQ(t[1] + 1, t[4]);  // just before "ghost-forces"
  EXPECT_LT(t[3], t[1]);
  auto serial = bed(600);
  serial->setOption("touch", "on", false);
  serial->setOption("detection", "margins", false);
  RunReport a = serial->runSteps(1500), b = lean->runSteps(1500);
  EXPECT_EQ(a.contacts, b.contacts);
  const auto x = serial->elementSnapshots(), y = lean->elementSnapshots();
  ASSERT_EQ(x.size(), y.size());
  for (size_t i = 0; i < x.size(); ++i) EXPECT_EQ(x[i].velocity, y[i].velocity) << i;
}

TEST(SimDistribute, RefusesWhatItCannotRun) {
  const auto refused = [](auto&& edit) {
    auto s = bed(20);
    edit(*s);
    const uint64_t before = s->stateDigest();
    EXPECT_EQ(codeOf([&] { s->distribute(); }), (std::vector<std::string>{"MPI", "UNSUPPORTED"}));
    EXPECT_EQ(s->stateDigest(), before);
    EXPECT_FALSE(s->distributed());
  };
  refused([](Simulation& s) {
    ElementDef e = grain({0.1, 0.1, 0.15}, 0, "glass");
    e.shape = "clump";
    e.shapeParams = {0, 0, 0, 0.004, 0.008, 0, 0, 0.003};
    s.addElement(e);
  });
  auto flat = makeSimulation(2);
  flat->addMaterial("glass", material(1e7, 0.5, 0.5));
  EXPECT_EQ(codeOf([&] { flat->distribute(); }), (std::vector<std::string>{"MPI", "UNSUPPORTED"}));
  // Once distributed: a second time, and edits of the elements.
  auto s = bed(20);
  s->distribute();
  EXPECT_EQ(codeOf([&] { s->distribute(); }), (std::vector<std::string>{"MPI", "DISTRIBUTED"}));
  EXPECT_EQ(codeOf([&] { s->removeElement(s->elementIds()[0]); }),
            (std::vector<std::string>{"MPI", "DISTRIBUTED"}));
  // An element added after: another shape refused, the scene unchanged; a ball gets the
  // serial scene's handle and the same bits after a run. (Of the bed's radius: a distributed
  // scene keeps the skin it was distributed with, a serial one takes 0.2 of the mean radius at
  // each run, so a smaller grain would move the serial run's searches and its damper's booking.)
  const uint64_t digest = s->stateDigest();
  ElementDef clump = grain({0.1, 0.1, 0.15}, 0, "glass");
  clump.shape = "clump";
  clump.shapeParams = {0, 0, 0, 0.004, 0.008, 0, 0, 0.003};
  EXPECT_EQ(codeOf([&] { s->addElement(clump); }),
            (std::vector<std::string>{"MPI", "UNSUPPORTED"}));
  EXPECT_EQ(s->stateDigest(), digest);
  auto serial = bed(20);
  serial->setOption("detection", "margins", false);
  EXPECT_EQ(s->addElement(grain({0.1, 0.1, 0.15}, 0.006, "glass")),
            serial->addElement(grain({0.1, 0.1, 0.15}, 0.006, "glass")));
  serial->runSteps(400);
  s->runSteps(400);
  const auto x = serial->elementSnapshots(), y = s->elementSnapshots();
  ASSERT_EQ(x.size(), 21u);
  ASSERT_EQ(y.size(), 21u);
  for (size_t i = 0; i < x.size(); ++i) EXPECT_EQ(x[i].position, y[i].position) << i;
  EXPECT_EQ(serial->energy().residual, s->energy().residual);
}

// Elements removed after distribute(): all or none (an id no rank owns: LOOKUP HANDLE, the
// scene unchanged); those of a settling bed, in contact with others, with the serial scene's
// positions and velocities bit for bit after it, their handles given back (the next element
// added takes the serial scene's).
TEST(SimDistribute, RemovesElementsAsTheSerialSceneDoes) {
  auto serial = bed(1500), dist = bed(1500);
  serial->setOption("detection", "margins", false);
  dist->distribute();
  serial->runSteps(600);
  dist->runSteps(600);
  const std::vector<ElementId> ids = serial->elementIds();
  const std::vector<ElementId> gone{ids[10], ids[700], ids[1499], ids[3], ids[700]};
  const uint64_t digest = dist->stateDigest();
  EXPECT_EQ(codeOf([&] { dist->removeElementList({ids[5], ElementId{99999, 1}}); }),
            (std::vector<std::string>{"LOOKUP", "HANDLE"}));
  EXPECT_EQ(dist->stateDigest(), digest);
  EXPECT_EQ(serial->removeElementList(gone), 4u);
  EXPECT_EQ(dist->removeElementList(gone), 4u);
  EXPECT_EQ(codeOf([&] { dist->element(ids[700]); }), (std::vector<std::string>{"LOOKUP", "HANDLE"}));
  RunReport a = serial->runSteps(600), b = dist->runSteps(600);
  EXPECT_GT(a.contacts, 1000u);
  EXPECT_EQ(a.contacts, b.contacts);
  // (The ledger to round-off: the serial removal parks the springs, keeping each contact's
  // damper loss still to book, which the distributed scene's next search drops, as every
  // search does: about 3e-6 of the damping loss here, the balance kept.)
  EXPECT_NEAR(serial->energy().residual, dist->energy().residual, 1e-14);
  EXPECT_EQ(serial->addElement(grain({0.1, 0.1, 0.15}, 0.006, "glass")),
            dist->addElement(grain({0.1, 0.1, 0.15}, 0.006, "glass")));
  serial->runSteps(300);
  dist->runSteps(300);
  const auto x = serial->elementSnapshots(), y = dist->elementSnapshots();
  ASSERT_EQ(x.size(), 1497u);
  ASSERT_EQ(y.size(), x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_EQ(x[i].id, y[i].id);
    EXPECT_EQ(x[i].position, y[i].position) << i;
    EXPECT_EQ(x[i].velocity, y[i].velocity) << i;
  }
  EXPECT_NEAR(serial->energy().residual, dist->energy().residual, 1e-14);
  EXPECT_NEAR(serial->energy().dampingLoss, dist->energy().dampingLoss,
              1e-5 * serial->energy().dampingLoss);
}

// A wall removed after distribute(), alike on every rank: the last wall's candidates and
// springs move into its place with it, the grains' stay; one rank gives the serial scene's
// positions and velocities bit for bit.
TEST(SimDistribute, RemovesAWallAsTheSerialSceneDoes) {
  auto serial = bed(1500), dist = bed(1500);
  serial->setOption("detection", "margins", false);
  dist->distribute();
  serial->runSteps(600);
  dist->runSteps(600);
  const WallId side = serial->wallIds().at(1);
  serial->removeWall(side);
  dist->removeWall(side);
  EXPECT_EQ(serial->wallIds(), dist->wallIds());
  const RunReport a = serial->runSteps(600), b = dist->runSteps(600);
  EXPECT_GT(a.contacts, 1000u);
  EXPECT_EQ(a.contacts, b.contacts);
  const auto x = serial->elementSnapshots(), y = dist->elementSnapshots();
  ASSERT_EQ(y.size(), x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_EQ(x[i].position, y[i].position) << i;
    EXPECT_EQ(x[i].velocity, y[i].velocity) << i;
  }
  // (The serial removal parks every spring whole; the distributed scene's next search drops
  // each contact's damper loss still to book, as every search does: 2e-10 of the scale here.)
  EXPECT_NEAR(serial->energy().residual, dist->energy().residual, 1e-9);
}

// A load and a torque ramp on one element each, set before distribute(): the rank owning the
// element finds it by the handle scripts hold (Scene::ownedIndexOfHandle), wherever it moves;
// one rank gives the serial scene's bits, ledger included (the behaviors' work).
TEST(SimDistribute, LoadsActOnTheElementScriptsName) {
  const auto loaded = [] {
    auto s = bed(1500);
    const std::vector<ElementId> ids = s->elementIds();
    LoadDef pull;
    pull.grain = ids[40];
    pull.force = {0.002, 0, 0.004};
    s->addLoad(pull);
    s->addBehavior("torque-ramp", {{"element", {}, {}, ids[41]}, vecParam("torque", {0, 1e-6, 0}),
                                   vecParam("rate", {0, 1e-4, 0})});
    return s;
  };
  auto serial = loaded(), dist = loaded();
  serial->setOption("detection", "margins", false);
  dist->distribute();
  EXPECT_TRUE(dist->distributed());
  serial->runSteps(1500);
  dist->runSteps(1500);
  const auto x = serial->elementSnapshots(), y = dist->elementSnapshots();
  ASSERT_EQ(y.size(), x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_EQ(x[i].position, y[i].position) << i;
    EXPECT_EQ(x[i].angularVelocity, y[i].angularVelocity) << i;
  }
  const ElementId pulled = serial->elementIds()[40];
  EXPECT_NE(serial->element(pulled).position, loaded()->element(pulled).position);
  EXPECT_GT(serial->energy().behaviorWork, 0);
  EXPECT_EQ(serial->energy().behaviorWork, dist->energy().behaviorWork);
  EXPECT_EQ(serial->energy().residual, dist->energy().residual);
}

// Blocked degrees of freedom (with the touch correction, on by default): set before
// distribute() and after a run, an element fixed at a speed, one held vertically, one kept from
// turning. The serial bits, the constraints' work and its reaction's as the serial scene books
// them, the masks answered by the owner, kept in a checkpoint, and dropped with the element.
TEST(SimDistribute, BlockedElementsHoldAsInTheSerialScene) {
  const auto blocked = [] {
    auto s = bed(1500);
    const std::vector<ElementId> ids = s->elementIds();
    s->setElementBlocked(ids[40], dof::all(3));
    s->setElementVelocity(ids[40], {0.02, 0, 0});
    s->setElementBlocked(ids[41], dof::Z);
    s->setElementBlocked(ids[42], dof::Rx | dof::Ry | dof::Rz);
    return s;
  };
  auto serial = blocked(), dist = blocked();
  serial->setOption("detection", "margins", false);
  dist->distribute();
  const std::vector<ElementId> ids = serial->elementIds();
  const ElementState fixed0 = serial->element(ids[40]), held0 = serial->element(ids[41]);
  for (Simulation* s : {serial.get(), dist.get()}) s->runSteps(700);
  // One more after the first run, and one freed.
  for (Simulation* s : {serial.get(), dist.get()}) {
    s->setElementBlocked(ids[43], dof::X | dof::Y);
    s->setElementBlocked(ids[42], 0);
    s->runSteps(700);
  }
  const auto x = serial->elementSnapshots(), y = dist->elementSnapshots();
  ASSERT_EQ(y.size(), x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_EQ(x[i].position, y[i].position) << i;
    EXPECT_EQ(x[i].velocity, y[i].velocity) << i;
  }
  // The fixed element moved at its speed, the held one kept its vertical speed.
  const double t = serial->time();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(serial->element(ids[40]).position[k], fixed0.position[k] + fixed0.velocity[k] * t, 1e-12);
  }
  EXPECT_EQ(serial->element(ids[41]).velocity[2], held0.velocity[2]);
  EXPECT_NE(serial->energy().behaviorWork, 0);
  EXPECT_EQ(serial->energy().behaviorWork, dist->energy().behaviorWork);
  EXPECT_EQ(serial->energy().residual, dist->energy().residual);
  EXPECT_EQ(dist->element(dist->ownedElement(ids[41])).blocked, dof::Z);
  EXPECT_EQ(dist->element(dist->ownedElement(ids[43])).blocked, dof::X | dof::Y);
  EXPECT_EQ(dist->element(dist->ownedElement(ids[42])).blocked, 0u);
  EXPECT_EQ(codeOf([&] { dist->setElementBlocked(ElementId{900000, 1}, dof::X); }),
            (std::vector<std::string>{"LOOKUP", "HANDLE"}));
  // A checkpoint holds them; a removed element leaves the list.
  auto loaded = makeSimulation(3);
  loaded->loadBytes(dist->saveBytes(false, nullptr));
  EXPECT_EQ(loaded->element(ids[40]).blocked, dof::all(3));
  EXPECT_EQ(loaded->element(ids[43]).blocked, dof::X | dof::Y);
  // (A checkpoint listing a removed element would not load: "blocked element handle".)
  dist->removeElementList({ids[40]});
  auto after = makeSimulation(3);
  after->loadBytes(dist->saveBytes(false, nullptr));
  EXPECT_EQ(after->element(ids[43]).blocked, dof::X | dof::Y);
  // Added blocked after the first run: as the serial scene adds it.
  ElementDef e = grain({0.1, 0.1, 0.15}, 0.006, "glass");
  e.blocked = dof::Z;
  const ElementId added = dist->addElement(e);
  EXPECT_EQ(dist->element(dist->ownedElement(added)).blocked, dof::Z);
}

// Names and tags under the scripts' handles, alike on every rank (each rank's pool renames its
// elements): a load on a tag acts as in the serial scene, bit for bit, before and after the
// tag changes; the members and names answered alike, errors changing nothing; a checkpoint
// keeps them; elements removed by their tag as the serial scene removes them.
TEST(SimDistribute, TagsAndNamesFollowTheScriptsHandles) {
  const auto tagged = [] {
    auto s = bed(1500);
    // (A removal first: the element added after takes a renamed handle, slot 3's next life.)
    s->removeElementList({s->elementIds()[3]});
    const std::vector<ElementId> ids = s->elementIds();
    for (int k = 60; k >= 40; k -= 2) s->tagElement(ids[k], "pushed");  // not in id order
    LoadDef push;
    push.tag = "pushed";
    push.force = {0.001, 0, 0.002};
    s->addLoad(push);
    ElementDef e = grain({0.1, 0.1, 0.15}, 0.006, "glass");
    e.name = "marker";
    e.tags = {"top", "pushed"};
    s->addElement(e);
    return s;
  };
  auto serial = tagged(), dist = tagged();
  serial->setOption("detection", "margins", false);
  dist->distribute();
  const std::vector<ElementId> ids = serial->elementIds();
  const ElementId marker = serial->findElement("marker");
  EXPECT_EQ(dist->findElement("marker"), marker);
  EXPECT_EQ(dist->elementsTagged("pushed"), serial->elementsTagged("pushed"));
  for (Simulation* s : {serial.get(), dist.get()}) s->runSteps(700);
  // (Each edit followed by a run of its own: a stale list of members would show in the bits.)
  // A load on one element and a torque ramp added after the first run act as the serial ones.
  for (Simulation* s : {serial.get(), dist.get()}) {
    s->untagElement(ids[50], "pushed");
    s->runSteps(500);
    s->tagElement(ids[70], "pushed");
    LoadDef pull;
    pull.grain = ids[90];
    pull.force = {-0.002, 0, 0.001};
    s->addLoad(pull);
    s->addBehavior("torque-ramp", {{"element", {}, {}, ids[91]},
                                   vecParam("torque", {0, 1e-6, 0}),
                                   vecParam("rate", {0, 1e-4, 0})});
    s->runSteps(500);
  }
  EXPECT_EQ(codeOf([&] {
              LoadDef none;
              none.grain = ElementId{900000, 1};
              dist->addLoad(none);
            }),
            (std::vector<std::string>{"LOOKUP", "HANDLE"}));
  // residual: how far the ledgers may differ (0 but after a removal: the serial removal parks
  // the springs with each contact's damper loss still to book, which the distributed scene's
  // next search drops; RemovesElementsAsTheSerialSceneDoes).
  const auto same = [&](double residual) {
    const auto x = serial->elementSnapshots(), y = dist->elementSnapshots();
    ASSERT_EQ(y.size(), x.size());
    for (size_t i = 0; i < x.size(); ++i) EXPECT_EQ(x[i].position, y[i].position) << i;
    EXPECT_EQ(serial->energy().behaviorWork, dist->energy().behaviorWork);
    EXPECT_NEAR(serial->energy().residual, dist->energy().residual, residual);
  };
  same(0);
  EXPECT_NE(serial->element(ids[70]).position, tagged()->element(ids[70]).position);
  EXPECT_NE(serial->energy().behaviorWork, 0);
  const std::vector<ElementId> members = serial->elementsTagged("pushed");
  EXPECT_EQ(dist->elementsTagged("pushed"), members);
  EXPECT_EQ(dist->tagNames(), serial->tagNames());
  EXPECT_EQ(dist->elementNames(), serial->elementNames());
  const ElementState m = dist->element(dist->ownedElement(marker));
  EXPECT_EQ(m.name, "marker");
  EXPECT_EQ(m.tags, (std::vector<std::string>{"top", "pushed"}));
  // The members this rank owns (all of them on one rank), in the tag's order.
  const std::vector<uint32_t> at = dist->taggedIndices("pushed");
  const std::vector<ElementId> local = dist->elementIds();
  ASSERT_EQ(at.size(), members.size());
  for (size_t k = 0; k < at.size(); ++k)
    EXPECT_EQ(dist->originalHandle(local[at[k]]), members[k]) << k;
  // Refused edits change nothing.
  const uint64_t digest = dist->stateDigest();
  EXPECT_EQ(codeOf([&] {
              dist->tagElement(ElementId{900000, 1}, "x");
            }),
            (std::vector<std::string>{"LOOKUP", "HANDLE"}));
  EXPECT_EQ(codeOf([&] { dist->tagElement(marker, "12"); }),
            (std::vector<std::string>{"VALUE", "TAG"}));
  ElementDef taken = grain({0.05, 0.05, 0.15}, 0.006, "glass");
  taken.name = "marker";
  EXPECT_EQ(codeOf([&] { dist->addElement(taken); }), (std::vector<std::string>{"EXISTS", "NAME"}));
  EXPECT_EQ(dist->stateDigest(), digest);
  EXPECT_EQ(dist->elementsTagged("x"), std::vector<ElementId>{});
  // A checkpoint keeps them.
  auto loaded = makeSimulation(3);
  loaded->loadBytes(dist->saveBytes(false, nullptr));
  EXPECT_EQ(loaded->elementsTagged("pushed"), members);
  EXPECT_EQ(loaded->findElement("marker"), marker);
  // Removed by a tag: the named element goes, its name and tags with it.
  EXPECT_EQ(dist->removeElements("top"), serial->removeElements("top"));
  EXPECT_EQ(codeOf([&] { dist->findElement("marker"); }),
            (std::vector<std::string>{"LOOKUP", "NAME"}));
  EXPECT_EQ(dist->elementsTagged("pushed"), serial->elementsTagged("pushed"));
  EXPECT_EQ(dist->elementsTagged("pushed").size(), members.size() - 1);
  for (Simulation* s : {serial.get(), dist.get()}) s->runSteps(300);
  same(1e-14);
}

}  // namespace sim_distribute_test
}  // namespace demlab::sim
