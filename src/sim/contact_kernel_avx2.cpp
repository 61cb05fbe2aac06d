// The SIMD kernels (contact_kernel.hpp) with AVX2: 4 doubles per register (16 registers).
// Compiled with -mavx2 -mno-fma -ffp-contract=off (cmake/sim.cmake); chosen at run time.
// Only the kernels' own functions live here (contact_kernel_impl.hpp, in namespace avx2).
#if defined(__x86_64__)
#define DEMLAB_KERNEL_NS avx2
#include "sim/contact_kernel_impl.hpp"

namespace demlab::sim::kernel {

IsaPasses avx2Passes() {
  return avx2::passesFor<4>();
}

}  // namespace demlab::sim::kernel
#endif
