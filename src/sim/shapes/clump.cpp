// The clump: a rigid assembly of balls (spheres in 3D, discs in 2D), the multi-sphere element of
// PFC, YADE and LIGGGHTS. Parameters: its members' centres and radii, {x y z r ...} in 3D and
// {x y r ...} in 2D, given about any point (the table moves them so that the centre of mass of
// their union is the element's position).
//
// Mass properties: of the union, overlaps counted once. Members that do not overlap give the
// balls' closed forms; otherwise those less the overlaps, integrated along lines (z in 3D, y in 2D: each
// line's chords merged and their moments integrated exactly) over a 256 x 256 (3D) or 65 536
// (2D) midpoint grid across the other axes.
//
// Rows: every member against the other element's members (or the ball), and against every wall
// kind through the ball's own narrow phase (physics/narrow_phase): each touching member is a
// contact point with the member's radius as its Hertz radius, keyed by the member (or the pair of
// members) so its spring follows it. At most kMaxContactPoints points a pair: beyond that the
// deepest are kept. Against a superquadric each member is a ball meeting it (its midway point).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "core/validity.hpp"
#include "physics/narrow_phase.hpp"
#include "sim/obj_manager.hpp"
#include "sim/shape.hpp"
#include "sim/shapes/level_set.hpp"
#include "sim/shapes/radial_mesh.hpp"
#include "physics/mesh_contact.hpp"
#include "sim/shapes/level_set.hpp"
#include "sim/shapes/polytope.hpp"
#include "sim/shapes/superquadric.hpp"

namespace demlab::sim {

namespace {

constexpr size_t kMaxMembers = 64;

template <int D>
constexpr size_t stride() {
  return D + 1;
}

// Member k's centre in the body frame, and its radius.
template <int D>
VecD<D> memberCentre(std::span<const double> p, size_t k) {
  VecD<D> c;
  for (int i = 0; i < D; ++i) c[i] = p[k * stride<D>() + i];
  return c;
}
template <int D>
Real memberRadius(std::span<const double> p, size_t k) {
  return p[k * stride<D>() + D];
}

// The union's moments about the origin: volume, first moments, second moments (3D: the matrix
// of integrals of x_i x_j).
template <int D>
struct Moments {
  Real volume = 0;
  VecD<D> first = VecD<D>::Zero();
  MatD<D> second = MatD<D>::Zero();
};

template <int D>
bool anyOverlap(std::span<const double> p) {
  const size_t n = p.size() / stride<D>();
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = a + 1; b < n; ++b) {
      const Real d = (memberCentre<D>(p, a) - memberCentre<D>(p, b)).norm();
      if (d < memberRadius<D>(p, a) + memberRadius<D>(p, b)) return true;
    }
  }
  return false;
}

// The balls' closed forms, for members that do not overlap.
template <int D>
Moments<D> separateMoments(std::span<const double> p) {
  Moments<D> m;
  for (size_t k = 0; k < p.size() / stride<D>(); ++k) {
    const VecD<D> c = memberCentre<D>(p, k);
    const Real r = memberRadius<D>(p, k);
    const Real v = ballMass<D>(1, r);
    // About its centre, the integral of x_i x_j over a ball is delta_ij v r^2 / (D + 2).
    m.volume += v;
    m.first += v * c;
    m.second += v * (c * c.transpose()) + MatD<D>::Identity() * (v * r * r / (D + 2));
  }
  return m;
}

