// The choice of the contact kernel (contact_kernel.hpp): once, by what the CPU supports.
#include "sim/contact_kernel.hpp"

#include <cstdlib>
#include <cstring>
#include <initializer_list>

namespace demlab::sim::kernel {

#if defined(__x86_64__)
HertzPassFn sse2HertzPass(bool history, bool rotation);
HertzPassFn avx2HertzPass(bool history, bool rotation);
HertzPassFn avx512HertzPass(bool history, bool rotation);
WallPassFn sse2WallPass(bool history, bool rotation);
WallPassFn avx2WallPass(bool history, bool rotation);
WallPassFn avx512WallPass(bool history, bool rotation);
RotationPassFn sse2RotationPass();
RotationPassFn avx2RotationPass();
RotationPassFn avx512RotationPass();
PredictPassFn sse2PredictPass();
PredictPassFn avx2PredictPass();
PredictPassFn avx512PredictPass();
CorrectPassFn sse2CorrectPass();
CorrectPassFn avx2CorrectPass();
CorrectPassFn avx512CorrectPass();
#endif

namespace {

struct Choice {
  bool use = false;
  Isa isa = Isa::Sse2;
};

Choice initialChoice() {
  Choice c;
#if defined(__x86_64__)
  c.use = true;
  c.isa = supported(Isa::Avx512) ? Isa::Avx512 : supported(Isa::Avx2) ? Isa::Avx2 : Isa::Sse2;
  if (const char* e = std::getenv("DEMLAB_KERNEL")) {
    if (std::strcmp(e, "eigen") == 0) c.use = false;
    for (Isa i : {Isa::Sse2, Isa::Avx2, Isa::Avx512}) {
      if (std::strcmp(e, isaName(i)) == 0 && supported(i)) c.isa = i;
    }
  }
#endif
  return c;
}

Choice& choice() {
  static Choice c = initialChoice();
  return c;
}

}  // namespace

const char* isaName(Isa isa) {
  switch (isa) {
    case Isa::Sse2:
      return "sse2";
    case Isa::Avx2:
      return "avx2";
    case Isa::Avx512:
      return "avx512";
  }
  return "?";
}

bool supported(Isa isa) {
#if defined(__x86_64__)
  switch (isa) {
    case Isa::Sse2:
      return true;
    case Isa::Avx2:
      return __builtin_cpu_supports("avx2");
    case Isa::Avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512vl");
  }
#endif
  (void)isa;
  return false;
}

HertzPassFn hertzPass(Isa isa, bool history, bool rotation) {
  if (!supported(isa)) return nullptr;
#if defined(__x86_64__)
  switch (isa) {
    case Isa::Sse2:
      return sse2HertzPass(history, rotation);
    case Isa::Avx2:
      return avx2HertzPass(history, rotation);
    case Isa::Avx512:
      return avx512HertzPass(history, rotation);
  }
#endif
  (void)history;
  (void)rotation;
  return nullptr;
}

WallPassFn wallPass(Isa isa, bool history, bool rotation) {
  if (!supported(isa)) return nullptr;
#if defined(__x86_64__)
  switch (isa) {
    case Isa::Sse2:
      return sse2WallPass(history, rotation);
    case Isa::Avx2:
      return avx2WallPass(history, rotation);
    case Isa::Avx512:
      return avx512WallPass(history, rotation);
  }
#endif
  (void)history;
  (void)rotation;
  return nullptr;
}

RotationPassFn rotationPass(Isa isa) {
  if (!supported(isa)) return nullptr;
#if defined(__x86_64__)
  switch (isa) {
    case Isa::Sse2:
      return sse2RotationPass();
    case Isa::Avx2:
      return avx2RotationPass();
    case Isa::Avx512:
      return avx512RotationPass();
  }
#endif
  return nullptr;
}

PredictPassFn predictPass(Isa isa) {
  if (!supported(isa)) return nullptr;
#if defined(__x86_64__)
  switch (isa) {
    case Isa::Sse2:
      return sse2PredictPass();
    case Isa::Avx2:
      return avx2PredictPass();
    case Isa::Avx512:
      return avx512PredictPass();
  }
#endif
  return nullptr;
}

CorrectPassFn correctPass(Isa isa) {
  if (!supported(isa)) return nullptr;
#if defined(__x86_64__)
  switch (isa) {
    case Isa::Sse2:
      return sse2CorrectPass();
    case Isa::Avx2:
      return avx2CorrectPass();
    case Isa::Avx512:
      return avx512CorrectPass();
  }
#endif
  return nullptr;
}

bool activeIsa(Isa* isa) {
  const Choice& c = choice();
  *isa = c.isa;
  return c.use;
}

bool setActive(bool use, Isa isa) {
  if (use && !supported(isa)) return false;
  choice() = Choice{use, isa};
  return true;
}

}  // namespace demlab::sim::kernel
