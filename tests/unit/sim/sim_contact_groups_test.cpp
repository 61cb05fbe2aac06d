// groupCandidates: the candidates in the threaded pass's order (a permutation that keeps the
// given order within each group, groups of one phase sharing no block), and a poll that stops
// it at any of its polls leaves the pairs as they were.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "sim/contact_groups.hpp"

namespace demlab::sim {
namespace sim_contact_groups_test {

struct Pair {
  uint32_t i = 0, j = 0;
  friend bool operator==(const Pair&, const Pair&) = default;
};

// Returns n random pairs of elements 0 .. elements-1, most of them near each other (as a
// spatially sorted bed's are), some far apart.
std::vector<Pair> randomPairs(std::mt19937_64& rng, size_t n, uint32_t elements) {
  std::uniform_int_distribution<uint32_t> any(0, elements - 1);
  std::uniform_int_distribution<int> near(1, 700);
  std::vector<Pair> pairs;
  for (size_t k = 0; k < n; ++k) {
    const uint32_t i = any(rng);
    const uint32_t j = (k % 5 == 0) ? any(rng) : std::min(elements - 1, i + uint32_t(near(rng)));
    if (i != j) pairs.push_back({std::min(i, j), std::max(i, j)});
  }
  return pairs;
}

// Returns the blocks pair p touches.
std::set<uint32_t> blocksOf(const Pair& p) {
  constexpr uint32_t B = ContactGroups::kBlockElements;
  return {p.i / B, p.j / B};
}

TEST(ContactGroups, APermutationInGroupsOfDisjointBlocksPerPhase) {
  std::mt19937_64 rng(3);
  for (const size_t n : {size_t(1), size_t(50), size_t(20000), size_t(200000)}) {
    const std::vector<Pair> given = randomPairs(rng, n, 40000);
    std::vector<Pair> pairs = given;
    ContactGroups groups;
    std::vector<uint32_t> moved;
    int polls = 0;
    groupCandidates(pairs, &groups, &moved, [&] { ++polls; });
    ASSERT_TRUE(groups.cover(pairs.size()));
    ASSERT_EQ(moved.size(), pairs.size());
    EXPECT_GT(polls, 0);
    for (size_t k = 0; k < pairs.size(); ++k) ASSERT_EQ(pairs[k], given[moved[k]]);
    std::vector<uint32_t> sortedMoved = moved;
    std::sort(sortedMoved.begin(), sortedMoved.end());
    for (size_t k = 0; k < sortedMoved.size(); ++k) ASSERT_EQ(sortedMoved[k], k);
    // Each group: one block pair, the given order kept within it.
    for (const ContactGroups::Range& g : groups.groups) {
      for (uint32_t k = g.begin; k + 1 < g.end; ++k) {
        ASSERT_EQ(blocksOf(pairs[k]), blocksOf(pairs[g.begin]));
        ASSERT_LT(moved[k], moved[k + 1]);
      }
    }
    // The groups of a phase after the first share no block.
    for (size_t ph = 1; ph < groups.phases.size(); ++ph) {
      std::set<uint32_t> seen;
      for (uint32_t g = groups.phases[ph].begin; g < groups.phases[ph].end; ++g) {
        for (uint32_t b : blocksOf(pairs[groups.groups[g].begin])) {
          ASSERT_TRUE(seen.insert(b).second) << "phase " << ph;
        }
      }
    }
    // A list already in that order keeps it.
    std::vector<Pair> again = pairs;
    groupCandidates(again, &groups, &moved, [] {});
    EXPECT_EQ(again, pairs);
  }
}

struct Stopped : std::runtime_error {
  Stopped() : std::runtime_error("stopped") {}
};

TEST(ContactGroups, StoppedAtAnyPollThePairsAreAsGiven) {
  std::mt19937_64 rng(5);
  const std::vector<Pair> given = randomPairs(rng, 150000, 60000);
  std::vector<Pair> grouped = given;
  ContactGroups groups;
  int polls = 0;
  groupCandidates(grouped, &groups, nullptr, [&] { ++polls; });
  ASSERT_GT(polls, 10);
  for (int stopAt = 1; stopAt <= polls; ++stopAt) {
    std::vector<Pair> pairs = given;
    int calls = 0;
    EXPECT_THROW(groupCandidates(pairs, &groups, nullptr,
                                 [&] {
                                   if (++calls == stopAt) throw Stopped();
                                 }),
                 Stopped);
    ASSERT_EQ(pairs, given) << "stopped at poll " << stopAt;
  }
  std::vector<Pair> pairs = given;
  groupCandidates(pairs, &groups, nullptr, [] {});
  EXPECT_EQ(pairs, grouped);
}

}  // namespace sim_contact_groups_test
}  // namespace demlab::sim
