// The distributed parts on real ranks (ctest runs this program under mpirun on 1, 2 and 3
// ranks): the collectives, the bisection of points spread over the ranks against the one rank's
// bisection of all of them, the migration of elements to their owners, and the ghosts against
// brute force over the whole scene (every rank makes the same scene from one seed and keeps its
// share, so each can check its own result against all of it).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <random>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <mpi.h>

#include "mpi/communicator.hpp"
#include "mpi/ghost_plan.hpp"
#include "mpi/partition.hpp"
#include "mpi/reach.hpp"
#include "mpi/records.hpp"

namespace demlab::mpi {
namespace {

const Communicator& world() { return Communicator::world(); }

// A grain as the ranks send it.
struct Grain {
  int64_t id;
  Point<3> x;
  double r;
  double payload;  // a value only the id determines, to check nothing is mixed up
};

double payloadOf(int64_t id) { return std::sqrt(static_cast<double>(id) + 0.5); }

// The whole scene (the same on every rank): a bed in the bottom third of a box, radii 1:4,
// a few large grains.
std::vector<Grain> scene(size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Grain> g(n);
  for (size_t i = 0; i < n; ++i) {
    g[i].id = static_cast<int64_t>(i);
    g[i].x = {u(rng), u(rng), u(rng) / 3};
    g[i].r = i % 500 == 7 ? 0.05 : 0.002 * (1 + 3 * u(rng));
    g[i].payload = payloadOf(g[i].id);
  }
  return g;
}

// This rank's part of a scene as a search leaves it: every rank starts with every P-th grain,
// the ranks bisect their centres, and this rank keeps the grains its box holds (with their
// centres and radii apart, as the reach table takes them).
struct Share {
  Partition<3> part;
  std::vector<Grain> owned;
  std::vector<Point<3>> x;
  std::vector<double> r;
};

Share shareOf(const std::vector<Grain>& all, const Communicator& c) {
  std::vector<Point<3>> start;
  for (const Grain& g : all) {
    if (g.id % c.size() == c.rank()) start.push_back(g.x);
  }
  Share s{Partition<3>::bisect(start, {}, c.size(), c), {}, {}, {}};
  for (const Grain& g : all) {
    if (s.part.ownerOf(g.x) != c.rank()) continue;
    s.owned.push_back(g);
    s.x.push_back(g.x);
    s.r.push_back(g.r);
  }
  return s;
}

TEST(Ranks, SumsAreTakenInRankOrderAndAgreeEverywhere) {
  const Communicator& c = world();
  // Values whose sum depends on the order of addition.
  const double mine = c.rank() % 2 ? 1e16 : 1.0 + c.rank();
  const std::vector<double> all = c.gather({mine});
  ASSERT_EQ(all.size(), static_cast<size_t>(c.size()));
  double expect = all[0];
  for (size_t k = 1; k < all.size(); ++k) expect += all[k];
  const double got = c.sum(mine);
  EXPECT_EQ(got, expect);
  EXPECT_EQ(c.max(mine), *std::max_element(all.begin(), all.end()));
  EXPECT_EQ(c.min(mine), *std::min_element(all.begin(), all.end()));
  EXPECT_EQ(c.sum(int64_t{c.rank() + 1}), int64_t{c.size()} * (c.size() + 1) / 2);
  // Every rank holds the same bits of the sum.
  EXPECT_EQ(c.max(got), c.min(got));
}

// idleBarrier holds every rank until the last has come: rank 0 comes 50 ms late, and no rank
// leaves before it came (the ranks share one machine, so one clock: system_clock).
TEST(Ranks, IdleBarrierWaitsForTheLastRank) {
  const Communicator& c = world();
  using Clock = std::chrono::system_clock;
  const auto micros = [](Clock::time_point t) {
    return static_cast<double>(std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count());
  };
  double came = 0;
  if (c.rank() == 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    came = micros(Clock::now());
  }
  c.idleBarrier();
  const double left = micros(Clock::now());
  const double last = c.max(came);  // rank 0's arrival, known everywhere
  EXPECT_GE(left, last) << "rank " << c.rank() << " left the barrier before rank 0 came";
}

TEST(Ranks, TheBisectionOfSpreadPointsIsTheBisectionOfAllOfThem) {
  const Communicator& c = world();
  const auto all = scene(20000, 3);
  std::vector<Point<3>> everything, mine;
  for (size_t i = 0; i < all.size(); ++i) {
    everything.push_back(all[i].x);
    if (static_cast<int>(i % static_cast<size_t>(c.size())) == c.rank()) mine.push_back(all[i].x);
  }
  // Weights: a cost per grain that only its id determines.
  std::vector<double> weightsAll, weightsMine;
  for (size_t i = 0; i < all.size(); ++i) {
    weightsAll.push_back(1 + std::fmod(0.618 * static_cast<double>(i), 7.0));
    if (static_cast<int>(i % static_cast<size_t>(c.size())) == c.rank()) {
      weightsMine.push_back(weightsAll.back());
    }
  }
  for (const bool weighted : {false, true}) {
    for (int parts : {c.size(), 2 * c.size() + 1}) {
      const Partition<3> spread =
          Partition<3>::bisect(mine, weighted ? weightsMine : std::vector<double>{}, parts, c);
      const Partition<3> one = Partition<3>::bisect(
          everything, weighted ? weightsAll : std::vector<double>{}, parts, Communicator::self());
      EXPECT_EQ(spread.parts(), one.parts());
      for (int k = 0; k < std::min(parts, one.parts()); ++k) {
        EXPECT_TRUE(spread.box(k) == one.box(k)) << k << (weighted ? " weighted" : "");
      }
    }
  }
}

// Every rank starts with a share that has nothing to do with the space (by id), sends each grain
// to the owner of its box, and must end with exactly the grains its box holds, each once, intact.
TEST(Ranks, MigrationDeliversEachGrainToItsOwnerOnce) {
  const Communicator& c = world();
  const auto all = scene(15000, 5);
  std::vector<Grain> mine;
  std::vector<Point<3>> centres;
  for (const Grain& g : all) {
    if (g.id % c.size() == c.rank()) {
      mine.push_back(g);
      centres.push_back(g.x);
    }
  }
  const Partition<3> part = Partition<3>::bisect(centres, {}, c.size(), c);
  std::vector<std::vector<Grain>> out(static_cast<size_t>(c.size()));
  for (const Grain& g : mine) out[static_cast<size_t>(part.ownerOf(g.x))].push_back(g);
  const std::vector<Grain> owned = exchangeRecords(c, out);
  std::vector<int64_t> want;
  for (const Grain& g : all) {
    if (part.box(c.rank()).contains(g.x)) want.push_back(g.id);
  }
  std::vector<int64_t> got;
  for (const Grain& g : owned) {
    got.push_back(g.id);
    EXPECT_EQ(g.payload, payloadOf(g.id));
    EXPECT_EQ(g.x, all[static_cast<size_t>(g.id)].x);
  }
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, want);
  EXPECT_EQ(c.sum(static_cast<int64_t>(owned.size())), static_cast<int64_t>(all.size()));
  // Balanced on count: the bed's cuts go through it.
  const std::vector<double> counts = c.gather({static_cast<double>(owned.size())});
  EXPECT_LT(Partition<3>::imbalance(counts), 1.01);
}

// After migration, each rank sends its grains as ghosts to the ranks the reach table names; a
// rank must then hold, owned or as a ghost, every grain that comes within the skin of one of
// its own (brute force over the whole scene), and never a ghost of its own grain.
TEST(Ranks, GhostsCoverEveryPairInReach) {
  const Communicator& c = world();
  const double skin = 0.001;
  const auto all = scene(6000, 9);
  const Share share = shareOf(all, c);
  const std::vector<Grain>& owned = share.owned;
  const ReachTable<3> table = ReachTable<3>::gather(share.x, share.r, c);
  std::vector<std::vector<Grain>> out(static_cast<size_t>(c.size()));
  for (const Grain& g : owned) {
    table.forEachRankNeeding(g.x, g.r, skin, c.rank(),
                             [&](int k) { out[static_cast<size_t>(k)].push_back(g); });
  }
  const std::vector<Grain> ghosts = exchangeRecords(c, out);
  std::vector<char> held(all.size(), 0);
  for (const Grain& g : owned) held[static_cast<size_t>(g.id)] = 1;
  for (const Grain& g : ghosts) {
    EXPECT_EQ(held[static_cast<size_t>(g.id)], 0) << "a ghost of an owned grain, or twice";
    held[static_cast<size_t>(g.id)] = 2;
    EXPECT_EQ(g.payload, payloadOf(g.id));
  }
  size_t pairs = 0, missing = 0;
  for (const Grain& a : owned) {
    for (const Grain& b : all) {
      if (b.id == a.id) continue;
      double d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += (a.x[k] - b.x[k]) * (a.x[k] - b.x[k]);
      const double reach = a.r + b.r + skin;
      if (d2 < reach * reach) {
        ++pairs;
        missing += held[static_cast<size_t>(b.id)] == 0;
      }
    }
  }
  EXPECT_EQ(missing, 0u);
  EXPECT_GT(c.sum(static_cast<int64_t>(pairs)), 0);
  const int64_t sent = c.sum(static_cast<int64_t>(ghosts.size()));
  if (c.size() > 1) {
    EXPECT_GT(sent, 0);
  }
}

// The plan made at a search sends the owners' states every step: the ghosts a rank receives are
// exactly the grains the reach table gives it (computed here from the whole scene), and after
// each step's moves every ghost holds its owner's new position, in the same place every step.
TEST(Ranks, TheGhostPlanSendsTheOwnersStatesEveryStep) {
  const Communicator& c = world();
  const double skin = 0.001;
  const auto all = scene(8000, 13);
  Share share = shareOf(all, c);
  const Partition<3>& part = share.part;
  std::vector<Point<3>>& x = share.x;
  const std::vector<double>& r = share.r;
  std::vector<int64_t> ids;
  for (const Grain& g : share.owned) ids.push_back(g.id);
  const ReachTable<3> table = ReachTable<3>::gather(x, r, c);
  const GhostPlan<3> plan = GhostPlan<3>::make(table, x, r, skin, c);
  // The ghosts this rank should get: every other rank's grains the table sends here.
  std::vector<int64_t> want;
  for (const Grain& g : all) {
    const int owner = part.ownerOf(g.x);
    if (owner == c.rank()) continue;
    bool here = false;
    table.forEachRankNeeding(g.x, g.r, skin, owner, [&](int k) { here |= k == c.rank(); });
    if (here) want.push_back(g.id);
  }
  std::vector<int64_t> ghostIds;
  plan.forward(ids, c, ghostIds);
  std::vector<int64_t> got = ghostIds;
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, want);
  EXPECT_EQ(plan.ghosts(), want.size());
  EXPECT_EQ(c.sum(static_cast<int64_t>(plan.sent())), c.sum(static_cast<int64_t>(plan.ghosts())));
  if (c.size() > 1) {
    EXPECT_FALSE(plan.receiveRanks().empty());
  }
  // Three steps: every grain moves by a function of its id and the step.
  const auto moved = [](int64_t id, int step, const Point<3>& p) {
    Point<3> q = p;
    for (int k = 0; k < 3; ++k) q[k] += 1e-5 * std::sin(0.37 * id + 1.3 * step + k);
    return q;
  };
  std::vector<Point<3>> ghostX;
  for (int step = 1; step <= 3; ++step) {
    for (size_t i = 0; i < x.size(); ++i) x[i] = moved(ids[i], step, x[i]);
    plan.forward(x, c, ghostX);
    size_t wrong = ghostX.size() == ghostIds.size() ? 0 : 1;
    for (size_t g = 0; g < ghostX.size() && g < ghostIds.size(); ++g) {
      Point<3> p = all[static_cast<size_t>(ghostIds[g])].x;
      for (int s = 1; s <= step; ++s) p = moved(ghostIds[g], s, p);
      wrong += ghostX[g] != p;
    }
    EXPECT_EQ(wrong, 0u) << "step " << step;
  }
}

}  // namespace
}  // namespace demlab::mpi
