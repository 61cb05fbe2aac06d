// bench_search: times every neighbor-search algorithm of the registry on the same inputs and
// prints one CSV row per algorithm and input (see usage() below and scripts/bench-search).
//
// Measurement model, chosen to match how a simulation calls the search:
//   - each row group is one input (dim, n, distribution, size ratio, seed); every algorithm of
//     the group runs on that same input in the same run, one after the other (with
//     --kill-seconds, each in a forked child that shares the input pages and can be stopped);
//   - the base workload is followed by K = 3 jittered copies (every centre moved by up to 1% of
//     its radius on each axis), and the timed repetitions cycle through the copies, so an
//     algorithm that exploits temporal coherence gets the benefit it would get from one time
//     step to the next, but never an input identical to the previous call's;
//   - a warm-up call on the base workload comes first and is left out of the median, so
//     buffers are grown once, as in the first step of a simulation;
//   - `seconds` is the median of the timed calls, each one full findPairs (binning plus
//     reporting every pair into the output vector), by the wall clock or, with --cpu-time,
//     by the CPU time of the calling thread (which leaves out the other threads' work: compare
//     thread counts by the wall clock);
//   - algorithms that run on the thread pool (the registry's usesThreads) run once per
//     --threads count, the pool set to it; the others once, their threads column empty.
// Every algorithm must report the same number of pairs on every input it ran; if not, the
// program says so on stderr and exits with status 1 after finishing the group.
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/thread_pool.hpp"
#include "search/registry.hpp"
#include "search/workload.hpp"

