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
#include "core/validity.hpp"
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

// The validity policy's checks of an element's state (core/validity.hpp). Each throws
// {VALUE <FIELD>} naming the bound; r is the element's bounding radius, already checked.
inline void checkRadiusRange(double r, const std::string& field = "radius") {
  if (!validity::inRange(r, validity::kMinRadius, validity::kMaxRadius)) {
    throwBad(field, physics::formatReal(r),
             "must be between " + physics::formatReal(validity::kMinRadius) + " and " +
                 physics::formatReal(validity::kMaxRadius) + " m");
  }
}
template <int D>
void checkPositionRange(const VecD<D>& x, double r) {
  const double limit = std::min(validity::kMaxCoordinate, validity::kMaxRadiiFromOrigin * r);
  if (x.template lpNorm<Eigen::Infinity>() > limit) {
    Vec3d p{0, 0, 0};
    for (int k = 0; k < D; ++k) p[k] = x[k];
    throwBad("position", formatVec(p, D),
             "must be within " + physics::formatReal(limit) +
                 " m of the origin on each axis (2^30 radii, at most 1e15 m: farther, the "
                 "coordinates cannot resolve the element's overlaps)");
  }
}
// Throws {VALUE <FIELD>} unless every component of a load's force, torque or rate is within
// the loads' bound (validity::kMaxCoefficient). angular: v is a torque or its rate, which a
// 2D scene gives as its z component alone.
inline void checkLoadRange(const Vec3d& v, const std::string& field, int dim, bool angular) {
  for (int k = 0; k < 3; ++k) {
    if (!(std::abs(v[k]) <= validity::kMaxCoefficient)) {
      throwBad(field, angular && dim == 2 ? physics::formatReal(v[2]) : formatVec(v, dim),
               "must be at most " + physics::formatReal(validity::kMaxCoefficient) +
                   " in magnitude on each axis");
    }
  }
}
template <int D>
void checkVelocityRange(const VecD<D>& v) {
  if (!(v.norm() <= validity::kMaxSpeed)) {
    Vec3d p{0, 0, 0};
    for (int k = 0; k < D; ++k) p[k] = v[k];
    throwBad("velocity", formatVec(p, D),
             "must be at most " + physics::formatReal(validity::kMaxSpeed) + " m/s in magnitude");
  }
}
template <class W>
void checkAngularRange(const W& w, double r, int dim) {
  double m;
  Vec3d p{0, 0, 0};
  if constexpr (std::is_same_v<W, Real>) {
    m = std::abs(w);
    p[2] = w;
  } else {
    m = w.norm();
    p = {w[0], w[1], w[2]};
  }
  if (!(m * r <= validity::kMaxSpeed)) {
    throwBad("angular velocity", formatVec(p, dim == 2 ? 3 : 3),
             "must be at most " + physics::formatReal(validity::kMaxSpeed) +
                 " m/s at the surface (|w| r)");
  }
}
inline void checkMassRange(double invMass, double r) {
  if (!validity::inRange(invMass, 1 / validity::kMaxMass, 1 / validity::kMinMass)) {
    throwBad("radius", physics::formatReal(r),
             "gives a mass of " + physics::formatReal(1 / invMass) + " kg, outside " +
                 physics::formatReal(validity::kMinMass) + " to " +
                 physics::formatReal(validity::kMaxMass) + " kg");
  }
}

}  // namespace demlab::sim
