#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "search/brute_force.hpp"

namespace demlab::search {
namespace brute_force_test {

using Box2 = Box<2, double>;

TEST(BruteForce, TouchingFacesCount) {
  std::vector<Box2> boxes = {{{0, 0}, {1, 1}}, {{1, 0}, {2, 1}}, {{2.5, 0}, {3, 1}}};
  BruteForce<2, double> bf;
  std::vector<IndexPair> out;
  bf.findPairs(boxes, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], (IndexPair{0, 1}));
}

TEST(BruteForce, NanBoxIsRejectedAndReportsNothing) {
  std::vector<Box2> boxes = {{{0, 0}, {1, 1}}, {{0, 0}, {1, std::nan("")}}};
  BruteForce<2, double> bf;
  std::vector<IndexPair> out = {{7, 8}};
  try {
    bf.findPairs(boxes, out);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), (std::vector<std::string>{"DEMLAB", "VALUE", "BOX"}));
    EXPECT_STREQ(e.what(), "bad box 1: coordinate is NaN on axis 1");
  }
  EXPECT_TRUE(out.empty());
}

}  // namespace brute_force_test
}  // namespace demlab::search
