// The observed order of accuracy of a convergence study: the least-squares slope of
// log(error) against log(dt). Shared by the C++ verification suite and `study convergence`.
#pragma once

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace demlab {

// Returns the least-squares slope of log(error) against log(dt) over the points {dt, error},
// each with dt > 0 and a finite error > 0 (the caller picks them); NaN with fewer than two.
// Changes nothing.
inline double logLogSlope(const std::vector<std::pair<double, double>>& dtError) {
  const size_t n = dtError.size();
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  double mx = 0, my = 0;
  for (const auto& [dt, e] : dtError) mx += std::log(dt), my += std::log(e);
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxy = 0, sxx = 0;
  for (const auto& [dt, e] : dtError) {
    const double x = std::log(dt) - mx;
    sxy += x * (std::log(e) - my);
    sxx += x * x;
  }
  return sxy / sxx;
}

}  // namespace demlab
