// Packing (sim/packing.hpp): lattice sites, drawn radii and random sequential addition.
#include "sim/packing.hpp"

#include <array>
#include <functional>
#include <unordered_map>

#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "physics/material.hpp"

namespace demlab::sim {

namespace {

// Hash grids of the balls placed so far, for the overlap test of random packing: level L has
// cells of h * 2^L and holds the balls of radius up to half its cell, so a query looks at a few
// cells per level however the radii differ (a grain of 1e-6 m beside one of 0.02 m would
// otherwise scan 10^12 cells of the small grains' size).
class BallGrid {
 public:
  BallGrid(double cell, int d) : h_(cell), d_(d) {}
  // Returns nothing; adds a ball of radius r at p.
  void add(const Vec3d& p, double r) {
    const std::size_t L = levelOf(r);
    if (L >= levels_.size()) levels_.resize(L + 1);
    Level& l = levels_[L];
    l.maxR = std::max(l.maxR, r);
    balls_.push_back({p, r});
    l.cells[key(cellOf(p, cellSize(L)))].push_back(balls_.size() - 1);
  }
  // Returns true if a ball of radius r at p overlaps none of the balls.
  bool free(const Vec3d& p, double r) const {
    for (std::size_t L = 0; L < levels_.size(); ++L) {
      const Level& l = levels_[L];
      if (l.cells.empty()) continue;
      const double h = cellSize(L);
      const auto c = cellOf(p, h);
      const long reach = long(std::ceil((r + l.maxR) / h));
      std::array<long, 3> lo{0, 0, 0}, hi{0, 0, 0};
      for (int k = 0; k < d_; ++k)
        lo[std::size_t(k)] = c[std::size_t(k)] - reach,
        hi[std::size_t(k)] = c[std::size_t(k)] + reach;
      for (long x = lo[0]; x <= hi[0]; ++x)
        for (long y = lo[1]; y <= hi[1]; ++y)
          for (long z = lo[2]; z <= hi[2]; ++z) {
            auto it = l.cells.find(key({x, y, z}));
            if (it == l.cells.end()) continue;
            for (std::size_t b : it->second) {
              double s = 0;
              for (int k = 0; k < d_; ++k)
                s += (p[std::size_t(k)] - balls_[b].p[std::size_t(k)]) *
                     (p[std::size_t(k)] - balls_[b].p[std::size_t(k)]);
              const double rr = r + balls_[b].r;
              if (s < rr * rr) return false;
            }
          }
    }
    return true;
  }

