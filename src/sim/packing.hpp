// Packing: regions, size distributions and the placement of many elements at once (a
// lattice, random sequential addition), for the pack commands and for anything that inserts
// elements into a region (sources). Positions and radii only: the caller makes the Defs.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "sim/simulation.hpp"

namespace demlab::sim {

// A region: a box [lo, hi], a sphere (a disc in 2D) or, in 3D, a cylinder (centre, unit axis,
// radius, half length). Coordinates beyond the dimension are 0.
struct Region {
  enum Kind { Box, Sphere, Cylinder } kind = Box;
  Vec3d lo{}, hi{};  // Box
  Vec3d centre{};    // Sphere (a disc in 2D), Cylinder
  double radius = 0;
  Vec3d axis{};           // Cylinder
  double halfLength = 0;  // Cylinder
  // Returns true if a ball of radius r at p lies inside the region.
  // Rounding of lattice coordinates is forgiven up to 1e-9 radii, so a lattice that exactly
  // fits its box keeps its last row.
  bool holds(const Vec3d& p, double r, int d) const {
    double tol = 1e-9 * r;
    if (kind == Box) {
      for (int k = 0; k < d; ++k)
        if (p[k] - r < lo[k] - tol || p[k] + r > hi[k] + tol) return false;
      return true;
    }
    if (kind == Cylinder) {
      double along = 0;
      for (int k = 0; k < 3; ++k) along += (p[k] - centre[k]) * axis[k];
      double s = 0;
      for (int k = 0; k < 3; ++k) {
        const double q = p[k] - centre[k] - along * axis[k];
        s += q * q;
      }
      return std::abs(along) + r <= halfLength + tol && std::sqrt(s) + r <= radius + tol;
    }
    double s = 0;
    for (int k = 0; k < d; ++k) s += (p[k] - centre[k]) * (p[k] - centre[k]);
    return std::sqrt(s) + r <= radius + tol;
  }
  double volume(int d) const {
    if (kind == Box) {
      double v = 1;
      for (int k = 0; k < d; ++k) v *= hi[k] - lo[k];
      return v;
    }
    if (kind == Cylinder) return std::numbers::pi * radius * radius * 2 * halfLength;
    return d == 2 ? std::numbers::pi * radius * radius
                  : 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  }
  void bounds(int d, Vec3d& a, Vec3d& b) const {
    a = lo, b = hi;
    if (kind == Sphere)
      for (int k = 0; k < d; ++k) a[k] = centre[k] - radius, b[k] = centre[k] + radius;
    if (kind == Cylinder) {
      for (int k = 0; k < d; ++k) {
        const double e = halfLength * std::abs(axis[k]) +
                         radius * std::sqrt(std::max(0.0, 1 - axis[k] * axis[k]));
        a[k] = centre[k] - e, b[k] = centre[k] + e;
      }
    }
  }
};

// A distribution of radii: "constant" {r}, "uniform" {a b}, "normal" {mean sd} (cut at 3 sd,
// positive), "powerlaw" {a b exponent} (density ~ r^exponent on [a, b]) or "discrete"
// {r1 w1 r2 w2 ...}. Checked by the caller (the pack command's parser).
struct SizeDistribution {
  std::string kind = "constant";
  std::vector<double> p;
  double maxRadius() const {
    if (kind == "constant") return p[0];
    if (kind == "uniform" || kind == "powerlaw") return p[1];
    if (kind == "normal") return p[0] + 3 * p[1];
    double m = 0;
    for (std::size_t k = 0; k < p.size(); k += 2) m = std::max(m, p[k]);
    return m;
  }
  // Returns the smallest radius it can draw (the normal's cut at 3 sd, when positive; else 0).
  double minRadius() const {
    if (kind == "constant" || kind == "uniform" || kind == "powerlaw") return p[0];
    if (kind == "normal") return std::max(0.0, p[0] - 3 * p[1]);
    double m = maxRadius();
    for (std::size_t k = 0; k + 1 < p.size(); k += 2)
      if (p[k + 1] > 0) m = std::min(m, p[k]);
    return m;
  }
  // Returns the probability that a drawn radius is at most r (the distribution function),
  // for the tests' Kolmogorov-Smirnov comparison and the sources' statistics.
  double cdf(double r) const;
  // Returns one radius drawn with rng, any 64-bit generator (reproducible: the transforms are
  // ours). Changes rng.
  template <class Rng>
  double draw(Rng& rng) const {
    auto u = [&] { return double(rng() >> 11) * 0x1.0p-53; };
    if (kind == "constant") return p[0];
    if (kind == "uniform") return p[0] + (p[1] - p[0]) * u();
    if (kind == "powerlaw") {  // density ~ r^exponent on [a, b]
      // The inverse of the distribution function in logarithms, so no power of a or b is
      // formed: a^(e+1) overflows for a large exponent even when the radii are ordinary.
      const double a = p[0], b = p[1], t = p[2] + 1, rho = std::log(b / a), x = u();
      double r;
      if (std::abs(t) * rho < 1e-12) {
        r = a * std::exp(rho * x);
      } else if (t > 0) {
        r = b * std::exp(std::log(x + (1 - x) * std::exp(-t * rho)) / t);
      } else {
        r = a * std::exp(std::log1p(x * std::expm1(t * rho)) / t);
      }
      return std::clamp(r, a, b);
    }
    if (kind == "normal") {
      while (true) {
        double z = std::sqrt(-2 * std::log(1 - u())) * std::cos(2 * std::numbers::pi * u());
        if (std::abs(z) <= 3) {
          double r = p[0] + p[1] * z;
          if (r > 0) return r;
        }
      }
    }
    double total = 0;
    for (std::size_t k = 1; k < p.size(); k += 2) total += p[k];
    double x = u() * total;
    for (std::size_t k = 0; k + 1 < p.size(); k += 2) {
      if (x < p[k + 1]) return p[k];
      x -= p[k + 1];
    }
    return p[p.size() - 2];
  }
};

// The largest number of elements one placement makes (2^27).
inline constexpr std::size_t kMaxPack = std::size_t(1) << 27;

struct LatticeDef {
  Region region;
  double radius = 0;
  double spacing = 0;  // between neighbours, >= 2 radius
  bool hex = false;    // triangular in 2D, FCC (ABC layers) in 3D; else square / cubic
};

// Returns the number of lattice sites tried for def (those in the region's bounds), to refuse a
// lattice beyond kMaxPack before making it. Changes nothing.
double latticeCandidates(const LatticeDef& def, int dim);

// Returns the centres of the lattice's elements that lie inside the region, in x-fastest order.
// Changes nothing.
std::vector<Vec3d> latticeSites(const LatticeDef& def, int dim);

// Returns radii drawn from dist with rng: count of them, or (count 0) as many as fill
// fraction x the region's volume (at most kMaxPack); sorted largest first. Changes rng.
std::vector<double> drawRadii(const SizeDistribution& dist, const Region& region, int dim,
                              std::size_t count, double fraction, std::mt19937_64& rng);

// Returns the centres of balls of the given radii (in that order) placed by random sequential
// addition inside region, overlapping neither each other nor the balls (existingPositions, dim
// numbers each; existingRadii) already there. Changes rng. Throws {PACK FULL} naming the first
// ball that found no place in `tries` attempts, {INTERRUPTED} when *stop reads true (polled
// every 4096 attempts).
std::vector<Vec3d> randomSites(const Region& region, int dim, const std::vector<double>& radii,
                               const std::vector<double>& existingPositions,
                               const std::vector<double>& existingRadii, std::int64_t tries,
                               std::mt19937_64& rng, const std::atomic<bool>* stop = nullptr);

}  // namespace demlab::sim
