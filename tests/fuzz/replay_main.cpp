// Runs a fuzz target in builds without libFuzzer (GCC, the sanitizer build of the test command):
//   fuzz_<name> [-seconds N] [-seed S] [-crashes DIR] PATH...
// First every file given (or in the folders given) once: the kept corpus as a regression test.
// Then, for N seconds (default 0), mutations of those inputs: libFuzzer's common byte-level
// mutations (bit flips, interesting bytes and integers, erased, repeated and inserted ranges,
// splices of two inputs), without its coverage guidance, so it finds less per execution than
// scripts/fuzz but needs no clang. A crash or sanitizer report ends the program; the input that
// caused it is written to DIR (default: the working folder) as crash-<hash> first, and the
// program says where. Exits 0 when every input ran, 1 without inputs, 2 on bad arguments.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/common_interface_defs.h>
#endif
#include <csignal>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

using Bytes = std::string;

// The input being run and where a crash writes it.
Bytes g_current;
std::string g_crashDir = ".";
bool g_mutating = false;

// Writes the current input to crash-<FNV-1a hash> in g_crashDir. Async-signal-safe enough for a
// dying process: no allocation after the name is formatted into a fixed buffer.
void saveCurrent() {
  if (!g_mutating) return;  // a kept corpus file crashed: it is already on disk
  uint64_t h = 1469598103934665603ull;
  for (const char c : g_current) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  char path[4096];
  std::snprintf(path, sizeof path, "%s/crash-%016llx", g_crashDir.c_str(),
                static_cast<unsigned long long>(h));
  if (FILE* f = std::fopen(path, "wb")) {
    std::fwrite(g_current.data(), 1, g_current.size(), f);
    std::fclose(f);
    std::fprintf(stderr, "fuzz: the failing input is saved as %s\n", path);
  }
}

void onSignal(int sig) {
  saveCurrent();
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

Bytes readFile(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return Bytes{std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void run(const Bytes& input) {
  g_current = input;
  LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(g_current.data()), g_current.size());
}

// Applies one random mutation to `b` (an input from `corpus`), keeping it at most kMaxSize.
class Mutator {
 public:
  static constexpr size_t kMaxSize = 1 << 20;

  explicit Mutator(uint64_t seed) : rng_(seed) {}

  void mutate(Bytes& b, const std::vector<Bytes>& corpus) {
    switch (pick(9)) {
      case 0:  // flip a bit
        if (!b.empty()) b[pick(b.size())] ^= static_cast<char>(1u << pick(8));
        break;
      case 1:  // a random byte
        if (!b.empty()) b[pick(b.size())] = static_cast<char>(pick(256));
        break;
      case 2: {  // an interesting byte
        static constexpr uint8_t kBytes[] = {0, 1, 0x7f, 0x80, 0xff, '-', '9', ' ', '\n', 'e'};
        if (!b.empty()) b[pick(b.size())] = static_cast<char>(kBytes[pick(sizeof kBytes)]);
        break;
      }
      case 3: {  // an interesting 32- or 64-bit value, either byte order
        static constexpr uint64_t kWords[] = {0, 1, 0xffffffffffffffffull, 0x7fffffffffffffffull,
                                              0x8000000000000000ull, 0x7ff0000000000000ull,
                                              0x7ff8000000000000ull, 0xffffffffull, 0x7fffffffull,
                                              0x80000000ull, 0x100000000ull, 0x000fffffffffffffull};
        const size_t width = pick(2) ? 8 : 4;
        if (b.size() < width) break;
        uint64_t v = kWords[pick(sizeof kWords / sizeof kWords[0])];
        if (pick(2)) v = __builtin_bswap64(v) >> (width == 4 ? 32 : 0);
        std::memcpy(b.data() + pick(b.size() - width + 1), &v, width);
        break;
      }
      case 4: {  // erase a range
        if (b.empty()) break;
        const size_t at = pick(b.size());
        b.erase(at, 1 + pick(std::min<size_t>(b.size() - at, 64)));
        break;
      }
      case 5: {  // repeat a range
        if (b.empty()) break;
        const size_t at = pick(b.size()), n = 1 + pick(std::min<size_t>(b.size() - at, 64));
        const Bytes part = b.substr(at, n);
        for (size_t k = 1 + pick(4); k > 0; --k) b.insert(pick(b.size() + 1), part);
        break;
      }
      case 6: {  // insert random bytes
        Bytes part(1 + pick(16), '\0');
        for (char& c : part) c = static_cast<char>(pick(256));
        b.insert(pick(b.size() + 1), part);
        break;
      }
      case 7: {  // splice: the front of this input, the back of another
        const Bytes& other = corpus[pick(corpus.size())];
        if (b.empty() || other.empty()) break;
        b = b.substr(0, pick(b.size())) + other.substr(pick(other.size()));
        break;
      }
      default:  // truncate
        if (!b.empty()) b.resize(pick(b.size()));
        break;
    }
    if (b.size() > kMaxSize) b.resize(kMaxSize);
  }

  size_t pick(size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }

 private:
  std::mt19937_64 rng_;
};

}  // namespace

int main(int argc, char** argv) {
  double seconds = 0;
  uint64_t seed = 1;
  std::vector<std::filesystem::path> inputs;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if ((a == "-seconds" || a == "-seed" || a == "-crashes") && k + 1 < argc) {
      const std::string v = argv[++k];
      if (a == "-crashes") {
        g_crashDir = v;
        continue;
      }
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end != '\0' || !(x >= 0) || x > 1e9) {
        std::fprintf(stderr, "fuzz: bad value \"%s\" for %s\n", v.c_str(), a.c_str());
        return 2;
      }
      if (a == "-seconds") {
        seconds = x;
      } else {
        seed = static_cast<uint64_t>(x);
      }
      continue;
    }
    const std::filesystem::path p(a);
    if (std::filesystem::is_directory(p)) {
      for (const auto& e : std::filesystem::directory_iterator(p))
        if (e.is_regular_file()) inputs.push_back(e.path());
    } else {
      inputs.push_back(p);
    }
  }
  std::sort(inputs.begin(), inputs.end());
  std::vector<Bytes> corpus;
  corpus.reserve(inputs.size());
  for (const auto& p : inputs) {
    corpus.push_back(readFile(p));
    run(corpus.back());
  }
  std::printf("replayed %zu inputs\n", inputs.size());
  if (corpus.empty()) return 1;
  if (seconds <= 0) return 0;

  g_mutating = true;
#if defined(__SANITIZE_ADDRESS__)
  __sanitizer_set_death_callback(saveCurrent);
#endif
  for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, onSignal);
  Mutator m(seed);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  uint64_t runs = 0;
  while (std::chrono::steady_clock::now() < end) {
    Bytes b = corpus[m.pick(corpus.size())];
    for (size_t k = 1 + m.pick(4); k > 0; --k) m.mutate(b, corpus);
    run(b);
    runs += 1;
  }
  std::printf("fuzzed %llu mutated inputs in %g s (seed %llu): no failure\n",
              static_cast<unsigned long long>(runs), seconds,
              static_cast<unsigned long long>(seed));
  return 0;
}
