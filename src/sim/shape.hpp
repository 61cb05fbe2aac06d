// Element shapes (thesis chapter 10: the modular Element and its shareable Geometry).
//
// A shape type is one class implementing ShapeType<D> (its parameters, checks, bounding radius
// and mass properties) plus rows in the ShapeTable: one contact routine per pair of shape types
// (the TypeInteractionManager's table) and one per (shape type, wall kind). Elements point at a
// Geometry: the shape type with its parameters and the mass properties derived from them once,
// shared (Shareable) by every element of the same shape and size, so 10^6 equal grains hold one.
//
// The first shape type is the ball (the sphere in 3D, the disc in 2D). It is sized by each
// element's radius, so all balls share one Geometry whatever their sizes, and its rows say that
// its pairs run through the ball contact passes (the SIMD kernels of sim/contacts.hpp) rather
// than through a per-contact routine: that is how the ball keeps its speed while going through
// the same table as every other shape. Every other pair runs through sim/shape_contacts.hpp,
// which calls the row's routine for the contact points and the scene's contact law on each.
//
// The ShapeTable is one per process and dimension; a shape type added from outside src/ (a
// plug-in, a test) is registered before scenes use it, like a module row (module_table.hpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/math.hpp"
#include "core/shareable.hpp"
#include "core/type_interaction.hpp"
#include "physics/contact.hpp"
#include "sim/simulation.hpp"

