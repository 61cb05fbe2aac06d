// Walls: few, large, rigid, of infinite mass, kept apart from the grains. Each wall keeps the
// geometry it was created with and an optional prescribed rigid motion (sim/simulation.hpp
// WallMotion), evaluated exactly at each time, so a drum turned for 10^6 steps has not drifted.
// The current geometry is a physics shape (physics/shapes.hpp) the narrow phase reads.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <variant>
#include <vector>

#include "core/handle.hpp"
#include "core/math.hpp"
#include "core/name_lookup.hpp"
#include "core/tag_table.hpp"
#include "physics/shapes.hpp"
#include "sim/convert.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim {

template <int D>
using WallGeometry = std::variant<physics::PlaneShape<D>, physics::FlatWallShape<D>,
                                  physics::BoxShape<D>, physics::DrumShape<D>,
                                  physics::MeshShape<D>>;

template <int D>
struct Wall {
  WallShape kind = WallShape::Plane;
  uint32_t material = 0;
  WallGeometry<D> shape0;  // geometry at creation (time t0)
  WallGeometry<D> shape;   // geometry now

  // Prescribed motion (moving == false: all zero).
  bool moving = false;
  VecD<D> velocity = VecD<D>::Zero(), amplitude = VecD<D>::Zero();
  AngularD<D> omega = zeroAngular();
  Real frequency = 0, phase = 0;
  double t0 = 0;

  // Kinematics now: reference point, its velocity, the rotation turned since t0.
  VecD<D> point = VecD<D>::Zero(), point0 = VecD<D>::Zero(), pointVelocity = VecD<D>::Zero();
  RotationD<D> turned = identity();

  // For the Verlet skin: reference point and time at the last neighbor search.
  VecD<D> pointAtBuild = VecD<D>::Zero();
  double timeAtBuild = 0;

  // Total force the grains exerted on the wall in the last step.
  VecD<D> force = VecD<D>::Zero();
  // Work the wall has done on the grains since it was made (J), summed by the contact passes.
  double work = 0;
  // The rotation turned before the last change of motion (rebase): orientation = turned * it.
  RotationD<D> turnedBefore = identity();
  // A servo (WallServoDef): its velocity along its normal is set each step from force.
  bool servo = false;
  double servoTarget = 0, servoGain = 0, servoMaxSpeed = 0;
  // A scripted motion (WallMotion's TimeFunctions; 2D: the spin's is omegaFn[2]), and the
  // angle it has turned since the last neighbor search (its rate changes, so the skin test
  // sums it step by step).
  std::array<TimeFunction, 3> velocityFn{}, omegaFn{};
  Real scriptedAngle = 0;

  bool scripted() const {
    for (int k = 0; k < 3; ++k)
      if (velocityFn[k] || omegaFn[k]) return true;
    return false;
  }

  // Eigen leaves its fixed-size types uninitialised: these give the zero and the identity.
  static AngularD<D> zeroAngular() {
    if constexpr (D == 2) {
      return 0.0;
    } else {
      return Vec3::Zero();
    }
  }
  static RotationD<D> identity() {
    if constexpr (D == 2) {
      return Rotation2::identity();
    } else {
      return Quat::Identity();
    }
  }

  // Returns the velocity of the wall's material at world point x now.
  VecD<D> surfaceVelocity(const VecD<D>& x) const {
    if (!moving) return VecD<D>::Zero();
    return pointVelocity + cross(omega, VecD<D>(x - point));
  }

