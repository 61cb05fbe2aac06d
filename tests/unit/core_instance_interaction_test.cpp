#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "core/instance_interaction.hpp"

namespace demlab {
namespace core_instance_interaction_test {

// A stand-in for a tangential spring: its value and how many steps the contact has lasted.
struct Spring {
  double shear = 0;
  int steps = 0;
  friend bool operator==(const Spring&, const Spring&) = default;
};

using Manager = InstanceInteractionManager<Spring>;
using Pair = Manager::Pair;

TEST(InstanceInteractionManager, TouchInsertsOnceAndKeepsState) {
  Manager m;
  auto t = m.touch(3, 9);
  EXPECT_TRUE(t.inserted);
  EXPECT_EQ(t.state, Spring{});
  t.state.shear = 1.5;
  auto u = m.touch(3, 9);
  EXPECT_FALSE(u.inserted);
  EXPECT_EQ(u.state.shear, 1.5);
  EXPECT_EQ(m.size(), 1u);
  EXPECT_EQ(m.find(9, 3), nullptr);  // (9, 3) is another pair: keys are ordered as given
  ASSERT_NE(m.find(3, 9), nullptr);
  EXPECT_EQ(m.find(3, 9)->shear, 1.5);
  EXPECT_TRUE(m.erase(3, 9));
  EXPECT_FALSE(m.erase(3, 9));
  EXPECT_TRUE(m.empty());
}

TEST(InstanceInteractionManager, SweepDropsTheContactsThatOpened) {
  Manager m;
  m.touch(0, 1).state.shear = 1;
  m.touch(0, 2).state.shear = 2;
  m.touch(1, 2).state.shear = 3;
  EXPECT_EQ(m.sweep(), 0u);  // all touched in this step
  m.touch(0, 2);             // next step: only (0,2) and a new pair are in contact
  m.touch(2, 5).state.shear = 4;
  std::vector<std::pair<Pair, double>> dropped;
  EXPECT_EQ(m.sweep([&](const Pair& p, Spring& s) { dropped.push_back({p, s.shear}); }), 2u);
  std::sort(dropped.begin(), dropped.end());
  EXPECT_EQ(dropped, (std::vector<std::pair<Pair, double>>{{{0, 1}, 1.0}, {{1, 2}, 3.0}}));
  EXPECT_EQ(m.size(), 2u);
  EXPECT_EQ(m.find(0, 2)->shear, 2);
  EXPECT_EQ(m.find(2, 5)->shear, 4);
  EXPECT_EQ(m.sweep(), 2u);  // a step with no contacts at all
  EXPECT_TRUE(m.empty());
}

TEST(InstanceInteractionManager, RemoveIdDropsEveryPairOfAnObject) {
  Manager m;
  for (uint32_t i = 0; i < 10; ++i) {
    m.touch(i, 7);
    m.touch(7, i + 20);
    m.touch(i + 50, i + 100);
  }
  EXPECT_EQ(m.removeId(7), 20u);
  EXPECT_EQ(m.size(), 10u);
  m.forEach([](const Pair& p, Spring&) {
    EXPECT_NE(p.first, 7u);
    EXPECT_NE(p.second, 7u);
  });
}

// Replays a random DEM-like sequence on the manager and on a std::map oracle: each step, most
// contacts persist, some open, some new ones close, with occasional erases, removals of
// objects and lookups. ids bounds the id range (small ranges make long probe runs).
void replayAgainstMap(uint32_t ids, int steps, unsigned seed) {
  Manager m;
  std::map<Pair, Spring> oracle;
  std::mt19937 rng(seed);
  std::vector<Pair> active;
  for (int step = 0; step < steps; ++step) {
    std::vector<Pair> next;
    for (const Pair& p : active) {
      if (rng() % 10 != 0) next.push_back(p);  // 90% of contacts persist
    }
    for (int k = 0, n = static_cast<int>(rng() % 40); k < n; ++k) {
      const auto a = static_cast<uint32_t>(rng() % ids), b = static_cast<uint32_t>(rng() % ids);
      if (a == b) continue;
      next.push_back({std::min(a, b), std::max(a, b)});
    }
    std::map<Pair, bool> touched;
    for (const Pair& p : next) {
      auto [it, isNew] = oracle.try_emplace(p);
      const bool firstTouch = touched.emplace(p, true).second;
      auto t = m.touch(p.first, p.second);
      ASSERT_EQ(t.inserted, isNew);
      ASSERT_EQ(t.state, it->second);
      t.state.shear += 0.25 * p.second;
      t.state.steps += firstTouch;
      it->second = t.state;
    }
    if (rng() % 5 == 0 && !oracle.empty()) {  // erase a pair outright (a bond broken)
      auto it = oracle.begin();
      std::advance(it, rng() % oracle.size());
      ASSERT_TRUE(m.erase(it->first.first, it->first.second));
      touched.erase(it->first);
      oracle.erase(it);
    }
    if (rng() % 17 == 0) {  // an object removed
      const uint32_t id = rng() % ids;
      size_t expect = std::erase_if(
          oracle, [&](const auto& kv) { return kv.first.first == id || kv.first.second == id; });
      std::erase_if(touched,
                    [&](const auto& kv) { return kv.first.first == id || kv.first.second == id; });
      ASSERT_EQ(m.removeId(id), expect);
    }
    for (int k = 0; k < 10; ++k) {  // lookups that must not mark anything
      const Pair q{static_cast<uint32_t>(rng() % ids), static_cast<uint32_t>(rng() % ids)};
      const auto it = oracle.find(q);
      const Spring* s = m.find(q.first, q.second);
      ASSERT_EQ(s != nullptr, it != oracle.end());
      if (s) {
        ASSERT_EQ(*s, it->second);
      }
    }
    std::map<Pair, Spring> dropped;
    m.sweep([&](const Pair& p, Spring& s) { ASSERT_TRUE(dropped.emplace(p, s).second); });
    std::map<Pair, Spring> expectDropped;
    std::erase_if(oracle, [&](const auto& kv) {
      if (touched.contains(kv.first)) return false;
      expectDropped.insert(kv);
      return true;
    });
    ASSERT_EQ(dropped, expectDropped) << "step " << step;
    ASSERT_EQ(m.size(), oracle.size());
    std::map<Pair, Spring> held;
    m.forEach([&](const Pair& p, Spring& s) { held.emplace(p, s); });
    ASSERT_EQ(held, oracle) << "step " << step;
    active.clear();
    for (const auto& [p, s] : oracle) active.push_back(p);
  }
}

TEST(InstanceInteractionManager, MatchesStdMapWithFewIds) {
  replayAgainstMap(12, 3000, 1);
}
TEST(InstanceInteractionManager, MatchesStdMapWithManyIds) {
  replayAgainstMap(5000, 3000, 2);
}
TEST(InstanceInteractionManager, MatchesStdMapWithHugeIds) {
  replayAgainstMap(0xFFFFFFFEu, 1500, 3);
}

TEST(InstanceInteractionManager, SteadyStateAllocatesNothing) {
  // A bed of 2000 grains where each step 5% of the contacts open and as many close.
  Manager m;
  std::mt19937 rng(11);
  std::vector<Pair> contacts;
  auto fresh = [&] {
    const uint32_t a = rng() % 2000;
    return Pair{a, a + 1 + static_cast<uint32_t>(rng() % 30)};
  };
  for (int i = 0; i < 6000; ++i) contacts.push_back(fresh());
  size_t bytes = 0;
  for (int step = 0; step < 2000; ++step) {
    for (Pair& p : contacts) {
      if (rng() % 20 == 0) p = fresh();
    }
    for (size_t i = 0; i < contacts.size(); ++i) {
      if (i + 8 < contacts.size()) m.prefetch(contacts[i + 8].first, contacts[i + 8].second);
      m.touch(contacts[i].first, contacts[i].second).state.steps++;
    }
    m.sweep();
    if (step == 200) bytes = m.memoryBytes();  // warm: peak size reached
    if (step > 200) {
      ASSERT_EQ(m.memoryBytes(), bytes) << "step " << step;
    }
  }
  EXPECT_LE(m.size(), contacts.size());
  EXPECT_GT(m.size(), contacts.size() * 9 / 10);
}

TEST(InstanceInteractionManager, GrowsAndReservesWithoutLosingPairs) {
  Manager m;
  for (uint32_t i = 0; i < 100000; ++i) m.touch(i, i * 7 + 1).state.shear = i;
  EXPECT_EQ(m.size(), 100000u);
  EXPECT_LE(4 * m.size(), 3 * m.bucketCount());  // the load limit
  for (uint32_t i = 0; i < 100000; ++i) ASSERT_EQ(m.find(i, i * 7 + 1)->shear, i);
  Manager r;
  r.reserve(5000);
  const size_t bytes = r.memoryBytes();
  for (uint32_t i = 0; i < 5000; ++i) r.touch(i, i);
  EXPECT_EQ(r.memoryBytes(), bytes);
  r.clear();
  EXPECT_TRUE(r.empty());
  EXPECT_EQ(r.find(3, 3), nullptr);
  EXPECT_EQ(r.memoryBytes(), bytes);
}

TEST(InstanceInteractionManager, OrderDependsOnlyOnTheOperations) {
  // Two managers fed the same operations iterate in the same order, and re-inserting the pairs
  // in that order into a table of the same bucket count (a checkpoint restore) reproduces it.
  Manager a, b;
  std::mt19937 rng(5);
  for (int step = 0; step < 50; ++step) {
    for (int k = 0; k < 100; ++k) {
      const auto x = static_cast<uint32_t>(rng() % 300), y = static_cast<uint32_t>(rng() % 300);
      a.touch(x, y).state.steps = k;
      b.touch(x, y).state.steps = k;
    }
    a.sweep();
    b.sweep();
  }
  auto listing = [](Manager& m) {
    std::vector<std::pair<Pair, Spring>> out;
    m.forEach([&](const Pair& p, Spring& s) { out.push_back({p, s}); });
    return out;
  };
  const auto order = listing(a);
  ASSERT_EQ(order.size(), a.size());
  EXPECT_EQ(listing(b), order);
  std::vector<Pair> keys;
  for (const auto& [p, s] : order) keys.push_back(p);
  EXPECT_FALSE(std::is_sorted(keys.begin(), keys.end()));  // the order is the table's
  Manager restored;
  restored.reserveBuckets(a.bucketCount());
  for (const auto& [p, s] : order) restored.touch(p.first, p.second).state = s;
  EXPECT_EQ(restored.sweep(), 0u);  // closes the restored step, as a sweep closed the saved one
  EXPECT_EQ(restored.bucketCount(), a.bucketCount());
  EXPECT_EQ(listing(restored), order);
  // ...and the restored table keeps behaving the same: drop the same pairs, in the same order.
  std::vector<Pair> droppedA, droppedR;
  for (const auto& [p, s] : order) {
    if (p.second % 3 != 0) {
      a.touch(p.first, p.second);
      restored.touch(p.first, p.second);
    }
  }
  a.sweep([&](const Pair& p, Spring&) { droppedA.push_back(p); });
  restored.sweep([&](const Pair& p, Spring&) { droppedR.push_back(p); });
  EXPECT_FALSE(droppedA.empty());
  EXPECT_EQ(droppedA, droppedR);
  EXPECT_EQ(listing(restored), listing(a));
}

}  // namespace core_instance_interaction_test
}  // namespace demlab
