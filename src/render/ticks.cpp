#include "render/ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace demlab::render {
namespace {

// Returns the ticks of [lo, hi] at multiples of step.
std::vector<double> multiples(double lo, double hi, double step) {
  std::vector<double> v;
  const double first = std::ceil(lo / step - 1e-9), last = std::floor(hi / step + 1e-9);
  for (double k = first; k <= last && v.size() < 64; ++k) v.push_back(k * step);
  return v;
}

}  // namespace

Ticks niceTicks(double lo, double hi) {
  // Steps from (hi - lo) / 6 up cover 3 to 6 ticks within two decades. 2.5 fills the gap where
  // one 1-2-5 step gives 7 ticks and the next 2.
  const double e = std::floor(std::log10((hi - lo) / 6));
  Ticks best;
  bool bestRound = false;
  for (const double decade : {std::pow(10.0, e), std::pow(10.0, e + 1)}) {
    for (const double m : {1.0, 2.0, 2.5, 5.0}) {
      std::vector<double> v = multiples(lo, hi, m * decade);
      if (v.size() < 3 || v.size() > 6) continue;
      const bool round = m != 2.5;
      if (best.values.empty() || (round && !bestRound) ||
          (round == bestRound && v.size() > best.values.size())) {
        best = {std::move(v), m * decade};
        bestRound = round;
      }
    }
  }
  if (best.values.empty()) best = {{lo, (lo + hi) / 2, hi}, (hi - lo) / 2};
  return best;
}

std::vector<std::string> tickLabels(const Ticks& t) {
  double largest = t.step;
  for (double v : t.values) largest = std::max(largest, std::abs(v));
  // One power of ten for all labels when plain decimals would be long.
  const int exponent = largest >= 1e5 || t.step < 1e-3 ? int(std::floor(std::log10(largest))) : 0;
  const double scale = std::pow(10.0, -exponent), step = t.step * scale;
  // Decimals the step needs: 0.25 needs 2, 0.5 needs 1, 20 needs 0.
  int decimals = 0;
  for (double p = 1; decimals < 6 && std::abs(step * p - std::round(step * p)) > 1e-6 * step * p;
       p *= 10)
    ++decimals;
  std::vector<std::string> out;
  for (double v : t.values) {
    char buf[40];
    if (std::abs(v) < t.step * 1e-6) {
      out.push_back("0");
      continue;
    }
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v * scale);
    out.push_back(exponent ? std::string(buf) + "e" + std::to_string(exponent) : buf);
  }
  return out;
}

}  // namespace demlab::render
