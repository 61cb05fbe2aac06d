// bench_decompose: what a distributed run of a scene would hold and send, rank by rank, for
// any number of ranks, measured on one process (doc/plans/mpi.md): the scene's grains are
// bisected into P boxes (mpi::Partition, as the ranks would), each rank's ghosts chosen by the
// reach table (mpi::ReachTable), and the step's forward exchange counted (x, v, w and q of every
// ghost: 13 doubles). The inputs of the scaling model in doc/performance.md.
//
// Usage: bench_decompose [--parts LIST] [--skin M] [--lattice N] [--no-header] DATAFILE...
//   --lattice N   also a bulk scene of N grains (radius 1 mm) on a simple cubic lattice of
//                 spacing 1.9 mm, each jittered by up to 0.05 mm, filling a cube (named
//                 lattice_N): a dense bed in three dimensions, where the scenes of
//                 ../shared/bench are layers on a floor
// Prints one CSV row per scene and rank count:
//   scene,n,parts,owned_mean,owned_max,imbalance,ghosts_mean,ghosts_max,ghost_fraction,
//   neighbours_mean,neighbours_max,bytes_per_step_mean,bytes_per_step_max
// ghost_fraction: all ranks' ghosts over the scene's grains; bytes a step: what one rank sends
// (the same as it receives, summed over the ranks).
#include <algorithm>
#include <cmath>
#include <random>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/lammps_data.hpp"
#include "mpi/partition.hpp"
#include "mpi/reach.hpp"

namespace {

using demlab::mpi::Communicator;
using demlab::mpi::Partition;
using demlab::mpi::Point;
using demlab::mpi::ReachTable;

constexpr double kBytesPerGhost = 13 * sizeof(double);  // x, v, w, q

void measure(const std::string& scene, const std::vector<Point<3>>& x, const std::vector<double>& r,
             int parts, double skin) {
  const Partition<3> part = Partition<3>::bisect(x, {}, parts, Communicator::self());
  const size_t p = static_cast<size_t>(parts);
  std::vector<int> owner(x.size());
  std::vector<std::vector<Point<3>>> cx(p);
  std::vector<std::vector<double>> cr(p);
  for (size_t i = 0; i < x.size(); ++i) {
    owner[i] = part.ownerOf(x[i]);
    cx[static_cast<size_t>(owner[i])].push_back(x[i]);
    cr[static_cast<size_t>(owner[i])].push_back(r[i]);
  }
  std::vector<std::vector<ReachTable<3>::Class>> classes(p);
  for (size_t k = 0; k < p; ++k) classes[k] = ReachTable<3>::classesOf(cx[k], cr[k]);
  const ReachTable<3> table = ReachTable<3>::of(classes);
  std::vector<double> ghosts(p, 0.0), sent(p, 0.0);
  std::vector<std::set<int>> neighbours(p);
  for (size_t i = 0; i < x.size(); ++i) {
    const int o = owner[i];
    table.forEachRankNeeding(x[i], r[i], skin, o, [&](int k) {
      ghosts[static_cast<size_t>(k)] += 1;
      sent[static_cast<size_t>(o)] += 1;
      neighbours[static_cast<size_t>(o)].insert(k);
      neighbours[static_cast<size_t>(k)].insert(o);
    });
  }
  double ownedMax = 0, ghostSum = 0, ghostMax = 0, nbSum = 0, nbMax = 0, sentSum = 0, sentMax = 0;
  std::vector<double> count(p);
  for (size_t k = 0; k < p; ++k) {
    count[k] = static_cast<double>(cx[k].size());
    ownedMax = std::max(ownedMax, count[k]);
    ghostSum += ghosts[k];
    ghostMax = std::max(ghostMax, ghosts[k]);
    nbSum += static_cast<double>(neighbours[k].size());
    nbMax = std::max(nbMax, static_cast<double>(neighbours[k].size()));
    sentSum += sent[k];
    sentMax = std::max(sentMax, sent[k]);
  }
  const double n = static_cast<double>(x.size());
  std::printf("%s,%zu,%d,%.1f,%.0f,%.4f,%.1f,%.0f,%.4f,%.2f,%.0f,%.0f,%.0f\n", scene.c_str(),
              x.size(), parts, n / parts, ownedMax, Partition<3>::imbalance(count),
              ghostSum / parts, ghostMax, ghostSum / n, nbSum / parts, nbMax,
              sentSum / parts * kBytesPerGhost, sentMax * kBytesPerGhost);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> parts{2, 4, 8, 16, 32, 64, 128, 256, 512, 1024};
  double skin = 2.5e-4;
  bool header = true;
  std::vector<std::string> files;
  long lattice = 0;
  for (int a = 1; a < argc; ++a) {
    const std::string s = argv[a];
    if (s == "--parts" && a + 1 < argc) {
      parts.clear();
      std::stringstream list(argv[++a]);
      for (std::string item; std::getline(list, item, ',');) parts.push_back(std::atoi(item.c_str()));
    } else if (s == "--skin" && a + 1 < argc) {
      skin = std::atof(argv[++a]);
    } else if (s == "--lattice" && a + 1 < argc) {
      lattice = std::atol(argv[++a]);
    } else if (s == "--no-header") {
      header = false;
    } else if (s == "-h" || s == "--help" || s.rfind("--", 0) == 0) {
      std::fprintf(stderr,
                   "usage: bench_decompose [--parts LIST] [--skin M] [--lattice N] [--no-header] "
                   "DATAFILE...\n");
      return s == "-h" || s == "--help" ? 0 : 2;
    } else {
      files.push_back(s);
    }
  }
  for (int p : parts) {
    if (p < 1) {
      std::fprintf(stderr, "bench_decompose: --parts takes counts of at least 1\n");
      return 2;
    }
  }
  if (header) {
    std::printf("scene,n,parts,owned_mean,owned_max,imbalance,ghosts_mean,ghosts_max,"
                "ghost_fraction,neighbours_mean,neighbours_max,bytes_per_step_mean,"
                "bytes_per_step_max\n");
  }
  if (lattice > 0) {
    const long side = std::lround(std::ceil(std::cbrt(static_cast<double>(lattice))));
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> jitter(-5e-5, 5e-5);
    std::vector<Point<3>> x;
    std::vector<double> r;
    for (long i = 0; i < lattice; ++i) {
      const long a = i % side, b = (i / side) % side, c = i / (side * side);
      x.push_back({1.9e-3 * a + jitter(rng), 1.9e-3 * b + jitter(rng), 1.9e-3 * c + jitter(rng)});
      r.push_back(1e-3);
    }
    for (int p : parts) measure("lattice_" + std::to_string(lattice), x, r, p, skin);
  }
  for (const std::string& f : files) {
    const demlab::io::SphereData d = demlab::io::readLammpsData(f);
    std::vector<Point<3>> x(d.positions.size());
    std::vector<double> r(d.positions.size());
    for (size_t i = 0; i < x.size(); ++i) {
      x[i] = {d.positions[i].x(), d.positions[i].y(), d.positions[i].z()};
      r[i] = d.diameters[i] / 2;
    }
    for (int p : parts) measure(demlab::io::sceneName(f), x, r, p, skin);
  }
  return 0;
}
