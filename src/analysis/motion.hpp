// The mean motion of a selection of elements: the mass-weighted mean velocity and the granular
// temperature, T = (1 / (d N)) sum m |v - <v>|^2 / <m> (m^2/s^2), <v> = sum m v / sum m and
// <m> the mean mass: the fluctuation kinetic energy per element and degree of freedom, over
// the mean mass, so equal elements give the plain velocity variance (Goldhirsch's definition
// with the mass-weighted mean, which keeps a mixture's temperature Galilean invariant).
#pragma once

#include "analysis/sample.hpp"

namespace demlab::analysis {

struct MotionResult {
  size_t elements = 0;
  double mass = 0;       // summed
  Vec3d velocity{};      // mass-weighted mean
  double temperature = 0;
  double fluctuationEnergy = 0;  // sum m |v - <v>|^2 / 2 (J)
};

// Returns the mean motion of the elements selects() counts (all zero when there is none).
// Changes nothing.
MotionResult meanMotion(const Sample& s, const Selection& sel);

}  // namespace demlab::analysis
