// Bonds (sim/bond.hpp, sim/bond_models/): a bonded pair pulled or sheared by a slowly rising
// load breaks at the model's strength; a straight chain of spheres joined by parallel bonds
// (spacing L, bond radius R) is an Euler-Bernoulli beam of E = kn L, G = ks L, area pi R^2,
// I = pi R^4 / 4, J = pi R^4 / 2, whose static tip deflection, stretch and twist under a tip
// load, and whose axial wave speed sqrt(E / rho_eff) (rho_eff = m / (A L)), follow beam theory;
// an undamped vibrating bonded beam keeps its energy; a run with breaks continued from a
// checkpoint is bit-identical to one that never stopped; bad inputs change nothing.
//
// The static cases settle under the test's own mass-proportional damping module (F = -c m v,
// T = -c I w: every mode decays as exp(-c t / 2)), which joins the loops of scenes with a
// material named "damped" through addModuleRow, as a plug-in would.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>

#include "sim/integrator.hpp"
#include "sim/module_table.hpp"
#include "sim/scene.hpp"
#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_bond_test {

using testing::codeOf;
using testing::grain;
using testing::material;

constexpr double kR = 0.01;         // sphere radius, m
constexpr double kL = 2.01 * kR;    // chain spacing: a gap, so the contact law never acts
constexpr double kDamping = 200.0;  // 1/s
constexpr double kInf = std::numeric_limits<double>::infinity();

template <int D>
class DampingModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "test-damping"; }
  SimLevel level() const override { return SimLevel::Behaviors; }
  void run(Scene<D>& s) override {
    ElementArrays<D>& a = s.elements.a;
    double work = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      const VecD<D> f = (-kDamping / a.invMass[i]) * a.v[i];
      a.f[i] += f;
      work += f.dot(halfStepVelocity(s, i)) * s.stepDt;
      if (s.rotating) a.t[i] += (-kDamping / a.invInertia[i]) * a.w[i];
    }
    s.ledger.behaviorWork += work;
  }
};

template <int D>
bool wantsDamping(const Scene<D>& s, const SceneUse&) {
  return std::find(s.materialNames.begin(), s.materialNames.end(), "damped") !=
         s.materialNames.end();
}

void registerDamping() {
  static const bool done = [] {
    addModuleRow<2>(
        {"test-damping", wantsDamping<2>, [](const Scene<2>&, const SceneUse&, ModuleList<2>& out) {
           out.push_back(std::make_unique<DampingModule<2>>());
         }});
    addModuleRow<3>(
        {"test-damping", wantsDamping<3>, [](const Scene<3>&, const SceneUse&, ModuleList<3>& out) {
           out.push_back(std::make_unique<DampingModule<3>>());
         }});
    return true;
  }();
  (void)done;
}

// A straight chain along x of n + 1 spheres joined by n parallel bonds; the first is clamped
// (every degree of freedom blocked). The material is "damped" when damped.
struct Chain {
  std::unique_ptr<Simulation> s;
  std::vector<ElementId> ids;
  double kn, ks;
};
Chain makeChain(int d, int n, bool damped, double kn = 1e10, double ks = 1e10,
                const std::string& model = "parallel") {
  registerDamping();
  Chain c{makeSimulation(d), {}, kn, ks};
  const std::string mat = damped ? "damped" : "rock";
  c.s->addMaterial(mat, material(1e7, 0.5, 0.0));
  for (int k = 0; k <= n; ++k) {
    ElementDef g = grain({k * kL, 0, 0}, kR, mat);
    if (k == 0) g.blocked = dof::all(d);
    c.ids.push_back(c.s->addElement(g));
  }
  c.s->addBondModel("b", model, {{"kn", kn}, {"ks", ks}, {"tensile", kInf}, {"shear", kInf}});
  EXPECT_EQ(c.s->addBondsWithin({}, 0.02 * kR, "b").size(), static_cast<size_t>(n));
  return c;
}

