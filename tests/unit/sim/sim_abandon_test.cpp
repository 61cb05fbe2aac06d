// A run stopped part way through a step (RunOptions::longStep): it goes back to its copy of an
// earlier step boundary, and the scene it leaves is the one a run of exactly the steps it
// reports gives, bit for bit, from which the run continues as if never stopped.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <random>

#include "core/thread_pool.hpp"
#include "sim/contacts.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_abandon_test {

using namespace testing;

// Returns a bed of grains bonded in pairs falling onto a floor through each other, with
// friction, and a load whose force function sets *stop once the scene's time reaches
// stopAt: the flag is then raised in the middle of a step (the loads run after the contacts
// and bonds, before the step's last half kick), as Ctrl-C would.
std::unique_ptr<Simulation> bed(std::atomic<bool>* stop, double stopAt, bool autoStep = false) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0.4));
  s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
  s->addGravity({0, 0, -9.81});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<ElementDef> defs;
  for (int k = 0; k < 60; ++k) {
    const double x = 0.03 * (k % 4) + 0.002 * u(rng), y = 0.02 * ((k / 4) % 4) + 0.002 * u(rng);
    const double z = 0.012 + 0.021 * (k / 16);
    defs.push_back(grain({x, y, z}, 0.005, "glass", {0.1 * u(rng), 0.1 * u(rng), 0}));
    defs.push_back(grain({x + 0.0101, y, z}, 0.005, "glass"));
  }
  const std::vector<ElementId> ids = s->addElements(defs);
  s->addBondModel("b", "pointspring", {{"kn", 1e4}, {"ks", 1e4}, {"tensile", 1e9}, {"shear", 1e9}});
  std::vector<std::pair<ElementId, ElementId>> pairs;
  for (size_t k = 0; k + 1 < ids.size(); k += 2) pairs.emplace_back(ids[k], ids[k + 1]);
  s->addBonds(pairs, "b");
  LoadDef load;
  load.grain = ids[0];
  load.forceFn[0] = [stop, stopAt](double t) {
    if (t >= stopAt) stop->store(true);
    return 0.0;
  };
  s->addLoad(load);
  if (autoStep) {
    s->setAutoTimeStep(0.2);
  } else {
    s->setTimeStep(2e-5);
  }
  return s;
}

// Runs s for up to n steps with the stop flag, keeping copies after steps longer than
// longStep (0: from the first step on).
RunReport stopped(Simulation& s, std::atomic<bool>& stop, uint64_t n, double longStep = 0) {
  RunOptions o;
  o.steps = n;
  o.stop = &stop;
  o.longStep = longStep;
  return s.run(o);
}

TEST(SimAbandon, AStepStoppedPartWayLeavesTheSceneOfTheStepsReported) {
  int wentBack = 0;
  for (const bool autoStep : {false, true}) {
    for (const double stopAt : {0.00211, 0.00471, 0.00931}) {
      SCOPED_TRACE(std::to_string(stopAt) + (autoStep ? " auto step" : " fixed step"));
      std::atomic<bool> stop{false};
      auto s = bed(&stop, stopAt, autoStep);
      s->runSteps(3);  // a run with contacts and springs behind it
      const auto reference = s->clone();
      const RunReport rep = stopped(*s, stop, 100000);
      ASSERT_TRUE(rep.interrupted);
      EXPECT_TRUE(rep.abandoned);
      EXPECT_LT(s->time(), stopAt);
      EXPECT_EQ(s->stepCount(), 3 + rep.steps);
      wentBack += rep.dropped > 0;
      if (!autoStep) {
        // The steps before the stopped one, reported and dropped, end before stopAt.
        EXPECT_NEAR((3 + rep.steps + rep.dropped + 0.5) * 2e-5, stopAt, 1e-5);
      }
      // The same steps without any stop give the same bits, and so do the steps after (the
      // automatic step measured at the same step counts).
      auto replay = reference->clone();
      replay->runSteps(rep.steps);
      EXPECT_EQ(replay->stateDigest(), s->stateDigest());
      stop = false;
      s->runSteps(250);
      replay->runSteps(250);
      EXPECT_EQ(replay->stateDigest(), s->stateDigest());
      EXPECT_EQ(replay->time(), s->time());
    }
  }
  // Copies are taken again as the run goes on (at most a tenth of its time): some stops go
  // back over finished steps.
  EXPECT_GT(wentBack, 0);
}

