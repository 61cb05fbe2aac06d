// The table of neighbor-search algorithms (search/registry.hpp), compiled once per configuration.
#include "search/registry.hpp"

#include "search/brute_force.hpp"
#include "search/cgrid.hpp"
#include "search/hgrid.hpp"
#include "search/nbs.hpp"
#include "search/sweep_prune.hpp"

namespace demlab::search {

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

#define DEMLAB_INSTANTIATE_TABLE(C, D, T) \
  template std::span<const BroadPhaseRow<D, T>> broadPhaseTable<D, T>();
DEMLAB_SEARCH_CONFIGS(DEMLAB_INSTANTIATE_TABLE, -)
#undef DEMLAB_INSTANTIATE_TABLE

}  // namespace demlab::search