// Runs s for about t seconds (whole steps). Returns the steps run.
uint64_t runFor(Simulation& s, double t) {
  const auto n = static_cast<uint64_t>(std::ceil(t / s.timeStep()));
  s.runSteps(n);
  return n;
}

Vec3d position(const Simulation& s, ElementId id) {
  return s.element(id).position;
}

double area(int d) {
  return d == 3 ? std::numbers::pi * kR * kR : 2 * kR;
}
double inertia(int d) {
  return d == 3 ? std::numbers::pi * std::pow(kR, 4) / 4 : 2 * std::pow(kR, 3) / 3;
}

class SimBond : public ::testing::TestWithParam<int> {};

// Pulls (axis x) or shears (along y) the second of a pair whose first is clamped, with a load
// rising at rate N/s; the second's rotation is blocked so a shear load makes no bending.
// Returns the break (fails when none).
BondBreakInfo breakPair(int d, const std::string& model, double tensile, double shear,
                        const Vec3d& rate) {
  auto s = makeSimulation(d);
  s->addMaterial("rock", material(1e7, 0.5, 0.0));
  ElementDef g0 = grain({0, 0, 0}, kR, "rock");
  g0.blocked = dof::all(d);
  const ElementId a = s->addElement(g0);
  ElementDef g1 = grain({kL, 0, 0}, kR, "rock");
  g1.blocked = d == 3 ? dof::Rx | dof::Ry | dof::Rz : dof::Rz;
  const ElementId b = s->addElement(g1);
  const double k = model == "parallel" ? 1e10 : 1e6;
  s->addBondModel("b", model, {{"kn", k}, {"ks", k}, {"tensile", tensile}, {"shear", shear}});
  s->addBonds({{a, b}}, "b");
  LoadDef load;
  load.grain = b;
  for (int c = 0; c < 3; ++c) {
    if (rate[c] != 0) load.forceFn[c] = [r = rate[c]](double t) { return r * t; };
  }
  s->addLoad(load);
  for (int k = 0; k < 400 && s->bondBreaks().empty(); ++k) s->runSteps(1000);
  const auto breaks = s->bondBreaks();
  EXPECT_EQ(breaks.size(), 1u);
  return breaks.empty() ? BondBreakInfo{} : breaks[0];
}

// Breaks a point-spring pair (strength 1 N, load rising at 20 N/s) and a parallel-bond pair
// (strength 1e4 Pa, the load reaching strength x A at 0.05 s) in mode ("tension": pulled along
// the axis, "shear": across it) and checks each broke in that mode, on the first step over the
// strength and when the load equalled it (quasi-static).
void checkPairBreaks(int d, const std::string& mode) {
  const bool tension = mode == "tension";
  const double stress = 1e4;
  struct Case {
    const char* model;
    double strength, rate;
  } cases[] = {{"pointspring", 1.0, 20.0}, {"parallel", stress, stress * area(d) / 0.05}};
  for (const Case& c : cases) {
    const Vec3d rate = tension ? Vec3d{c.rate, 0, 0} : Vec3d{0, c.rate, 0};
    const BondBreakInfo b =
        breakPair(d, c.model, tension ? c.strength : kInf, tension ? kInf : c.strength, rate);
    EXPECT_EQ(b.mode, mode) << c.model;
    EXPECT_GT(b.measure, c.strength) << c.model;
    EXPECT_LT(b.measure / c.strength - 1, 1e-3) << c.model;  // the first step over it
    // The load then equals the strength, within the pair's lag behind a load rising from rest.
    EXPECT_NEAR(b.time / 0.05, 1.0, 0.02) << c.model;
    std::printf("[bond] %dD %s: %s pair broke at %.6g (strength %g), load then / strength %.5f\n",
                d, mode.c_str(), c.model, b.measure, c.strength, b.time / 0.05);
  }
}

TEST_P(SimBond, APairBreaksInTensionAtTheTensileStrength) {
  checkPairBreaks(GetParam(), "tension");
}

TEST_P(SimBond, APairBreaksInShearAtTheShearStrength) {
  checkPairBreaks(GetParam(), "shear");
}

