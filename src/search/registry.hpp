// The table of neighbor-search algorithms: one row per algorithm, so benchmarks and property
// tests run every algorithm the project has without naming them one by one.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string_view>

#include "search/broad_phase.hpp"
#include "search/configs.hpp"

namespace demlab::search {

template <int D, class T>
struct BroadPhaseRow {
  std::string_view name;
  bool usesCellFactor;  // true if SearchOptions::cellFactor changes what it does
  std::unique_ptr<BroadPhase<D, T>> (*make)(const SearchOptions&);
  bool usesThreads = false;  // true if it runs on ThreadPool::global() when that has threads
};

// Returns the table of all algorithms, the brute-force oracle first. Defined in registry.cpp
// for every configuration of search/configs.hpp, so a file that only runs the table does not
// compile the algorithms again.
template <int D, class T>
std::span<const BroadPhaseRow<D, T>> broadPhaseTable();

#define DEMLAB_EXTERN_TABLE(C, D, T) \
  extern template std::span<const BroadPhaseRow<D, T>> broadPhaseTable<D, T>();
DEMLAB_SEARCH_CONFIGS(DEMLAB_EXTERN_TABLE, -)
#undef DEMLAB_EXTERN_TABLE

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
