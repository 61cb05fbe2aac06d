// The shape table (sim/shape.hpp): registration, lookup and Geometry making.
#include "sim/shape.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "sim/obj_manager.hpp"

namespace demlab::sim {

template <int D>
ShapeTable<D>& ShapeTable<D>::get() {
  static ShapeTable table;
  return table;
}

template <int D>
ShapeTable<D>::ShapeTable() {
  // The built-in shape types, the ball first (id 0): one line each.
  registerBall<D>(*this);
  registerSuperquadric<D>(*this);
  registerPolytope<D>(*this);
  registerLevelSet<D>(*this);
  registerClump<D>(*this);
  registerAssembly<D>(*this);
}

template <int D>
TypeId ShapeTable<D>::add(std::unique_ptr<ShapeType<D>> type) {
  const std::string name(type->name());
  if (registry_.find(name)) {
    throw Error("shape type \"" + name + "\" already exists", {"EXISTS", "NAME"});
  }
  const TypeId id = registry_.add(name);
  types_.push_back(std::move(type));
  walls_.emplace_back();
  return id;
}

template <int D>
void ShapeTable<D>::addPair(std::string_view a, std::string_view b, ElementPairEntry<D> entry) {
  pairs_.add(registry_.get(a), registry_.get(b), entry);
}

template <int D>
void ShapeTable<D>::addWall(std::string_view a, WallShape wall, ElementWallEntry<D> entry) {
  const TypeId id = registry_.get(a);
  ElementWallEntry<D>& e = walls_[id.value][static_cast<int>(wall)];
  if (e.fn != nullptr || e.ballPass) {
    throw Error("contact routine for shape type \"" + std::string(a) + "\" and wall kind " +
                    std::to_string(static_cast<int>(wall)) + " already exists",
                {"EXISTS", "INTERACTION"});
  }
  e = entry;
}

template <int D>
const ShapeType<D>* ShapeTable<D>::find(std::string_view name) const {
  const auto id = registry_.find(name);
  return id ? types_[id->value].get() : nullptr;
}

template <int D>
std::vector<std::string> ShapeTable<D>::names() const {
  std::vector<std::string> out;
  for (const auto& t : types_) out.emplace_back(t->name());
  return out;
}

template <int D>
Geometry<D> ShapeTable<D>::makeGeometry(std::string_view name,
                                        std::span<const double> params) const {
  const auto id = registry_.find(name);
  if (!id) {
    std::string list;
    const std::vector<std::string> all = names();
    for (size_t k = 0; k < all.size(); ++k) {
      list += (k == 0 ? "" : k + 1 == all.size() ? " or " : ", ") + all[k];
    }
    throw Error("bad shape \"" + std::string(name) + "\": a " + std::to_string(D) +
                    "D scene takes " + list,
                {"VALUE", "SHAPE"});
  }
  const ShapeType<D>& t = *types_[id->value];
  Geometry<D> g;
  g.shape = *id;
  if (t.sizedByRadius()) {
    if (!params.empty()) {
      throw Error("bad shape parameters: a " + std::string(name) +
                      " takes none (its size is -radius)",
                  {"VALUE", "SHAPE"});
    }
    return g;
  }
  t.check(params);
  g.params.assign(params.begin(), params.end());
  MassProperties<D> m = t.massProperties(params);
  // A type that can move its parameters is moved so that the centroid is the origin (unless it
  // is there already, to the check's tolerance: a checkpoint's moved parameters stay as saved,
  // so the loaded Geometry is the saved one bit for bit).
  if (m.volume > 0 && m.centroid.norm() > 0) {
    auto moved = t.translated(g.params, VecD<D>(-m.centroid));
    if (moved && m.centroid.norm() > 1e-12 * t.boundingRadius(params)) {
      g.params = std::move(*moved);
      m = t.massProperties(g.params);
    }
  }
  g.boundRadius = t.boundingRadius(g.params);
  g.volume = m.volume;
  const Real scale = std::max(g.boundRadius, Real{1e-300});
  if (!(m.centroid.norm() <= 1e-9 * scale)) {
    throw Error("shape type \"" + std::string(name) +
                    "\" puts the centroid away from the origin: it must describe the shape "
                    "about its centroid",
                {"VALUE", "CENTROID"});
  }
  if (!(g.boundRadius > 0 && std::isfinite(g.boundRadius) && m.volume > 0 &&
        std::isfinite(m.volume))) {
    throw Error("bad shape parameters: the " + std::string(name) + " has no size",
                {"VALUE", "SHAPE"});
  }
  if constexpr (D == 2) {
    g.principalMoments = Vec3(0, 0, m.inertia(2, 2));
    g.isotropic = true;
    if (!(m.inertia(2, 2) > 0 && std::isfinite(m.inertia(2, 2)))) {
      throw Error("bad shape parameters: the " + std::string(name) + " has no rotational inertia",
                  {"VALUE", "SHAPE"});
    }
  } else {
    // The principal axes: a right-handed frame of the symmetric tensor's eigenvectors.
    Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (m.inertia + m.inertia.transpose()));
    Mat3 axes = eig.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
    g.principalMoments = eig.eigenvalues();
    g.principal = Quat(axes).normalized();
    const Real lo = g.principalMoments.minCoeff(), hi = g.principalMoments.maxCoeff();
    if (!(lo > 0 && std::isfinite(hi))) {
      throw Error("bad shape parameters: the " + std::string(name) + " has no rotational inertia",
                  {"VALUE", "SHAPE"});
    }
    g.isotropic = hi - lo <= 1e-12 * hi;
  }
  g.data = t.derive(g.params);
  g.placedSize = t.placedSize(g.params);
  if (auto b = t.balls(g.params)) g.balls = std::move(*b);
  return g;
}

void throwNoRoutine(std::string_view a, std::string_view b) {
  throw Error("no contact routine for shape type \"" + std::string(a) + "\" and " +
                  (b == "a wall" ? std::string(b) : "shape type \"" + std::string(b) + "\"") +
                  ": the scene can't run until one is registered",
              {"LOOKUP", "INTERACTION"});
}

template <int D>
std::pair<Real, Real> inverseMassAndInertia(const Geometry<D>& g, Real rho, Real r) {
  if (g.boundRadius == 0) {
    const Real mass = ballMass<D>(rho, r);
    return {1 / mass, 1 / ballInertia<D>(mass, r)};
  }
  const Real invMass = 1 / (rho * g.volume);
  if (D == 2) return {invMass, 1 / (rho * g.principalMoments[2])};
  if (g.isotropic) return {invMass, 1 / (rho * g.principalMoments[0])};
  return {invMass, 0};
}

template class ShapeTable<2>;
template class ShapeTable<3>;
template std::pair<Real, Real> inverseMassAndInertia<2>(const Geometry<2>&, Real, Real);
template std::pair<Real, Real> inverseMassAndInertia<3>(const Geometry<3>&, Real, Real);

}  // namespace demlab::sim
