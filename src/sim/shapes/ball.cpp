// The ball shape type: the sphere in 3D, the disc in 2D (unit thickness), the first shape of the
// table (sim/shape.hpp). It is sized by each element's radius, so every ball shares one
// Geometry; its rows hand ball pairs to the ball contact passes (sim/contacts.hpp), and their
// routines, the narrow phase of physics/narrow_phase.hpp, serve queries and tests.
#include <numbers>

#include "core/error.hpp"
#include "physics/mesh_contact.hpp"
#include "physics/narrow_phase.hpp"
#include "sim/obj_manager.hpp"
#include "sim/shape.hpp"

namespace demlab::sim {

namespace {

template <int D>
class Ball final : public ShapeType<D> {
 public:
  std::string_view name() const override { return D == 3 ? "sphere" : "disc"; }
  std::string_view parameters() const override { return "none: its size is -radius"; }
  bool sizedByRadius() const override { return true; }
  void check(std::span<const double> params) const override {
    if (!params.empty()) throw Error("bad shape parameters: a ball takes none", {"VALUE", "SHAPE"});
  }
  // A ball's Geometry is shared by every size: the element's radius is its bound.
  Real boundingRadius(std::span<const double>) const override { return 0; }
  // Per unit radius: mass and inertia scale with r^D and r^(D+2) (ballMass, ballInertia).
  MassProperties<D> massProperties(std::span<const double>) const override {
    MassProperties<D> m;
    m.volume = ballMass<D>(1, 1);
    const Real i = ballInertia<D>(m.volume, 1);
    m.inertia = Mat3::Identity() * i;
    return m;
  }
};

// One contact point from physics' single-point narrow phase.
template <int D>
int fromGeometry(const std::optional<physics::ContactGeometry<D>>& g, Real effRadius,
                 ContactPoint<D>* out) {
  if (!g) return 0;
  out[0] = {*g, effRadius};
  return 1;
}

template <int D>
int ballBall(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  return fromGeometry<D>(physics::intersect<D>(physics::SphereShape<D>{a.x, a.r},
                                               physics::SphereShape<D>{b.x, b.r}),
                         a.r * b.r / (a.r + b.r), out);
}

template <int D, class Wall>
int ballWall(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  return fromGeometry<D>(
      physics::intersect<D>(physics::SphereShape<D>{a.x, a.r}, *static_cast<const Wall*>(wall)),
      a.r, out);
}

// A ball against a mesh wall: a point per surface feature it touches (physics/mesh_contact.hpp),
// through the shape pass (several points a pair, each with its own spring).
template <int D>
int ballMesh(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  physics::MeshContact<D> c[kMaxContactPoints];
  const int n = physics::sphereMeshContacts<D>({a.x, a.r}, *static_cast<const physics::MeshShape<D>*>(wall),
                                               c, kMaxContactPoints);
  for (int k = 0; k < n; ++k) out[k] = {c[k].g, a.r, c[k].feature};
  return n;
}

}  // namespace

template <int D>
void registerBall(ShapeTable<D>& t) {
  t.add(std::make_unique<Ball<D>>());
  const std::string_view n = D == 3 ? "sphere" : "disc";
  t.addPair(n, n, {ballBall<D>, true});
  t.addWall(n, WallShape::Plane, {ballWall<D, physics::PlaneShape<D>>, true});
  t.addWall(n, WallShape::Finite, {ballWall<D, physics::FlatWallShape<D>>, true});
  t.addWall(n, WallShape::Box, {ballWall<D, physics::BoxShape<D>>, true});
  t.addWall(n, WallShape::Drum, {ballWall<D, physics::DrumShape<D>>, true});
  if (D == 3) t.addWall(n, WallShape::Mesh, {ballMesh<D>, false});
}

template void registerBall<2>(ShapeTable<2>&);
template void registerBall<3>(ShapeTable<3>&);

}  // namespace demlab::sim
