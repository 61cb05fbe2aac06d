// Workloads for neighbor-search benchmarks and property tests: deterministic sets of balls
// (discs in 2D, D-balls in general) given as their bounding boxes.
//
// Why these distributions: they are the inputs that separate the algorithms. Uniform
// monodisperse beds are what single-size grids were designed for; bidisperse and power-law
// radii break a grid whose cell is sized by the largest object; domain-sized walls break it
// completely (figure 3-9 of the seed); a sparse clustered scene breaks grids whose cost
// depends on the empty space they cover; elongated shapes (rods) at random orientations give
// boxes long on some axes and thin on others, whose bounding spheres are far larger than their
// volume, as non-spherical elements give the neighbour search.
//
// Scale: the smallest radius is 1 (the results are scale free). The domain is sized so that
// the scene has the density of a granular bed: in the monodisperse case each object's box
// overlaps about 9 others (the expected count of a 3D bed of random centres at ball volume
// fraction 0.6). The same neighbour count is used in every dimension, so the reporting work
// per object is the same in 1D..4D and times per object compare across dimensions. Equal
// volume fractions would not give that: 0.8 in 2D gives about 4 neighbours, and 0.6 in 4D
// about 31. For polydisperse sets the domain volume comes from the total ball volume (the sum
// of r^D), as a bed of the same solid fraction would fill.
//
// Determinism: std::mt19937_64 is fully specified by the standard, but the distributions of
// <random> are not, so the real numbers are mapped from raw 64-bit draws here and the same
// seed gives the same boxes with every standard library.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "search/box.hpp"

