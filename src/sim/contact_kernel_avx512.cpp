// The Hertz-Mindlin contact kernel (contact_kernel.hpp) for avx512: compiled with
// -mavx512f -mavx512dq -mavx512vl -mno-fma -ffp-contract=off (cmake/sim.cmake), 8 contacts per register.
// Only the kernel's own functions live here (contact_kernel_impl.hpp, in namespace avx512).
#if defined(__x86_64__)
#define DEMLAB_KERNEL_NS avx512
#include "sim/contact_kernel_impl.hpp"

namespace demlab::sim::kernel {

HertzPassFn avx512HertzPass(bool history, bool rotation) {
  return avx512::hertzPassFor<8>(history, rotation);
}

RotationPassFn avx512RotationPass() {
  return &avx512::rotationPass<4>;
}

PredictPassFn avx512PredictPass() {
  return &avx512::predictPass<4>;
}

CorrectPassFn avx512CorrectPass() {
  return &avx512::correctPass<4>;
}

}  // namespace demlab::sim::kernel
#endif