TEST_P(SimBond, ACantileverChainDeflectsAsEulerBernoulli) {
  const int d = GetParam();
  const int n = 10;
  Chain c = makeChain(d, n, true);
  const double force = 0.5;
  LoadDef load;
  load.grain = c.ids.back();
  load.force = {0, -force, 0};
  c.s->addLoad(load);
  runFor(*c.s, 0.2);
  const double deflection = -position(*c.s, c.ids.back())[1];
  const double length = n * kL;
  const double e = c.kn * kL;
  const double expected = force * std::pow(length, 3) / (3 * e * inertia(d));
  std::printf(
      "[bond] %dD cantilever of %d bonds: tip deflection %.6g m, F L^3/(3 E I) %.6g m, "
      "ratio %.5f\n",
      d, n, deflection, expected, deflection / expected);
  EXPECT_NEAR(deflection / expected, 1.0, 0.02);
}

TEST_P(SimBond, AChainStretchesAsABar) {
  const int d = GetParam();
  const int n = 10;
  Chain c = makeChain(d, n, true);
  const double force = 0.5;
  LoadDef load;
  load.grain = c.ids.back();
  load.force = {force, 0, 0};
  c.s->addLoad(load);
  runFor(*c.s, 0.2);
  const double stretch = position(*c.s, c.ids.back())[0] - n * kL;
  const double expected = force * n * kL / (c.kn * kL * area(d));
  std::printf("[bond] %dD bar of %d bonds: stretch %.6g m, F L/(E A) %.6g m, ratio %.7f\n", d, n,
              stretch, expected, stretch / expected);
  EXPECT_NEAR(stretch / expected, 1.0, 1e-3);
}

TEST(SimBond3, AChainTwistsAsTorsionTheory) {
  const int n = 10;
  Chain c = makeChain(3, n, true);
  const double torque = 1e-3;
  LoadDef load;
  load.grain = c.ids.back();
  load.torque = {torque, 0, 0};
  c.s->addLoad(load);
  runFor(*c.s, 0.2);
  const auto q = c.s->element(c.ids.back()).orientation;  // w x y z
  const double angle = 2 * std::atan2(q[1], q[0]);
  const double j = std::numbers::pi * std::pow(kR, 4) / 2;
  const double expected = torque * n * kL / (c.ks * kL * j);
  std::printf("[bond] 3D torsion of %d bonds: twist %.6g rad, T L/(G J) %.6g rad, ratio %.7f\n", n,
              angle, expected, angle / expected);
  EXPECT_NEAR(angle / expected, 1.0, 1e-3);
}

// A long free chain whose first sphere is driven at a constant speed along the axis: the front
// of the step in velocity travels at c = sqrt(E / rho_eff) = L sqrt(kn A / m). Measured between
// two spheres (the time each first reaches half the driven speed), which cancels the start.
TEST_P(SimBond, TheAxialWaveTravelsAtTheBarSpeed) {
  const int d = GetParam();
  const int n = 120;
  Chain c = makeChain(d, n, false);
  const double v0 = 1e-3;
  c.s->setElementVelocity(c.ids[0], {v0, 0, 0});
  const int probes[2] = {40, 100};
  double crossed[2] = {-1, -1}, before[2] = {0, 0};
  double tPrev = 0;
  while (crossed[1] < 0 && c.s->time() < 1) {
    c.s->runSteps(1);
    for (int k = 0; k < 2; ++k) {
      const double v = c.s->element(c.ids[probes[k]]).velocity[0];
      if (crossed[k] < 0 && v >= v0 / 2) {
        // Linear interpolation between the two steps around the crossing.
        crossed[k] = tPrev + (c.s->time() - tPrev) * (v0 / 2 - before[k]) / (v - before[k]);
      }
      before[k] = v;
    }
    tPrev = c.s->time();
  }
  ASSERT_GT(crossed[1], 0);
  const double speed = (probes[1] - probes[0]) * kL / (crossed[1] - crossed[0]);
  const double mass = c.s->element(c.ids[1]).mass;
  const double expected = kL * std::sqrt(c.kn * area(d) / mass);
  std::printf("[bond] %dD axial wave: %.6g m/s, sqrt(E/rho_eff) %.6g m/s, ratio %.5f\n", d, speed,
              expected, speed / expected);
  EXPECT_NEAR(speed / expected, 1.0, 0.02);
}

