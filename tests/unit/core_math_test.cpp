#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <type_traits>

#include "core/math.hpp"

namespace demlab {
namespace core_math_test {

constexpr double kPi = std::numbers::pi;

Vec3 embed(const Vec2& v) {
  return Vec3(v.x(), v.y(), 0);
}

// The same rotation: q and -q are equal rotations, so compare what they do to the axes.
void expectSameRotation(const Quat& a, const Quat& b, double tol) {
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = Vec3::Unit(k);
    EXPECT_LT((a * e - b * e).norm(), tol) << "axis " << k;
  }
}

TEST(Math, CrossProducts2DAreThe3DFormulaInThePlane) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int t = 0; t < 100; ++t) {
    const Vec2 a(u(rng), u(rng)), b(u(rng), u(rng));
    const double w = u(rng);
    EXPECT_NEAR(cross(a, b), embed(a).cross(embed(b)).z(), 1e-14);
    const Vec3 wr = Vec3(0, 0, w).cross(embed(b));
    EXPECT_NEAR((cross(w, b) - wr.head<2>()).norm(), 0, 1e-14);
    EXPECT_NEAR(wr.z(), 0, 0);
    const Vec3 rw = embed(b).cross(Vec3(0, 0, w));
    EXPECT_NEAR((cross(b, w) - rw.head<2>()).norm(), 0, 1e-14);
    EXPECT_EQ(cross(w, b), w * perp(b));
  }
  EXPECT_EQ(cross(Vec3(1, 0, 0), Vec3(0, 1, 0)), Vec3(0, 0, 1));
  EXPECT_EQ(cross(Vec2(1, 0), Vec2(0, 1)), 1.0);
}

// A contact-point velocity and a rotational energy written once for both dimensions.
template <int D>
double pointSpeedSquared(const VecD<D>& v, const AngularD<D>& w, const VecD<D>& r) {
  return squaredNorm<D>(v + cross(w, r));
}

TEST(Math, DimensionGenericCodeReadsTheSameIn2DAnd3D) {
  static_assert(std::is_same_v<AngularD<2>, double>);
  static_assert(std::is_same_v<AngularD<3>, Vec3>);
  static_assert(std::is_same_v<RotationD<2>, Rotation2>);
  static_assert(std::is_same_v<RotationD<3>, Quat>);
  static_assert(Dim<2>::kAngularDof == 1 && Dim<3>::kAngularDof == 3);
  // A disc rolling without slip: the contact point (r below the centre) is at rest.
  const double R = 0.5, w = -4;  // clockwise spin rolls to the right
  EXPECT_NEAR(pointSpeedSquared<2>(Vec2(-w * R, 0), w, Vec2(0, -R)), 0, 1e-28);
  EXPECT_NEAR(pointSpeedSquared<3>(Vec3(-w * R, 0, 0), Vec3(0, 0, w), Vec3(0, -R, 0)), 0, 1e-28);
  EXPECT_EQ(squaredNorm(3.0), 9.0);
}

TEST(Math, QuaternionStepIsExactForConstantAngularVelocity) {
  const Vec3 omega(0.3, -1.2, 2.0);
  const double dt = 1e-3;
  const int n = 10000;
  Quat q = Quat::Identity();
  for (int i = 0; i < n; ++i) q = integrate(q, omega, dt);
  const Quat exact(AngleAxis(omega.norm() * n * dt, omega.normalized()));
  expectSameRotation(q, exact, 1e-11);
  // A first-order update (q += dt/2 (0, omega) q, renormalised) is off by far more: the
  // exactness above is the exponential map's, not the tolerance's.
  Quat f = Quat::Identity();
  for (int i = 0; i < n; ++i) {
    Quat dq = Quat(0, omega.x(), omega.y(), omega.z()) * f;
    f.coeffs() += 0.5 * dt * dq.coeffs();
    f.normalize();
  }
  EXPECT_GT((f * Vec3::UnitX() - exact * Vec3::UnitX()).norm(), 1e-6);
}

TEST(Math, QuaternionStaysUnitOverManyLargeSteps) {
  Quat q(AngleAxis(0.4, Vec3(1, 2, 3).normalized()));
  const Vec3 omega(70, -30, 55);  // about 0.1 rad per step
  for (int i = 0; i < 100000; ++i) q = integrate(q, omega, 1e-3);
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
}

