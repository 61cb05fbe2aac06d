// SimulationManager<D>: walls (checking a WallDef, adding, removing, querying).
#include <cmath>
#include <numbers>

#include <type_traits>

#include "sim/convert.hpp"
#include "sim/distribution.hpp"
#include "sim/record_geometry.hpp"
#include "physics/triangle_mesh.hpp"
#include "sim/simulation_manager.hpp"

namespace demlab::sim {

// ---- walls ---------------------------------------------------------------------------------

namespace {

// Throws {VALUE <FIELD>} unless v is zero (a field the wall's shape does not use).
inline void checkUnused(const Vec3d& v, const std::string& field, const char* shape) {
  if (v[0] != 0 || v[1] != 0 || v[2] != 0) {
    throwBad(field, formatVec(v, 3), std::string("not used by a ") + shape + " wall");
  }
}
inline void checkUnused(double x, const std::string& field, const char* shape) {
  if (x != 0)
    throwBad(field, physics::formatReal(x), std::string("not used by a ") + shape + " wall");
}

// Returns v / |v|. Throws {VALUE <FIELD>} for a zero vector.
template <int D>
VecD<D> unit(const VecD<D>& v, const std::string& field) {
  // Scaled by the largest component first: the norm of (1e300 1e300 0) overflows and that of
  // (1e-200 0 0) underflows, either of which would make a zero or NaN direction.
  const Real m = v.template lpNorm<Eigen::Infinity>();
  if (!(m > 0)) throwBad(field, formatVec(fromVec<D>(v), D), "must be a non-zero vector");
  const VecD<D> u = v / m;
  return u / u.norm();
}

// Returns nothing. Throws {VALUE <FIELD>} unless every component of v is at most limit in
// magnitude (the validity policy's bounds on coordinates and speeds).
template <int D>
void checkMagnitude(const VecD<D>& v, double limit, const std::string& field,
                    const std::string& unit) {
  if (!(v.template lpNorm<Eigen::Infinity>() <= limit)) {
    throwBad(field, formatVec(fromVec<D>(v), D),
             "must be at most " + physics::formatReal(limit) + " " + unit + " on each axis");
  }
}

// Gives w the motion m (checked first: VALUE <FIELD>, w unchanged then), from w.t0 on.
// Changes w's motion fields and its moving flag.
template <int D>
void setMotion(Wall<D>& w, const WallMotion& m) {
  const VecD<D> velocity = toVec<D>(m.velocity, "velocity");
  const AngularD<D> omega = toAngular<D>(m.angularVelocity, "angular velocity");
  const VecD<D> amplitude = toVec<D>(m.amplitude, "amplitude");
  checkMagnitude<D>(velocity, validity::kMaxSpeed, "velocity", "m/s");
  checkMagnitude<D>(amplitude, validity::kMaxCoordinate, "amplitude", "m");
  const Vec3d om = fromAngular(omega);
  if (!(std::hypot(om[0], om[1], om[2]) <= validity::kMaxWallSpin)) {
    throwBad("angular velocity", formatVec(m.angularVelocity, 3), "must be at most 1e9 rad/s");
  }
  if (!(m.frequency >= 0 && m.frequency <= 1e9)) {
    throwBad("frequency", physics::formatReal(m.frequency), "must be a number from 0 to 1e9 Hz");
  }
  if (m.frequency == 0 && amplitude.squaredNorm() > 0) {
    throwBad("frequency", "0", "a vibration needs a positive frequency");
  }
  if (!std::isfinite(m.phase)) throwBad("phase", physics::formatReal(m.phase), "must be finite");
  w.velocity = velocity;
  w.omega = omega;
  w.amplitude = amplitude;
  w.frequency = m.frequency;
  w.phase = m.phase;
  w.velocityFn = m.velocityFn;
  w.omegaFn = m.angularVelocityFn;
  if constexpr (D == 2) w.omegaFn[0] = w.omegaFn[1] = nullptr;
  for (int k = D; k < 3; ++k) w.velocityFn[k] = nullptr;
  w.scriptedAngle = 0;
  w.moving = w.velocity.squaredNorm() > 0 || w.amplitude.squaredNorm() > 0 ||
             squaredNorm(w.omega) > 0 || w.scripted();
  // The velocity of the reference point at t0, as moveTo(t0) gives it.
  w.pointVelocity =
      w.velocity + w.amplitude * (2 * std::numbers::pi * m.frequency * std::cos(m.phase));
}

}  // namespace

template <int D>
Wall<D> SimulationManager<D>::checkWall(const WallDef& def) const {
  Wall<D> w;
  w.kind = def.shape;
  w.material = materialIndex(def.material);
  const VecD<D> p = toVec<D>(def.point, "point");
  checkMagnitude<D>(p, validity::kMaxCoordinate, "point", "m");
  for (double h : def.halfExtents) {
    if (h > validity::kMaxCoordinate) {
      throwBad("half extents", physics::formatReal(h),
               "must be at most " + physics::formatReal(validity::kMaxCoordinate) + " m");
    }
  }
  if (def.radius > validity::kMaxCoordinate) {
    throwBad("radius", physics::formatReal(def.radius),
             "must be at most " + physics::formatReal(validity::kMaxCoordinate) + " m");
  }
  switch (def.shape) {
    case WallShape::Plane: {
      const char* sh = "plane";
      checkUnused(def.hole, "hole", sh);
      checkUnused(def.axis, "axis", sh);
      checkUnused(def.halfExtents, "half extents", sh);
      checkUnused(def.rotation, "rotation", sh);
      checkUnused(def.radius, "radius", sh);
      checkUnused(def.halfLength, "half length", sh);
      w.shape0 = physics::PlaneShape<D>{p, unit<D>(toVec<D>(def.normal, "normal"), "normal")};
      break;
    }
    case WallShape::Finite: {
      const char* sh = "finite";
      checkUnused(def.rotation, "rotation", sh);
      checkUnused(def.radius, "radius", sh);
      checkUnused(def.halfLength, "half length", sh);
      const VecD<D> n = unit<D>(toVec<D>(def.normal, "normal"), "normal");
      physics::FlatWallShape<D> f;
      f.centre = p;
      if constexpr (D == 2) {
        checkUnused(def.axis, "axis", sh);
        if (def.halfExtents[1] != 0 || def.halfExtents[2] != 0) {
          throwBad("half extents", formatVec(def.halfExtents, 3), "a segment has one half length");
        }
        checkPositive(def.halfExtents[0], "half extents");
        f.axes[0] = perp(n);
        f.halfExtents[0] = def.halfExtents[0];
      } else {
        const VecD<D> u = unit<D>(toVec<D>(def.axis, "axis"), "axis");
        if (std::abs(u.dot(n)) > 1e-9) {
          throwBad("axis", formatVec(def.axis, 3), "must be perpendicular to the normal");
        }
        if (def.halfExtents[2] != 0) {
          throwBad("half extents", formatVec(def.halfExtents, 3),
                   "a rectangle has two half lengths");
        }
        checkPositive(def.halfExtents[0], "half extents");
        checkPositive(def.halfExtents[1], "half extents");
        const VecD<D> u2 = (u - u.dot(n) * n).normalized();
        f.axes[0] = u2;
        f.axes[1] = n.cross(u2);
        f.halfExtents[0] = def.halfExtents[0];
        f.halfExtents[1] = def.halfExtents[1];
      }
      checkWallHole<D>(f, def.hole);
      f.hole = def.hole;
      w.shape0 = f;
      break;
    }
    case WallShape::Box: {
      const char* sh = "box";
      checkUnused(def.hole, "hole", sh);
      checkUnused(def.normal, "normal", sh);
      checkUnused(def.axis, "axis", sh);
      checkUnused(def.radius, "radius", sh);
      checkUnused(def.halfLength, "half length", sh);
      physics::BoxShape<D> b;
      b.centre = p;
      for (int k = 0; k < D; ++k) checkPositive(def.halfExtents[k], "half extents");
      if (D == 2 && def.halfExtents[2] != 0) {
        throwBad("half extents", formatVec(def.halfExtents, 3), "a 2D box has two half lengths");
      }
      for (int k = 0; k < D; ++k) b.halfExtents[k] = def.halfExtents[k];
      const AngularD<D> rv = toAngular<D>(def.rotation, "rotation");
      if constexpr (D == 2) {
        b.axes = Rotation2{rv}.matrix();
      } else {
        b.axes = quatFromRotationVector(rv).toRotationMatrix();
      }
      w.shape0 = b;
      break;
    }
    case WallShape::Drum: {
      const char* sh = "drum";
      checkUnused(def.hole, "hole", sh);
      checkUnused(def.normal, "normal", sh);
      checkUnused(def.halfExtents, "half extents", sh);
      checkUnused(def.rotation, "rotation", sh);
      physics::DrumShape<D> d;
      d.centre = p;
      checkPositive(def.radius, "radius");
      d.radius = def.radius;
      if constexpr (D == 2) {
        checkUnused(def.axis, "axis", sh);
        checkUnused(def.halfLength, "half length", sh);
      } else {
        d.axis = unit<D>(toVec<D>(def.axis, "axis"), "axis");
        if (!(def.halfLength > 0)) {
          throwBad("half length", physics::formatReal(def.halfLength), "must be a positive number");
        }
        d.halfLength = def.halfLength;
      }
      w.shape0 = d;
      break;
    }
    case WallShape::Mesh: {
      const char* sh = "mesh";
      if (D != 3) throw Error("bad wall: a mesh wall is 3D only", {"VALUE", "SHAPE"});
      checkUnused(def.hole, "hole", sh);
      checkUnused(def.normal, "normal", sh);
      checkUnused(def.axis, "axis", sh);
      checkUnused(def.halfExtents, "half extents", sh);
      checkUnused(def.radius, "radius", sh);
      checkUnused(def.halfLength, "half length", sh);
      if (!def.mesh || def.mesh->triangles.empty()) throw Error("bad wall: a mesh wall needs a mesh", {"VALUE", "MESH"});
      physics::MeshShape<D> m;
      m.mesh = def.mesh;
      if constexpr (D == 3) {
        m.rotation = quatFromRotationVector(toAngular<D>(def.rotation, "rotation")).toRotationMatrix();
        m.offset = p;
        // Every corner where it goes must lie within the coordinates' bound.
        const physics::Bounds<D> b = physics::bounds(m);
        for (int k = 0; k < D; ++k) {
          if (!(std::abs(b.lo[k]) <= validity::kMaxCoordinate && std::abs(b.hi[k]) <= validity::kMaxCoordinate)) {
            throwBad("point", formatVec(def.point, 3), "puts the mesh beyond the coordinates' bound");
          }
        }
      }
      w.shape0 = m;
      break;
    }
    default:
      throw Error("bad wall shape", {"VALUE", "SHAPE"});
  }
  if (def.motion) setMotion(w, *def.motion);
  for (const std::string& t : def.tags) checkTagName(t);
  if (!def.name.empty()) {
    checkObjectName("wall", def.name);
    if (s_.walls.names().find(def.name)) throwNameExists("wall", def.name);
  }
  w.t0 = s_.time;
  w.point0 = p;
  w.moveTo(s_.time);
  w.pointAtBuild = w.point;
  w.timeAtBuild = s_.time;
  return w;
}

template <int D>
WallId SimulationManager<D>::addWall(const WallDef& def) {
  Wall<D> w = checkWall(def);
  const WallId id = s_.walls.add(std::move(w), def.name, def.tags);
  markPlaced(id);
  s_.needRebuild = true;
  touchConfig();
  return id;
}

template <int D>
void SimulationManager<D>::removeWall(WallId id) {
  const uint32_t w = s_.walls.pool().denseIndex(id);
  if (s_.dist) {
    dropWallCandidates(s_, w);  // (every rank removes it alike)
  } else {
    forgetCandidates();
  }
  if (s_.keepHistory) s_.histories.removeId(wallPairId(id.index));
  // Its slot may come back for a new wall: its shape springs go with it.
  s_.shapeSprings.eraseIf([&](const ShapeSpringKey& k) { return k.b == wallPairId(id.index); });
  s_.walls.remove(id);
  std::erase(s_.placedWalls, id);
  s_.needRebuild = true;
  touchConfig();
}

template <int D>
void SimulationManager<D>::setWallMotion(WallId id, const WallMotion& m) {
  Wall<D>& live = s_.walls.items[s_.walls.pool().denseIndex(id)];
  Wall<D> w = live;
  w.rebase(s_.time);
  setMotion(w, m);  // throws before anything changed
  w.servo = false;
  // Its candidates and springs are kept (same dense index): the contacts go on.
  live = w;
  // A new search (the reach of a changed rotation is not what the last one allowed for), and
  // the loop rebuilt (the walls module comes or goes); the forces of the state stay valid (the
  // wall has not moved), so a run goes on as if the motion had changed within it.
  s_.needRebuild = true;
  configDirty_ = true;
}

template <int D>
void SimulationManager<D>::setWallServo(WallId id, const WallServoDef& d) {
  Wall<D>& live = s_.walls.items[s_.walls.pool().denseIndex(id)];
  if (live.kind != WallShape::Plane && live.kind != WallShape::Finite) {
    throw Error("bad wall: a servo moves a plane or a finite wall along its normal",
                {"VALUE", "SHAPE"});
  }
  if (!(std::isfinite(d.target) && d.target >= 0)) {
    throwBad("target", physics::formatReal(d.target), "must be a non-negative number");
  }
  checkPositive(d.gain, "gain");
  checkPositive(d.maxSpeed, "maxspeed");
  live.rebase(s_.time);
  live.velocityFn = {};
  live.omegaFn = {};
  live.servo = true;
  live.servoTarget = d.target;
  live.servoGain = d.gain;
  live.servoMaxSpeed = d.maxSpeed;
  s_.needRebuild = true;
  configDirty_ = true;
}

template <int D>
WallState SimulationManager<D>::wall(WallId id) const {
  const Wall<D>& w = s_.walls.items[s_.walls.pool().denseIndex(id)];
  WallState st;
  st.id = id;
  if (auto n = s_.walls.names().nameOf(id)) st.name = std::string(*n);
  for (std::string_view t : s_.walls.tags().tagsOf(id)) st.tags.emplace_back(t);
  st.material = s_.materialNames[w.material];
  st.shape = w.kind;
  st.point = fromVec<D>(w.point);
  st.velocity = fromVec<D>(w.pointVelocity);
  st.angularVelocity = fromAngular(w.omega);
  st.orientation = fromRotation((w.turned * w.turnedBefore).normalized());
  st.force = fromVec<D>(w.force);
  st.work = w.work;
  st.servo = w.servo;
  st.scripted = w.scripted();
  // The torque about the reference point, from the records of the last step that kept them.
  const uint32_t dense = s_.walls.pool().denseIndex(id);
  AngularD<D> torque = Wall<D>::zeroAngular();
  RecordGeometryReader<D> reader;
  for (const ContactRecord<D>& c : s_.contacts) {
    if (!c.wall || c.b != dense) continue;
    if (const auto g = reader.next(s_, c))
      torque += cross(VecD<D>(g->g.point - w.point), c.force);
  }
  st.torque = fromAngular(torque);
  const physics::Bounds<D> b =
      std::visit([](const auto& sh) { return physics::bounds(sh); }, w.shape);
  for (int k = 0; k < D; ++k) {
    st.boundsLo[k] = b.lo[k];
    st.boundsHi[k] = b.hi[k];
  }
  std::visit(
      [&](const auto& sh) {
        using S = std::decay_t<decltype(sh)>;
        if constexpr (std::is_same_v<S, physics::PlaneShape<D>>) {
          st.centre = fromVec<D>(sh.point);
          st.normal = fromVec<D>(sh.normal);
        } else if constexpr (std::is_same_v<S, physics::FlatWallShape<D>>) {
          st.centre = fromVec<D>(sh.centre);
          for (int k = 0; k < D - 1; ++k) {
            st.axes[k] = fromVec<D>(sh.axes[k]);
            st.halfExtents[k] = sh.halfExtents[k];
          }
          st.hole = sh.hole;
          if constexpr (D == 2) {
            st.normal = {sh.axes[0].y(), -sh.axes[0].x(), 0};  // axes[0] = perp(normal)
          } else {
            st.normal = fromVec<D>(VecD<D>(sh.axes[0].cross(sh.axes[1]).normalized()));
          }
        } else if constexpr (std::is_same_v<S, physics::BoxShape<D>>) {
          st.centre = fromVec<D>(sh.centre);
          for (int k = 0; k < D; ++k) {
            st.axes[k] = fromVec<D>(VecD<D>(sh.axes.col(k)));
            st.halfExtents[k] = sh.halfExtents[k];
          }
        } else if constexpr (std::is_same_v<S, physics::MeshShape<D>>) {
          if constexpr (D == 3) {
            st.centre = fromVec<D>(sh.offset);
            for (int k = 0; k < 3; ++k) st.axes[k] = fromVec<D>(Vec3(sh.rotation.col(k)));
          }
          st.mesh = sh.mesh;
        } else {
          st.centre = fromVec<D>(sh.centre);
          st.radius = sh.radius;
          if constexpr (D == 3) {
            st.axes[0] = fromVec<D>(sh.axis);
            st.halfLength = sh.halfLength;
          }
        }
      },
      w.shape);
  return st;
}

template <int D>
WallId SimulationManager<D>::findWall(const std::string& name) const {
  return s_.walls.names().get(name);
}

template <int D>
std::vector<WallId> SimulationManager<D>::wallIds() const {
  const auto h = s_.walls.pool().handles();
  return {h.begin(), h.end()};
}

template class SimulationManager<2>;
template class SimulationManager<3>;

}  // namespace demlab::sim
