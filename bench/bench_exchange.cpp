// bench_exchange: the decomposition's own costs on real ranks (run it under mpirun): each rank
// reads the scene, keeps a share that has nothing to do with space (every P-th grain), and
// then does what a distributed run does at a neighbour search (bisect, migrate the grains to
// their owners, gather the reach table, make the ghost plan) and at every step (send the
// ghosts' x, v, w and q: 13 doubles, point to point). Times are the slowest rank's, taken
// between barriers.
//
// With --work US each step also computes about US microseconds (the same arithmetic and memory
// reads on every rank, sized once) before its exchange, as a step's passes do: the step then
// costs the work, the exchange and the wait for the slowest rank's work, which on a machine
// whose cores run a fixed work in varying times (jitter) is most of an exchange's cost. With
// --overlap the exchange is posted before the work and received after it (mpi::PostedExchange,
// as the step sends its ghosts' forces before the walls' pass).
//
// Usage: mpirun -np P bench_exchange [--steps N] [--skin M] [--work US] [--overlap]
//                                    [--no-header] DATAFILE...
// Prints on rank 0 one CSV row per scene:
//   scene,n,ranks,owned_max,ghosts_max,sent_bytes_max,neighbours_max,search_ms,step_us,
//   work_us,work_p10_us,work_p90_us,overlap
// (work_us: the fixed work's mean time a step, the largest rank's; work_p10_us, work_p90_us: its
// 10th and 90th percentiles, the largest rank's.)
#include <mpi.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/lammps_data.hpp"
#include "mpi/communicator.hpp"
#include "mpi/ghost_plan.hpp"
#include "mpi/partition.hpp"
#include "mpi/reach.hpp"
#include "mpi/records.hpp"

