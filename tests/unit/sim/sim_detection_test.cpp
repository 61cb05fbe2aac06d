// Contact detection with a Verlet skin never misses a contact: every step, the contacts the
// loop found are compared with a brute-force test of every pair, in scenes with fast movers
// planted among slow grains, with walls, and after grains are moved by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <utility>

#include "sim/detection.hpp"
#include "sim/simulation.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_detection_test {

using testing::grain;
using testing::material;
using testing::setWatchdog;

// Returns the grain-grain pairs (by handle bits, ordered) that overlap now, by brute force.
std::set<std::pair<uint64_t, uint64_t>> bruteForce(const Simulation& s) {
  const auto x = s.positions();
  const auto r = s.radii();
  const auto ids = s.elementIds();
  const int d = s.dim();
  std::set<std::pair<uint64_t, uint64_t>> out;
  for (size_t i = 0; i < ids.size(); ++i) {
    for (size_t j = i + 1; j < ids.size(); ++j) {
      double d2 = 0;
      for (int k = 0; k < d; ++k)
        d2 += (x[d * i + k] - x[d * j + k]) * (x[d * i + k] - x[d * j + k]);
      const double rs = r[i] + r[j];
      if (d2 < rs * rs) out.emplace(std::minmax(ids[i].bits(), ids[j].bits()));
    }
  }
  return out;
}

std::set<std::pair<uint64_t, uint64_t>> found(const Simulation& s) {
  std::set<std::pair<uint64_t, uint64_t>> out;
  for (const ContactInfo& c : s.contacts()) {
    if (!c.b.isNull()) out.emplace(std::minmax(c.a.bits(), c.b.bits()));
  }
  return out;
}

// Runs 400 steps of fast movers (one in every `every`) among slow grains in a box
// [origin, origin + side]^d and checks every step's contacts against brute force; the number
// of searches in *searches when given. wideMargins: the detection's margins option;
// apart: the grains on a lattice (spacing 16 mm, 3D only), none touching at the start.
void checkFastMoversAreNeverMissed(int d, double origin, int every = 25,
                                   uint64_t* searches = nullptr, bool wideMargins = true,
                                   bool apart = false) {
  auto s = makeSimulation(d);
  s->setOption("detection", "margins", wideMargins);
  MaterialDef m = material(1e6, 0.9, 0.0);
  s->addMaterial("m", m);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  const double side = 0.2;
  std::vector<ElementDef> defs;
  for (int k = 0; k < 300; ++k) {
    Vec3d x{0, 0, 0}, v{0, 0, 0};
    const bool fast = k % every == 0;
    for (int a = 0; a < d; ++a) {
      x[a] = origin + 0.02 + (side - 0.04) * u(rng);
      v[a] = (fast ? 20.0 : 0.05) * (2 * u(rng) - 1);
    }
    if (apart) {
      const int site[3] = {k % 10, (k / 10) % 10, k / 100};
      for (int a = 0; a < d; ++a) x[a] = origin + 0.02 + 0.016 * site[a];
    }
    // A wide spread of sizes, so some pairs are far more than a cell apart when they meet.
    defs.push_back(grain(x, 0.002 + 0.006 * u(rng), "m", v));
  }
  s->addElements(defs);
  for (int k = 0; k < d; ++k) {
    Vec3d n{0, 0, 0}, p{origin, origin, d == 3 ? origin : 0.0};
    n[k] = 1;
    s->addWall(testing::plane(p, n, "m"));
    n[k] = -1;
    p[k] = origin + side;
    s->addWall(testing::plane(p, n, "m"));
  }
  s->setTimeStep(2e-5);  // a fast grain crosses the skin in a few steps
  // The grains are placed at random, up to several radii into each other: a test of the
  // search, not of physics, so the watchdog's overlap checks (which would stop the run before
  // its first step) are off; its other checks stay on.
  WatchdogOptions wd;
  wd.overlap = 0;
  wd.placed = 0;
  setWatchdog(*s, wd);
  uint64_t checked = 0, rebuilds = 0;
  for (int step = 0; step < 400; ++step) {
    rebuilds += s->step().neighborRebuilds;
    const auto truth = bruteForce(*s);
    ASSERT_EQ(found(*s), truth) << "step " << step;
    // Grain-wall contacts: every grain closer to a box face than its radius, once per face.
    size_t wallTruth = 0, wallFound = 0;
    const auto x = s->positions();
    const auto r = s->radii();
    for (size_t i = 0; i < r.size(); ++i) {
      for (int k = 0; k < d; ++k) {
        const double in = x[d * i + k] - origin;
        wallTruth += (in < r[i]) + (side - in < r[i]);
      }
    }
    for (const ContactInfo& c : s->contacts()) wallFound += !c.wall.isNull();
    ASSERT_EQ(wallFound, wallTruth) << "step " << step;
    checked += truth.size();
    if (step == 200) {
      // Grains moved by hand far away: the next step must search anew.
      const auto ids = s->elementIds();
      s->setElementPosition(ids[5], s->element(ids[6]).position);
    }
  }
  EXPECT_GT(checked, apart ? 500u : 1000u);
  EXPECT_LT(rebuilds, 400u);  // the skin does spare searches
  EXPECT_GT(rebuilds, 10u);
  if (searches) *searches = rebuilds;
}

