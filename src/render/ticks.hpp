// Tick values for a colour bar: 3 to 6 round numbers (steps of 1, 2 or 5 times a power of ten)
// inside a range, and their labels, so a legend reads "0  0.5  1  1.5" rather than the
// field's raw minimum and maximum.
#pragma once

#include <string>
#include <vector>

namespace demlab::render {

struct Ticks {
  std::vector<double> values;  // ascending, inside [lo, hi]
  double step = 1;
};

// Returns 3 to 6 ticks inside [lo, hi] (lo < hi, both finite) at multiples of the finest step
// 1, 2 or 5 x 10^k that gives at most 6; 2.5 x 10^k where none of those gives 3.
Ticks niceTicks(double lo, double hi);

// Returns the labels of ticks t: as many decimals as the step needs, "0" for a value that is
// zero up to rounding; where the values reach 10^5 or the step is below 10^-3, every label but
// "0" is a mantissa with the same power of ten, e.g. "0.5e5 1.0e5 1.5e5".
std::vector<std::string> tickLabels(const Ticks& t);

}  // namespace demlab::render
