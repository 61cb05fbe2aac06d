// The assembly: a rigid body made of members of every other shape type (balls, superquadrics,
// polygons and polyhedra, level sets, clumps), the thesis's rigid assembly element (seed 1.2):
// a drum built of quadrilaterals, a drum lined with lifters, a grain of glued parts.
//
// Parameters, per member: its shape type's id in the table, the count of its own parameters,
// its position (D numbers) and orientation (2D an angle in rad, 3D a unit quaternion w x y z) in
// the assembly's frame, then its parameters (a ball's: its radius), each member about its own
// centroid. `element assembly` builds the list from names and centres the members.
//
// Mass properties: the members' own, turned and moved to their places and summed; so members
// must not overlap (check() refuses a pair deeper than 1e-9 of the assembly's size: a clump
// takes overlapping balls, a level set any union). One material for the whole body.
//
// Rows: the assembly against every other type (itself included) and every wall kind, by the
// members' own rows: each member, placed in the world, meets the other element (or each of its
// members) through the table, so every pair a member's type has a row for works, and a point's
// feature is the row's feature with the member indices mixed in, so its spring follows it.
// Beyond kMaxContactPoints points a pair keeps the deepest.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "core/validity.hpp"
#include "sim/obj_manager.hpp"
#include "sim/shape.hpp"
#include "sim/shapes/assembly.hpp"
#include "sim/shapes/radial_mesh.hpp"

