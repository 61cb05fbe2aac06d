// MaterialDef::check and mixPair: bad fields are rejected with the right code and message,
// and mixing is symmetric and reproduces the documented formulas.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "physics/critical_step.hpp"
#include "physics/material.hpp"
#include "physics/pair_params.hpp"

namespace demlab::physics {
namespace physics_material_test {

MaterialDef glass() {
  MaterialDef m;
  m.density = 2500;
  m.young = 5e6;
  m.poisson = 0.3;
  m.restitution = 0.5;
  m.friction = 0.5;
  return m;
}

void expectError(const MaterialDef& m, const std::string& message, const std::string& field) {
  try {
    m.check();
    FAIL() << "expected an error: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(e.what(), message);
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", field}));
  }
}

constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
constexpr Real kInf = std::numeric_limits<Real>::infinity();

TEST(PhysicsMaterial, GoodMaterialPasses) {
  EXPECT_NO_THROW(glass().check());
  MaterialDef m = glass();
  m.poisson = -0.99;
  m.restitution = 1;
  m.friction = 0;
  m.normalStiffness = 1e5;
  m.shearStiffness = 1e4;
  EXPECT_NO_THROW(m.check());
}

TEST(PhysicsMaterial, UnsetFieldsAreNaNAndRejected) {
  expectError(MaterialDef{}, "bad density \"NaN\": must be a number from 1e-06 to 1000000000", "DENSITY");
}

TEST(PhysicsMaterial, EachBadFieldHasItsCode) {
  struct Case {
    Real MaterialDef::*field;
    Real value;
    std::string message;
    std::string code;
  };
  const std::vector<Case> cases{
      {&MaterialDef::density, -1, "bad density \"-1\": must be a number from 1e-06 to 1000000000", "DENSITY"},
      {&MaterialDef::density, 0, "bad density \"0\": must be a number from 1e-06 to 1000000000", "DENSITY"},
      {&MaterialDef::density, kInf, "bad density \"Inf\": must be a number from 1e-06 to 1000000000", "DENSITY"},
      {&MaterialDef::density, 1e300,
       "bad density \"1e+300\": must be a number from 1e-06 to 1000000000", "DENSITY"},
      {&MaterialDef::young, 1e-300,
       "bad Young's modulus \"1e-300\": must be a number from 0.001 to 1e+15 (Inf: rigid, for "
       "walls)",
       "YOUNG"},
      {&MaterialDef::cohesion, 1e308, "bad cohesion \"1e+308\": must be a number from 0 to 1e+30",
       "COHESION"},
      {&MaterialDef::young, kNaN, "bad Young's modulus \"NaN\": must be a number from 0.001 to 1e+15 (Inf: rigid, for walls)",
       "YOUNG"},
      {&MaterialDef::young, -5e6, "bad Young's modulus \"-5000000\": must be a number from 0.001 to 1e+15 (Inf: rigid, for walls)",
       "YOUNG"},
      {&MaterialDef::poisson, 0.5,
       "bad Poisson's ratio \"0.5\": must be a number greater than -1 and less than 0.5",
       "POISSON"},
      {&MaterialDef::poisson, -1,
       "bad Poisson's ratio \"-1\": must be a number greater than -1 and less than 0.5", "POISSON"},
      {&MaterialDef::poisson, kNaN,
       "bad Poisson's ratio \"NaN\": must be a number greater than -1 and less than 0.5",
       "POISSON"},
      {&MaterialDef::restitution, 0,
       "bad restitution \"0\": must be a number greater than 0 and at most 1", "RESTITUTION"},
      {&MaterialDef::restitution, 1.01,
       "bad restitution \"1.01\": must be a number greater than 0 and at most 1", "RESTITUTION"},
      {&MaterialDef::restitution, kNaN,
       "bad restitution \"NaN\": must be a number greater than 0 and at most 1", "RESTITUTION"},
      {&MaterialDef::friction, -0.1, "bad friction \"-0.1\": must be a number from 0 to 1e+30",
       "FRICTION"},
      {&MaterialDef::friction, kNaN, "bad friction \"NaN\": must be a number from 0 to 1e+30",
       "FRICTION"},
      {&MaterialDef::friction, kInf, "bad friction \"Inf\": must be a number from 0 to 1e+30",
       "FRICTION"},
      {&MaterialDef::rollingFriction, -0.01,
       "bad rolling friction \"-0.01\": must be a number from 0 to 1e+30", "ROLLINGFRICTION"},
      {&MaterialDef::rollingFriction, kInf,
       "bad rolling friction \"Inf\": must be a number from 0 to 1e+30", "ROLLINGFRICTION"},
      {&MaterialDef::normalStiffness, -1,
       "bad normal stiffness \"-1\": must be a number from 0 to 1e+30", "NORMALSTIFFNESS"},
      {&MaterialDef::shearStiffness, kNaN,
       "bad shear stiffness \"NaN\": must be a number from 0 to 1e+30", "SHEARSTIFFNESS"},
      {&MaterialDef::shearStiffness, 100,
       "bad shear stiffness \"100\": must be 0 when the normal stiffness is 0 (derived)",
       "SHEARSTIFFNESS"},
  };
  for (const Case& c : cases) {
    MaterialDef m = glass();
    m.*c.field = c.value;
    const MaterialDef before = m;
    expectError(m, c.message, c.code);
    // check() is const: nothing changed (compare bitwise, NaN included).
    EXPECT_EQ(std::memcmp(&m, &before, sizeof m), 0);
  }
}

TEST(PhysicsMaterial, MixPairChecksBothMaterials) {
  MaterialDef bad = glass();
  bad.restitution = 2;
  try {
    mixPair(LawKind::HertzMindlin, glass(), bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", "RESTITUTION"}));
  }
}

TEST(PhysicsMaterial, MixingIsSymmetricBitForBit) {
  MaterialDef a = glass();
  MaterialDef b = glass();
  b.density = 7800;
  b.young = 2.1e11;
  b.poisson = 0.29;
  b.restitution = 0.9;
  b.friction = 0.2;
  b.normalStiffness = 3e5;
  for (LawKind law : {LawKind::Linear, LawKind::HertzMindlin}) {
    const PairParams ab = mixPair(law, a, b);
    const PairParams ba = mixPair(law, b, a);
    EXPECT_EQ(std::memcmp(&ab, &ba, sizeof ab), 0) << lawName(law);
  }
}

TEST(PhysicsMaterial, MixingFormulas) {
  MaterialDef a = glass();
  MaterialDef b = glass();
  b.young = 2e7;
  b.poisson = 0.25;
  b.restitution = 0.8;
  b.friction = 0.3;
  const PairParams p = mixPair(LawKind::HertzMindlin, a, b);
  const Real ystar = 1 / ((1 - 0.09) / 5e6 + (1 - 0.0625) / 2e7);
  const Real gstar = 1 / (2 * 1.7 * 1.3 / 5e6 + 2 * 1.75 * 1.25 / 2e7);
  EXPECT_NEAR(p.youngEff, ystar, 1e-9 * ystar);
  EXPECT_NEAR(p.shearEff, gstar, 1e-9 * gstar);
  EXPECT_DOUBLE_EQ(p.friction, 0.3);
  EXPECT_DOUBLE_EQ(p.restitution, std::sqrt(0.4));
  // zeta reproduces e through the cut-off oscillator's restitution (pair_params.hpp).
  EXPECT_NEAR(linearRestitution(p.dampingRatio), p.restitution, 1e-14);
  // One material: e and the Mindlin ratio 2(1-nu)/(2-nu).
  const PairParams q = mixPair(LawKind::Linear, a, a);
  EXPECT_EQ(q.restitution, 0.5);
  EXPECT_NEAR(q.shearRatio, 2 * 0.7 / 1.7, 1e-14);
  EXPECT_EQ(q.knFixed, 0);
  EXPECT_NEAR(q.knPerRadius, 5e6 / (2 * 0.91), 1e-6);
  // Explicit stiffness: one material keeps its value; a partner without one adopts it.
  MaterialDef s = glass();
  s.normalStiffness = 1e5;
  EXPECT_EQ(mixPair(LawKind::Linear, s, s).knFixed, 1e5);
  EXPECT_EQ(mixPair(LawKind::Linear, s, a).knFixed, 1e5);
  MaterialDef t = s;
  t.normalStiffness = 3e5;
  t.shearStiffness = 1e5;
  const PairParams st = mixPair(LawKind::Linear, s, t);
  EXPECT_NEAR(st.knFixed, 2 * 1e5 * 3e5 / 4e5, 1e-6);
  EXPECT_NEAR(st.shearRatio, 1e5 / st.knFixed, 1e-14);  // the only shear stiffness given
}

TEST(PhysicsMaterial, CutOffRestitution) {
  // Small damping: the cut-off barely matters and the textbook formula holds to O(zeta^2).
  for (Real z : {1e-4, 1e-3}) {
    const Real textbook = std::exp(-std::numbers::pi * z / std::sqrt(1 - z * z));
    EXPECT_NEAR(linearRestitution(z), textbook, 4 * z * z);
  }
  // The three branches join continuously at zeta = 1 (e = exp(-2), duration 2/omega_n).
  EXPECT_DOUBLE_EQ(linearRestitution(1), std::exp(-2.0));
  EXPECT_NEAR(linearRestitution(1 - 1e-9), std::exp(-2.0), 1e-8);
  EXPECT_NEAR(linearRestitution(1 + 1e-9), std::exp(-2.0), 1e-8);
  EXPECT_NEAR(linearForceDuration(1 - 1e-9), 2, 1e-8);
  EXPECT_NEAR(linearForceDuration(1 + 1e-9), 2, 1e-8);
  EXPECT_DOUBLE_EQ(linearForceDuration(0), std::numbers::pi);
  // Overdamped: e ~ 1/(4 zeta^2) for large zeta.
  EXPECT_NEAR(linearRestitution(100) * 4e4, 1, 1e-3);
  // Absurdly small restitutions stay finite.
  EXPECT_TRUE(std::isfinite(linearDampingRatio(1e-250)));
  EXPECT_TRUE(std::isfinite(linearDampingRatio(std::numeric_limits<Real>::denorm_min())));
  // The inverse, over the whole range, including overdamped e < exp(-2).
  Real last = 1;
  for (Real e : {1.0, 0.99, 0.9, 0.5, 0.2, 0.1353, 0.1, 0.01, 1e-4}) {
    const Real z = linearDampingRatio(e);
    EXPECT_NEAR(linearRestitution(z), e, 1e-13 * (1 + 1 / e) * e) << e;
    EXPECT_LE(z, e == 1.0 ? 0 : 1e9);
    EXPECT_LE(linearRestitution(z), last + 1e-15);
    last = linearRestitution(z);
  }
}

TEST(PhysicsMaterial, TimeSteps) {
  const MaterialDef m = glass();
  const Real r = 1e-3;
  const Real g = 5e6 / 2.6;
  EXPECT_NEAR(rayleighTimeStep(m, r),
              std::numbers::pi * r * std::sqrt(2500 / g) / (0.1631 * 0.3 + 0.8766), 1e-18);
  const PairParams hm = mixPair(LawKind::HertzMindlin, m, m);
  EXPECT_DOUBLE_EQ(criticalTimeStep(hm, 1.0, r, false), rayleighTimeStep(m, r));
  EXPECT_DOUBLE_EQ(criticalTimeStep(hm, 1.0, r, true), rayleighTimeStep(m, r));
  // Linear, frictionless, explicit kn: omega^2 = 2 kn / m (two equal grains).
  MaterialDef s = m;
  s.friction = 0;
  s.normalStiffness = 1e4;
  const PairParams lin = mixPair(LawKind::Linear, s, s);
  const Real mass = 1e-5, w = std::sqrt(2 * 1e4 / mass), z = lin.dampingRatio;
  EXPECT_NEAR(criticalTimeStep(lin, mass, r, false), 2 / w * (std::sqrt(1 + z * z) - z), 1e-18);
  // Synchronized velocities: the damper's part doubled (dampedStepFactor).
  EXPECT_NEAR(criticalTimeStep(lin, mass, r, true),
              2 / w * (std::sqrt(1 + 4 * z * z) - 2 * z), 1e-18);
  // With friction the tangential-rotational mode 7 kt/m is faster (kt = 0.82 kn).
  s.friction = 0.5;
  const PairParams fr = mixPair(LawKind::Linear, s, s);
  const Real wt = std::sqrt(7 * fr.shearRatio * 1e4 / mass);
  EXPECT_NEAR(criticalTimeStep(fr, mass, r, false), 2 / wt * (std::sqrt(1 + z * z) - z), 1e-18);
}

}  // namespace physics_material_test
}  // namespace demlab::physics

namespace demlab::physics {
namespace physics_material_test {

TEST(PhysicsMaterial, FormatRealLikeTcl) {
  EXPECT_EQ(formatReal(-1), "-1");
  EXPECT_EQ(formatReal(0.1), "0.1");
  EXPECT_EQ(formatReal(5e6), "5000000");
  EXPECT_EQ(formatReal(1e20), "1e+20");
  EXPECT_EQ(formatReal(1.5e-7), "1.5e-07");
  EXPECT_EQ(formatReal(0.0001), "0.0001");
  EXPECT_EQ(formatReal(-std::numeric_limits<Real>::infinity()), "-Inf");
}

}  // namespace physics_material_test
}  // namespace demlab::physics
