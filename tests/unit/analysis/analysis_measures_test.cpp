// The stress, coordination, fabric and motion of small hand-made samples, against hand counts.
#include <gtest/gtest.h>

#include "analysis/coarse_grain.hpp"
#include "analysis/motion.hpp"
#include "analysis/stress.hpp"
#include "analysis/structure.hpp"

namespace demlab::analysis {
namespace analysis_measures_test {

// Two balls of radius 1 touching on the x axis, pressed together by 5 N, the first also on a
// wall below it (force 2 N down on the wall).
Sample pairOnAWall() {
  Sample s;
  s.dim = 3;
  s.ids.resize(2);
  s.position = {{0, 0, 1}, {2, 0, 1}};
  s.velocity = {{1, 0, 0}, {-1, 0, 0}};
  s.radius = {1, 1};
  s.mass = {2, 2};
  s.volume = {4.18879, 4.18879};
  s.ball = {1, 1};
  s.contacts.push_back({0, 1, -1, {1, 0, 1}, {1, 0, 0}, {5, 0, 0}});
  s.contacts.push_back({0, -1, 0, {0, 0, 0}, {0, 0, -1}, {0, 0, -2}});
  return s;
}

TEST(AnalysisMeasures, StressOfAPairAndAWallContact) {
  const Sample s = pairOnAWall();
  StressResult st = loveWeberStress(s, Selection{}, 10);
  // Pair: f (x) l = 5 x 2 on xx; wall: f_w (x) (x_c - x_a) = (-2)(-1) on zz; compression > 0.
  EXPECT_NEAR(st.contact[0], 1.0, 1e-15);
  EXPECT_NEAR(st.contact[8], 0.2, 1e-15);
  // Kinetic: mean velocity 0, sum m v v = 2 + 2 on xx.
  EXPECT_NEAR(st.kinetic[0], 0.4, 1e-15);
  // A region holding half of the pair's branch and the whole wall arm.
  Selection half;
  Region r;
  r.lo = {-1, -1, -1}, r.hi = {1, 1, 3};
  half.region = r;
  st = loveWeberStress(s, half, 10);
  EXPECT_NEAR(st.contact[0], 0.5, 1e-15);
  EXPECT_NEAR(st.contact[8], 0.2, 1e-15);
}

TEST(AnalysisMeasures, CoordinationAndFabric) {
  const Sample s = pairOnAWall();
  Coordination z = coordination(s, Selection{}, false);
  EXPECT_EQ(z.ends, 2u);
  EXPECT_EQ(z.rattlers1, 2u);
  EXPECT_DOUBLE_EQ(z.plain, 1);
  EXPECT_DOUBLE_EQ(z.mechanical, 0);
  z = coordination(s, Selection{}, true);
  EXPECT_EQ(z.ends, 3u);
  EXPECT_DOUBLE_EQ(z.mechanical, 2);  // (3 - 1) / (2 - 0 - 1)
  Fabric f = fabric(s, Selection{}, true);
  EXPECT_DOUBLE_EQ(f.contacts, 2);
  EXPECT_DOUBLE_EQ(f.tensor[0], 0.5);
  EXPECT_DOUBLE_EQ(f.tensor[8], 0.5);
}

TEST(AnalysisMeasures, TemperatureIsTheVelocityVarianceOfEqualElements) {
  const Sample s = pairOnAWall();
  MotionResult m = meanMotion(s, Selection{});
  EXPECT_DOUBLE_EQ(m.velocity[0], 0);
  EXPECT_DOUBLE_EQ(m.temperature, 1.0 / 3.0);  // (1/(3 x 2)) (2 + 2) / 2
  EXPECT_DOUBLE_EQ(m.fluctuationEnergy, 2);
}

TEST(AnalysisMeasures, CoarseGrainedContactStressIntegratesToTheLoveWeberSum) {
  const Sample s = pairOnAWall();
  for (CgKernel k : {CgKernel::Gaussian, CgKernel::Lucy}) {
    CgSpec spec;
    spec.kernel = k;
    spec.width = 0.5;
    spec.spacing = 0.1;
    spec.lo = {-3, -3, -2}, spec.hi = {5, 3, 4};
    CgField f = coarseGrain(s, Selection{}, spec);
    double mass = 0, sxx = 0, cell = 1e-3;
    for (double x : f.find("density")->values) mass += x * cell;
    const auto& sc = f.find("contactStress")->values;
    for (size_t p = 0; p < f.points(); ++p) sxx += sc[9 * p] * cell;
    // The grid sum of the kernel is not its integral: within 0.1 % at spacing w / 5 (the
    // Gaussian's cut at 3w is a step of 1 % of its peak).
    EXPECT_NEAR(mass, 4, 4e-3);
    EXPECT_NEAR(sxx, 10, 1e-2);
  }
}

}  // namespace analysis_measures_test
}  // namespace demlab::analysis