// The grid's float boxes hold their double boxes: rounding is outward, by at most one float.
TEST(SimDetectionBoxes, FloatBoundsRoundOutwardByAtMostOneStep) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> mant(-1, 1);
  std::uniform_int_distribution<int> expo(-160, 140);  // float denormals and overflow too
  const float inf = std::numeric_limits<float>::infinity();
  for (int k = 0; k < 200000; ++k) {
    double v = std::ldexp(mant(rng), expo(rng));
    // Exactly representable: kept as is.
    if (k % 10 == 0 && std::abs(v) <= std::numeric_limits<float>::max()) {
      v = static_cast<float>(v);
    }
    const float lo = floatBelow(v), hi = floatAbove(v);
    ASSERT_LE(static_cast<double>(lo), v) << v;
    ASSERT_GE(static_cast<double>(hi), v) << v;
    ASSERT_GT(static_cast<double>(std::nextafter(lo, inf)), v) << v;
    ASSERT_LT(static_cast<double>(std::nextafter(hi, -inf)), v) << v;
  }
  EXPECT_EQ(floatBelow(0.0), 0.0f);
  EXPECT_EQ(floatAbove(-inf), -inf);
}

class SimDetection : public ::testing::TestWithParam<int> {};

TEST_P(SimDetection, FastMoversAreNeverMissed) {
  checkFastMoversAreNeverMissed(GetParam(), 0.0);
}

// The grid's boxes are floats taken from the domain's corner: 4 km from the origin a float's
// spacing would be 2.4e-4 m, a tenth of the smallest radius.
TEST_P(SimDetection, FastMoversAreNeverMissedFarFromTheOrigin) {
  checkFastMoversAreNeverMissed(GetParam(), 4000.0);
}

// Two fast movers among 298 slow grains: fewer than the quantile the margins are chosen from,
// so their boxes are grown by wide margins (detection.hpp); no contact is missed, and the
// searches are fewer than with half a skin for every grain (the margins option off).
TEST_P(SimDetection, FastMoversWithWideMarginsAreNeverMissed) {
  // In 3D the grains start apart on a lattice: placed at random, their deep overlaps would
  // throw many apart fast in the first steps, more than the quantile. 2D has no room for that.
  const bool apart = GetParam() == 3;
  uint64_t wide = 0, narrow = 0;
  checkFastMoversAreNeverMissed(GetParam(), 0.0, 150, &wide, true, apart);
  checkFastMoversAreNeverMissed(GetParam(), 0.0, 150, &narrow, false, apart);
  std::printf("searches: %llu with wide margins, %llu without\n",
              static_cast<unsigned long long>(wide), static_cast<unsigned long long>(narrow));
  EXPECT_LT(4 * wide, 3 * narrow);
}

INSTANTIATE_TEST_SUITE_P(Dims, SimDetection, ::testing::Values(2, 3),
                         [](const auto& info) { return std::to_string(info.param) + "D"; });

}  // namespace sim_detection_test
}  // namespace demlab::sim
