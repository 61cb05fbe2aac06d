// What is particular to NBS; the oracle checks on hard inputs that every algorithm shares are
// in search_edge_cases_test.cpp.
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "search/nbs.hpp"
#include "support/oracle_scenes.hpp"

namespace demlab::search {
namespace nbs_test {

using namespace test_support;

// One domain-sized box makes NBS's one cell domain-sized: still exact, never unbounded memory.
TEST(Nbs, OneHugeBoxStaysExactAndBounded) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> size(0.2, 1.0);
  auto boxes = randomCubes<3, double>(rng, 400, sideFor<3>(400, 0.6), size);
  Nbs<3, double> nbs;
  EXPECT_TRUE(matchesOracle(nbs, boxes));
  const std::size_t small = nbs.workingBytes();
  boxes.push_back(makeBox<3, double>({0, 0, 0}, {1e7, 1e7, 1e7}));
  EXPECT_TRUE(matchesOracle(nbs, boxes));
  EXPECT_LT(nbs.workingBytes(), 4 * small + (std::size_t{1} << 16));
}

TEST(Nbs, NameAndNoWorkForTinyInputs) {
  Nbs<3, double> nbs;
  EXPECT_EQ(nbs.name(), "nbs");
  std::vector<IndexPair> out = {{0, 1}};
  nbs.findPairs(std::span<const Box<3, double>>{}, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(nbs.workingBytes(), 0u);
}

}  // namespace nbs_test
}  // namespace demlab::search
