// The SIMD kernels (contact_kernel.hpp) with AVX-512 (F, DQ, VL): the AVX2 kernels' 4 doubles
// per register, with 32 registers and EVEX encodings. (8 per register measured slower on Zen 5,
// 12-18% by the median of 11 runs: the gathers and scatters of 3-vectors grow with the lanes,
// and the arithmetic is a third of the kernel.) Compiled with -mavx512f -mavx512dq -mavx512vl
// -mno-fma -ffp-contract=off (cmake/sim.cmake); chosen at run time. Only the kernels' own functions
// live here (contact_kernel_impl.hpp, in namespace avx512).
#if defined(__x86_64__)
#define DEMLAB_KERNEL_NS avx512
#include "sim/contact_kernel_impl.hpp"

namespace demlab::sim::kernel {

IsaPasses avx512Passes() {
  return avx512::passesFor<4>();
}

}  // namespace demlab::sim::kernel
#endif
