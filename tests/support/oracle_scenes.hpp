// Scenes and the oracle check shared by the search tests: random cubes, exact boxes, and a
// comparison with brute force that names the first missing or extra pair.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <memory>
#include <random>
#include <vector>

#include "search/brute_force.hpp"
#include "search/registry.hpp"

namespace demlab::search::test_support {

template <int D_, class T_>
struct Config {
  static constexpr int D = D_;
  using T = T_;
};

// Returns a box with the given centre and edge lengths, rounded to T (rounding is monotone, so
// lo <= hi survives). Changes nothing.
template <int D, class T>
Box<D, T> makeBox(const std::array<double, D>& centre, const std::array<double, D>& size) {
  Box<D, T> b;
  for (int k = 0; k < D; ++k) {
    b.lo[k] = static_cast<T>(centre[k] - 0.5 * size[k]);
    b.hi[k] = static_cast<T>(centre[k] + 0.5 * size[k]);
  }
  return b;
}

// Returns n cubes with edges drawn by edgeOf(rng) and centres uniform in
// [offset, offset + side)^D. Changes rng.
template <int D, class T, class EdgeFn>
std::vector<Box<D, T>> randomCubes(std::mt19937_64& rng, int n, double side, EdgeFn edgeOf,
                                   double offset = 0.0) {
  std::uniform_real_distribution<double> pos(offset, offset + side);
  std::vector<Box<D, T>> boxes;
  for (int i = 0; i < n; ++i) {
    std::array<double, D> c, s;
    const double edge = edgeOf(rng);
    for (int k = 0; k < D; ++k) {
      c[k] = pos(rng);
      s[k] = edge;
    }
    boxes.push_back(makeBox<D, T>(c, s));
  }
  return boxes;
}

// Returns the side of a cube in which n boxes of edge `edge` have a few contacts each.
template <int D>
double sideFor(int n, double edge) {
  return edge * std::pow(static_cast<double>(n), 1.0 / D) * 1.3;
}

// Returns success if algo finds exactly the oracle's pairs on boxes (each once), else the
// first difference. Changes algo's buffers.
template <int D, class T>
::testing::AssertionResult matchesOracle(BroadPhase<D, T>& algo,
                                         const std::vector<Box<D, T>>& boxes) {
  BruteForce<D, T> oracle;
  std::vector<IndexPair> expected, got;
  oracle.findPairs(boxes, expected);
  algo.findPairs(boxes, got);
  for (const IndexPair& p : got) {
    if (p.first >= p.second) {
      return ::testing::AssertionFailure() << "pair not ordered: " << p.first << "," << p.second;
    }
  }
  std::sort(expected.begin(), expected.end());
  std::sort(got.begin(), got.end());
  if (std::adjacent_find(got.begin(), got.end()) != got.end()) {
    return ::testing::AssertionFailure() << "a pair is reported twice";
  }
  if (expected == got) return ::testing::AssertionSuccess();
  std::vector<IndexPair> missing, extra;
  std::set_difference(expected.begin(), expected.end(), got.begin(), got.end(),
                      std::back_inserter(missing));
  std::set_difference(got.begin(), got.end(), expected.begin(), expected.end(),
                      std::back_inserter(extra));
  auto result = ::testing::AssertionFailure()
                << boxes.size() << " boxes: expected " << expected.size() << " pairs, got "
                << got.size() << " (" << missing.size() << " missing, " << extra.size()
                << " extra)";
  if (!missing.empty())
    result << "; first missing " << missing[0].first << "," << missing[0].second;
  if (!extra.empty()) result << "; first extra " << extra[0].first << "," << extra[0].second;
  return result;
}

using Configs =
    ::testing::Types<Config<1, double>, Config<2, double>, Config<3, double>, Config<4, double>,
                     Config<1, float>, Config<2, float>, Config<3, float>, Config<4, float>>;

// Returns a fresh instance of every algorithm in the registry, brute force included.
template <int D, class T>
std::vector<std::unique_ptr<BroadPhase<D, T>>> everyAlgorithm() {
  std::vector<std::unique_ptr<BroadPhase<D, T>>> all;
  for (const auto& row : broadPhaseTable<D, T>()) all.push_back(row.make(SearchOptions{}));
  return all;
}

}  // namespace demlab::search::test_support
