// The one compiled copy of BruteForce for every configuration of search/configs.hpp; the header
// declares these extern, so its template errors and warnings also surface here, once.
#include "search/brute_force.hpp"

namespace demlab::search {

DEMLAB_SEARCH_CONFIGS(DEMLAB_SEARCH_INSTANTIATE_CLASS, BruteForce)

}  // namespace demlab::search