 private:
  struct Ball {
    Vec3d p;
    double r;
  };
  struct Level {
    double maxR = 0;
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells;
  };
  double cellSize(std::size_t L) const { return std::ldexp(h_, int(L)); }
  // Returns the first level whose cells are at least the ball's diameter wide.
  std::size_t levelOf(double r) const {
    std::size_t L = 0;
    while (cellSize(L) < 2 * r && L < 1000) ++L;
    return L;
  }
  std::array<long, 3> cellOf(const Vec3d& p, double h) const {
    std::array<long, 3> c{0, 0, 0};
    for (int k = 0; k < d_; ++k) c[std::size_t(k)] = long(std::floor(p[std::size_t(k)] / h));
    return c;
  }
  static std::uint64_t key(const std::array<long, 3>& c) {
    return std::uint64_t(c[0]) * 0x9E3779B97F4A7C15ull ^
           std::uint64_t(c[1]) * 0xC2B2AE3D27D4EB4Full ^
           std::uint64_t(c[2]) * 0x165667B19E3779F9ull;
  }
  double h_;
  int d_;
  std::vector<Ball> balls_;
  std::vector<Level> levels_;
};

}  // namespace

namespace {

// The lattice's steps per axis: hex rows are a sqrt(3)/2 apart, FCC layers a sqrt(2/3).
Vec3d latticeStep(const LatticeDef& def, int d) {
  const double a = def.spacing;
  return {a, def.hex ? a * std::sqrt(3.0) / 2 : a,
          def.hex && d == 3 ? a * std::sqrt(2.0 / 3.0) : a};
}

std::array<double, 3> latticeCounts(const LatticeDef& def, int d) {
  const Vec3d step = latticeStep(def, d);
  Vec3d lo, hi;
  def.region.bounds(d, lo, hi);
  std::array<double, 3> n{1, 1, 1};
  for (int k = 0; k < d; ++k)
    n[std::size_t(k)] =
        std::floor((hi[std::size_t(k)] - lo[std::size_t(k)]) / step[std::size_t(k)]) + 2;
  return n;
}

}  // namespace

double latticeCandidates(const LatticeDef& def, int dim) {
  const auto n = latticeCounts(def, dim);
  return n[0] * n[1] * n[2];
}

std::vector<Vec3d> latticeSites(const LatticeDef& def, int d) {
  const Vec3d step = latticeStep(def, d);
  const auto n = latticeCounts(def, d);
  const double a = def.spacing, rad = def.radius;
  const bool hex = def.hex;
  Vec3d lo, hi;
  def.region.bounds(d, lo, hi);
  std::vector<Vec3d> out;
  InterruptPoll poll("pack");
  for (long z = 0; z < long(n[2]); ++z)
    for (long y = 0; y < long(n[1]); ++y)
      for (long x = 0; x < long(n[0]); ++x) {
        poll();
        Vec3d p{lo[0] + rad + double(x) * step[0], lo[1] + rad + double(y) * step[1], 0};
        if (d == 3) p[2] = lo[2] + rad + double(z) * step[2];
        if (hex) {
          if (d == 2 && (y & 1)) p[0] += a / 2;
          if (d == 3) {  // FCC: rows offset within a layer, layers in ABC stacking
            if (y & 1) p[0] += a / 2;
            long layer = z % 3;
            p[0] += double(layer) * a / 2;
            p[1] += double(layer) * a * std::sqrt(3.0) / 6;
          }
        }
        if (def.region.holds(p, rad, d)) out.push_back(p);
      }
  return out;
}

double SizeDistribution::cdf(double r) const {
  auto clamp01 = [](double x) { return std::min(1.0, std::max(0.0, x)); };
  if (kind == "constant") return r >= p[0] ? 1 : 0;
  if (kind == "uniform")
    return p[1] > p[0] ? clamp01((r - p[0]) / (p[1] - p[0])) : (r >= p[0] ? 1 : 0);
  if (kind == "powerlaw") {
    const double a = p[0], b = p[1], e = p[2];
    if (r <= a) return 0;
    if (r >= b) return 1;
    if (std::abs(e + 1) < 1e-12) return std::log(r / a) / std::log(b / a);
    return (std::pow(r, e + 1) - std::pow(a, e + 1)) / (std::pow(b, e + 1) - std::pow(a, e + 1));
  }
  if (kind == "normal") {
    if (p[1] == 0) return r >= p[0] ? 1 : 0;
    // Cut at 3 sd and at zero, as draw() cuts it.
    auto phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
    const double lo = std::max(-3.0, -p[0] / p[1]);
    const double z = std::min(3.0, (r - p[0]) / p[1]);
    if (z <= lo) return 0;
    return clamp01((phi(z) - phi(lo)) / (phi(3) - phi(lo)));
  }
  double total = 0, below = 0;
  for (std::size_t k = 0; k + 1 < p.size(); k += 2) {
    total += p[k + 1];
    if (p[k] <= r) below += p[k + 1];
  }
  return below / total;
}

std::vector<double> drawRadii(const SizeDistribution& dist, const Region& region, int d,
                              std::size_t count, double fraction, std::mt19937_64& rng) {
  std::vector<double> radii;
  if (count > 0) {
    for (std::size_t k = 0; k < count; ++k) radii.push_back(dist.draw(rng));
  } else {
    double target = fraction * region.volume(d), vol = 0;
    while (vol < target && radii.size() < kMaxPack) {
      double rr = dist.draw(rng);
      radii.push_back(rr);
      vol += d == 2 ? std::numbers::pi * rr * rr : 4.0 / 3.0 * std::numbers::pi * rr * rr * rr;
    }
  }
  std::sort(radii.begin(), radii.end(), std::greater<>());
  return radii;
}

std::vector<Vec3d> randomSites(const Region& reg, int d, const std::vector<double>& radii,
                               const std::vector<double>& pos, const std::vector<double>& rs,
                               std::int64_t tries, std::mt19937_64& rng,
                               const std::atomic<bool>* stop) {
  std::vector<Vec3d> out;
  if (radii.empty()) return out;
  double rmax = *std::max_element(radii.begin(), radii.end());
  BallGrid grid(2 * rmax, d);
  for (std::size_t k = 0; k < rs.size(); ++k) {  // the elements already there
    Vec3d p{pos[k * std::size_t(d)], pos[k * std::size_t(d) + 1], d == 3 ? pos[k * 3 + 2] : 0};
    grid.add(p, rs[k]);
  }
  Vec3d lo, hi;
  reg.bounds(d, lo, hi);
  auto u = [&] { return double(rng() >> 11) * 0x1.0p-53; };
  out.reserve(radii.size());
  std::uint64_t attempts = 0;
  for (double rr : radii) {
    bool placed = false;
    for (std::int64_t t = 0; t < tries && !placed; ++t) {
      if ((++attempts & 4095) == 0 && stop && stop->load(std::memory_order_relaxed)) {
        throw Error("pack interrupted after placing " + std::to_string(out.size()) + " of " +
                        std::to_string(radii.size()) + " elements; nothing was added",
                    {"INTERRUPTED"});
      }
      Vec3d p{0, 0, 0};
      for (int k = 0; k < d; ++k)
        p[std::size_t(k)] =
            lo[std::size_t(k)] + rr + (hi[std::size_t(k)] - lo[std::size_t(k)] - 2 * rr) * u();
      if (!reg.holds(p, rr, d) || !grid.free(p, rr)) continue;
      grid.add(p, rr);
      out.push_back(p);
      placed = true;
    }
    if (!placed) {
      throw Error("couldn't place element " + std::to_string(out.size() + 1) + " of " +
                      std::to_string(radii.size()) + " (radius " + physics::formatReal(rr) +
                      ") after " + std::to_string(tries) +
                      " tries: the region is too full; use fewer elements, a larger region or "
                      "more -tries",
                  {"PACK", "FULL"});
    }
  }
  return out;
}

}  // namespace demlab::sim