// Integrates the union along lines of the last axis over a midpoint grid of the others.
template <int D>
Moments<D> integratedMoments(std::span<const double> p) {
  const size_t n = p.size() / stride<D>();
  VecD<D> lo = VecD<D>::Constant(1e300), hi = VecD<D>::Constant(-1e300);
  for (size_t k = 0; k < n; ++k) {
    const VecD<D> c = memberCentre<D>(p, k);
    const Real r = memberRadius<D>(p, k);
    lo = lo.cwiseMin(c - VecD<D>::Constant(r));
    hi = hi.cwiseMax(c + VecD<D>::Constant(r));
  }
  constexpr int grid = D == 3 ? 256 : 65536;
  const int cols = D == 3 ? grid * grid : grid;
  const Real dx = (hi[0] - lo[0]) / grid, dy = D == 3 ? (hi[1] - lo[1]) / grid : 1;
  const Real area = dx * dy;
  // m: the union's integral; each: the members' own, by the same rule. Their difference is the
  // overlaps' part, whose error is the grid's at the few lines where members meet, while the
  // balls' rims (the rule's large error) cancel.
  Moments<D> m, each;
  std::vector<std::pair<Real, Real>> chords;
  for (int col = 0; col < cols; ++col) {
    Vec3 at = Vec3::Zero();  // the line's fixed coordinates (3D: x, y; 2D: x)
    at[0] = lo[0] + (col % grid + 0.5) * dx;
    if (D == 3) at[1] = lo[1] + (col / grid + 0.5) * dy;
    chords.clear();
    for (size_t k = 0; k < n; ++k) {
      const VecD<D> c = memberCentre<D>(p, k);
      const Real r = memberRadius<D>(p, k);
      Real d2 = (at[0] - c[0]) * (at[0] - c[0]);
      if (D == 3) d2 += (at[1] - c[1]) * (at[1] - c[1]);
      if (d2 >= r * r) continue;
      const Real h = std::sqrt(r * r - d2);
      chords.emplace_back(c[D - 1] - h, c[D - 1] + h);
    }
    if (chords.empty()) continue;
    std::sort(chords.begin(), chords.end());
    Real z0 = chords[0].first, z1 = chords[0].second;
    const auto addTo = [&](Moments<D>& to, Real a, Real b) {
      const Real len = b - a, mz = (b * b - a * a) / 2, mzz = (b * b * b - a * a * a) / 3;
      to.volume += len * area;
      for (int i = 0; i < D - 1; ++i) {
        to.first[i] += at[i] * len * area;
        to.second(i, D - 1) += at[i] * mz * area;
        for (int j = 0; j < D - 1; ++j) to.second(i, j) += at[i] * at[j] * len * area;
      }
      to.first[D - 1] += mz * area;
      to.second(D - 1, D - 1) += mzz * area;
    };
    const auto add = [&](Real a, Real b) { addTo(m, a, b); };
    for (const auto& [a, b] : chords) addTo(each, a, b);
    for (size_t k = 1; k < chords.size(); ++k) {
      if (chords[k].first <= z1) {
        z1 = std::max(z1, chords[k].second);
      } else {
        add(z0, z1);
        z0 = chords[k].first, z1 = chords[k].second;
      }
    }
    add(z0, z1);
  }
  for (int i = 0; i < D - 1; ++i) {
    m.second(D - 1, i) = m.second(i, D - 1);
    each.second(D - 1, i) = each.second(i, D - 1);
  }
  Moments<D> out = separateMoments<D>(p);
  out.volume += m.volume - each.volume;
  out.first += m.first - each.first;
  out.second += m.second - each.second;
  return out;
}

