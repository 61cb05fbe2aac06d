// The one compiled copy of SweepAndPrune for every configuration of search/configs.hpp; the header
// declares these extern, so its template errors and warnings also surface here, once.
#include "search/sweep_prune.hpp"

namespace demlab::search {

#define DEMLAB_INSTANTIATE_SWEEPANDPRUNE(D, T) template class SweepAndPrune<D, T>;
DEMLAB_SEARCH_CONFIGS(DEMLAB_INSTANTIATE_SWEEPANDPRUNE)
#undef DEMLAB_INSTANTIATE_SWEEPANDPRUNE

}  // namespace demlab::search
