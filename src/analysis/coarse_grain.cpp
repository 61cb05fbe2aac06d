#include "analysis/coarse_grain.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "analysis/tensor.hpp"
#include "core/interrupt.hpp"

namespace demlab::analysis {

namespace {

constexpr double kPi = std::numbers::pi;

// The kernel of one spec in d dimensions, normalised to integrate to 1.
struct Kernel {
  CgKernel kind;
  double w, cutoff, norm;
  int d;
  Kernel(const CgSpec& spec, int dim)
      : kind(spec.kernel), w(spec.width), cutoff(kernelCutoff(spec)), d(dim) {
    if (kind == CgKernel::Lucy) {
      norm = d == 2 ? 5.0 / (kPi * w * w) : 105.0 / (16.0 * kPi * w * w * w);
      return;
    }
    // The integral of exp(-r^2 / 2w^2) over the ball of radius 3w.
    const double c = cutoff / w;
    double integral = d == 2 ? 2 * kPi * w * w * (1 - std::exp(-c * c / 2))
                             : std::pow(2 * kPi, 1.5) * w * w * w *
                                   (std::erf(c / std::sqrt(2.0)) -
                                    std::sqrt(2 / kPi) * c * std::exp(-c * c / 2));
    norm = 1 / integral;
  }
  // Returns W at squared distance r2 (0 beyond the cutoff).
  double operator()(double r2) const {
    if (r2 >= cutoff * cutoff) return 0;
    if (kind == CgKernel::Gaussian) return norm * std::exp(-r2 / (2 * w * w));
    double q = std::sqrt(r2) / w, m = 1 - q;
    return norm * (1 + 3 * q) * m * m * m;
  }
};

// The grid and its accumulation: adds a weighted kernel at a point to the arrays.
struct Grid {
  CgField& f;
  const Kernel& W;
  int d;
  // Polled once per row of grid points: a wide kernel on a fine grid visits thousands of
  // points per element.
  mutable InterruptPoll poll{"coarse-graining"};
  // Calls add(point index, W) for each grid point within the cutoff of x.
  template <class Add>
  void spread(const Vec3d& x, const Add& add) const {
    std::array<long, 3> from{0, 0, 0}, to{0, 0, 0};
    for (int k = 0; k < d; ++k) {
      double h = f.spacing[k];
      from[k] = std::max(0L, long(std::ceil((x[k] - W.cutoff - f.origin[k]) / h)));
      to[k] = std::min(long(f.dims[k]) - 1, long(std::floor((x[k] + W.cutoff - f.origin[k]) / h)));
      if (to[k] < from[k]) return;
    }
    for (long k = from[2]; k <= to[2]; ++k)
      for (long j = from[1]; j <= to[1]; ++j) {
        poll();
        for (long i = from[0]; i <= to[0]; ++i) {
          const long idx[3] = {i, j, k};
          double r2 = 0;
          for (int a = 0; a < d; ++a) {
            double dx = f.origin[a] + double(idx[a]) * f.spacing[a] - x[a];
            r2 += dx * dx;
          }
          double w = W(r2);
          if (w > 0) add(size_t(i) + f.dims[0] * (size_t(j) + f.dims[1] * size_t(k)), w);
        }
      }
  }
};

}  // namespace

double kernelCutoff(const CgSpec& spec) {
  return spec.kernel == CgKernel::Gaussian ? 3 * spec.width : spec.width;
}

double cgPointCount(const CgSpec& spec, int d) {
  double n = 1;
  for (int k = 0; k < d; ++k) n *= std::floor((spec.hi[k] - spec.lo[k]) / spec.spacing + 1e-9) + 1;
  return n;
}

CgField coarseGrain(const Sample& s, const Selection& sel, const CgSpec& spec) {
  const int d = s.dim;
  CgField f;
  for (int k = 0; k < 3; ++k) {
    f.origin[k] = k < d ? spec.lo[k] : 0;
    f.spacing[k] = spec.spacing;
    f.dims[k] = k < d ? size_t(std::floor((spec.hi[k] - spec.lo[k]) / spec.spacing + 1e-9)) + 1 : 1;
  }
  const size_t n = f.points();
  const auto zeros = [](size_t count) { return polledFill(count, 0.0, "coarse-graining"); };
  std::vector<double> rho = zeros(n), mom = zeros(3 * n), vv = zeros(9 * n), sc = zeros(9 * n);
  const Kernel W(spec, d);
  const Grid g{f, W, d};
  for (size_t i = 0; i < s.size(); ++i) {
    if (!sel.hasTag(i)) continue;
    const double m = s.mass[i];
    const Vec3d& v = s.velocity[i];
    const Tensor mvv = outer(v, v);
    g.spread(s.position[i], [&](size_t p, double w) {
      rho[p] += m * w;
      for (int k = 0; k < 3; ++k) mom[3 * p + k] += m * v[k] * w;
      for (int k = 0; k < 9; ++k) vv[9 * p + k] += m * mvv[k] * w;
    });
  }
  for (const SampleContact& c : s.contacts) {
    for (const Arm& a : armsOf(s, c)) {
      if (!sel.hasTag(a.element)) continue;
      Tensor t = outer(a.force, a.branch);
      double len = 0;
      for (int k = 0; k < d; ++k) len += a.branch[k] * a.branch[k];
      const int pieces = std::max(1, int(std::ceil(4 * std::sqrt(len) / spec.width)));
      const Vec3d& x0 = s.position[a.element];
      for (int q = 0; q < pieces; ++q) {
        double at = (q + 0.5) / pieces;
        Vec3d x{x0[0] + at * a.branch[0], x0[1] + at * a.branch[1], x0[2] + at * a.branch[2]};
        g.spread(x, [&](size_t p, double w) {
          for (int k = 0; k < 9; ++k) sc[9 * p + k] -= t[k] * w / pieces;
        });
      }
    }
  }
  std::vector<double> vel = zeros(3 * n), sk = zeros(9 * n);
  for (size_t p = 0; p < n; ++p) {
    g.poll();
    Vec3d V{};
    if (rho[p] > 0)
      for (int k = 0; k < 3; ++k) V[k] = mom[3 * p + k] / rho[p];
    for (int k = 0; k < 3; ++k) vel[3 * p + k] = V[k];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        sk[9 * p + 3 * a + b] = vv[9 * p + 3 * a + b] - rho[p] * V[a] * V[b];
  }
  f.arrays.push_back({"density", 1, std::move(rho)});
  f.arrays.push_back({"momentum", 3, std::move(mom)});
  f.arrays.push_back({"velocity", 3, std::move(vel)});
  f.arrays.push_back({"contactStress", 9, std::move(sc)});
  f.arrays.push_back({"kineticStress", 9, std::move(sk)});
  return f;
}

}  // namespace demlab::analysis
