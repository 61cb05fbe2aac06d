// Explicit instantiations: every BroadPhase is compiled once here for the dimensions and
// coordinate types the project tests, so template errors and warnings surface in one place.
#include "search/brute_force.hpp"
#include "search/cgrid.hpp"

namespace demlab::search {

template class BruteForce<1, double>;
template class BruteForce<2, double>;
template class BruteForce<3, double>;
template class BruteForce<4, double>;
template class BruteForce<2, float>;
template class BruteForce<3, float>;

template class CGrid<1, double>;
template class CGrid<2, double>;
template class CGrid<3, double>;
template class CGrid<4, double>;
template class CGrid<2, float>;
template class CGrid<3, float>;

}  // namespace demlab::search
