// The choice of the contact kernel (contact_kernel.hpp): once, by what the CPU supports.
#include "sim/contact_kernel.hpp"

#include <cstdlib>
#include <cstring>
#include <initializer_list>

namespace demlab::sim::kernel {

#if defined(__x86_64__)
IsaPasses sse2Passes();
IsaPasses avx2Passes();
IsaPasses avx512Passes();
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

namespace {

// Returns isa's row of the table of kernels, or nullptr if this CPU cannot run it.
const IsaPasses* passesOf(Isa isa) {
  if (!supported(isa)) return nullptr;
#if defined(__x86_64__)
  static const IsaPasses table[] = {sse2Passes(), avx2Passes(), avx512Passes()};  // by Isa
  return &table[static_cast<int>(isa)];
#else
  return nullptr;
#endif
}

}  // namespace

HertzPassFn hertzPass(Isa isa, bool history, bool rotation) {
  const IsaPasses* p = passesOf(isa);
  return p != nullptr ? p->hertz(history, rotation) : nullptr;
}

WallPassFn wallPass(Isa isa, bool history, bool rotation) {
  const IsaPasses* p = passesOf(isa);
  return p != nullptr ? p->wall(history, rotation) : nullptr;
}

RotationPassFn rotationPass(Isa isa) {
  const IsaPasses* p = passesOf(isa);
  return p != nullptr ? p->rotation : nullptr;
}

PredictPassFn predictPass(Isa isa) {
  const IsaPasses* p = passesOf(isa);
  return p != nullptr ? p->predict : nullptr;
}

CorrectPassFn correctPass(Isa isa) {
  const IsaPasses* p = passesOf(isa);
  return p != nullptr ? p->correct : nullptr;
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
