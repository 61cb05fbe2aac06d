// The ghost reach (mpi/reach.hpp) against brute force, with the ranks simulated on one: every
// pair of elements whose bounding spheres come within the skin and whose owners differ must be
// ghosted both ways, and a large element must bring onto its rank only the elements within its
// own reach, not everything within its radius of the rank's box.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "mpi/partition.hpp"
#include "mpi/reach.hpp"

namespace demlab::mpi {
namespace mpi_reach_test {

struct Scene {
  std::vector<Point<3>> centres;
  std::vector<double> radii;
};

// Grains of radii spread 1:30 in the unit cube, plus `big` large ones (radius 0.25) with no
// grain inside them.
Scene randomScene(size_t n, unsigned seed, int big) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), e(0, 1);
  Scene s;
  for (int b = 0; b < big; ++b) {
    s.centres.push_back({0.3 + 0.4 * u(rng), 0.3 + 0.4 * u(rng), 0.3 + 0.4 * u(rng)});
    s.radii.push_back(0.25);
  }
  while (s.centres.size() < n + static_cast<size_t>(big)) {
    const Point<3> c{u(rng), u(rng), u(rng)};
    bool inside = false;
    for (int b = 0; b < big; ++b) {
      double d2 = 0;
      for (int a = 0; a < 3; ++a) d2 += (c[a] - s.centres[b][a]) * (c[a] - s.centres[b][a]);
      inside |= d2 < 0.25 * 0.25;
    }
    if (inside) continue;
    s.centres.push_back(c);
    s.radii.push_back(0.001 * std::pow(30.0, e(rng)));
  }
  return s;
}

double distance(const Point<3>& a, const Point<3>& b) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(d2);
}

// The partition, each element's owner and the table the ranks would gather.
struct Split {
  Partition<3> part;
  std::vector<int> owner;
  ReachTable<3> table;
};

Split split(const Scene& s, int parts) {
  Split out{Partition<3>::bisect(s.centres, {}, parts, Communicator::self()), {}, {}};
  std::vector<std::vector<Point<3>>> c(static_cast<size_t>(parts));
  std::vector<std::vector<double>> r(static_cast<size_t>(parts));
  for (size_t i = 0; i < s.centres.size(); ++i) {
    out.owner.push_back(out.part.ownerOf(s.centres[i]));
    c[static_cast<size_t>(out.owner[i])].push_back(s.centres[i]);
    r[static_cast<size_t>(out.owner[i])].push_back(s.radii[i]);
  }
  std::vector<std::vector<ReachTable<3>::Class>> classes;
  for (int k = 0; k < parts; ++k) {
    classes.push_back(ReachTable<3>::classesOf(c[static_cast<size_t>(k)], r[static_cast<size_t>(k)]));
  }
  out.table = ReachTable<3>::of(classes);
  return out;
}

// ghosts[k]: the elements ghosted on rank k.
std::vector<std::vector<size_t>> ghostsOf(const Scene& s, const Split& sp, double skin, int parts) {
  std::vector<std::vector<size_t>> ghosts(static_cast<size_t>(parts));
  for (size_t i = 0; i < s.centres.size(); ++i) {
    sp.table.forEachRankNeeding(s.centres[i], s.radii[i], skin, sp.owner[i],
                                [&](int k) { ghosts[static_cast<size_t>(k)].push_back(i); });
  }
  return ghosts;
}