// An undamped cantilever set vibrating by a transverse kick of its tip: over 10^5 steps the
// energy ledger's residual (all the energy is motion and bond strain) stays bounded, without
// drift, and is velocity Verlet's O(dt^2) fluctuation: half the step, a quarter of it.
TEST_P(SimBond, AnUndampedVibratingBeamKeepsItsEnergy) {
  const int d = GetParam();
  // Returns the largest residual of each tenth of n steps at fraction f of the critical step.
  auto residuals = [&](double f, int n) {
    Chain c = makeChain(d, 10, false);
    c.s->setAutoTimeStep(f);
    c.s->setElementVelocity(c.ids.back(), {0, 0.05, 0});
    std::vector<double> out;
    for (int k = 0; k < 10; ++k) {
      double worst = 0;
      for (int j = 0; j < 10; ++j) {
        c.s->runSteps(n / 100);
        worst = std::max(worst, c.s->energy().residual);
      }
      out.push_back(worst);
    }
    EXPECT_GT(c.s->energy().elastic, 0);
    return out;
  };
  const std::vector<double> full = residuals(0.2, 100000);
  const std::vector<double> half = residuals(0.1, 100000);  // the first half of full's time
  const double early = *std::max_element(full.begin(), full.begin() + 5);
  const double late = *std::max_element(full.begin() + 5, full.end());
  const double halfStep = *std::max_element(half.begin(), half.end());
  std::printf(
      "[bond] %dD undamped beam, 1e5 steps: largest residual %.3g (first half), %.3g "
      "(second half); at half the step %.3g over the first half's time\n",
      d, early, late, halfStep);
  EXPECT_LT(std::max(early, late), 5e-3);
  EXPECT_LT(late, 2 * early);      // no drift
  EXPECT_LT(halfStep, early / 3);  // second order in the step
}

// A bonded pack broken in part by a pull, saved halfway: the run continued from the checkpoint
// gives the digest of the run that never stopped.
TEST_P(SimBond, ARunWithBreaksContinuesBitIdenticallyFromACheckpoint) {
  const int d = GetParam();
  auto build = [&] {
    Chain c = makeChain(d, 8, false, 1e10, 1e10, "parallel");
    c.s->addBondModel("weak", "pointspring",
                      {{"kn", 1e5},
                       {"ks", 1e5},
                       {"tensile", 0.05},
                       {"shear", 0.05},
                       {"scatter", 0.2},
                       {"seed", 7}});
    // A second row of spheres beside the chain, bonded to it by weak springs.
    std::vector<ElementDef> row;
    for (int k = 1; k <= 8; ++k) row.push_back(grain({k * kL, kL, 0}, kR, "rock"));
    const auto ids = c.s->addElements(row);
    std::vector<std::pair<ElementId, ElementId>> pairs;
    for (int k = 0; k < 8; ++k) pairs.emplace_back(c.ids[k + 1], ids[k]);
    c.s->addBonds(pairs, "weak");
    for (ElementId id : ids) c.s->setElementVelocity(id, {0, 0.2, 0});
    return c;
  };
  Chain whole = build();
  whole.s->runSteps(4000);
  Chain first = build();
  first.s->runSteps(2000);
  std::stringstream file;
  first.s->save(file);
  auto resumed = makeSimulation(d);
  resumed->load(file);
  EXPECT_EQ(resumed->stateDigest(), first.s->stateDigest());
  resumed->runSteps(2000);
  EXPECT_GT(whole.s->bondBreaks().size(), 0u);
  EXPECT_EQ(resumed->bondBreaks().size(), whole.s->bondBreaks().size());
  EXPECT_EQ(resumed->stateDigest(), whole.s->stateDigest());
  // The ledger books the released energy: the balance still closes.
  EXPECT_GT(whole.s->energy().bondReleased, 0);
  EXPECT_LT(whole.s->energy().residual, 1e-3);
}

