// DEM math: the thesis's Vector, Rotation and Quaternion, as thin aliases over Eigen's fixed-size
// types plus the few helpers a DEM step needs that Eigen does not spell the DEM way.
//
// Code that must run in 2D and 3D is written once against Dim<D>: in 2D an orientation is an
// angle (Rotation2) and an angular velocity or a torque is a scalar; in 3D they are a unit
// quaternion and a vector. The overloads below (cross, rotate, integrate, squaredNorm) take
// either form, so a contact law or an integrator templated on D reads the same in both.
//
// Eigen's fixed-size vectorisable types (Vec2, Vec4, Quat, Mat2) need 16-byte alignment; C++17
// aligned new makes std::vector<Vec2> and heap members safe without Eigen's aligned_allocator.
// Eigen leaves a default-constructed Quat uninitialised: write Quat::Identity().
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace demlab {

using Real = double;

template <int D>
using VecD = Eigen::Matrix<Real, D, 1>;
template <int D>
using MatD = Eigen::Matrix<Real, D, D>;

using Vec2 = VecD<2>;
using Vec3 = VecD<3>;
using Mat2 = MatD<2>;
using Mat3 = MatD<3>;
using Quat = Eigen::Quaterniond;
using AngleAxis = Eigen::AngleAxisd;

// Rotation2: an orientation in the plane, kept as the angle turned counterclockwise from the
// reference orientation. The angle is deliberately not wrapped, so it counts whole turns: a
// rolling test compares it with distance / radius, a drum reports its revolutions.
struct Rotation2 {
  Real angle = 0;

  // Returns the identity rotation (angle 0).
  static Rotation2 identity() { return Rotation2{0}; }

  // Returns the rotation matrix [[c, -s], [s, c]].
  Mat2 matrix() const {
    const Real c = std::cos(angle), s = std::sin(angle);
    Mat2 m;
    m << c, -s, s, c;
    return m;
  }

  // Returns the inverse rotation (the opposite angle).
  Rotation2 inverse() const { return Rotation2{-angle}; }

  // Returns the same orientation with its angle wrapped into (-pi, pi]; forgets the turn count.
  Rotation2 normalized() const {
    Real a = std::remainder(angle, 2 * std::numbers::pi);
    if (a <= -std::numbers::pi) a += 2 * std::numbers::pi;
    return Rotation2{a};
  }

  // Returns the composition: first rotate by b, then by a. Plane rotations commute.
  friend Rotation2 operator*(Rotation2 a, Rotation2 b) { return Rotation2{a.angle + b.angle}; }
};

// What changes with the dimension: Dim<D>::Rotation is the orientation, Dim<D>::Angular the
// type of an angular velocity, angular momentum or torque, kAngularDof its number of components.
template <int D>
struct Dim;

template <>
struct Dim<2> {
  using Vec = Vec2;
  using Rotation = Rotation2;
  using Angular = Real;
  static constexpr int kAngularDof = 1;
};

template <>
struct Dim<3> {
  using Vec = Vec3;
  using Rotation = Quat;
  using Angular = Vec3;
  static constexpr int kAngularDof = 3;
};

template <int D>
using RotationD = typename Dim<D>::Rotation;
template <int D>
using AngularD = typename Dim<D>::Angular;

// ---- cross products -------------------------------------------------------------------------
// In 2D the angular quantities are the z components of the 3D ones, so each 2D overload is the
// 3D formula with the plane vectors embedded at z = 0.

// Returns a x b, a scalar in 2D: the z component of the 3D product (torque = r x F).
inline Real cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Returns w x r for a scalar angular velocity w about z: the velocity of a point at offset r.
inline Vec2 cross(Real w, const Vec2& r) {
  return Vec2(-w * r.y(), w * r.x());
}

// Returns r x w for a scalar w about z; equal to -(w x r).
inline Vec2 cross(const Vec2& r, Real w) {
  return Vec2(w * r.y(), -w * r.x());
}

// Returns a x b.
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return a.cross(b);
}

