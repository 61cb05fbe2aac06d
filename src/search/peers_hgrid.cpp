// Explicit instantiations of HGrid for the dimensions and coordinate types the project tests,
// so its template errors and warnings surface in the library build (kept apart from
// search.cpp, which other peers share).
#include "search/hgrid.hpp"

namespace demlab::search {

template class HGrid<1, double>;
template class HGrid<2, double>;
template class HGrid<3, double>;
template class HGrid<4, double>;
template class HGrid<2, float>;
template class HGrid<3, float>;

}  // namespace demlab::search