template <int D>
class ClumpType final : public ShapeType<D> {
 public:
  std::string_view name() const override { return "clump"; }
  std::string_view parameters() const override {
    return D == 3 ? "x y z r ...: its members' centres and radii (m), about any point"
                  : "x y r ...: its members' centres and radii (m), about any point";
  }
  void check(std::span<const double> p) const override {
    const size_t s = stride<D>();
    if (p.empty() || p.size() % s != 0 || p.size() / s > kMaxMembers) {
      throw Error("bad shape parameters: a clump takes " + std::to_string(s) +
                      " numbers a member (" + std::string(parameters()) + "), 1 to " +
                      std::to_string(kMaxMembers) + " members, got " + std::to_string(p.size()) +
                      " numbers",
                  {"VALUE", "SHAPE"});
    }
    Real lo = 1e300, hi = 0, reach = 0;
    for (size_t k = 0; k < p.size() / s; ++k) {
      const Real r = memberRadius<D>(p, k);
      if (!validity::inRange(r, validity::kMinRadius, validity::kMaxRadius)) {
        throw Error("bad shape parameters: member " + std::to_string(k + 1) +
                        "'s radius must be between 1e-12 and 1e9 m",
                    {"VALUE", "SHAPE"});
      }
      lo = std::min(lo, r), hi = std::max(hi, r);
      reach = std::max(reach, memberCentre<D>(p, k).norm() + r);
    }
    if (!(reach <= validity::kMaxRadius) || hi > 1e6 * lo || reach > 1e6 * lo) {
      throw Error("bad shape parameters: the clump's members must lie within 1e6 of its "
                  "smallest member's radius of each other",
                  {"VALUE", "SHAPE"});
    }
  }
  Real boundingRadius(std::span<const double> p) const override {
    Real b = 0;
    for (size_t k = 0; k < p.size() / stride<D>(); ++k) {
      b = std::max(b, memberCentre<D>(p, k).norm() + memberRadius<D>(p, k));
    }
    return b;
  }
  MassProperties<D> massProperties(std::span<const double> p) const override {
    const Moments<D> mo = anyOverlap<D>(p) ? integratedMoments<D>(p) : separateMoments<D>(p);
    MassProperties<D> m;
    m.volume = mo.volume;
    m.centroid = mo.first / mo.volume;
    // About the centroid: the second moments less the volume's at the centroid, then the
    // inertia tensor trace(S) I - S.
    const MatD<D> s = mo.second - mo.volume * (m.centroid * m.centroid.transpose());
    m.inertia = Mat3::Zero();
    if constexpr (D == 3) {
      m.inertia = Mat3::Identity() * s.trace() - s;
    } else {
      m.inertia(2, 2) = s.trace();
    }
    return m;
  }
  std::optional<std::vector<double>> scaled(std::span<const double> p, Real f) const override {
    std::vector<double> out(p.begin(), p.end());
    for (double& x : out) x *= f;
    return out;
  }
  std::optional<std::vector<double>> translated(std::span<const double> p,
                                                const VecD<D>& offset) const override {
    std::vector<double> out(p.begin(), p.end());
    for (size_t k = 0; k < out.size() / stride<D>(); ++k) {
      for (int i = 0; i < D; ++i) out[k * stride<D>() + i] += offset[i];
    }
    return out;
  }
  std::optional<std::vector<double>> balls(std::span<const double> p) const override {
    return std::vector<double>(p.begin(), p.end());
  }
  // The placed form: the members' centres in the world, D numbers each.
  uint32_t placedSize(std::span<const double> p) const override {
    return static_cast<uint32_t>(p.size() / stride<D>() * D);
  }
  void place(const ElementRef<D>& e, double* out) const override {
    const std::span<const double> p = e.g->params;
    for (size_t k = 0; k < p.size() / stride<D>(); ++k) {
      const VecD<D> c = e.x + rotate(e.q, memberCentre<D>(p, k));
      for (int i = 0; i < D; ++i) out[k * D + i] = c[i];
    }
  }
  std::vector<Vec3> renderTriangles(std::span<const double> p) const override {
    std::vector<Vec3> out;
    for (size_t k = 0; k < p.size() / stride<D>(); ++k) {
      appendBallTriangles<D>(out, memberCentre<D>(p, k), memberRadius<D>(p, k));
    }
    return out;
  }
};

// The members of element e in the world: a ball is its own one member.
template <int D>
struct WorldMembers {
  VecD<D> c[kMaxMembers];
  Real r[kMaxMembers];
  size_t n = 0;
};

template <int D>
void worldMembers(const ElementRef<D>& e, WorldMembers<D>& out) {
  const std::vector<double>& p = e.g->params;
  if (p.empty()) {
    out.c[0] = e.x, out.r[0] = e.r, out.n = 1;
    return;
  }
  out.n = p.size() / stride<D>();
  for (size_t k = 0; k < out.n; ++k) {
    if (e.placed != nullptr) {
      for (int i = 0; i < D; ++i) out.c[k][i] = e.placed[k * D + i];
    } else {
      out.c[k] = e.x + rotate(e.q, memberCentre<D>(p, k));
    }
    out.r[k] = memberRadius<D>(p, k);
  }
}

// Returns whether balls of centres at x and y and radii summing to r overlap (no square root:
// most candidates of a bed are apart, and these tests are most of their cost).
template <int D>
bool ballsOverlap(const VecD<D>& x, const VecD<D>& y, Real r) {
  return (y - x).squaredNorm() < r * r;
}

template <int D>
int pairRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!ballsOverlap<D>(a.x, b.x, a.r + b.r)) return 0;
  WorldMembers<D> ma, mb;
  thread_local std::vector<ContactPoint<D>> all;
  worldMembers(a, ma);
  worldMembers(b, mb);
  all.clear();
  for (size_t i = 0; i < ma.n; ++i) {
    // A member beyond b's bounding ball meets none of b's.
    if (!ballsOverlap<D>(ma.c[i], b.x, ma.r[i] + b.r)) continue;
    for (size_t j = 0; j < mb.n; ++j) {
      if (!ballsOverlap<D>(ma.c[i], mb.c[j], ma.r[i] + mb.r[j])) continue;
      const auto g = physics::intersect<D>(physics::SphereShape<D>{ma.c[i], ma.r[i]},
                                           physics::SphereShape<D>{mb.c[j], mb.r[j]});
      if (!g) continue;
      ContactPoint<D> p;
      p.g = *g;
      p.effRadius = ma.r[i] * mb.r[j] / (ma.r[i] + mb.r[j]);
      p.feature = static_cast<uint32_t>(i * kMaxMembers + j);
      all.push_back(p);
    }
  }
  return keepDeepestPoints<D>(all, out);
}

