// Second-order tensors of the analysis queries (stress, fabric): 3 x 3, row-major, with the
// rows and columns beyond the dimension zero in 2D, and the invariants the queries report.
#pragma once

#include <array>
#include <cmath>

#include "sim/simulation.hpp"

namespace demlab::analysis {

using sim::Vec3d;
using Tensor = std::array<double, 9>;  // row-major: t[3 * i + j]

// Returns a (x) b (the dyad a_i b_j). Changes nothing.
inline Tensor outer(const Vec3d& a, const Vec3d& b) {
  Tensor t{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t[3 * i + j] = a[i] * b[j];
  return t;
}

// Adds w x t to sum. Changes sum.
inline void addScaled(Tensor& sum, const Tensor& t, double w) {
  for (int k = 0; k < 9; ++k) sum[k] += w * t[k];
}

// Returns the mean normal component, trace / d (the pressure of a stress). Changes nothing.
inline double meanNormal(const Tensor& t, int d) {
  double s = 0;
  for (int k = 0; k < d; ++k) s += t[4 * k];
  return s / d;
}

// Returns the deviator t - (trace / d) I over the first d axes. Changes nothing.
inline Tensor deviator(const Tensor& t, int d) {
  Tensor s = t;
  double p = meanNormal(t, d);
  for (int k = 0; k < d; ++k) s[4 * k] -= p;
  return s;
}

// Returns the deviatoric magnitude sqrt(d / (d - 1) s:s) of t: the von Mises equivalent in 3D,
// scaled so that in both dimensions it is the difference of the largest and smallest principal
// values of an axisymmetric (3D) or any (2D) state, as the triaxial q = sigma_1 - sigma_3.
inline double deviatorMagnitude(const Tensor& t, int d) {
  Tensor s = deviator(t, d);
  double ss = 0;
  for (int k = 0; k < 9; ++k) ss += s[k] * s[k];
  return std::sqrt(double(d) / (d - 1) * ss);
}

}  // namespace demlab::analysis
