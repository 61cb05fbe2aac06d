// Conversions between the plain types of the public API (Vec3d) and the dimension's Eigen
// types, with the checks every Def goes through before anything is created.
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/math.hpp"
#include "physics/material.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim {

// Returns s in upper case without spaces (error code words: "angular velocity" ->
// "ANGULARVELOCITY").
inline std::string upperWord(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c != ' ') out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return out;
}

// Returns "x y z" (or "x y" in 2D), formatted as Tcl prints doubles.
inline std::string formatVec(const Vec3d& v, int dim) {
  std::string out;
  for (int k = 0; k < dim; ++k) {
    if (k) out += ' ';
    out += physics::formatReal(v[k]);
  }
  return out;
}

// Throws {VALUE <FIELD>}: `bad <field> "<value>": <why>`.
[[noreturn]] inline void throwBad(const std::string& field, const std::string& value,
                                  const std::string& why) {
  throw Error("bad " + field + " \"" + value + "\": " + why, {"VALUE", upperWord(field)});
}

// Returns v as a VecD<D>. Throws {VALUE <FIELD>} unless every component is finite and, in 2D,
// z is 0.
template <int D>
VecD<D> toVec(const Vec3d& v, const std::string& field) {
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(v[k])) throwBad(field, formatVec(v, 3), "must be finite numbers");
  }
  if (D == 2 && v[2] != 0) throwBad(field, formatVec(v, 3), "must have z = 0 in 2D");
  VecD<D> out;
  for (int k = 0; k < D; ++k) out[k] = v[k];
  return out;
}

// Returns v as an angular quantity of dimension D. Throws {VALUE <FIELD>} unless finite and,
// in 2D, x = y = 0 (rotation about z only).
template <int D>
AngularD<D> toAngular(const Vec3d& v, const std::string& field) {
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(v[k])) throwBad(field, formatVec(v, 3), "must be finite numbers");
  }
  if constexpr (D == 2) {
    if (v[0] != 0 || v[1] != 0) throwBad(field, formatVec(v, 3), "must be about z only in 2D");
    return v[2];
  } else {
    return Vec3(v[0], v[1], v[2]);
  }
}

template <int D>
Vec3d fromVec(const VecD<D>& v) {
  Vec3d out{0, 0, 0};
  for (int k = 0; k < D; ++k) out[k] = v[k];
  return out;
}

inline Vec3d fromAngular(Real w) {
  return {0, 0, w};
}
inline Vec3d fromAngular(const Vec3& w) {
  return {w.x(), w.y(), w.z()};
}

inline std::array<double, 4> fromRotation(const Rotation2& r) {
  return {r.angle, 0, 0, 0};
}
inline std::array<double, 4> fromRotation(const Quat& q) {
  return {q.w(), q.x(), q.y(), q.z()};
}

// Returns the orientation o (3D: a quaternion {w x y z}, normalised; 2D: {angle}; empty: the
// identity). Throws {VALUE ORIENTATION} for the wrong count, a non-finite number or a zero
// quaternion.
template <int D>
RotationD<D> toRotation(const std::vector<double>& o) {
  std::string text;
  for (double x : o) text += (text.empty() ? "" : " ") + physics::formatReal(x);
  if constexpr (D == 2) {
    if (o.empty()) return Rotation2::identity();
    if (o.size() != 1 || !std::isfinite(o[0])) {
      throwBad("orientation", text, "must be one finite angle (rad) in 2D");
    }
    return Rotation2{o[0]};
  } else {
    if (o.empty()) return Quat::Identity();
    const bool finite = std::all_of(o.begin(), o.end(), [](double x) { return std::isfinite(x); });
    if (o.size() != 4 || !finite) {
      throwBad("orientation", text, "must be a quaternion of four finite numbers w x y z");
    }
    Quat q(o[0], o[1], o[2], o[3]);
    const double n = q.norm();
    if (!(n > 0 && std::isfinite(n))) throwBad("orientation", text, "must not be zero");
    q.coeffs() /= n;
    return q;
  }
}

// Throws {VALUE <FIELD>} unless x is a positive finite number.
inline void checkPositive(double x, const std::string& field) {
  if (!(std::isfinite(x) && x > 0))
    throwBad(field, physics::formatReal(x), "must be a positive number");
}

}  // namespace demlab::sim