// Runs whose steps are short keep no copy: a stop is answered at the next step boundary, as
// before, and nothing is dropped.
TEST(SimAbandon, ShortStepsStopAtABoundaryWithoutACopy) {
  std::atomic<bool> stop{false};
  auto s = bed(&stop, 0.00211);
  const auto reference = s->clone();
  const RunReport rep = stopped(*s, stop, 100000, RunOptions{}.longStep);
  ASSERT_TRUE(rep.interrupted);
  EXPECT_FALSE(rep.abandoned);
  EXPECT_EQ(rep.dropped, 0u);
  EXPECT_GE(s->time(), 0.00211);  // the step under way finished
  reference->runSteps(rep.steps);
  EXPECT_EQ(reference->stateDigest(), s->stateDigest());
}

// The first step of a scene edited since its last step, stopped part way: the run goes back
// to the copy it took at its start for the watchdog, the scene as it was before the run.
TEST(SimAbandon, TheFirstStepOfAnEditedSceneGoesBackToTheSceneBeforeTheRun) {
  std::atomic<bool> stop{false};
  auto s = bed(&stop, 1e-5);  // raised in the first step (its loads evaluated at t = 2e-5)
  const uint64_t before = s->stateDigest();
  const RunReport rep = stopped(*s, stop, 100, RunOptions{}.longStep);
  ASSERT_TRUE(rep.interrupted);
  EXPECT_TRUE(rep.abandoned);
  EXPECT_EQ(rep.steps, 0u);
  EXPECT_EQ(s->stepCount(), 0u);
  EXPECT_EQ(s->stateDigest(), before);
}

// Stopped by the load of an edited scene's first force pass (at t = 0; without the touch
// correction the last module of the pass, which then polls no more), under the automatic step: the
// pass over every candidate that takes the contacts' step next polls, and the run goes back to the
// scene before it (where the stop was seen only at the first step boundary, abandoning nothing).
TEST(SimAbandon, TheContactsStepAfterTheFirstForcePassAnswersAStop) {
  std::atomic<bool> stop{false};
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0.4));
  const ElementId a = s->addElement(grain({0, 0, 0}, 0.005, "glass"));
  s->addElement(grain({0.0099, 0, 0}, 0.005, "glass"));
  LoadDef load;
  load.grain = a;
  load.forceFn[0] = [&stop](double) {
    stop.store(true);
    return 0.0;
  };
  s->addLoad(load);
  s->setOption("touch", "on", false);  // its module would follow the load's, and poll first
  s->setAutoTimeStep(0.2);
  const uint64_t before = s->stateDigest();
  const RunReport rep = stopped(*s, stop, 100, RunOptions{}.longStep);
  ASSERT_TRUE(rep.interrupted);
  EXPECT_TRUE(rep.abandoned);
  EXPECT_EQ(s->stepCount(), 0u);
  EXPECT_EQ(s->stateDigest(), before);
}

// Returns a lattice of 5 x 5 x 5 grains 5 % overlapping, and a floor far below whose scripted
// motion (zero) counts the force passes in *passes and raises *stop at the stopAt-th: the
// walls move first in a force pass, so a relax pass's search and contacts see the flag.
std::unique_ptr<Simulation> squeezed(std::atomic<bool>* stop, int* passes, int stopAt) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0.4));
  WallDef floor = plane({0, 0, -1}, {0, 0, 1}, "glass");
  floor.motion = WallMotion{};
  floor.motion->velocityFn[0] = [=](double) {
    if (++*passes == stopAt) stop->store(true);
    return 0.0;
  };
  s->addWall(floor);
  std::vector<ElementDef> defs;
  for (int k = 0; k < 125; ++k) {
    defs.push_back(grain({0.019 * (k % 5), 0.019 * ((k / 5) % 5), 0.019 * (k / 25)}, 0.01, "glass"));
  }
  s->addElements(defs);
  s->setTimeStep(1e-5);
  return s;
}