// A clump against a superquadric or a polytope: each member as a ball, through the other
// shape's ball routine (sim/shapes/superquadric.hpp, sim/shapes/polytope.hpp).
template <int D, bool (*BallContact)(const VecD<D>&, Real, const ElementRef<D>&, ContactPoint<D>&)>
int memberRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!((b.x - a.x).norm() < a.r + b.r)) return 0;
  thread_local WorldMembers<D> m;
  thread_local std::vector<ContactPoint<D>> all;
  worldMembers(a, m);
  all.clear();
  for (size_t k = 0; k < m.n; ++k) {
    ContactPoint<D> p;
    if (!BallContact(m.c[k], m.r[k], b, p)) continue;
    p.feature = static_cast<uint32_t>(k);
    all.push_back(p);
  }
  return keepDeepestPoints<D>(all, out);
}

template <int D, class Wall>
int wallRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const Wall& w = *static_cast<const Wall*>(wall);
  if (!physics::intersect<D>(physics::SphereShape<D>{a.x, a.r}, w)) return 0;
  thread_local WorldMembers<D> m;
  thread_local std::vector<ContactPoint<D>> all;
  worldMembers(a, m);
  all.clear();
  for (size_t k = 0; k < m.n; ++k) {
    const auto g = physics::intersect<D>(physics::SphereShape<D>{m.c[k], m.r[k]}, w);
    if (!g) continue;
    ContactPoint<D> p;
    p.g = *g;
    p.effRadius = m.r[k];
    p.feature = static_cast<uint32_t>(k);
    all.push_back(p);
  }
  return keepDeepestPoints<D>(all, out);
}

// A clump against a mesh wall: each member as a ball (physics/mesh_contact.hpp), its points'
// features its member's and their rank there.
template <int D>
int meshRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  const auto& mesh = *static_cast<const physics::MeshShape<D>*>(wall);
  thread_local WorldMembers<D> m;
  thread_local std::vector<ContactPoint<D>> all;
  worldMembers(a, m);
  all.clear();
  physics::MeshContact<D> c[kMaxContactPoints];
  for (size_t k = 0; k < m.n; ++k) {
    const int n = physics::sphereMeshContacts<D>({m.c[k], m.r[k]}, mesh, c, kMaxContactPoints);
    for (int j = 0; j < n; ++j) {
      all.push_back({c[j].g, m.r[k], static_cast<uint32_t>(k * kMaxContactPoints) + c[j].feature});
    }
  }
  return keepDeepestPoints<D>(all, out);
}

}  // namespace

template <int D>
void registerClump(ShapeTable<D>& t) {
  t.add(std::make_unique<ClumpType<D>>());
  const std::string_view ball = D == 3 ? "sphere" : "disc";
  t.addPair("clump", "clump", {pairRow<D>, false});
  t.addPair("clump", ball, {pairRow<D>, false});
  t.addPair("clump", D == 3 ? "superquadric" : "superellipse",
            {memberRow<D, ballSuperquadricContact<D>>, false});
  t.addPair("clump", D == 3 ? "polyhedron" : "polygon", {memberRow<D, ballPolytopeContact<D>>, false});
  t.addPair("clump", "levelset", {memberRow<D, ballLevelSetContact<D>>, false});
  t.addWall("clump", WallShape::Plane, {wallRow<D, physics::PlaneShape<D>>, false});
  t.addWall("clump", WallShape::Finite, {wallRow<D, physics::FlatWallShape<D>>, false});
  t.addWall("clump", WallShape::Box, {wallRow<D, physics::BoxShape<D>>, false});
  t.addWall("clump", WallShape::Drum, {wallRow<D, physics::DrumShape<D>>, false});
  if (D == 3) t.addWall("clump", WallShape::Mesh, {meshRow<D>, false});
}

template void registerClump<2>(ShapeTable<2>&);
template void registerClump<3>(ShapeTable<3>&);

}  // namespace demlab::sim
