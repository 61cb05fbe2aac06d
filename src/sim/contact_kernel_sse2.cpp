// The SIMD kernels (contact_kernel.hpp) for baseline x86-64: SSE2, 2 doubles per register.
// Only the kernels' own functions live here (contact_kernel_impl.hpp, in namespace sse2).
#if defined(__x86_64__)
#define DEMLAB_KERNEL_NS sse2
#include "sim/contact_kernel_impl.hpp"

namespace demlab::sim::kernel {

HertzPassFn sse2HertzPass(bool history, bool rotation) {
  return sse2::hertzPassFor<2>(history, rotation);
}

WallPassFn sse2WallPass(bool history, bool rotation) {
  return sse2::wallPassFor<2>(history, rotation);
}

RotationPassFn sse2RotationPass() {
  return &sse2::rotationPass<2>;
}

PredictPassFn sse2PredictPass() {
  return &sse2::predictPass<2>;
}

CorrectPassFn sse2CorrectPass() {
  return &sse2::correctPass<2>;
}

}  // namespace demlab::sim::kernel
#endif