  // Places the wall at time t: evaluates the motion and rebuilds the current shape from
  // shape0. Changes point, pointVelocity, turned and shape.
  void moveTo(double t) {
    const Real tau = t - t0;
    const Real arg = 2 * std::numbers::pi * frequency * tau + phase;
    point = point0 + velocity * tau + amplitude * (std::sin(arg) - std::sin(phase));
    pointVelocity = velocity + amplitude * (2 * std::numbers::pi * frequency * std::cos(arg));
    MatD<D> R;
    if constexpr (D == 2) {
      turned = Rotation2{omega * tau};
      R = turned.matrix();
    } else {
      turned = quatFromRotationVector(omega * tau);
      R = turned.toRotationMatrix();
    }
    const VecD<D> shift = point - point0;
    shape = std::visit(
        [&](const auto& s0) -> WallGeometry<D> {
          auto s = s0;
          using S = std::decay_t<decltype(s0)>;
          if constexpr (std::is_same_v<S, physics::PlaneShape<D>>) {
            s.point = point0 + shift + R * (s0.point - point0);
            s.normal = R * s0.normal;
          } else if constexpr (std::is_same_v<S, physics::FlatWallShape<D>>) {
            s.centre = point0 + shift + R * (s0.centre - point0);
            for (int k = 0; k < D - 1; ++k) s.axes[k] = R * s0.axes[k];
          } else if constexpr (std::is_same_v<S, physics::BoxShape<D>>) {
            s.centre = point0 + shift + R * (s0.centre - point0);
            s.axes = R * s0.axes;
          } else if constexpr (std::is_same_v<S, physics::MeshShape<D>>) {
            if constexpr (D == 3) {
              s.offset = point0 + shift + R * (s0.offset - point0);
              s.rotation = R * s0.rotation;
            }
          } else {
            s.centre = point0 + shift + R * (s0.centre - point0);
            if constexpr (D == 3) s.axis = R * s0.axis;
          }
          return s;
        },
        shape0);
  }

  // Makes the geometry at time t the new reference of the motion (shape0, point0, t0), so a new
  // motion starts from where the wall is, without a jump; the motion itself is left to the
  // caller. Changes shape0, point0, t0, turnedBefore (and the current geometry, to t).
  void rebase(double t) {
    if (moving) moveTo(t);  // a still wall is where it is: no rounding of its geometry
    shape0 = shape;
    point0 = point;
    t0 = t;
    turnedBefore = (turned * turnedBefore).normalized();
    turned = identity();
  }

  // Returns the unit normal of a plane or finite wall now (the side the grains are on for a
  // plane), zero for the other shapes.
  VecD<D> normalNow() const {
    if (const auto* p = std::get_if<physics::PlaneShape<D>>(&shape)) return p->normal;
    if (const auto* f = std::get_if<physics::FlatWallShape<D>>(&shape)) {
      if constexpr (D == 2) {
        return VecD<D>(f->axes[0].y(), -f->axes[0].x());
      } else {
        return f->axes[0].cross(f->axes[1]).normalized();
      }
    }
    return VecD<D>::Zero();
  }

  // Sets a servo wall's velocity for the step from the force the grains put on it in the last
  // one: v = n gain (target - measured), measured = -force . n (what pushes the wall back along
  // its normal), capped at servoMaxSpeed; the motion is rebased at t so the new velocity
  // starts there. Changes velocity, moving and the reference of the motion.
  void servoStep(double t, const VecD<D>& wholeForce) {
    const VecD<D> n = normalNow();
    const double measured = -wholeForce.dot(n);
    double speed = servoGain * (servoTarget - measured);
    speed = std::clamp(speed, -servoMaxSpeed, servoMaxSpeed);
    rebase(t);
    velocity = n * speed;
    amplitude.setZero();
    omega = zeroAngular();
    frequency = phase = 0;
    moving = true;
  }

  // Sets a scripted wall's motion for the step from t to t + dt: the scripted components of
  // its velocity and rotation rate take their functions' values at the step's midpoint (the
  // position is then their midpoint-rule integral: exact for rates linear in time), the motion
  // rebased at t and a vibration's phase carried over. Changes velocity, omega, phase, the
  // motion's reference and scriptedAngle.
  void scriptStep(double t, double dt) {
    const double mid = t + 0.5 * dt;
    const Real advanced = phase + 2 * std::numbers::pi * frequency * (t - t0);
    rebase(t);
    phase = std::remainder(advanced, 2 * std::numbers::pi);
    for (int k = 0; k < D; ++k)
      if (velocityFn[k]) velocity[k] = velocityFn[k](mid);
    if constexpr (D == 2) {
      if (omegaFn[2]) omega = omegaFn[2](mid);
    } else {
      for (int k = 0; k < 3; ++k)
        if (omegaFn[k]) omega[k] = omegaFn[k](mid);
    }
    moving = true;
    scriptedAngle += angularNorm() * Real(dt);
  }

  // Returns an upper bound of how far any point of the wall that can touch a grain has moved
  // since the last neighbor search (time now). Rotation of a drum about its own axis moves no
  // surface point off the surface, so it counts nothing; a turning infinite plane gives +inf.
  Real displacementSinceBuild(double now) const {
    if (!moving) return 0;
    Real d = (point - pointAtBuild).norm();
    const Real angle = scripted() ? scriptedAngle : angularNorm() * (now - timeAtBuild);
    if (angle == 0) return d;
    return d + angle * reach();
  }

