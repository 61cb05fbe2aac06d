// The SIMD kernels (contact_kernel.hpp) for baseline x86-64: SSE2, 2 doubles per register.
// Only the kernels' own functions live here (contact_kernel_impl.hpp, in namespace sse2).
#if defined(__x86_64__)
#define DEMLAB_KERNEL_NS sse2
#include "sim/contact_kernel_impl.hpp"

namespace demlab::sim::kernel {

IsaPasses sse2Passes() {
  return sse2::passesFor<2>();
}

}  // namespace demlab::sim::kernel
#endif