namespace demlab::bench {
namespace {

using search::Box;
using search::Distribution;
using search::IndexPair;

// The O(N^2) oracle would dominate any sweep; it runs only where it takes well under a second.
constexpr std::string_view kOracleName = "brute";
constexpr std::size_t kOracleMaxN = 20000;
// Jittered copies of the base workload the repetitions cycle through.
constexpr int kCopies = 3;
// Largest move of a centre per axis, as a fraction of its radius.
constexpr double kJitter = 0.01;

// Returns the current time in seconds: the calling thread's CPU time if `cpu`, else the
// steady wall clock's.
double now(bool cpu) {
  if (cpu) {
    timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Options {
  std::vector<int> dims = {3};
  std::vector<std::size_t> ns = {10000};
  std::vector<Distribution> distributions = {Distribution::Uniform};
  std::vector<double> sizeRatios = {10.0};
  std::vector<double> cellFactors = {0.0};        // 0: each algorithm's automatic default
  std::vector<unsigned> threads = {1};            // pool threads, for algorithms that use it
  std::set<std::string, std::less<>> algorithms;  // empty: every algorithm of the table
  bool cellFactorOnly = false;
  int reps = 5;
  bool cpuTime = false;  // time calls by the thread's CPU time instead of wall time
  std::uint64_t seed = 1;
  double maxSeconds = 0.0;  // 0: no limit
  double killSeconds = -1;  // 0: never kill; negative: 10 x maxSeconds
  std::string memoryPath;   // empty: memory lines go to stderr
  bool header = true;
};

void usage(std::FILE* f) {
  std::fprintf(
      f,
      "usage: bench_search [options]\n"
      "Times every neighbor-search algorithm of the registry on the same inputs; prints CSV\n"
      "  algorithm,dim,n,distribution,size_ratio,cell_factor,seconds,pairs,ns_per_object,threads\n"
      "Lists are comma-separated; every combination is run.\n"
      "  --dim LIST            dimensions, 1..4 (default 3)\n"
      "  --n LIST              object counts, e.g. 1e4,1e5 (default 1e4)\n"
      "  --distribution LIST   uniform,bidisperse,powerlaw,powerlaw_walls,clustered,rods\n"
      "                        (default uniform)\n"
      "  --size-ratio LIST     largest/smallest radius (rods: length/width), >= 1 (default\n"
      "                        10; monodisperse\n"
      "                        distributions run once, at 1)\n"
      "  --cell-factor LIST    cell factors for algorithms that have one; 0 = automatic\n"
      "                        (default 0); other algorithms run once per input\n"
      "  --algorithms LIST     names from the registry (default: all)\n"
      "  --threads LIST        thread counts of the pool for the algorithms that run on it\n"
      "                        (cgrid, sgrid), e.g. 1,2 (default 1); the others run once,\n"
      "                        their threads column empty\n"
      "  --cell-factor-only    run only the algorithms that use the cell factor\n"
      "  --reps N              timed repetitions, median reported (default 5)\n"
      "  --cpu-time            time each call by the CPU time of its thread, not wall time:\n"
      "                        steadier on a shared machine (it leaves out the time spent\n"
      "                        waiting for a core, not the cost of sharing the caches)\n"
      "  --seed N              workload seed (default 1)\n"
      "  --max-seconds S       once one call of an algorithm takes longer than S, report that\n"
      "                        call alone and skip the algorithm for larger n of the same\n"
      "                        dim/distribution/size ratio; also skip it where its time scaled\n"
      "                        linearly from the last n would exceed S (default: no limit)\n"
      "  --kill-seconds S      stop a call still running after S seconds (it runs in a child\n"
      "                        process); it prints no row and is skipped for larger n\n"
      "                        (default 10 x --max-seconds; 0 = never)\n"
      "  --memory FILE         write working memory per algorithm as CSV to FILE\n"
      "                        (default: one line per algorithm on stderr)\n"
      "  --no-header           omit the CSV header (to append to an earlier table)\n"
      "  --help\n");
}

[[noreturn]] void die(const std::string& message) {
  std::fprintf(stderr, "bench_search: %s\n", message.c_str());
  std::exit(2);
}

std::vector<std::string> splitList(std::string_view s) {
  std::vector<std::string> items;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t comma = std::min(s.find(',', start), s.size());
    if (comma > start) items.emplace_back(s.substr(start, comma - start));
    start = comma + 1;
  }
  return items;
}

double parseNumber(const std::string& s, const char* flag) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !std::isfinite(v))
    die(std::string("bad number for ") + flag + ": " + s);
  return v;
}

Options parseOptions(int argc, char** argv) {
  Options o;
  const auto validNames = [] {
    std::set<std::string, std::less<>> names;
    for (const auto& row : search::broadPhaseTable<3, double>()) names.emplace(row.name);
    return names;
  }();
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) die("missing value for " + flag);
      return argv[++i];
    };
    if (flag == "--help" || flag == "-h") {
      usage(stdout);
      std::exit(0);
    } else if (flag == "--dim") {
      o.dims.clear();
      for (const auto& s : splitList(value())) {
        const double d = parseNumber(s, "--dim");
        if (d != 1 && d != 2 && d != 3 && d != 4) die("--dim must be 1, 2, 3 or 4: " + s);
        o.dims.push_back(static_cast<int>(d));
      }
    } else if (flag == "--n") {
      o.ns.clear();
      for (const auto& s : splitList(value())) {
        const double n = parseNumber(s, "--n");
        if (n < 1 || n != std::floor(n) || n > 4e9) die("--n must be a whole number >= 1: " + s);
        o.ns.push_back(static_cast<std::size_t>(n));
      }
    } else if (flag == "--distribution") {
      o.distributions.clear();
      for (const auto& s : splitList(value())) {
        const auto d = search::parseDistribution(s);
        if (!d) die("unknown distribution: " + s);
        o.distributions.push_back(*d);
      }
    } else if (flag == "--size-ratio") {
      o.sizeRatios.clear();
      for (const auto& s : splitList(value())) {
        const double r = parseNumber(s, "--size-ratio");
        if (r < 1) die("--size-ratio must be >= 1: " + s);
        o.sizeRatios.push_back(r);
      }
    } else if (flag == "--cell-factor") {
      o.cellFactors.clear();
      for (const auto& s : splitList(value())) {
        const double c = parseNumber(s, "--cell-factor");
        if (c < 0) die("--cell-factor must be >= 0: " + s);
        o.cellFactors.push_back(c);
      }
    } else if (flag == "--algorithms") {
      o.algorithms.clear();
      for (const auto& s : splitList(value())) {
        if (!validNames.contains(s)) {
          std::string known;
          for (const auto& name : validNames) known += " " + name;
          die("unknown algorithm: " + s + " (known:" + known + ")");
        }
        o.algorithms.insert(s);
      }
    } else if (flag == "--threads") {
      o.threads.clear();
      for (const auto& s : splitList(value())) {
        const double t = parseNumber(s, "--threads");
        if (t < 1 || t != std::floor(t) || t > ThreadPool::kMaxThreads) {
          die("--threads must be whole numbers from 1 to " +
              std::to_string(ThreadPool::kMaxThreads) + ": " + s);
        }
        o.threads.push_back(static_cast<unsigned>(t));
      }
    } else if (flag == "--cell-factor-only") {
      o.cellFactorOnly = true;
    } else if (flag == "--cpu-time") {
      o.cpuTime = true;
    } else if (flag == "--reps") {
      const double r = parseNumber(value(), "--reps");
      if (r < 1 || r != std::floor(r)) die("--reps must be a whole number >= 1");
      o.reps = static_cast<int>(r);
    } else if (flag == "--seed") {
      const double s = parseNumber(value(), "--seed");
      if (s < 0 || s != std::floor(s)) die("--seed must be a whole number >= 0");
      o.seed = static_cast<std::uint64_t>(s);
    } else if (flag == "--max-seconds") {
      o.maxSeconds = parseNumber(value(), "--max-seconds");
      if (o.maxSeconds < 0) die("--max-seconds must be >= 0");
    } else if (flag == "--kill-seconds") {
      o.killSeconds = parseNumber(value(), "--kill-seconds");
      if (o.killSeconds < 0) die("--kill-seconds must be >= 0");
    } else if (flag == "--memory") {
      o.memoryPath = value();
    } else if (flag == "--no-header") {
      o.header = false;
    } else {
      usage(stderr);
      die("unknown option: " + flag);
    }
  }
  if (o.dims.empty() || o.ns.empty() || o.distributions.empty() || o.sizeRatios.empty() ||
      o.cellFactors.empty() || o.threads.empty()) {
    die("an empty list leaves nothing to run");
  }
  if (o.killSeconds < 0) o.killSeconds = 10.0 * o.maxSeconds;
  // Ascending n, so --max-seconds can drop an algorithm for the larger sizes that follow.
  std::sort(o.ns.begin(), o.ns.end());
  o.ns.erase(std::unique(o.ns.begin(), o.ns.end()), o.ns.end());
  return o;
}

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Returns a copy of `base` with every box moved by up to kJitter times its radius on each axis
// (radius: half the box's smallest extent, so a wall moves like a small ball, not by a
// fraction of the domain).
template <int D>
std::vector<Box<D, double>> jittered(const std::vector<Box<D, double>>& base, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Box<D, double>> out(base);
  for (auto& b : out) {
    double r = 0.5 * (b.hi[0] - b.lo[0]);
    for (int k = 1; k < D; ++k) r = std::min(r, 0.5 * (b.hi[k] - b.lo[k]));
    for (int k = 0; k < D; ++k) {
      const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;
      const double delta = (2.0 * u - 1.0) * kJitter * r;
      b.lo[k] += delta;
      b.hi[k] += delta;
    }
  }
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// What --max-seconds remembers about one algorithm (and cell factor) along a sweep over n.
struct Progress {
  std::size_t lastN = 0;
  double lastSeconds = 0.0;
  bool dropped = false;
};

// One algorithm's result on one group, passed from a measuring child process as raw bytes.
struct Measurement {
  double seconds = 0.0;  // median of the repetitions, or the warm-up call alone if `single`
  bool single = false;   // the warm-up call exceeded --max-seconds, so nothing else ran
  long long counts[kCopies + 1];  // pairs per input; -1: not run
  std::size_t workingBytes = 0;
  char error[512] = "";  // findPairs threw this message
};
static_assert(std::is_trivially_copyable_v<Measurement>);

class Runner {
 public:
  explicit Runner(const Options& o) : o_(o) {
    if (!o_.memoryPath.empty()) {
      memory_ = std::fopen(o_.memoryPath.c_str(), "w");
      if (!memory_) die("cannot write " + o_.memoryPath);
      std::fprintf(memory_,
                   "algorithm,dim,n,distribution,size_ratio,cell_factor,working_bytes,"
                   "bytes_per_object,threads\n");
    }
  }
  ~Runner() {
    if (memory_) std::fclose(memory_);
  }
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;

  // Runs everything; returns the process exit status.
  int run() {
    if (o_.header) {
      std::printf(
          "algorithm,dim,n,distribution,size_ratio,cell_factor,seconds,pairs,ns_per_object,"
          "threads\n");
      std::fflush(stdout);
    }
    for (int dim : o_.dims) {
      // The templates are over D; this switch is the one place the run-time value meets them.
      switch (dim) {
        case 1:
          runDim<1>();
          break;
        case 2:
          runDim<2>();
          break;
        case 3:
          runDim<3>();
          break;
        case 4:
          runDim<4>();
          break;
        default:
          die("unsupported dimension " + std::to_string(dim));
      }
      if (mismatch_) return 1;
    }
    return 0;
  }

 private:
  template <int D>
  struct Entry {
    const search::BroadPhaseRow<D, double>* row;
    double cellFactor;
    std::string cellColumn;  // empty for algorithms that ignore the cell factor
    unsigned threads;        // the pool's thread count for the run; 0: the pool is not used
    std::string threadsColumn;  // empty for algorithms that do not use the pool
    std::string key() const {
      return std::string(row->name) + "@" + cellColumn + "@" + threadsColumn;
    }
  };

  template <int D>
  std::vector<Entry<D>> entries() const {
    std::vector<Entry<D>> list;
    for (const auto& row : search::broadPhaseTable<D, double>()) {
      if (!o_.algorithms.empty() && !o_.algorithms.contains(row.name)) continue;
      if (o_.cellFactorOnly && !row.usesCellFactor) continue;
      std::vector<double> factors = {0.0};
      if (row.usesCellFactor) factors = o_.cellFactors;
      std::vector<unsigned> threads = {0};
      if (row.usesThreads) threads = o_.threads;
      for (double c : factors) {
        for (unsigned t : threads) {
          list.push_back({&row, c, row.usesCellFactor ? formatNumber(c) : "", t,
                          t > 0 ? std::to_string(t) : ""});
        }
      }
    }
    return list;
  }

  template <int D>
  void runDim() {
    const auto list = entries<D>();
    if (list.empty()) {
      // An empty selection has an empty table, not an error: a sweep script may combine
      // --algorithms with --cell-factor-only and pick nothing.
      std::fprintf(stderr, "bench_search: no algorithm selected for dim=%d\n", D);
      return;
    }
    for (Distribution dist : o_.distributions) {
      std::vector<double> ratios = o_.sizeRatios;
      if (search::isMonodisperse(dist)) ratios = {1.0};  // the ratio would change nothing
      for (double ratio : ratios) {
        std::map<std::string, Progress> progress;  // one sweep over n
        for (std::size_t n : o_.ns) {
          runGroup<D>(list, {dist, n, ratio, o_.seed}, progress);
          if (mismatch_) return;
        }
      }
    }
  }

  // Times one algorithm on one group's inputs: a warm-up call on inputs[0] (then afterWarmUp()),
  // and, unless that call exceeded --max-seconds, the repetitions cycling through the copies.
  // A failing findPairs is reported in `error`, not thrown, so a child process can pass it on.
  template <int D, class AfterWarmUp>
  Measurement measure(const Entry<D>& e, const std::vector<std::vector<Box<D, double>>>& inputs,
                      AfterWarmUp afterWarmUp) const {
    Measurement m;
    std::fill(std::begin(m.counts), std::end(m.counts), -1);
    try {
      if (e.threads > 0) ThreadPool::global().setThreads(e.threads);
      auto algo = e.row->make(search::SearchOptions{e.cellFactor});
      std::vector<IndexPair> pairs;
      const auto call = [&](std::size_t input) {
        const double t0 = now(o_.cpuTime);
        algo->findPairs(inputs[input], pairs);
        const double s = now(o_.cpuTime) - t0;
        m.counts[input] = static_cast<long long>(pairs.size());
        return s;
      };
      m.seconds = call(0);
      afterWarmUp();
      if (o_.maxSeconds > 0 && m.seconds > o_.maxSeconds) {
        m.single = true;
      } else {
        std::vector<double> times;
        for (int r = 0; r < o_.reps; ++r) times.push_back(call(1 + r % kCopies));
        m.seconds = median(times);
      }
      m.workingBytes = algo->workingBytes();
    } catch (const std::exception& ex) {
      std::snprintf(m.error, sizeof m.error, "%s", ex.what());
    }
    return m;
  }

  // Runs measure() in a child process, so that a call running past --kill-seconds (a
  // quadratic case, or a hung algorithm) can be stopped: a thread could not be. Returns nothing
  // if the warm-up call was killed. The child shares the inputs copy-on-write and only reads
  // them, so forking copies no data and the timed calls run as they would in this process.
  template <int D>
  std::optional<Measurement> measureIsolated(
      const Entry<D>& e, const std::vector<std::vector<Box<D, double>>>& inputs) const {
    // A forked child has only the thread that forked: the pool's workers must not exist yet,
    // so the parent stops them and the child starts its own (measure() sets the count).
    ThreadPool::global().setThreads(1);
    std::fflush(stdout);  // else the child's copy of the buffers could be written twice
    std::fflush(stderr);
    if (memory_) std::fflush(memory_);
    int fd[2];
    if (pipe(fd) != 0) die("pipe failed");
    const pid_t pid = fork();
    if (pid < 0) die("fork failed");
    if (pid == 0) {
      close(fd[0]);
      const Measurement m = measure<D>(e, inputs, [&] {
        const char done = 'w';
        writeAll(fd[1], &done, 1);  // tells the parent the warm-up call has returned
      });
      writeAll(fd[1], &m, sizeof m);
      _exit(0);
    }
    close(fd[1]);
    pollfd pfd{fd[0], POLLIN, 0};
    const int timeoutMs = static_cast<int>(std::min(o_.killSeconds * 1000.0, 2e9));
    int ready;
    do {
      ready = poll(&pfd, 1, timeoutMs);
    } while (ready < 0 && errno == EINTR);
    std::optional<Measurement> result;
    char done = 0;
    if (ready == 0) {
      kill(pid, SIGKILL);
    } else {
      Measurement m;
      if (!readAll(fd[0], &done, 1) || !readAll(fd[0], &m, sizeof m)) {
        die("the measuring process of " + std::string(e.row->name) + " died");
      }
      result = m;
    }
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return result;
  }

  static void writeAll(int fd, const void* data, std::size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
      const ssize_t k = write(fd, p, size);
      if (k < 0 && errno == EINTR) continue;
      if (k <= 0) _exit(3);
      p += k;
      size -= static_cast<std::size_t>(k);
    }
  }

  static bool readAll(int fd, void* data, std::size_t size) {
    char* p = static_cast<char*>(data);
    while (size > 0) {
      const ssize_t k = read(fd, p, size);
      if (k < 0 && errno == EINTR) continue;
      if (k <= 0) return false;
      p += k;
      size -= static_cast<std::size_t>(k);
    }
    return true;
  }

  template <int D>
  void runGroup(const std::vector<Entry<D>>& list, const search::WorkloadSpec& spec,
                std::map<std::string, Progress>& progress) {
    const std::size_t n = spec.n;
    // inputs[0] is the base workload (warm-up); inputs[1..kCopies] are the jittered copies.
    std::vector<std::vector<Box<D, double>>> inputs;
    inputs.push_back(search::makeWorkload<D, double>(spec));
    for (int k = 1; k <= kCopies; ++k) {
      inputs.push_back(jittered<D>(inputs[0], spec.seed * 0x9E3779B97F4A7C15ull + k));
    }
    const std::string dist(search::distributionName(spec.distribution));
    const std::string ratio = formatNumber(spec.sizeRatio);
    const std::string where = "dim=" + std::to_string(D) + " n=" + std::to_string(n) +
                              " distribution=" + dist + " size_ratio=" + ratio;

    // Pair counts per input of the first algorithm that ran: the reference for the others.
    std::vector<long long> reference(inputs.size(), -1);
    std::string referenceName;
    for (const auto& e : list) {
      const std::string label =
          std::string(e.row->name) + (e.cellColumn.empty() ? "" : " cell_factor=" + e.cellColumn) +
          (e.threadsColumn.empty() ? "" : " threads=" + e.threadsColumn);
      if (e.row->name == kOracleName && n > kOracleMaxN) {
        if (!oracleNoted_) {
          std::fprintf(stderr, "bench_search: %.*s is skipped above n=%zu (O(N^2))\n",
                       static_cast<int>(kOracleName.size()), kOracleName.data(), kOracleMaxN);
          oracleNoted_ = true;
        }
        continue;
      }
      Progress& p = progress[e.key()];
      if (p.dropped) continue;
      if (o_.maxSeconds > 0 && p.lastN > 0) {
        // Any search reads all its input, so its time grows at least linearly in n.
        const double predicted = p.lastSeconds * static_cast<double>(n) / p.lastN;
        if (predicted > o_.maxSeconds) {
          std::fprintf(stderr,
                       "bench_search: skipping %s at %s and above: %.3g s at n=%zu predicts "
                       "at least %.3g s > --max-seconds\n",
                       label.c_str(), where.c_str(), p.lastSeconds, p.lastN, predicted);
          p.dropped = true;
          continue;
        }
      }

      std::optional<Measurement> m;
      if (o_.killSeconds > 0) {
        m = measureIsolated<D>(e, inputs);
        if (!m) {
          std::fprintf(stderr,
                       "bench_search: %s at %s: killed after %.3g s (--kill-seconds); no row, "
                       "skipping larger n\n",
                       label.c_str(), where.c_str(), o_.killSeconds);
          p.dropped = true;
          continue;
        }
      } else {
        m = measure<D>(e, inputs, [] {});
      }
      if (m->error[0] != '\0') die(label + " at " + where + ": " + m->error);
      if (m->single) {
        std::fprintf(stderr,
                     "bench_search: %s at %s: one call took %.3g s > --max-seconds; reporting "
                     "that call alone and skipping larger n\n",
                     label.c_str(), where.c_str(), m->seconds);
        p.dropped = true;
      }
      p.lastN = n;
      p.lastSeconds = m->seconds;
      const auto& counts = m->counts;

      std::printf("%.*s,%d,%zu,%s,%s,%s,%.6g,%lld,%.2f,%s\n",
                  static_cast<int>(e.row->name.size()), e.row->name.data(), D, n, dist.c_str(),
                  ratio.c_str(), e.cellColumn.c_str(), m->seconds, counts[0],
                  m->seconds * 1e9 / static_cast<double>(n), e.threadsColumn.c_str());
      std::fflush(stdout);
      reportMemory(e.row->name, D, n, dist, ratio, e.cellColumn, e.threadsColumn,
                   m->workingBytes);

      for (std::size_t i = 0; i < inputs.size(); ++i) {
        if (counts[i] < 0) continue;
        if (reference[i] < 0) {
          reference[i] = counts[i];
          if (referenceName.empty()) referenceName = label;
        } else if (reference[i] != counts[i]) {
          std::fprintf(stderr,
                       "bench_search: PAIR COUNT MISMATCH at %s, input %s: %s found %lld pairs, "
                       "%s found %lld\n",
                       where.c_str(), i == 0 ? "base" : ("copy " + std::to_string(i)).c_str(),
                       label.c_str(), counts[i], referenceName.c_str(), reference[i]);
          mismatch_ = true;
        }
      }
    }
  }

  void reportMemory(std::string_view name, int dim, std::size_t n, const std::string& dist,
                    const std::string& ratio, const std::string& cell, const std::string& threads,
                    std::size_t bytes) {
    const double perObject = static_cast<double>(bytes) / static_cast<double>(n);
    if (memory_) {
      std::fprintf(memory_, "%.*s,%d,%zu,%s,%s,%s,%zu,%.2f,%s\n", static_cast<int>(name.size()),
                   name.data(), dim, n, dist.c_str(), ratio.c_str(), cell.c_str(), bytes,
                   perObject, threads.c_str());
      std::fflush(memory_);
    } else {
      std::fprintf(stderr,
                   "memory: %.*s dim=%d n=%zu distribution=%s size_ratio=%s cell_factor=%s "
                   "working_bytes=%zu bytes_per_object=%.2f threads=%s\n",
                   static_cast<int>(name.size()), name.data(), dim, n, dist.c_str(), ratio.c_str(),
                   cell.c_str(), bytes, perObject, threads.c_str());
    }
  }

  const Options& o_;
  std::FILE* memory_ = nullptr;
  bool mismatch_ = false;
  bool oracleNoted_ = false;
};

}  // namespace
}  // namespace demlab::bench

int main(int argc, char** argv) {
  try {
    const auto options = demlab::bench::parseOptions(argc, argv);
    demlab::bench::Runner runner(options);
    return runner.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_search: %s\n", e.what());
    return 2;
  }
}
