// The one compiled copy of CGrid for every configuration of search/configs.hpp; the header
// declares these extern, so its template errors and warnings also surface here, once.
#include "search/cgrid.hpp"

namespace demlab::search {

#define DEMLAB_INSTANTIATE_CGRID(D, T) template class CGrid<D, T>;
DEMLAB_SEARCH_CONFIGS(DEMLAB_INSTANTIATE_CGRID)
#undef DEMLAB_INSTANTIATE_CGRID

}  // namespace demlab::search