namespace demlab::sim {

// What a shape type computes from its parameters, per unit density, in its body frame.
template <int D>
struct MassProperties {
  Real volume = 0;                        // 2D: the area (unit thickness, as discs)
  VecD<D> centroid = VecD<D>::Zero();     // must be the origin (the element's position)
  Mat3 inertia = Mat3::Zero();            // about the centroid; 2D: only (2, 2) is read
};

// The shareable Geometry component: a shape type, its parameters, and what follows from them.
template <int D>
struct Geometry {
  TypeId shape;
  std::vector<double> params;  // the shape type's own, in its body frame (m)
  Real boundRadius = 0;        // of the sphere about the centroid holding the shape (0: ball)
  Real volume = 0;
  // Principal moments of inertia per unit density, and the rotation taking the principal frame
  // to the body frame (the body frame is the shape's own; the integrator turns in the principal
  // one). 2D: principalMoments[2] is the moment about z and principal is the identity.
  Vec3 principalMoments = Vec3::Zero();
  Quat principal = Quat::Identity();
  // All principal moments equal (to a relative 1e-12): the element turns as a ball does, and
  // the isotropic integrator serves it. Always true in 2D.
  bool isotropic = true;
  // What the shape type derives once from its parameters for its contact routines (a
  // polyhedron's faces and edges: ShapeType::derive), or null.
  std::shared_ptr<const void> data;
  // How many numbers the type's place() writes for an element of this geometry (0: the type
  // has no placed form; ShapeType::placedSize).
  uint32_t placedSize = 0;
  // The shape as balls when it is exactly a union of them (ShapeType::balls), {centre (D
  // numbers), radius} each in the body frame, else empty.
  std::vector<double> balls;
};

template <int D>
struct ElementRef;

// A shape type's interface. Implementations are stateless: every method is const and reads the
// parameters it is given.
template <int D>
class ShapeType {
 public:
  virtual ~ShapeType() = default;
  // Returns the name `element add -shape` takes.
  virtual std::string_view name() const = 0;
  // Returns the parameter list's description, for help and errors ("a b c: half axes (m)").
  virtual std::string_view parameters() const = 0;
  // Returns true if the shape is sized by the element's radius (the ball), with no parameters.
  virtual bool sizedByRadius() const { return false; }
  // Throws demlab::Error {VALUE SHAPE} unless params describe a shape of this type (counts,
  // signs, finiteness). Changes nothing.
  virtual void check(std::span<const double> params) const = 0;
  // Returns the radius of the smallest sphere about the centroid that holds the shape.
  virtual Real boundingRadius(std::span<const double> params) const = 0;
  // Returns the volume, centroid and inertia tensor per unit density.
  virtual MassProperties<D> massProperties(std::span<const double> params) const = 0;
  // Returns params describing the same shape scaled by factor about its centroid (packings of
  // a shape in a size distribution), or nothing if the type cannot be scaled (the default).
  virtual std::optional<std::vector<double>> scaled(std::span<const double>, Real) const {
    return std::nullopt;
  }
  // Returns params describing the same shape moved by offset (a clump's members given about any
  // point are moved so that its centre of mass is the origin), or nothing if the type's
  // parameters are always about the centroid (the default).
  virtual std::optional<std::vector<double>> translated(std::span<const double>,
                                                        const VecD<D>&) const {
    return std::nullopt;
  }
  // The renderer's row: the shape as triangles in its body frame (3 points each; 2D: z = 0),
  // which snapshots draw turned and placed. Empty (the default): drawn as its bounding ball.
  virtual std::vector<Vec3> renderTriangles(std::span<const double>) const { return {}; }
  // Returns what the contact routines read of a shape besides its parameters, computed once per
  // Geometry (checked parameters about the centroid), or null (the default).
  virtual std::shared_ptr<const void> derive(std::span<const double>) const { return nullptr; }
  // Returns the shape types whose rows this type's rows call (an assembly's members'), so that
  // a run checks their routines too before it starts; empty (the default) for a type whose rows
  // are its own.
  virtual std::vector<TypeId> memberTypes(std::span<const double>) const { return {}; }
  // The placed form: what a type's rows would otherwise work out from an element's pose for
  // every pair it is in (a clump's members' centres in the world). The shape pass writes it
  // once a step for each element with a candidate and hands it to the rows in
  // ElementRef::placed. placedSize returns how many numbers place() writes (0, the default:
  // no placed form); place writes them to out for element e. Rows must give the same bits with
  // or without it.
  virtual uint32_t placedSize(std::span<const double>) const { return 0; }
  // Returns the shape as balls, {centre (D numbers), radius} each in the body frame, when it is
  // exactly a union of balls (the clump), or nothing (the default). Such bodies meet each other
  // and balls member by member through the ball contact kernel (sim/member_balls.hpp).
  virtual std::optional<std::vector<double>> balls(std::span<const double>) const {
    return std::nullopt;
  }
  virtual void place(const ElementRef<D>&, double*) const {}
};

// An element as a contact routine sees it: pose, bounding radius and shared geometry.
template <int D>
struct ElementRef {
  VecD<D> x;
  RotationD<D> q;
  Real r;  // bounding radius (the ball's radius)
  const Geometry<D>* g;
  // The scene asks for ContactPoint::localRadius (law -curvature local); rows that know a
  // surface's curvature compute it only then.
  bool localCurvature = false;
  // The element's placed form this step (ShapeType::place), or null: rows then work it out.
  const double* placed = nullptr;
};

// One contact point of a pair: the geometry the laws read (normal from A to B, overlap, point)
// and the effective radius of curvature the Hertz law takes there.
template <int D>
struct ContactPoint {
  physics::ContactGeometry<D> g;
  Real effRadius = 0;
  // Which feature of the pair touches (a vertex's index, say), stable from step to step: the
  // point's tangential spring is kept under it, as Box2D keys its warm starts by feature ids.
  uint32_t feature = 0;
  // The pair's Hertz radius from the two surfaces' own curvature at the point (law -curvature
  // local), or 0 where the row has none (the scene then takes effRadius).
  Real localRadius = 0;
  // Returns the Hertz radius the law takes: localRadius when the scene asks for the local
  // curvature and the row has one, else effRadius.
  Real hertzRadius(bool localCurvature) const {
    return localCurvature && localRadius > 0 ? localRadius : effRadius;
  }
};

// Returns the radius of the ball (the disc in 2D) of geometry g's volume (area): the Hertz
// radius the shapes without a curvature of their own take.
template <int D>
Real volumeEquivalentRadius(const Geometry<D>& g) {
  if constexpr (D == 3) return std::cbrt(3 * g.volume / (4 * std::numbers::pi));
  return std::sqrt(g.volume / std::numbers::pi);
}

// A pair may touch at up to this many points (a box face down on a plane: four corners; a
// clump's members; a level set's surface nodes).
inline constexpr int kMaxContactPoints = 64;

// Moves the points of all to out, or beyond kMaxContactPoints the deepest of them (ties by
// feature, so the choice is deterministic), and returns their count. Changes all's order.
template <int D>
int keepDeepestPoints(std::vector<ContactPoint<D>>& all, ContactPoint<D>* out) {
  if (all.size() > static_cast<size_t>(kMaxContactPoints)) {
    std::partial_sort(all.begin(), all.begin() + kMaxContactPoints, all.end(),
                      [](const ContactPoint<D>& x, const ContactPoint<D>& y) {
                        return x.g.overlap != y.g.overlap ? x.g.overlap > y.g.overlap
                                                          : x.feature < y.feature;
                      });
    all.resize(kMaxContactPoints);
  }
  std::copy(all.begin(), all.end(), out);
  return static_cast<int>(all.size());
}

// Writes the contact points of elements a and b to out[0..n) and returns n (0: apart). The
// normals point from a to b. Changes nothing else.
template <int D>
using ElementPairFn = int (*)(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out);
// The same for element a and a wall's shape now (physics::PlaneShape<D>, FlatWallShape<D>,
// BoxShape<D> or DrumShape<D>, as the row's wall kind says); normals from a to the wall.
template <int D>
using ElementWallFn = int (*)(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out);

// A row of the pair table. ballPass: the ball contact passes handle the pair (fn then serves
// queries and tests only).
template <int D>
struct ElementPairEntry {
  ElementPairFn<D> fn = nullptr;
  bool ballPass = false;
  int operator()(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) const {
    return fn(a, b, out);
  }
};
template <int D>
struct ElementWallEntry {
  ElementWallFn<D> fn = nullptr;
  bool ballPass = false;
};

inline constexpr int kWallKinds = 5;  // WallShape's values

template <int D>
class ShapeTable {
 public:
  // Returns the process's table, the ball registered first (id 0) with its rows.
  static ShapeTable& get();

