// Standalone driver: times CGrid<3,double>::findPairs on uniform workloads (jittered copies).
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <algorithm>
#include <string>
#define private public
#include "search/cgrid.hpp"
#undef private
#include "search/workload.hpp"
using namespace demlab::search;
int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::strtod(argv[1], nullptr) : 1e6;
  const int reps = argc > 2 ? std::atoi(argv[2]) : 5;
  const std::string dist = argc > 3 ? argv[3] : "uniform";
  Distribution dd = dist == "clustered" ? Distribution::Clustered : dist == "bidisperse" ? Distribution::Bidisperse : dist == "powerlaw_walls" ? Distribution::PowerLawWalls : Distribution::Uniform;
  WorkloadSpec spec{dd, n, argc > 4 ? std::atof(argv[4]) : 1.0, 1};
  std::vector<std::vector<Box<3, double>>> in;
  in.push_back(makeWorkload<3, double>(spec));
  if (argc > 5) {  // rods: every box stretched along axis 1 by this many widths
    const double f = std::atof(argv[5]);
    const int ax = argc > 6 ? std::atoi(argv[6]) : 1;
    for (auto& b : in[0]) b.hi[ax] += f * (b.hi[ax] - b.lo[ax]);
  }
  for (int k = 1; k <= 3; ++k) {
    std::mt19937_64 rng(k * 77);
    auto c = in[0];
    for (auto& b : c) {
      double r = 0.5 * (b.hi[0] - b.lo[0]);
      for (int a = 0; a < 3; ++a) {
        double d = ((rng() >> 11) * 0x1.0p-53 * 2 - 1) * 0.01 * r;
        b.lo[a] += d; b.hi[a] += d;
      }
    }
    in.push_back(c);
  }
  CGrid<3, double> g;
#ifdef NARROW
  g.useWideScans(false);
#endif
  std::vector<IndexPair> out;
  g.findPairs(in[0], out);
  std::vector<double> t;
  std::size_t pairs = 0;
  for (int r = 0; r < reps; ++r) {
    timespec t0, t1;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    g.findPairs(in[1 + r % 3], out);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
    t.push_back((t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec));
    pairs = out.size();
  }
  std::vector<double> td;
  for (int r = 0; r < reps; ++r) {
    timespec t0, t1;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
    g.discretize(in[1 + r % 3]);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
    td.push_back((t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec));
  }
  std::sort(td.begin(), td.end());
  std::printf("discretize median=%.1f min=%.1f  ", td[td.size() / 2] * 1e9 / n, td[0] * 1e9 / n);
  std::sort(t.begin(), t.end());
  std::printf("n=%zu pairs=%zu ns/obj median=%.1f min=%.1f bytes/obj=%.1f\n", n, pairs,
              t[t.size() / 2] * 1e9 / n, t[0] * 1e9 / n, double(g.workingBytes()) / n);
}
