// Restitution through the Simulation API: a binary head-on impact rebounds with the material's
// e under both laws (Hertz-Mindlin with its calibrated damping; LIGGGHTS's damping rebounds
// higher), and the damping choice is checked, digested, cloned and saved.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "physics/pair_params.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_restitution_test {

using physics::HertzDamping;
using testing::grain;
using testing::material;
using testing::setWatchdog;

constexpr double kR = 1e-3, kV0 = 1, kYoung = 5e6;

// Returns the rebound -(relative velocity after) / (before) of two equal grains (radius kR)
// meeting head-on at kV0 in `dim` dimensions, at dt = tc/1000 (tc of the elastic impact).
double binaryImpact(int dim, LawKind law, double e, HertzDamping damping) {
  auto s = makeSimulation(dim);
  s->addMaterial("m", material(kYoung, e, 0));
  s->setContactLaw(law);
  s->setHertzDamping(damping);
  const int up = dim - 1;
  Vec3d xa{0, 0, 0}, xb{0, 0, 0}, va{0, 0, 0}, vb{0, 0, 0};
  xb[up] = 2 * kR + 1e-9;
  va[up] = 0.5 * kV0;
  vb[up] = -0.5 * kV0;
  const ElementId a = s->addElement(grain(xa, kR, "m", va));
  const ElementId b = s->addElement(grain(xb, kR, "m", vb));
  const double mstar = 0.5 * s->element(a).mass, rstar = 0.5 * kR;
  const double ystar = kYoung / (2 * (1 - 0.09));
  const double tc =
      law == LawKind::Linear
          ? std::numbers::pi / std::sqrt(ystar * rstar / mstar)
          : 2.868 * std::pow(mstar * mstar / (rstar * ystar * ystar * kV0), 0.2);
  s->setTimeStep(tc / 1000);
  s->runSteps(3000);
  EXPECT_EQ(s->contactCount(), 0u);
  return (s->element(b).velocity[up] - s->element(a).velocity[up]) / kV0;
}

TEST(SimRestitution, BinaryImpactReboundsWithTheMaterialsRestitution) {
  for (int dim : {2, 3}) {
    for (double e : {0.1, 0.5, 0.9}) {
      SCOPED_TRACE(::testing::Message() << "D=" << dim << " e=" << e);
      EXPECT_NEAR(binaryImpact(dim, LawKind::Linear, e, HertzDamping::Calibrated), e, 1e-3);
      EXPECT_NEAR(binaryImpact(dim, LawKind::HertzMindlin, e, HertzDamping::Calibrated), e, 1e-3);
      // LIGGGHTS's beta with the cut-off: the rebound of the dimensionless law, not e.
      const double c = -std::sqrt(5.0) * physics::liggghtsBeta(e);
      EXPECT_NEAR(binaryImpact(dim, LawKind::HertzMindlin, e, HertzDamping::Liggghts),
                  physics::hertzRestitution(c), 1e-3);
    }
  }
}

TEST(SimRestitution, DampingChoiceIsPartOfTheScene) {
  auto s = makeSimulation(3);
  s->addMaterial("m", material(kYoung, 0.5, 0));
  s->addElement(grain({0, 0, 0}, kR, "m"));
  EXPECT_EQ(s->hertzDamping(), HertzDamping::Calibrated);
  const uint64_t calibrated = s->stateDigest();
  s->setHertzDamping(HertzDamping::Liggghts);
  EXPECT_EQ(s->hertzDamping(), HertzDamping::Liggghts);
  EXPECT_NE(s->stateDigest(), calibrated);
  EXPECT_EQ(s->clone()->hertzDamping(), HertzDamping::Liggghts);
  EXPECT_EQ(testing::codeOf([&] { s->setHertzDamping(static_cast<HertzDamping>(7)); }),
            (std::vector<std::string>{"VALUE", "DAMPING"}));
  EXPECT_EQ(s->hertzDamping(), HertzDamping::Liggghts);
  // Saved and loaded both ways; a checkpoint without the calibrated tag (as every file written
  // before the choice existed) loads as liggghts.
  // With the optional sections before it (watchdog options, touch correction) too; first
  // without them (the touch correction, on by default, writes its tag).
  s->setOption("touch", "on", false);
  for (bool others : {false, true}) {
    if (others) {
      WatchdogOptions w;
      w.overlap = 0.3;
      setWatchdog(*s, w);
      s->setOption("touch", "on", true);
    }
    for (HertzDamping d : {HertzDamping::Calibrated, HertzDamping::Liggghts}) {
      s->setHertzDamping(d);
      std::stringstream io;
      s->save(io);
      auto t = makeSimulation(3);
      t->load(io);
      EXPECT_EQ(t->hertzDamping(), d) << others;
      EXPECT_EQ(std::get<bool>(t->option("touch", "on")), others);
      EXPECT_EQ(t->stateDigest(), s->stateDigest()) << others;
    }
  }
  s->setOption("touch", "on", false);
  setWatchdog(*s, WatchdogOptions{});
  std::stringstream io;
  s->setHertzDamping(HertzDamping::Calibrated);
  s->save(io);
  std::string bytes = testing::editCheckpoint(io.str(), [](std::string& b) {
    ASSERT_EQ(b.substr(b.size() - 4), "HCAL");
    b.resize(b.size() - 4);
  });
  std::stringstream old(bytes);
  auto t = makeSimulation(3);
  t->load(old);
  EXPECT_EQ(t->hertzDamping(), HertzDamping::Liggghts);
}

}  // namespace sim_restitution_test
}  // namespace demlab::sim