  // Registers a shape type. Returns its id. Throws demlab::Error, changing nothing: {EXISTS
  // NAME} if the name is taken, {VALUE NAME} or {LIMIT TYPE} as TypeRegistry::add. Not
  // thread-safe: register before building scenes.
  TypeId add(std::unique_ptr<ShapeType<D>> type);
  // Registers the contact routine of the shape types named a and b (in that orientation).
  // Throws {LOOKUP NAME} for an unknown name, {EXISTS INTERACTION} if the pair has one.
  void addPair(std::string_view a, std::string_view b, ElementPairEntry<D> entry);
  // Registers the routine of shape type a against walls of kind `wall`. Throws {LOOKUP NAME},
  // {EXISTS INTERACTION}.
  void addWall(std::string_view a, WallShape wall, ElementWallEntry<D> entry);

  // Returns the type named name, or null.
  const ShapeType<D>* find(std::string_view name) const;
  // Returns the id of the type named name, or nothing.
  std::optional<TypeId> id(std::string_view name) const { return registry_.find(name); }
  const ShapeType<D>& type(TypeId id) const { return *types_[id.value]; }
  // Returns the id of the ball (the sphere in 3D, the disc in 2D): 0.
  static constexpr TypeId ball() { return TypeId{0}; }
  // Returns the names of the registered types, in registration order.
  std::vector<std::string> names() const;

  // Returns the pair's entry, or null (swapped: call it with b, a and negate the normals).
  const typename TypeInteractionManager<ElementPairEntry<D>>::Entry* pair(TypeId a,
                                                                          TypeId b) const {
    return pairs_.find(a, b);
  }
  // Returns the entry of shape a against walls of kind w, or null.
  const ElementWallEntry<D>* wall(TypeId a, WallShape w) const {
    const ElementWallEntry<D>& e = walls_[a.value][static_cast<int>(w)];
    return e.fn != nullptr || e.ballPass ? &e : nullptr;
  }

