// The one compiled copy of Nbs for every configuration of search/configs.hpp; the header
// declares these extern, so its template errors and warnings also surface here, once.
#include "search/nbs.hpp"

namespace demlab::search {

#define DEMLAB_INSTANTIATE_NBS(D, T) template class Nbs<D, T>;
DEMLAB_SEARCH_CONFIGS(DEMLAB_INSTANTIATE_NBS)
#undef DEMLAB_INSTANTIATE_NBS

}  // namespace demlab::search