namespace demlab::sim {

namespace {

constexpr size_t kMaxMembers = 64;

template <int D>
constexpr size_t rotationCount() {
  return D == 3 ? 4 : 1;
}
template <int D>
constexpr size_t headerCount() {
  return 2 + D + rotationCount<D>();
}

// One member's record, read from the parameters (views into them).
template <int D>
struct MemberRecord {
  TypeId type;
  std::span<const double> params;
  VecD<D> position;
  RotationD<D> rotation;
};

[[noreturn]] void badMember(size_t k, const std::string& what) {
  throw Error("bad shape parameters: assembly member " + std::to_string(k + 1) + ": " + what,
              {"VALUE", "SHAPE"});
}

// Returns the members of p, their records' structure checked (not their shapes). Throws
// {VALUE SHAPE}.
template <int D>
std::vector<MemberRecord<D>> readMembers(std::span<const double> p) {
  const ShapeTable<D>& t = ShapeTable<D>::get();
  const size_t types = t.names().size();
  const auto self = t.id("assembly");
  std::vector<MemberRecord<D>> out;
  size_t at = 0;
  while (at < p.size()) {
    const size_t k = out.size();
    if (k == kMaxMembers) {
      throw Error("bad shape parameters: an assembly has at most " + std::to_string(kMaxMembers) +
                      " members",
                  {"VALUE", "SHAPE"});
    }
    if (p.size() - at < headerCount<D>()) badMember(k, "its record is cut short");
    const double type = p[at], count = p[at + 1];
    if (!(type >= 0 && type < static_cast<double>(types) && type == std::floor(type)) ||
        (self && type == self->value)) {
      badMember(k, "its shape type must be the id of a registered type other than the assembly");
    }
    if (!(count >= 0 && count == std::floor(count) &&
          count <= static_cast<double>(p.size() - at - headerCount<D>()))) {
      badMember(k, "its parameter count must be a whole number within the list");
    }
    MemberRecord<D> m;
    m.type = TypeId{static_cast<uint16_t>(type)};
    for (int i = 0; i < D; ++i) {
      m.position[i] = p[at + 2 + static_cast<size_t>(i)];
      if (!(std::abs(m.position[i]) <= validity::kMaxRadius)) {
        badMember(k, "its position must be finite and within 1e9 m");
      }
    }
    const size_t r = at + 2 + D;
    if constexpr (D == 3) {
      m.rotation = Quat(p[r], p[r + 1], p[r + 2], p[r + 3]);
      if (!(std::abs(m.rotation.norm() - 1) <= 1e-9)) {
        badMember(k, "its orientation must be a unit quaternion {w x y z}");
      }
    } else {
      m.rotation = Rotation2{p[r]};
      if (!(std::abs(p[r]) <= 1e6)) badMember(k, "its orientation must be a finite angle");
    }
    m.params = p.subspan(at + headerCount<D>(), static_cast<size_t>(count));
    at += headerCount<D>() + static_cast<size_t>(count);
    out.push_back(m);
  }
  if (out.empty()) {
    throw Error("bad shape parameters: an assembly needs at least one member", {"VALUE", "SHAPE"});
  }
  return out;
}

// Appends one member's record to out.
template <int D>
void appendRecord(std::vector<double>& out, TypeId type, const VecD<D>& position,
                  const RotationD<D>& rotation, std::span<const double> own) {
  out.push_back(type.value);
  out.push_back(static_cast<double>(own.size()));
  for (int i = 0; i < D; ++i) out.push_back(position[i]);
  if constexpr (D == 3) {
    out.insert(out.end(), {rotation.w(), rotation.x(), rotation.y(), rotation.z()});
  } else {
    out.push_back(rotation.angle);
  }
  out.insert(out.end(), own.begin(), own.end());
}

// A member's own parameters in the sense of its type: a ball's are empty (its radius is apart).
template <int D>
bool isBall(const MemberRecord<D>& m) {
  return m.type == ShapeTable<D>::ball();
}

// Returns member m's bounding radius about its own position.
template <int D>
Real memberReach(const MemberRecord<D>& m) {
  if (isBall(m)) return m.params[0];
  return ShapeTable<D>::get().type(m.type).boundingRadius(m.params);
}

// What the rows read: each member's Geometry and place.
template <int D>
struct Member {
  Geometry<D> g;
  VecD<D> position;
  RotationD<D> rotation;
  Real r;  // its bounding radius (a ball's radius)
};
template <int D>
using Members = std::vector<Member<D>>;

template <int D>
Members<D> makeMembers(std::span<const double> p) {
  const ShapeTable<D>& t = ShapeTable<D>::get();
  Members<D> out;
  for (const MemberRecord<D>& m : readMembers<D>(p)) {
    const std::string name(t.type(m.type).name());
    Member<D> e;
    e.g = isBall(m) ? t.makeGeometry(name, {}) : t.makeGeometry(name, m.params);
    e.position = m.position;
    e.rotation = m.rotation;
    e.r = isBall(m) ? m.params[0] : e.g.boundRadius;
    out.push_back(std::move(e));
  }
  return out;
}

// The assembly's pose as its members are placed: the rotation as a matrix, made once a pair (a
// 2D angle's sine and cosine would otherwise be taken for every member).
template <int D>
struct Pose {
  VecD<D> x;
  RotationD<D> q;
  MatD<D> m;
  bool localCurvature = false;  // passed on to the members (ElementRef::localCurvature)
  Pose(const VecD<D>& at, const RotationD<D>& turn, bool curvature = false)
      : x(at), q(turn), localCurvature(curvature) {
    if constexpr (D == 3) {
      m = turn.toRotationMatrix();
    } else {
      m = turn.matrix();
    }
  }
  // Returns where member k's centre is.
  VecD<D> centre(const Member<D>& k) const { return x + m * k.position; }
  // Returns member k as the rows see it.
  ElementRef<D> ref(const Member<D>& k) const {
    return {centre(k), q * k.rotation, k.r, &k.g, localCurvature};
  }
};

template <int D>
class AssemblyType final : public ShapeType<D> {
 public:
  std::string_view name() const override { return "assembly"; }
  std::string_view parameters() const override {
    return D == 3 ? "type n x y z qw qx qy qz p1 .. pn ...: per member its shape type's id, "
                    "its parameter count, position (m), orientation and parameters (`element "
                    "assembly` builds them)"
                  : "type n x y angle p1 .. pn ...: per member its shape type's id, its "
                    "parameter count, position (m), angle (rad) and parameters (`element "
                    "assembly` builds them)";
  }
  void check(std::span<const double> p) const override {
    const ShapeTable<D>& t = ShapeTable<D>::get();
    const std::vector<MemberRecord<D>> ms = readMembers<D>(p);
    Real reach = 0, smallest = 1e300;
    for (size_t k = 0; k < ms.size(); ++k) {
      const MemberRecord<D>& m = ms[k];
      const ShapeType<D>& type = t.type(m.type);
      try {
        if (isBall(m)) {
          if (m.params.size() != 1 ||
              !validity::inRange(m.params[0], validity::kMinRadius, validity::kMaxRadius)) {
            throw Error("a " + std::string(type.name()) +
                            " takes one parameter, its radius, between 1e-12 and 1e9 m",
                        {"VALUE", "SHAPE"});
          }
        } else {
          type.check(m.params);
          const MassProperties<D> mp = type.massProperties(m.params);
          if (!(mp.centroid.norm() <= 1e-9 * type.boundingRadius(m.params))) {
            throw Error("it must be given about its centroid (`element assembly` moves it there)",
                        {"VALUE", "SHAPE"});
          }
        }
      } catch (const Error& e) {
        std::string what = e.what();
        const std::string prefix = "bad shape parameters: ";
        if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
        badMember(k, what);
      }
      const Real r = memberReach(m);
      reach = std::max(reach, m.position.norm() + r);
      smallest = std::min(smallest, r);
    }
    if (!(reach <= validity::kMaxRadius) || reach > 1e6 * smallest) {
      throw Error("bad shape parameters: an assembly's members must lie within 1e6 of its "
                  "smallest member's size of each other",
                  {"VALUE", "SHAPE"});
    }
    // The mass is the members' sum, so they must not overlap.
    const Members<D> members = makeMembers<D>(p);
    const Real tolerance = 1e-9 * reach;
    ContactPoint<D> points[kMaxContactPoints];
    const Pose<D> body(VecD<D>::Zero(), ElementArrays<D>::identityRotation());
    for (size_t i = 0; i < members.size(); ++i) {
      for (size_t j = i + 1; j < members.size(); ++j) {
        const ElementRef<D> a = body.ref(members[i]), b = body.ref(members[j]);
        if (!((a.x - b.x).norm() < a.r + b.r)) continue;
        const int n = shapePairPoints(a, b, points);
        for (int k = 0; k < n; ++k) {
          if (points[k].g.overlap > tolerance) {
            char depth[32];
            std::snprintf(depth, sizeof depth, "%.3g", points[k].g.overlap);
            throw Error("bad shape parameters: assembly members " + std::to_string(i + 1) +
                            " and " + std::to_string(j + 1) + " overlap by " + depth +
                            " m: an assembly's mass is its members' sum, so they must not "
                            "overlap (a clump takes overlapping balls, a level set any union)",
                        {"VALUE", "SHAPE"});
          }
        }
      }
    }
  }
  Real boundingRadius(std::span<const double> p) const override {
    Real b = 0;
    for (const MemberRecord<D>& m : readMembers<D>(p)) b = std::max(b, m.position.norm() + memberReach(m));
    return b;
  }
  MassProperties<D> massProperties(std::span<const double> p) const override {
    const ShapeTable<D>& t = ShapeTable<D>::get();
    // Sums of volume, first moments and inertia about the assembly's origin, then moved to the
    // centroid by the parallel-axis theorem.
    Real volume = 0;
    VecD<D> first = VecD<D>::Zero();
    Mat3 inertia = Mat3::Zero();
    for (const MemberRecord<D>& m : readMembers<D>(p)) {
      MassProperties<D> own;
      if (isBall(m)) {
        const Real r = m.params[0];
        own.volume = ballMass<D>(1, r);
        const Real i = ballInertia<D>(own.volume, r);
        own.inertia = D == 3 ? Mat3(Mat3::Identity() * i) : Mat3::Zero();
        own.inertia(2, 2) = i;
      } else {
        own = t.type(m.type).massProperties(m.params);
      }
      Mat3 turned = own.inertia;
      if constexpr (D == 3) {
        const Mat3 rot = m.rotation.toRotationMatrix();
        turned = rot * own.inertia * rot.transpose();
      }
      Vec3 d = Vec3::Zero();
      d.template head<D>() = m.position;
      volume += own.volume;
      first += own.volume * m.position;
      inertia += turned + own.volume * (Mat3::Identity() * d.squaredNorm() - d * d.transpose());
    }
    MassProperties<D> out;
    out.volume = volume;
    out.centroid = first / volume;
    Vec3 c = Vec3::Zero();
    c.template head<D>() = out.centroid;
    out.inertia = inertia - volume * (Mat3::Identity() * c.squaredNorm() - c * c.transpose());
    if constexpr (D == 2) {
      const Real izz = out.inertia(2, 2);
      out.inertia = Mat3::Zero();
      out.inertia(2, 2) = izz;
    }
    return out;
  }
  std::optional<std::vector<double>> scaled(std::span<const double> p, Real f) const override {
    const ShapeTable<D>& t = ShapeTable<D>::get();
    std::vector<double> out;
    for (const MemberRecord<D>& m : readMembers<D>(p)) {
      std::vector<double> own;
      if (isBall(m)) {
        own = {m.params[0] * f};
      } else if (auto s = t.type(m.type).scaled(m.params, f)) {
        own = std::move(*s);
      } else {
        return std::nullopt;
      }
      appendRecord<D>(out, m.type, m.position * f, m.rotation, own);
    }
    return out;
  }
  std::optional<std::vector<double>> translated(std::span<const double> p,
                                                const VecD<D>& offset) const override {
    std::vector<double> out;
    for (const MemberRecord<D>& m : readMembers<D>(p)) {
      appendRecord<D>(out, m.type, m.position + offset, m.rotation, m.params);
    }
    return out;
  }
  std::vector<Vec3> renderTriangles(std::span<const double> p) const override {
    const ShapeTable<D>& t = ShapeTable<D>::get();
    std::vector<Vec3> out;
    for (const MemberRecord<D>& m : readMembers<D>(p)) {
      std::vector<Vec3> own;
      if (!isBall(m)) own = t.type(m.type).renderTriangles(m.params);
      if (own.empty()) {
        appendBallTriangles<D>(own, VecD<D>::Zero(), memberReach(m));
      }
      for (const Vec3& v : own) {
        if constexpr (D == 3) {
          out.push_back(m.position + rotate(m.rotation, v));
        } else {
          const Vec2 w = m.position + rotate(m.rotation, Vec2(v.x(), v.y()));
          out.emplace_back(w.x(), w.y(), 0);
        }
      }
    }
    return out;
  }
  std::shared_ptr<const void> derive(std::span<const double> p) const override {
    return std::make_shared<const Members<D>>(makeMembers<D>(p));
  }
  std::vector<TypeId> memberTypes(std::span<const double> p) const override {
    std::vector<TypeId> out;
    try {
      for (const MemberRecord<D>& m : readMembers<D>(p)) {
        if (std::find(out.begin(), out.end(), m.type) == out.end()) out.push_back(m.type);
      }
    } catch (const Error&) {
      // Unreadable parameters are refused where the element is made; they meet nothing.
    }
    return out;
  }

};

template <int D>
const Members<D>& membersOf(const ElementRef<D>& e) {
  return *static_cast<const Members<D>*>(e.g->data.get());
}

// A point's feature with a member's index mixed in (the same member keeps the same key).
inline uint32_t mixFeature(uint32_t feature, size_t member) {
  return feature * static_cast<uint32_t>(kMaxMembers) + static_cast<uint32_t>(member);
}

// The assembly a against element b (of any type, an assembly too): each member of a near b
// against b, or against each of b's members near it.
template <int D>
int pairRow(const ElementRef<D>& a, const ElementRef<D>& b, ContactPoint<D>* out) {
  if (!((b.x - a.x).norm() < a.r + b.r)) return 0;
  thread_local std::vector<ContactPoint<D>> all;
  thread_local ContactPoint<D> points[kMaxContactPoints];
  all.clear();
  const Members<D>& ma = membersOf(a);
  const bool assemblyB = b.g->shape == a.g->shape;
  const Pose<D> pa(a.x, a.q, a.localCurvature);
  // b's pose, read only when b is an assembly (no rotation matrix made for a grain).
  const Pose<D> pb = assemblyB ? Pose<D>(b.x, b.q, b.localCurvature) : pa;
  for (size_t i = 0; i < ma.size(); ++i) {
    if (!((pa.centre(ma[i]) - b.x).norm() < ma[i].r + b.r)) continue;
    const ElementRef<D> ai = pa.ref(ma[i]);
    if (!assemblyB) {
      const int n = shapePairPoints(ai, b, points);
      for (int k = 0; k < n; ++k) {
        points[k].feature = mixFeature(points[k].feature, i);
        all.push_back(points[k]);
      }
      continue;
    }
    const Members<D>& mb = membersOf(b);
    for (size_t j = 0; j < mb.size(); ++j) {
      if (!((ai.x - pb.centre(mb[j])).norm() < ai.r + mb[j].r)) continue;
      const ElementRef<D> bj = pb.ref(mb[j]);
      const int n = shapePairPoints(ai, bj, points);
      for (int k = 0; k < n; ++k) {
        points[k].feature = mixFeature(mixFeature(points[k].feature, j), i);
        all.push_back(points[k]);
      }
    }
  }
  return keepDeepestPoints<D>(all, out);
}

// The assembly a against a wall of kind Kind: each member through its type's wall row.
template <int D, WallShape Kind>
int wallRow(const ElementRef<D>& a, const void* wall, ContactPoint<D>* out) {
  thread_local std::vector<ContactPoint<D>> all;
  thread_local ContactPoint<D> points[kMaxContactPoints];
  all.clear();
  const Members<D>& ma = membersOf(a);
  const Pose<D> pa(a.x, a.q, a.localCurvature);
  for (size_t i = 0; i < ma.size(); ++i) {
    const int n = shapeWallPoints(pa.ref(ma[i]), Kind, wall, points);
    for (int k = 0; k < n; ++k) {
      points[k].feature = mixFeature(points[k].feature, i);
      all.push_back(points[k]);
    }
  }
  return keepDeepestPoints<D>(all, out);
}

}  // namespace

template <int D>
std::vector<double> assemblyParams(const std::vector<AssemblyMemberDef>& members) {
  const ShapeTable<D>& t = ShapeTable<D>::get();
  std::vector<double> out;
  for (size_t k = 0; k < members.size(); ++k) {
    const AssemblyMemberDef& def = members[k];
    const auto id = t.id(def.shape);
    if (!id || def.shape == "assembly") {
      std::string list;
      for (const std::string& n : t.names()) {
        if (n != "assembly") list += (list.empty() ? "" : ", ") + n;
      }
      badMember(k, "bad shape \"" + def.shape + "\": must be one of " + list);
    }
    if (def.position.size() != D) {
      badMember(k, "its position needs " + std::to_string(D) + " numbers");
    }
    MemberRecord<D> m;
    m.type = *id;
    for (int i = 0; i < D; ++i) m.position[i] = def.position[static_cast<size_t>(i)];
    if constexpr (D == 3) {
      m.rotation = Quat::Identity();
      if (!def.orientation.empty()) {
        const auto& o = def.orientation;
        const Quat q(o.size() == 4 ? o[0] : 0, o.size() == 4 ? o[1] : 0,
                     o.size() == 4 ? o[2] : 0, o.size() == 4 ? o[3] : 0);
        if (!(q.norm() > 0 && std::isfinite(q.norm()))) {
          badMember(k, "its orientation must be a non-zero quaternion {w x y z}");
        }
        m.rotation = q.normalized();
      }
    } else {
      m.rotation = Rotation2{0};
      if (!def.orientation.empty()) {
        if (def.orientation.size() != 1) badMember(k, "its orientation must be one angle (rad)");
        m.rotation = Rotation2{def.orientation[0]};
      }
    }
    std::vector<double> own;
    if (*id == ShapeTable<D>::ball()) {
      if (!def.params.empty() || !(def.radius > 0)) {
        badMember(k, "a " + def.shape + " takes -radius, not -params");
      }
      own = {def.radius};
    } else {
      if (def.radius != 0) badMember(k, "a " + def.shape + " takes -params, not -radius");
      Geometry<D> g;
      try {
        g = t.makeGeometry(def.shape, def.params);
      } catch (const Error& e) {
        std::string what = e.what();
        const std::string prefix = "bad shape parameters: ";
        if (what.rfind(prefix, 0) == 0) what = what.substr(prefix.size());
        badMember(k, what);
      }
      // Given about another point, the type moved it about its centroid: the member's position
      // follows, so the body is where it was given.
      const ShapeType<D>& type = t.type(*id);
      const VecD<D> c = type.massProperties(def.params).centroid;
      if (g.params != def.params) m.position += rotate(m.rotation, c);
      own = std::move(g.params);
    }
    appendRecord<D>(out, m.type, m.position, m.rotation, own);
  }
  t.type(*t.id("assembly")).check(out);
  return out;
}

template <int D>
void registerAssembly(ShapeTable<D>& t) {
  const std::vector<std::string> before = t.names();
  t.add(std::make_unique<AssemblyType<D>>());
  for (const std::string& other : before) t.addPair("assembly", other, {pairRow<D>, false});
  t.addPair("assembly", "assembly", {pairRow<D>, false});
  t.addWall("assembly", WallShape::Plane, {wallRow<D, WallShape::Plane>, false});
  t.addWall("assembly", WallShape::Finite, {wallRow<D, WallShape::Finite>, false});
  t.addWall("assembly", WallShape::Box, {wallRow<D, WallShape::Box>, false});
  t.addWall("assembly", WallShape::Drum, {wallRow<D, WallShape::Drum>, false});
  if (D == 3) t.addWall("assembly", WallShape::Mesh, {wallRow<D, WallShape::Mesh>, false});
}

template void registerAssembly<2>(ShapeTable<2>&);
template void registerAssembly<3>(ShapeTable<3>&);
template std::vector<double> assemblyParams<2>(const std::vector<AssemblyMemberDef>&);
template std::vector<double> assemblyParams<3>(const std::vector<AssemblyMemberDef>&);

}  // namespace demlab::sim