  // Returns a new Geometry of the shape type named name with params: checked, its mass
  // properties computed and diagonalised. Throws {VALUE SHAPE} for an unknown name (listing
  // the names) or bad params (the type's check), {VALUE CENTROID} when the type puts the
  // centroid away from the origin. Changes nothing.
  Geometry<D> makeGeometry(std::string_view name, std::span<const double> params) const;

 private:
  ShapeTable();
  TypeRegistry registry_{"shape type"};
  std::vector<std::unique_ptr<ShapeType<D>>> types_;
  TypeInteractionManager<ElementPairEntry<D>> pairs_{registry_, "contact routine"};
  std::vector<std::array<ElementWallEntry<D>, kWallKinds>> walls_;
};

// Throws demlab::Error {LOOKUP INTERACTION}: no contact routine for shape types a and b.
[[noreturn]] void throwNoRoutine(std::string_view a, std::string_view b);

// Returns a's contact points with b by the table's row for their shape types, into out, normals
// from a to b (a row registered the other way round is called swapped, its normals negated).
// Throws {LOOKUP INTERACTION} if no row serves the pair.
template <int D>
int shapePairPoints(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  const ShapeTable<D>& t = ShapeTable<D>::get();
  const auto* e = t.pair(a.g->shape, b.g->shape);
  if (e == nullptr) throwNoRoutine(t.type(a.g->shape).name(), t.type(b.g->shape).name());
  if (!e->swapped()) return e->fn(a, b, out);
  const int n = e->fn(b, a, out);
  for (int k = 0; k < n; ++k) out[k].g.normal = -out[k].g.normal;
  return n;
}

// Returns a's contact points with a wall of kind `kind` whose shape is at wall, into out.
// Throws {LOOKUP INTERACTION} if no row serves the pair.
template <int D>
int shapeWallPoints(const ElementRef<D>& a, WallShape kind, const void* wall, ContactPoint<D>* out) {
  const ShapeTable<D>& t = ShapeTable<D>::get();
  const ElementWallEntry<D>* e = t.wall(a.g->shape, kind);
  if (e == nullptr || e->fn == nullptr) throwNoRoutine(t.type(a.g->shape).name(), "a wall");
  return e->fn(a, wall, out);
}

// Returns {1 / mass, 1 / moment of inertia} of an element of geometry g, density rho and
// (bounding) radius r; the second is 0 when its inertia is not isotropic (3D), which marks the
// element for the rigid-body rotation (sim/rigid_body.hpp).
template <int D>
std::pair<Real, Real> inverseMassAndInertia(const Geometry<D>& g, Real rho, Real r);

// Registers the ball shape type and its rows in t (sim/shapes/ball.cpp). Called once by
// ShapeTable's constructor.
template <int D>
void registerBall(ShapeTable<D>& t);
// Registers the superquadric (3D) or superellipse (2D) and its rows (sim/shapes/superquadric.cpp).
template <int D>
void registerSuperquadric(ShapeTable<D>& t);
// Registers the polygon (2D) or polyhedron (3D) and its rows (sim/shapes/polytope.cpp).
template <int D>
void registerPolytope(ShapeTable<D>& t);
// Registers the level set (an arbitrary shape by its signed distance on a grid) and its rows
// (sim/shapes/level_set.cpp).
template <int D>
void registerLevelSet(ShapeTable<D>& t);
// Registers the clump (a rigid assembly of balls) and its rows (sim/shapes/clump.cpp).
template <int D>
void registerClump(ShapeTable<D>& t);
// Registers the assembly (a rigid body of members of every other type) and its rows against
// every type registered before it (sim/shapes/assembly.cpp). Called last.
template <int D>
void registerAssembly(ShapeTable<D>& t);

}  // namespace demlab::sim