namespace demlab::search {

enum class Distribution { Uniform, Bidisperse, PowerLaw, PowerLawWalls, Clustered, Rods };

struct WorkloadSpec {
  Distribution distribution;
  std::size_t n;     // number of boxes returned, walls included
  double sizeRatio;  // largest / smallest radius; ignored (taken as 1) by monodisperse sets
  std::uint64_t seed = 1;
};

// Returns the short name used on command lines and in CSV tables.
inline std::string_view distributionName(Distribution d) {
  switch (d) {
    case Distribution::Uniform:
      return "uniform";
    case Distribution::Bidisperse:
      return "bidisperse";
    case Distribution::PowerLaw:
      return "powerlaw";
    case Distribution::PowerLawWalls:
      return "powerlaw_walls";
    case Distribution::Clustered:
      return "clustered";
    case Distribution::Rods:
      return "rods";
  }
  return "?";
}

// Returns the distribution named `name` (as printed by distributionName), or nothing.
inline std::optional<Distribution> parseDistribution(std::string_view name) {
  for (Distribution d : {Distribution::Uniform, Distribution::Bidisperse, Distribution::PowerLaw,
                         Distribution::PowerLawWalls, Distribution::Clustered, Distribution::Rods}) {
    if (distributionName(d) == name) return d;
  }
  return std::nullopt;
}

// Returns true for the distributions whose radii are all r_min, whatever sizeRatio says.
inline bool isMonodisperse(Distribution d) {
  return d == Distribution::Uniform || d == Distribution::Clustered;
}
// Returns true for the distributions where sizeRatio is an aspect ratio, not a size ratio.
inline bool isElongated(Distribution d) { return d == Distribution::Rods; }

namespace workload_detail {

// The smallest radius; every length below is a multiple of it.
inline constexpr double kRMin = 1.0;
// Expected number of other boxes overlapping one box in a monodisperse set: a D-box of side
// 2r overlaps another when their centres lie within a box of side 4r, so the count is
// density * (4r)^D; 3D at ball volume fraction 0.6 gives 0.6 * 64 / (4 pi / 3) = 9.17.
inline constexpr double kNeighbours = 0.6 * 64.0 / (4.0 * 3.14159265358979323846 / 3.0);
// Distance between the centres of neighbouring clusters of the clustered scene.
inline constexpr double kClusterSpacing = 1e6 * kRMin;
inline constexpr int kClusters = 8;
// Fraction of large balls in a bidisperse set, by count.
inline constexpr double kLargeFraction = 0.1;

// Returns a real in [0, 1) from the top 53 bits of one draw.
inline double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Returns x^D for a small positive integer D without pow's rounding differences.
template <int D>
inline double powD(double x) {
  double p = 1.0;
  for (int k = 0; k < D; ++k) p *= x;
  return p;
}

// Returns x^(1/D) for x > 0 using only IEEE-exact operations (frexp, ldexp, + - * /), because
// std::pow and std::cbrt may differ in the last bit between C libraries, and the domain side
// scales every coordinate.
template <int D>
inline double rootD(double x) {
  if (!(x > 0.0)) return 0.0;
  int e = 0;
  std::frexp(x, &e);
  double y = std::ldexp(1.0, e / D);  // a power of two near the root
  // Newton's iteration converges quadratically from there; a fixed count keeps the result a
  // pure function of x even if the last bit oscillates.
  for (int it = 0; it < 64; ++it) y -= (powD<D>(y) - x) / (D * powD<D - 1>(y));
  return y;
}

// Returns the side of a cube holding balls whose radii have sum(r^D) = sumRD at the density
// that gives each monodisperse box kNeighbours overlapping boxes: (4 r)^D * n / L^D = k.
template <int D>
inline double domainSide(double sumRD) {
  return 4.0 * rootD<D>(sumRD / kNeighbours);
}

// Draws one radius of a truncated power law p(r) ~ r^-3 on [kRMin, ratio * kRMin] by inverting
// its CDF F(r) = (1 - (r_min/r)^2) / (1 - ratio^-2).
inline double powerLawRadius(double u, double ratio) {
  const double r = kRMin / std::sqrt(1.0 - u * (1.0 - 1.0 / (ratio * ratio)));
  return std::clamp(r, kRMin, ratio * kRMin);  // guards the last ulp against rounding
}

template <int D, class T>
inline Box<D, T> ballBox(const std::array<double, D>& centre, double r) {
  Box<D, T> b;
  for (int k = 0; k < D; ++k) {
    b.lo[k] = static_cast<T>(centre[k] - r);
    b.hi[k] = static_cast<T>(centre[k] + r);
  }
  return b;
}

}  // namespace workload_detail

// Returns spec.n boxes: the bounding boxes of balls with centres uniformly random in a cube
// domain (per cluster for Clustered), plus for PowerLawWalls four walls (two in 1D) that are
// counted in n and come last. Radii by distribution:
//   Uniform, Clustered: all r_min = 1.
//   Bidisperse: r_min and sizeRatio * r_min, exactly round(n / 10) large ones, spread evenly
//     over the indices (positions are random, so indices carry no spatial order).
//   PowerLaw, PowerLawWalls: truncated power law p(r) ~ r^-3 on [r_min, sizeRatio * r_min].
//   Rods: spherocylinders of radius r_min and aspect ratio sizeRatio (length over width),
//     pointing in directions uniform on the sphere; each box is its rod's, and the domain
//     holds their total volume as a bed of balls of the same volume would.
// Walls are boxes 2 r_min thick, centred on the low and high faces of axes 0 and 1, spanning
// the whole domain on every other axis; in 1D, segments from each end face (r_min inside the
// domain) reaching one domain length outward. Clustered puts the balls in 8 dense cubic clusters
// (granular density each) whose centres are 1e6 r_min apart on a lattice.
// Throws demlab::Error {DEMLAB VALUE WORKLOAD} if sizeRatio is below 1 or not finite.
template <int D, class T>
std::vector<Box<D, T>> makeWorkload(const WorkloadSpec& spec) {
  using namespace workload_detail;
  static_assert(D >= 1, "a workload needs at least one axis");
  const Distribution dist = spec.distribution;
  const double ratio = isMonodisperse(dist) ? 1.0 : spec.sizeRatio;
  if (!std::isfinite(ratio) || ratio < 1.0) {
    throw Error("bad workload: size ratio must be a finite number >= 1, got " +
                    std::to_string(spec.sizeRatio),
                {"VALUE", "WORKLOAD"});
  }
  const std::size_t n = spec.n;
  const std::size_t nWalls =
      dist == Distribution::PowerLawWalls ? std::min<std::size_t>(n, D == 1 ? 2 : 4) : 0;
  const std::size_t nBalls = n - nWalls;
  std::mt19937_64 rng(spec.seed);

  // Radii first: the domain size depends on their total volume.
  std::vector<double> radius(nBalls, kRMin);
  if (dist == Distribution::Bidisperse) {
    const auto nLarge = static_cast<std::size_t>(std::llround(kLargeFraction * nBalls));
    // Ball i is large when the running quota floor(i * nLarge / nBalls) steps up at i.
    for (std::size_t i = 0; i < nBalls; ++i) {
      if ((i + 1) * nLarge / nBalls > i * nLarge / nBalls) radius[i] = ratio * kRMin;
    }
  } else if (dist == Distribution::PowerLaw || dist == Distribution::PowerLawWalls) {
    for (double& r : radius) r = powerLawRadius(uniform01(rng), ratio);
  }

  std::vector<Box<D, T>> boxes;
  boxes.reserve(n);
  std::array<double, D> c{};
  if (dist == Distribution::Clustered) {
    // Each cluster holds its share of the balls at the same density as a uniform bed.
    const std::size_t perCluster = (nBalls + kClusters - 1) / kClusters;
    const double side = domainSide<D>(static_cast<double>(perCluster) * powD<D>(kRMin));
    const double spacing = std::max(kClusterSpacing, 2.0 * side);  // clusters never touch
    for (std::size_t i = 0; i < nBalls; ++i) {
      // Consecutive runs of indices share a cluster; the bits of the cluster number are
      // dealt round-robin over the axes, giving a 2x2x2 lattice in 3D, 4x2 in 2D, a row in 1D.
      const auto cluster = static_cast<unsigned>(i / perCluster);
      std::array<double, D> origin{};
      for (int bit = 0; bit < 3; ++bit) {
        if (cluster & (1u << bit)) origin[bit % D] += spacing * static_cast<double>(1 << (bit / D));
      }
      for (int k = 0; k < D; ++k) c[k] = origin[k] + side * uniform01(rng);
      boxes.push_back(ballBox<D, T>(c, radius[i]));
    }
    return boxes;
  }

  if (dist == Distribution::Rods) {
    // Half the segment's length; a rod's volume over its end ball's (3D 1 + 1.5 h, 2D
    // 1 + 4 h / pi, 1D 1 + h, per unit r_min), which sizes the domain.
    const double h = (ratio - 1.0) * kRMin;
    const double volume = D == 3 ? 1.0 + 1.5 * h : D == 2 ? 1.0 + 4.0 * h / 3.14159265358979323846 : 1.0 + h;
    const double side = domainSide<D>(static_cast<double>(nBalls) * volume);
    for (std::size_t i = 0; i < nBalls; ++i) {
      // A direction uniform on the sphere: a point uniform in the cube [-1, 1]^D kept when it
      // lies in the unit ball (and not at its centre), then scaled to length 1.
      std::array<double, D> d{};
      double len2 = 0.0;
      do {
        len2 = 0.0;
        for (int k = 0; k < D; ++k) {
          d[k] = 2.0 * uniform01(rng) - 1.0;
          len2 += d[k] * d[k];
        }
      } while (!(len2 <= 1.0 && len2 > 1e-12));
      const double len = std::sqrt(len2);
      for (int k = 0; k < D; ++k) c[k] = side * uniform01(rng);
      Box<D, T> b;
      for (int k = 0; k < D; ++k) {
        const double reach = h * std::abs(d[k]) / len + kRMin;
        b.lo[k] = static_cast<T>(c[k] - reach);
        b.hi[k] = static_cast<T>(c[k] + reach);
      }
      boxes.push_back(b);
    }
    return boxes;
  }

  double sumRD = 0.0;
  for (double r : radius) sumRD += powD<D>(r);
  const double side = domainSide<D>(sumRD);
  for (std::size_t i = 0; i < nBalls; ++i) {
    for (int k = 0; k < D; ++k) c[k] = side * uniform01(rng);
    boxes.push_back(ballBox<D, T>(c, radius[i]));
  }

  // Walls last, in the order low 0, high 0, low 1, high 1.
  for (std::size_t w = 0; w < nWalls; ++w) {
    const int axis = static_cast<int>(w / 2);
    const bool low = w % 2 == 0;
    const double face = low ? 0.0 : side;
    Box<D, T> b;
    for (int k = 0; k < D; ++k) {
      b.lo[k] = static_cast<T>(k == axis ? face - kRMin : 0.0);
      b.hi[k] = static_cast<T>(k == axis ? face + kRMin : side);
    }
    if constexpr (D == 1) {
      // A 1D wall has no axis to span, so it is made domain-long the only way it can be:
      // extended outward, away from the balls. It still touches only the balls at its face,
      // as a wall does in 2D and 3D, while its extent is what stresses single-size grids.
      if (low) {
        b.lo[0] = static_cast<T>(-side);
      } else {
        b.hi[0] = static_cast<T>(2.0 * side);
      }
    }
    boxes.push_back(b);
  }
  return boxes;
}

}  // namespace demlab::search
