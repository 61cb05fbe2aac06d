// The one compiled copy of HGrid for every configuration of search/configs.hpp; the header
// declares these extern, so its template errors and warnings also surface here, once.
#include "search/hgrid.hpp"

namespace demlab::search {

#define DEMLAB_INSTANTIATE_HGRID(D, T) template class HGrid<D, T>;
DEMLAB_SEARCH_CONFIGS(DEMLAB_INSTANTIATE_HGRID)
#undef DEMLAB_INSTANTIATE_HGRID

}  // namespace demlab::search
