// The one compiled copy of BruteForce for every configuration of search/configs.hpp; the header
// declares these extern, so its template errors and warnings also surface here, once.
#include "search/brute_force.hpp"

namespace demlab::search {

#define DEMLAB_INSTANTIATE_BRUTEFORCE(D, T) template class BruteForce<D, T>;
DEMLAB_SEARCH_CONFIGS(DEMLAB_INSTANTIATE_BRUTEFORCE)
#undef DEMLAB_INSTANTIATE_BRUTEFORCE

}  // namespace demlab::search
