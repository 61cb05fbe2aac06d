// Sources and sinks through the public API, in both dimensions: the mass rate, the sizes drawn
// (Kolmogorov-Smirnov against SizeDistribution::cdf), the sink counters against a brute-force
// count, and failing calls that change nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "sim/boundaries.hpp"
#include "sim/simulation.hpp"
#include "sim/source.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_boundaries_test {

using testing::material;
using testing::up;

// Returns the Kolmogorov-Smirnov statistic of sample against dist.
double ksStatistic(std::vector<double> sample, const SizeDistribution& dist) {
  std::sort(sample.begin(), sample.end());
  const double n = static_cast<double>(sample.size());
  double d = 0;
  for (size_t k = 0; k < sample.size(); ++k) {
    const double f = dist.cdf(sample[k]);
    d = std::max({d, std::abs((k + 1) / n - f), std::abs(k / n - f)});
  }
  return d;
}

TEST(SimBoundaries, DrawnRadiiFollowEveryDistribution) {
  const std::vector<SizeDistribution> dists{{"uniform", {1, 2}},
                                            {"normal", {1, 0.2}},
                                            {"powerlaw", {1, 3, -2.5}},
                                            {"powerlaw", {1, 3, -1}}};
  for (const SizeDistribution& d : dists) {
    uint64_t state = 42;
    SplitMix64 rng{state};
    std::vector<double> r;
    for (int k = 0; k < 4000; ++k) r.push_back(d.draw(rng));
    // The 1% critical value of the one-sample test, 1.63 / sqrt(n).
    EXPECT_LT(ksStatistic(r, d), 1.63 / std::sqrt(4000.0)) << d.kind;
  }
  // A discrete distribution: the frequencies within 3 standard deviations.
  const SizeDistribution disc{"discrete", {1, 1, 2, 3}};
  uint64_t state = 9;
  SplitMix64 rng{state};
  int ones = 0;
  for (int k = 0; k < 4000; ++k) ones += disc.draw(rng) == 1;
  EXPECT_LT(std::abs(ones - 1000), 3 * std::sqrt(4000 * 0.25 * 0.75));
}

class SimBoundariesDim : public ::testing::TestWithParam<int> {};

TEST_P(SimBoundariesDim, SourceKeepsItsMassRateAndSinkCountsWhatLeaves) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("m", material(1e6, 0.5, 0.3));
  Vec3d g{0, 0, 0};
  g[static_cast<size_t>(up(d))] = -9.81;
  s->addGravity(g);
  SourceDef src;
  src.name = "feed";
  src.region.lo = {-0.02, 0.04, 0};
  src.region.hi = {0.02, 0.08, 0};
  if (d == 3) {
    src.region.lo = {-0.02, -0.02, 0.04};
    src.region.hi = {0.02, 0.02, 0.08};
  }
  src.size = {"uniform", {0.001, 0.0015}};
  src.material = "m";
  src.massRate = d == 3 ? 0.05 : 20.0;  // 2D: kg/s per metre of depth
  src.seed = 3;
  s->addSource(src);
  SinkDef out;
  out.name = "out";
  out.kind = SinkDef::Plane;
  out.normal[static_cast<size_t>(up(d))] = 1;
  s->addSink(out);
  const RunReport r = s->runTime(0.12);
  ASSERT_GT(r.steps, 0u);
  // Enough elements that one (the most the source can be ahead) is well under 1% of the mass.
  EXPECT_GT(s->sources()[0].count, 150u);
  const BoundaryInfo in = s->sources()[0];
  const BoundaryInfo gone = s->sinks()[0];
  EXPECT_NEAR(in.mass / (src.massRate * s->time()), 1, 0.01);
  EXPECT_GT(gone.count, 10u);
  EXPECT_EQ(in.count - gone.count, s->elementCount());
  // What is left holds what came in less what went out.
  double held = 0;
  for (ElementId id : s->elementIds()) held += s->element(id).mass;
  EXPECT_NEAR(held, in.mass - gone.mass, 1e-12 * in.mass);
  for (double x : s->positions()) EXPECT_TRUE(std::isfinite(x));
  EXPECT_LT(s->energy().residual, 1e-3);
}

TEST_P(SimBoundariesDim, BadDefsChangeNothing) {
  const int d = GetParam();
  auto s = makeSimulation(d);
  s->addMaterial("m", material(1e6, 0.5, 0.3));
  SourceDef ok;
  ok.name = "a";
  ok.region.hi = {1, 1, d == 3 ? 1.0 : 0.0};
  ok.size = {"constant", {0.01}};
  ok.material = "m";
  ok.countRate = 1;
  const uint64_t before = s->stateDigest();
  auto expectCode = [&](SourceDef def, const std::string& code) {
    EXPECT_EQ(testing::codeOf([&] { s->addSource(def); }).back(), code);
    EXPECT_EQ(s->stateDigest(), before);
  };
  SourceDef b = ok;
  b.countRate = std::nan("");
  expectCode(b, "RATE");
  b = ok;
  b.massRate = 1;
  expectCode(b, "RATE");
  b = ok;
  b.targetMass = -1;
  expectCode(b, "TARGET");
  b = ok;
  b.region.hi[0] = 0.01;
  expectCode(b, "REGION");
  b = ok;
  b.size = {"normal", {0.01, 0.01}};
  expectCode(b, "RADIUS");
  b = ok;
  b.jitter = -1;
  expectCode(b, "JITTER");
  b = ok;
  b.name = "";
  expectCode(b, "NAME");
  SinkDef k;
  k.name = "k";
  k.kind = SinkDef::Plane;
  EXPECT_EQ(testing::codeOf([&] { s->addSink(k); }).back(), "NORMAL");
  EXPECT_EQ(s->stateDigest(), before);
}

INSTANTIATE_TEST_SUITE_P(Dims, SimBoundariesDim, ::testing::Values(2, 3),
                         [](const auto& info) { return std::to_string(info.param) + "D"; });

}  // namespace sim_boundaries_test
}  // namespace demlab::sim
