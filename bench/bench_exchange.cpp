// bench_exchange: the decomposition's own costs on real ranks (run it under mpirun): each rank
// reads the scene, keeps a share that has nothing to do with space (every P-th grain), and
// then does what a distributed run does at a neighbour search (bisect, migrate the grains to
// their owners, gather the reach table, make the ghost plan) and at every step (send the
// ghosts' x, v, w and q: 13 doubles, point to point). Times are the slowest rank's, taken
// between barriers.
//
// Usage: mpirun -np P bench_exchange [--steps N] [--skin M] [--no-header] DATAFILE...
// Prints on rank 0 one CSV row per scene:
//   scene,n,ranks,owned_max,ghosts_max,sent_bytes_max,neighbours_max,search_ms,step_us
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

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  const Communicator& c = Communicator::world();
  long steps = 1000;
  double skin = 2.5e-4;
  bool header = true;
  std::vector<std::string> files;
  for (int a = 1; a < argc; ++a) {
    const std::string s = argv[a];
    if (s == "--steps" && a + 1 < argc) {
      steps = std::atol(argv[++a]);
    } else if (s == "--skin" && a + 1 < argc) {
      skin = std::atof(argv[++a]);
    } else if (s == "--no-header") {
      header = false;
    } else if (s.rfind("--", 0) == 0) {
      if (c.rank() == 0) {
        std::fprintf(stderr, "usage: mpirun -np P bench_exchange [--steps N] [--skin M] "
                             "[--no-header] DATAFILE...\n");
      }
      MPI_Finalize();
      return 2;
    } else {
      files.push_back(s);
    }
  }
  if (header && c.rank() == 0) {
    std::printf("scene,n,ranks,owned_max,ghosts_max,sent_bytes_max,neighbours_max,search_ms,step_us\n");
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
    c.barrier();
    const double t1 = seconds();
    size_t received = 0;
    std::vector<State> ghosts;
    for (long s = 0; s < steps; ++s) {
      plan.forward(state, c, ghosts);
      received += ghosts.size();
    }
    const double step = c.max(seconds() - t1) / static_cast<double>(std::max(1L, steps));
    const double ownedMax = c.max(static_cast<double>(owned.size()));
    const double ghostsMax = c.max(static_cast<double>(plan.ghosts()));
    const double sentMax = c.max(static_cast<double>(plan.sent() * sizeof(State)));
    const double nbMax = c.max(static_cast<double>(
        std::max(plan.sendRanks().size(), plan.receiveRanks().size())));
    if (c.rank() == 0) {
      std::printf("%s,%zu,%d,%.0f,%.0f,%.0f,%.0f,%.3f,%.2f\n", demlab::io::sceneName(f).c_str(), d.positions.size(),
                  c.size(), ownedMax, ghostsMax, sentMax, nbMax, 1e3 * search, 1e6 * step);
    }
    if (received != plan.ghosts() * static_cast<size_t>(steps)) std::abort();
  }
  MPI_Finalize();
  return 0;
}