// Returns v turned a quarter turn counterclockwise: (-y, x), so that cross(w, r) = w perp(r).
inline Vec2 perp(const Vec2& v) {
  return Vec2(-v.y(), v.x());
}

// Returns the squared magnitude of an angular quantity (for the rotational kinetic energy).
inline Real squaredNorm(Real w) {
  return w * w;
}
template <int D>
inline Real squaredNorm(const VecD<D>& v) {
  return v.squaredNorm();
}

// ---- rotations ------------------------------------------------------------------------------

// Returns v rotated by r.
inline Vec2 rotate(const Rotation2& r, const Vec2& v) {
  const Real c = std::cos(r.angle), s = std::sin(r.angle);
  return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}

// Returns v rotated by the unit quaternion q.
inline Vec3 rotate(const Quat& q, const Vec3& v) {
  return q * v;
}

// Returns v rotated by the inverse of r (world frame to body frame).
inline Vec2 rotateInverse(const Rotation2& r, const Vec2& v) {
  return rotate(r.inverse(), v);
}

// Returns v rotated by the inverse of the unit quaternion q (world frame to body frame).
inline Vec3 rotateInverse(const Quat& q, const Vec3& v) {
  return q.conjugate() * v;
}

// Returns the unit quaternion of the rotation vector phi (axis phi/|phi|, angle |phi|): the
// exact exponential map. Near zero the series replaces sin(t/2)/t, so a grain at rest or
// nearly at rest gets a finite, exact-to-rounding result instead of 0/0.
inline Quat quatFromRotationVector(const Vec3& phi) {
  const Real t2 = phi.squaredNorm();
  Real c, s;  // c = cos(t/2), s = sin(t/2) / t
  if (t2 < 1e-8) {
    c = 1 - t2 / 8 + t2 * t2 / 384;
    s = 0.5 - t2 / 48 + t2 * t2 / 3840;
  } else {
    const Real t = std::sqrt(t2);
    c = std::cos(t / 2);
    s = std::sin(t / 2) / t;
  }
  return Quat(c, s * phi.x(), s * phi.y(), s * phi.z());
}

// Returns the rotation vector of the unit quaternion q (the logarithm map), with angle in
// [0, pi]; q and -q give the same result, as they are the same rotation.
inline Vec3 rotationVector(const Quat& q) {
  const Real w = q.w() < 0 ? -q.w() : q.w();
  const Vec3 v = q.w() < 0 ? Vec3(-q.vec()) : Vec3(q.vec());
  const Real sn = v.norm();
  // atan2(sn, w) / sn tends to 1 / w; the cut-off keeps the series error below rounding.
  if (sn < 1e-8) return (2 / w) * v;
  return (2 * std::atan2(sn, w) / sn) * v;
}

// Returns q advanced by one step of the world-frame angular velocity omega held constant over
// dt: exp(omega dt) * q, renormalised so rounding cannot drift the norm over millions of steps.
// Exact for a constant omega, unlike the first-order q + dt/2 (0, omega) q update.
inline Quat integrate(const Quat& q, const Vec3& omega, Real dt) {
  Quat r = quatFromRotationVector(omega * dt) * q;
  r.normalize();
  return r;
}

// Returns q advanced by one step of the body-frame angular velocity omegaBody: q * exp(w dt).
// The same rotation as integrate() with omega = rotate(q, omegaBody).
inline Quat integrateBody(const Quat& q, const Vec3& omegaBody, Real dt) {
  Quat r = q * quatFromRotationVector(omegaBody * dt);
  r.normalize();
  return r;
}

// Returns r advanced by one step of the scalar angular velocity omega (exact in the plane).
inline Rotation2 integrate(const Rotation2& r, Real omega, Real dt) {
  return Rotation2{r.angle + omega * dt};
}

}  // namespace demlab