  // Returns |omega|.
  Real angularNorm() const {
    if constexpr (D == 2) {
      return std::abs(omega);
    } else {
      return omega.norm();
    }
  }

  // Returns the largest distance from the reference point to a wall point that matters for a
  // rotation's displacement (inf for planes; 0 for a drum turning about its own axis).
  Real reach() const {
    const Real inf = std::numeric_limits<Real>::infinity();
    return std::visit(
        [&](const auto& s) -> Real {
          using S = std::decay_t<decltype(s)>;
          if constexpr (std::is_same_v<S, physics::PlaneShape<D>>) {
            return inf;
          } else if constexpr (std::is_same_v<S, physics::FlatWallShape<D>>) {
            Real h2 = 0;
            for (Real e : s.halfExtents) h2 += e * e;
            return (s.centre - point).norm() + std::sqrt(h2);
          } else if constexpr (std::is_same_v<S, physics::BoxShape<D>>) {
            return (s.centre - point).norm() + s.halfExtents.norm();
          } else if constexpr (std::is_same_v<S, physics::MeshShape<D>>) {
            // The farthest corner of the mesh's bounds from the reference point.
            const physics::Bounds<D> b = physics::bounds(s);
            Real far = 0;
            for (int c = 0; c < (1 << D); ++c) {
              VecD<D> x;
              for (int k = 0; k < D; ++k) x[k] = (c >> k & 1) ? b.hi[k] : b.lo[k];
              far = std::max(far, (x - point).norm());
            }
            return far;
          } else {
            bool aboutAxis;
            if constexpr (D == 2) {
              aboutAxis = true;
            } else {
              aboutAxis = omega.cross(s.axis).norm() <= 1e-12 * omega.norm();
            }
            const Real off = (s.centre - point).norm();
            if (aboutAxis && off == 0) return 0;
            if constexpr (D == 2) {
              return off + s.radius;
            } else {
              return off + std::sqrt(s.radius * s.radius + s.halfLength * s.halfLength);
            }
          }
        },
        shape);
  }
};

// Returns nothing. Throws demlab::Error {VALUE HOLE} unless hole is 0 (no hole) or a positive
// number below every half extent of f (the hole lies inside the wall and leaves a rim). The
// command and the checkpoint reader both check a hole with it.
template <int D>
void checkWallHole(const physics::FlatWallShape<D>& f, double hole) {
  if (hole == 0) return;
  if (!(std::isfinite(hole) && hole > 0)) {
    throwBad("hole", physics::formatReal(hole), "must be a positive number");
  }
  for (int k = 0; k < D - 1; ++k) {
    if (!(hole < f.halfExtents[k])) {
      throwBad(
          "hole", physics::formatReal(hole),
          "must be less than every half extent (" + physics::formatReal(f.halfExtents[k]) + " m)");
    }
  }
}

template <int D>
class WallSet {
 public:
  WallSet() : pool_("wall"), names_("wall") {}

  std::vector<Wall<D>> items;  // dense order

  HandlePool<WallKind>& pool() { return pool_; }
  const HandlePool<WallKind>& pool() const { return pool_; }
  NameLookup<WallId>& names() { return names_; }
  const NameLookup<WallId>& names() const { return names_; }
  TagTable<WallKind>& tags() { return tags_; }
  const TagTable<WallKind>& tags() const { return tags_; }

  WallId add(Wall<D> w, const std::string& name, const std::vector<std::string>& tagList) {
    const WallId id = pool_.allocate();
    items.push_back(std::move(w));
    if (!name.empty()) names_.add(name, id);
    for (const std::string& t : tagList) tags_.add(id, t);
    return id;
  }
  void remove(WallId id) {
    applySwapRemove(items, pool_.free(id));
    names_.remove(id);
    tags_.removeObject(id);
  }
  bool anyMoving() const {
    for (const auto& w : items) {
      if (w.moving || w.servo) return true;
    }
    return false;
  }
  size_t size() const { return items.size(); }

 private:
  HandlePool<WallKind> pool_;
  NameLookup<WallId> names_;
  TagTable<WallKind> tags_;
};

// Returns true if some wall of walls has a scripted motion (a TimeFunction).
template <int D>
bool anyScripted(const std::vector<Wall<D>>& walls) {
  return std::any_of(walls.begin(), walls.end(), [](const Wall<D>& w) { return w.scripted(); });
}

}  // namespace demlab::sim
