// Explicit instantiations of the NBS and sweep-and-prune peers for the dimensions and
// coordinate types the project tests, so their template errors and warnings surface in the
// library build rather than only where a test or benchmark happens to use them.
#include "search/nbs.hpp"
#include "search/sweep_prune.hpp"

namespace demlab::search {

template class Nbs<1, double>;
template class Nbs<2, double>;
template class Nbs<3, double>;
template class Nbs<4, double>;
template class Nbs<2, float>;
template class Nbs<3, float>;

template class SweepAndPrune<1, double>;
template class SweepAndPrune<2, double>;
template class SweepAndPrune<3, double>;
template class SweepAndPrune<4, double>;
template class SweepAndPrune<2, float>;
template class SweepAndPrune<3, float>;

}  // namespace demlab::search