TEST_P(SimBond, BadInputsAreRefusedAndChangeNothing) {
  const int d = GetParam();
  Chain c = makeChain(d, 2, false);
  const uint64_t digest = c.s->stateDigest();
  using V = std::vector<std::string>;
  Simulation& s = *c.s;
  EXPECT_EQ(
      codeOf([&] {
        s.addBondModel("x", "pointspring", {{"kn", 1}, {"ks", 1}, {"tensile", -1}, {"shear", 1}});
      }),
      (V{"VALUE", "TENSILE"}));
  EXPECT_EQ(codeOf([&] {
              s.addBondModel("x", "parallel", {{"kn", 0}, {"ks", 1}, {"tensile", 1}, {"shear", 1}});
            }),
            (V{"VALUE", "KN"}));
  EXPECT_EQ(codeOf([&] {
              s.addBondModel("x", "parallel", {{"kn", 1}, {"ks", 1}, {"tensile", 1}});
            }),
            (V{"VALUE", "OPTION"}));
  EXPECT_EQ(codeOf([&] { s.addBondModel("x", "glue", {}); }), (V{"LOOKUP", "BONDTYPE"}));
  EXPECT_EQ(codeOf([&] {
              s.addBondModel("b", "parallel", {{"kn", 1}, {"ks", 1}, {"tensile", 1}, {"shear", 1}});
            }),
            (V{"EXISTS", "BONDMODEL"}));
  EXPECT_EQ(codeOf([&] { s.addBondsWithin({}, std::nan(""), "b"); }), (V{"VALUE", "GAP"}));
  EXPECT_EQ(codeOf([&] { s.addBondsWithin({}, 0.1, "nope"); }), (V{"LOOKUP", "BONDMODEL"}));
  ElementId ghost;
  ghost.index = 99;
  ghost.generation = 1;
  EXPECT_EQ(codeOf([&] { s.addBonds({{c.ids[0], ghost}}, "b"); }), (V{"LOOKUP", "HANDLE"}));
  EXPECT_EQ(codeOf([&] { s.addBonds({{c.ids[0], c.ids[0]}}, "b"); }), (V{"VALUE", "PAIR"}));
  EXPECT_EQ(codeOf([&] { s.addBonds({{c.ids[0], c.ids[1]}}, "b"); }), (V{"VALUE", "PAIR"}));
  EXPECT_EQ(codeOf([&] { s.removeBonds({1, 77}); }), (V{"LOOKUP", "BOND"}));
  EXPECT_EQ(s.stateDigest(), digest);
  EXPECT_EQ(s.bonds().size(), 2u);
}

TEST_P(SimBond, TheCriticalStepSeesTheBonds) {
  const int d = GetParam();
  Chain soft = makeChain(d, 3, false, 1e10, 1e10);
  Chain stiff = makeChain(d, 3, false, 1e13, 1e13);
  // The stiffer the bonds, the shorter the step: 1000x the stiffness, 1/sqrt(1000) the step.
  EXPECT_NEAR(stiff.s->criticalTimeStep() * std::sqrt(1000.0), soft.s->criticalTimeStep(),
              1e-9 * soft.s->criticalTimeStep());
}

TEST_P(SimBond, RemovingAnElementRemovesItsBonds) {
  Chain c = makeChain(GetParam(), 3, false);
  c.s->removeElement(c.ids[1]);
  EXPECT_EQ(c.s->bonds().size(), 1u);
  EXPECT_FALSE(testing::hasModule(*c.s, "bonds") && c.s->bonds().empty());
}

INSTANTIATE_TEST_SUITE_P(Dims, SimBond, ::testing::Values(2, 3),
                         [](const auto& info) { return std::to_string(info.param) + "D"; });

}  // namespace sim_bond_test
}  // namespace demlab::sim
