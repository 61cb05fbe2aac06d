// The SIMD kernels (contact_kernel.hpp) with AVX2: 4 doubles per register (16 registers).
// Compiled with -mavx2 -mno-fma -ffp-contract=off (cmake/sim.cmake); chosen at run time.
// Only the kernels' own functions live here (contact_kernel_impl.hpp, in namespace avx2).
#if defined(__x86_64__)
#define DEMLAB_KERNEL_NS avx2
#include "sim/contact_kernel_impl.hpp"

namespace demlab::sim::kernel {

HertzPassFn avx2HertzPass(bool history, bool rotation) {
  return avx2::hertzPassFor<4>(history, rotation);
}

WallPassFn avx2WallPass(bool history, bool rotation) {
  return avx2::wallPassFor<4>(history, rotation);
}

RotationPassFn avx2RotationPass() {
  return &avx2::rotationPass<4>;
}

PredictPassFn avx2PredictPass() {
  return &avx2::predictPass<4>;
}

CorrectPassFn avx2CorrectPass() {
  return &avx2::correctPass<4>;
}

}  // namespace demlab::sim::kernel
#endif