// A relax pass stopped part way goes back to the copy taken before it: the scene, and the grains
// reported moved, of the passes reported, bit for bit, from which relax goes on as if never
// stopped. The first moving pass has no copy (no pass was measured yet; the scene is small):
// stopped there, it finishes and the call ends after it.
TEST(SimAbandon, ARelaxPassStoppedPartWayLeavesTheSceneOfThePassesReported) {
  for (const int stopAt : {2, 3, 6}) {
    SCOPED_TRACE("stopped in force pass " + std::to_string(stopAt));
    std::atomic<bool> stop{false};
    int passes = 0, unused = 0;
    auto s = squeezed(&stop, &passes, stopAt);
    const RelaxReport rep = s->relax(1e-6, 1000, &stop, 0);
    ASSERT_TRUE(rep.interrupted);
    EXPECT_EQ(rep.iterations, stopAt == 2 ? 1u : uint64_t(stopAt - 2));
    auto replay = squeezed(&stop, &unused, 0);
    const RelaxReport same = replay->relax(1e-6, rep.iterations);
    EXPECT_EQ(replay->stateDigest(), s->stateDigest());
    EXPECT_EQ(same.moved, rep.moved);
    stop = false;
    const RelaxReport rest = s->relax(1e-6, 1000, &stop, 0);
    const RelaxReport restReplay = replay->relax(1e-6, 1000);
    EXPECT_FALSE(rest.interrupted);
    EXPECT_GT(rest.iterations, 3u);  // the lattice takes many passes
    EXPECT_EQ(rest.iterations, restReplay.iterations);
    EXPECT_EQ(replay->stateDigest(), s->stateDigest());
  }
}

// The contact pass runs each phase of its groups in rounds with a poll between them: rounds of a
// few candidates give the bits of whole phases, on one thread and on three.
TEST(SimAbandon, ContactPassRoundsGiveTheBitsOfWholePhases) {
  const auto bedOf = [] {
    auto s = makeSimulation(3);
    s->addMaterial("glass", material(1e7, 0.5, 0.4));
    s->addWall(plane({0, 0, 0}, {0, 0, 1}, "glass"));
    s->addGravity({0, 0, -9.81});
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<ElementDef> defs;
    for (int k = 0; k < 12 * 12 * 12; ++k) {  // blocks of 512 grains: several groups a phase
      defs.push_back(grain({0.0199 * (k % 12), 0.0199 * ((k / 12) % 12), 0.0101 + 0.0199 * (k / 144)},
                           0.01, "glass", {0.05 * u(rng), 0.05 * u(rng), 0.05 * u(rng)}));
    }
    WatchdogOptions w;
    w.placed = 0;  // placed overlapping: contacts from the first step
    setWatchdog(*s, w);
    s->addElements(defs);
    s->setTimeStep(2e-5);
    return s;
  };
  const size_t keepRound = contactRoundCandidates();
  const unsigned keepThreads = ThreadPool::global().threads();
  auto whole = bedOf();
  whole->runSteps(40);
  ASSERT_GT(whole->contactCount(), 1000u);
  for (const unsigned threads : {1u, 3u}) {
    contactRoundCandidates() = 7;
    ThreadPool::global().setThreads(threads);
    auto rounds = bedOf();
    rounds->runSteps(40);
    contactRoundCandidates() = keepRound;
    ThreadPool::global().setThreads(keepThreads);
    EXPECT_EQ(rounds->stateDigest(), whole->stateDigest()) << threads << " threads";
  }
}

}  // namespace sim_abandon_test
}  // namespace demlab::sim