TEST(ReachTable, EveryPairInReachIsGhostedBothWays) {
  const double skin = 0.002;
  for (int parts : {2, 3, 5, 8}) {
    for (int big : {0, 1, 2}) {
      SCOPED_TRACE("parts " + std::to_string(parts) + " big " + std::to_string(big));
      const Scene s = randomScene(3000, 17 + parts + big, big);
      const Split sp = split(s, parts);
      const auto ghosts = ghostsOf(s, sp, skin, parts);
      auto has = [&](int k, size_t i) {
        const auto& g = ghosts[static_cast<size_t>(k)];
        return std::find(g.begin(), g.end(), i) != g.end();
      };
      size_t cross = 0;
      for (size_t i = 0; i < s.centres.size(); ++i) {
        for (size_t j = i + 1; j < s.centres.size(); ++j) {
          if (sp.owner[i] == sp.owner[j]) continue;
          if (!(distance(s.centres[i], s.centres[j]) < s.radii[i] + s.radii[j] + skin)) continue;
          ++cross;
          ASSERT_TRUE(has(sp.owner[j], i)) << i << " " << j;
          ASSERT_TRUE(has(sp.owner[i], j)) << i << " " << j;
        }
      }
      EXPECT_GT(cross, 0u);
      // No element is its own owner's ghost.
      for (int k = 0; k < parts; ++k) {
        for (size_t i : ghosts[static_cast<size_t>(k)]) EXPECT_NE(sp.owner[i], k);
      }
    }
  }
}

// Two large elements among fine grains: with one reach per rank (its largest radius) every
// grain within a large radius of a large element's rank would be copied there. By size class
// the ghosts are the fine grains' boundary layers (within a fine grain's reach of another
// rank's box) and, near a large element, only the grains within its own reach: never more,
// and several times fewer than one reach per rank.
TEST(ReachTable, ALargeElementBringsOnlyWhatItReaches) {
  const double skin = 0.002;
  const int parts = 4;
  const Scene s = randomScene(4000, 3, 2);
  const Split sp = split(s, parts);
  const auto ghosts = ghostsOf(s, sp, skin, parts);
  size_t ours = 0, bound = 0, perRank = 0;
  for (const auto& g : ghosts) ours += g.size();
  std::vector<double> rMax(parts, 0.0), rFine(parts, 0.0);
  for (size_t i = 0; i < s.centres.size(); ++i) {
    double& m = rMax[static_cast<size_t>(sp.owner[i])];
    m = std::max(m, s.radii[i]);
    if (s.radii[i] < 0.25) {
      double& f = rFine[static_cast<size_t>(sp.owner[i])];
      f = std::max(f, s.radii[i]);
    }
  }
  for (size_t i = 0; i < s.centres.size(); ++i) {
    for (int k = 0; k < parts; ++k) {
      if (k == sp.owner[i]) continue;
      const double fine = s.radii[i] + rFine[static_cast<size_t>(k)] + skin;
      bool near = sp.part.box(k).distance2(s.centres[i]) < fine * fine;
      for (size_t b = 0; b < 2; ++b) {  // the large elements are the first two
        near |= sp.owner[b] == k && b != i &&
                distance(s.centres[i], s.centres[b]) < s.radii[i] + s.radii[b] + skin;
      }
      bound += near;
      const double reach = s.radii[i] + rMax[static_cast<size_t>(k)] + skin;
      perRank += sp.part.box(k).distance2(s.centres[i]) < reach * reach;
    }
  }
  EXPECT_GT(ours, 0u);
  EXPECT_LE(ours, bound);
  EXPECT_GT(perRank, 3 * ours);
}

TEST(ReachTable, BadElementsAreRefused) {
  const std::vector<Point<3>> c{{0, 0, 0}, {1, 1, 1}};
  EXPECT_THROW(ReachTable<3>::gather(c, {1.0}, Communicator::self()), std::invalid_argument);
  EXPECT_THROW(ReachTable<3>::gather(c, {1.0, -1.0}, Communicator::self()), std::invalid_argument);
  EXPECT_THROW(ReachTable<3>::gather({{0, 0, 0}, {std::nan(""), 0, 0}}, {1.0, 1.0},
                                     Communicator::self()),
               std::invalid_argument);
  EXPECT_THROW(ReachTable<3>::of({}), std::invalid_argument);
  // A table of one rank sends nothing anywhere.
  const ReachTable<3> one = ReachTable<3>::gather(c, {1.0, 2.0}, Communicator::self());
  int calls = 0;
  one.forEachRankNeeding({0, 0, 0}, 1.0, 0.1, 0, [&](int) { ++calls; });
  EXPECT_EQ(calls, 0);
}

}  // namespace mpi_reach_test
}  // namespace demlab::mpi
