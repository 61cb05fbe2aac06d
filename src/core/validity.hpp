// The range of values a scene may hold: what double precision and the neighbor search can
// resolve, with room to spare for the products a step forms (m v^2, k delta, m g x). Values
// outside it are refused where they enter (commands, data files, checkpoints) with a VALUE
// error naming the bound, so no NaN, Inf or lost precision appears later in a run. Units: SI.
// doc/reliability.md, "Validity policy", gives the reasoning for each bound.
#pragma once

#include <cmath>

namespace demlab::validity {

// An element's size (bounding radius) in metres: nanometre grains to kilometre boulders and
// beyond; the lower bound keeps a grain's mass and inertia (r^3, r^5) far from underflow.
inline constexpr double kMinRadius = 1e-12;
inline constexpr double kMaxRadius = 1e9;
// Any coordinate (positions, wall points, regions) within 1e15 m of the origin, and an
// element's centre within 2^30 of its radii of the origin: a coordinate's rounding (|x| 2^-52)
// then stays below 2^-22 of the radius, so overlaps of a millionth of a radius are resolved
// and the search's float boxes stay within a few radii of the truth.
inline constexpr double kMaxCoordinate = 1e15;
inline constexpr double kMaxRadiiFromOrigin = 1073741824.0;  // 2^30
// Speeds (m/s; an element's surface speed |w| r for spins) up to a thousand kilometres a
// second: a hundred times any ballistic impact, and |v|^2 m stays finite for any mass.
inline constexpr double kMaxSpeed = 1e6;
// An element's mass (kg) between these: their products with speeds, gravity and coordinates
// stay far inside double's range.
inline constexpr double kMinMass = 1e-60;
inline constexpr double kMaxMass = 1e60;
// Material coefficients: densities (kg/m^3, kg/m^2 for discs) and Young's moduli (Pa).
inline constexpr double kMinDensity = 1e-6, kMaxDensity = 1e9;
inline constexpr double kMinYoung = 1e-3, kMaxYoung = 1e15;
// Any other non-negative coefficient (friction, cohesion, stiffness, loads): at most this.
inline constexpr double kMaxCoefficient = 1e30;
// Times a scene's settings name (a ramp's start, s): within this of zero, as coordinates.
inline constexpr double kMaxTime = 1e15;
// A wall's rotation rate (rad/s).
inline constexpr double kMaxWallSpin = 1e9;
// Accelerations (gravity, m/s^2).
inline constexpr double kMaxAcceleration = 1e9;

// Returns true when lo <= x <= hi (false for NaN).
inline bool inRange(double x, double lo, double hi) { return x >= lo && x <= hi; }

}  // namespace demlab::validity