namespace {

using namespace demlab::mpi;

struct Grain {
  Point<3> x;
  double r;
};

// A grain's state as a step sends it: x, v, w and q.
using State = std::array<double, 13>;

double seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// A fixed work: `rounds` passes of reads and multiply-adds over 1.6 MB (a step's arrays do not
// fit a core's first caches either). Returns a value the compiler cannot drop.
double work(const std::vector<double>& data, long rounds) {
  double sum = 0;
  for (long r = 0; r < rounds; ++r) {
    for (size_t i = 0; i < data.size(); i += 8) sum = sum * 0.999999 + data[i];
  }
  return sum;
}

// Returns the rounds of work() that take about us microseconds on this rank (the median of
// repeated timings of one round).
long roundsFor(const std::vector<double>& data, double us) {
  if (us <= 0) return 0;
  std::vector<double> t(51);
  volatile double keep = 0;
  for (double& x : t) {
    const double t0 = seconds();
    keep = keep + work(data, 1);
    x = seconds() - t0;
  }
  std::nth_element(t.begin(), t.begin() + 25, t.end());
  return std::max(1L, static_cast<long>(us * 1e-6 / t[25] + 0.5));
}

// Returns the q-th quantile (0..1) of v (reorders v).
double quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  const Communicator& c = Communicator::world();
  long steps = 1000;
  double skin = 2.5e-4, workUs = 0;
  bool header = true, overlap = false;
  std::vector<std::string> files;
  for (int a = 1; a < argc; ++a) {
    const std::string s = argv[a];
    if (s == "--steps" && a + 1 < argc) {
      steps = std::atol(argv[++a]);
    } else if (s == "--skin" && a + 1 < argc) {
      skin = std::atof(argv[++a]);
    } else if (s == "--work" && a + 1 < argc) {
      workUs = std::atof(argv[++a]);
    } else if (s == "--overlap") {
      overlap = true;
    } else if (s == "--no-header") {
      header = false;
    } else if (s.rfind("--", 0) == 0) {
      if (c.rank() == 0) {
        std::fprintf(stderr, "usage: mpirun -np P bench_exchange [--steps N] [--skin M] "
                             "[--work US] [--overlap] [--no-header] DATAFILE...\n");
      }
      MPI_Finalize();
      return 2;
    } else {
      files.push_back(s);
    }
  }
  if (header && c.rank() == 0) {
    std::printf("scene,n,ranks,owned_max,ghosts_max,sent_bytes_max,neighbours_max,search_ms,step_us,"
                "work_us,work_p10_us,work_p90_us,overlap\n");
  }
  for (const std::string& f : files) {
    const demlab::io::SphereData d = demlab::io::readLammpsData(f);
    std::vector<Grain> mine;
    std::vector<Point<3>> centres;
    for (size_t i = 0; i < d.positions.size(); ++i) {
      if (static_cast<int>(i % static_cast<size_t>(c.size())) != c.rank()) continue;
      mine.push_back({{d.positions[i].x(), d.positions[i].y(), d.positions[i].z()}, d.diameters[i] / 2});
      centres.push_back(mine.back().x);
    }
    c.barrier();
    const double t0 = seconds();
    // A search's decomposition: bisect, migrate, reach table, ghost plan.
    const Partition<3> part = Partition<3>::bisect(centres, {}, c.size(), c);
    std::vector<std::vector<Grain>> out(static_cast<size_t>(c.size()));
    for (const Grain& g : mine) out[static_cast<size_t>(part.ownerOf(g.x))].push_back(g);
    const std::vector<Grain> owned = exchangeRecords(c, out);
    std::vector<Point<3>> x;
    std::vector<double> r;
    for (const Grain& g : owned) {
      x.push_back(g.x);
      r.push_back(g.r);
    }
    const ReachTable<3> table = ReachTable<3>::gather(x, r, c);
    const GhostPlan<3> plan = GhostPlan<3>::make(table, x, r, skin, c);
    const double search = c.max(seconds() - t0);
    // The steps' exchange.
    std::vector<State> state(owned.size());
    for (size_t i = 0; i < owned.size(); ++i) {
      state[i].fill(0.0);
      for (int k = 0; k < 3; ++k) state[i][static_cast<size_t>(k)] = owned[i].x[static_cast<size_t>(k)];
    }
    const std::vector<double> data(200000, 1.0);
    // (The ranks agree on one size of work: the smallest any rank measured.)
    const long rounds = static_cast<long>(c.min(static_cast<double>(roundsFor(data, workUs))));
    std::vector<double> worked;
    worked.reserve(static_cast<size_t>(steps));
    volatile double keep = 0;
    const auto timedWork = [&] {
      if (rounds == 0) return;
      const double w0 = seconds();
      keep = keep + work(data, rounds);
      worked.push_back(seconds() - w0);
    };
    c.barrier();
    const double t1 = seconds();
    size_t received = 0;
    std::vector<State> ghosts;
    for (long s = 0; s < steps; ++s) {
      if (overlap) {
        plan.sendForward<State>([&](uint32_t i, State& out) { out = state[i]; }, c);
        timedWork();
        plan.receiveForward<State>([&](size_t, const State&) { ++received; });
      } else {
        timedWork();
        plan.forward(state, c, ghosts);
        received += ghosts.size();
      }
    }
    plan.finishSends();
    const double step = c.max(seconds() - t1) / static_cast<double>(std::max(1L, steps));
    double workSum = 0;
    for (double w : worked) workSum += w;
    const double workMean = c.max(worked.empty() ? 0.0 : workSum / static_cast<double>(worked.size()));
    const double workP10 = c.max(quantile(worked, 0.1)), workP90 = c.max(quantile(worked, 0.9));
    const double ownedMax = c.max(static_cast<double>(owned.size()));
    const double ghostsMax = c.max(static_cast<double>(plan.ghosts()));
    const double sentMax = c.max(static_cast<double>(plan.sent() * sizeof(State)));
    const double nbMax = c.max(static_cast<double>(
        std::max(plan.sendRanks().size(), plan.receiveRanks().size())));
    if (c.rank() == 0) {
      std::printf("%s,%zu,%d,%.0f,%.0f,%.0f,%.0f,%.3f,%.2f,%.2f,%.2f,%.2f,%d\n",
                  demlab::io::sceneName(f).c_str(), d.positions.size(), c.size(), ownedMax,
                  ghostsMax, sentMax, nbMax, 1e3 * search, 1e6 * step, 1e6 * workMean,
                  1e6 * workP10, 1e6 * workP90, overlap ? 1 : 0);
    }
    if (received != plan.ghosts() * static_cast<size_t>(steps)) std::abort();
  }
  MPI_Finalize();
  return 0;
}