TEST(Math, QuaternionStepAtRestAndNearRestIsFinite) {
  const Quat q(AngleAxis(1.0, Vec3(0, 1, 0)));
  const Quat same = integrate(q, Vec3::Zero(), 1e-3);
  EXPECT_NEAR((same.coeffs() - q.coeffs()).norm(), 0, 1e-16);
  const Quat tiny = integrate(q, Vec3(1e-300, 0, 0), 1e-3);
  EXPECT_TRUE(tiny.coeffs().allFinite());
  // Both sides of the series cut-off (|phi| = 1e-4) agree with Eigen's angle-axis quaternion.
  for (double t : {0.5e-4, 0.999e-4, 1.001e-4, 2e-4, 1e-2}) {
    const Vec3 axis = Vec3(1, -2, 2) / 3;
    const Quat a = quatFromRotationVector(t * axis);
    const Quat b(AngleAxis(t, axis));
    EXPECT_NEAR((a.coeffs() - b.coeffs()).norm(), 0, 1e-17) << t;
  }
}

TEST(Math, BodyFrameStepIsTheWorldFrameStepWithTheRotatedVelocity) {
  const Quat q(AngleAxis(2.1, Vec3(0.2, -0.5, 1).normalized()));
  const Vec3 wBody(1.5, -0.3, 0.8);
  const Quat a = integrateBody(q, wBody, 0.01);
  const Quat b = integrate(q, rotate(q, wBody), 0.01);
  expectSameRotation(a, b, 1e-15);
}

TEST(Math, RotationVectorInvertsTheExponentialMap) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int t = 0; t < 200; ++t) {
    Vec3 phi(u(rng), u(rng), u(rng));
    phi *= (t < 100 ? 3.0 : 1e-9) * std::abs(u(rng)) / std::max(phi.norm(), 1.0);
    const Quat q = quatFromRotationVector(phi);
    EXPECT_LT((rotationVector(q) - phi).norm(), 1e-14);
    EXPECT_LT((rotationVector(Quat(-q.coeffs())) - phi).norm(), 1e-14);  // -q: same rotation
  }
  EXPECT_EQ(rotationVector(Quat::Identity()), Vec3::Zero());
}

TEST(Math, RotateAndRotateInverseAreInverses) {
  const Quat q(AngleAxis(0.7, Vec3(1, 1, 0).normalized()));
  const Vec3 v(0.3, -2, 5);
  EXPECT_LT((rotateInverse(q, rotate(q, v)) - v).norm(), 1e-15);
  EXPECT_LT((rotate(q, v) - q.toRotationMatrix() * v).norm(), 1e-14);
  const Rotation2 r{2.5};
  const Vec2 p(1, -4);
  EXPECT_LT((rotateInverse(r, rotate(r, p)) - p).norm(), 1e-15);
}

TEST(Math, Rotation2MatchesEigenAndTheQuaternionAboutZ) {
  for (double angle : {0.0, 0.3, -1.7, 3 * kPi + 0.2}) {
    const Rotation2 r{angle};
    const Vec2 v(0.6, -1.1);
    EXPECT_LT((rotate(r, v) - Eigen::Rotation2Dd(angle) * v).norm(), 1e-15);
    EXPECT_LT((rotate(r, v) - r.matrix() * v).norm(), 1e-15);
    const Vec3 v3 = Quat(AngleAxis(angle, Vec3::UnitZ())) * embed(v);
    EXPECT_LT((rotate(r, v) - v3.head<2>()).norm(), 1e-15);
  }
  const Rotation2 a{0.4}, b{-1.3};
  EXPECT_DOUBLE_EQ((a * b).angle, -0.9);
  EXPECT_LT((rotate(a * b, Vec2(1, 2)) - rotate(a, rotate(b, Vec2(1, 2)))).norm(), 1e-15);
  EXPECT_EQ((a * a.inverse()).angle, 0.0);
}

TEST(Math, Rotation2CountsTurnsAndNormalizesOnRequest) {
  // A drum at 2 rad/s for 10 s has turned 20 rad: the angle keeps the turns.
  Rotation2 r;
  for (int i = 0; i < 10000; ++i) r = integrate(r, 2.0, 1e-3);
  EXPECT_NEAR(r.angle, 20.0, 1e-11);
  const double wrapped = r.normalized().angle;
  EXPECT_GT(wrapped, -kPi);
  EXPECT_LE(wrapped, kPi);
  EXPECT_NEAR(wrapped, 20.0 - 6 * kPi, 1e-11);
  EXPECT_EQ(Rotation2{kPi}.normalized().angle, kPi);
  EXPECT_EQ(Rotation2{-kPi}.normalized().angle, kPi);
  // The 2D step equals the 3D step about z.
  const Quat q = integrate(Quat(AngleAxis(0.25, Vec3::UnitZ())), Vec3(0, 0, 3.0), 0.1);
  EXPECT_NEAR(rotationVector(q).z(), integrate(Rotation2{0.25}, 3.0, 0.1).angle, 1e-15);
}

}  // namespace core_math_test
}  // namespace demlab
