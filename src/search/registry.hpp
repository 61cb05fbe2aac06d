// The table of neighbor-search algorithms: one row per algorithm, so benchmarks and property
// tests run every algorithm the project has without naming them one by one.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string_view>

#include "search/broad_phase.hpp"
#include "search/brute_force.hpp"
#include "search/cgrid.hpp"
#include "search/hgrid.hpp"
#include "search/nbs.hpp"
#include "search/sweep_prune.hpp"

namespace demlab::search {

template <int D, class T>
struct BroadPhaseRow {
  std::string_view name;
  bool usesCellFactor;  // true if SearchOptions::cellFactor changes what it does
  std::unique_ptr<BroadPhase<D, T>> (*make)(const SearchOptions&);
};

// Returns the table of all algorithms, the brute-force oracle first.
template <int D, class T>
std::span<const BroadPhaseRow<D, T>> broadPhaseTable() {
  static const BroadPhaseRow<D, T> rows[] = {
      {"brute", false,
       [](const SearchOptions&) -> std::unique_ptr<BroadPhase<D, T>> {
         return std::make_unique<BruteForce<D, T>>();
       }},
      {"cgrid", true,
       [](const SearchOptions& o) -> std::unique_ptr<BroadPhase<D, T>> {
         return std::make_unique<CGrid<D, T>>(o);
       }},
      {"sgrid", true,
       [](const SearchOptions& o) -> std::unique_ptr<BroadPhase<D, T>> {
         return std::make_unique<CGrid<D, T>>(o, CGrid<D, T>::Extents::Fixed);
       }},
      {"nbs", false,
       [](const SearchOptions&) -> std::unique_ptr<BroadPhase<D, T>> {
         return std::make_unique<Nbs<D, T>>();
       }},
      {"sap", false,
       [](const SearchOptions&) -> std::unique_ptr<BroadPhase<D, T>> {
         return std::make_unique<SweepAndPrune<D, T>>();
       }},
      {"hgrid", true,
       [](const SearchOptions& o) -> std::unique_ptr<BroadPhase<D, T>> {
         return std::make_unique<HGrid<D, T>>(o);
       }},
  };
  return rows;
}

// Returns a new instance of the named algorithm, or nullptr if there is none by that name.
template <int D, class T>
std::unique_ptr<BroadPhase<D, T>> makeBroadPhase(std::string_view name,
                                                 const SearchOptions& options = {}) {
  for (const auto& row : broadPhaseTable<D, T>()) {
    if (row.name == name) return row.make(options);
  }
  return nullptr;
}

}  // namespace demlab::search
