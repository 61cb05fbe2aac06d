// The table of neighbor-search algorithms (search/registry.hpp), compiled once per configuration.
#include "search/registry.hpp"

#include <memory>
#include <type_traits>

#include "search/brute_force.hpp"
#include "search/cgrid.hpp"
#include "search/hgrid.hpp"
#include "search/nbs.hpp"
#include "search/sweep_prune.hpp"

namespace demlab::search {

// Returns a new Algorithm: built from the options where it takes them (usesCellFactor), else
// from nothing; extra are the constructor's further arguments.
template <int D, class T, class Algorithm, auto... extra>
std::unique_ptr<BroadPhase<D, T>> make(const SearchOptions& o) {
  if constexpr (std::is_constructible_v<Algorithm, const SearchOptions&, decltype(extra)...>) {
    return std::make_unique<Algorithm>(o, extra...);
  } else {
    return std::make_unique<Algorithm>();
  }
}

template <int D, class T>
std::span<const BroadPhaseRow<D, T>> broadPhaseTable() {
  static const BroadPhaseRow<D, T> rows[] = {
      {"brute", false, &make<D, T, BruteForce<D, T>>},
      {"cgrid", true, &make<D, T, CGrid<D, T>>, true},
      {"sgrid", true, &make<D, T, CGrid<D, T>, CGrid<D, T>::Extents::Fixed>, true},
      {"nbs", false, &make<D, T, Nbs<D, T>>},
      {"sap", false, &make<D, T, SweepAndPrune<D, T>>},
      {"hgrid", true, &make<D, T, HGrid<D, T>>},
  };
  return rows;
}

#define DEMLAB_INSTANTIATE_TABLE(C, D, T) \
  template std::span<const BroadPhaseRow<D, T>> broadPhaseTable<D, T>();
DEMLAB_SEARCH_CONFIGS(DEMLAB_INSTANTIATE_TABLE, -)
#undef DEMLAB_INSTANTIATE_TABLE

}  // namespace demlab::search
