// writeScene / readScene (sim/scene_io.hpp): the sections of a scene, in one order, written
// and read by mirror-image code.
#include "sim/scene_io.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "core/free_aside.hpp"
#include "core/interrupt.hpp"
#include "core/validity.hpp"
#include "sim/behaviors/gravity.hpp"
#include "sim/behaviors/load.hpp"
#include "sim/convert.hpp"
#include "sim/option_table.hpp"

namespace demlab::sim {

namespace {

// Writes a tangential history: the spring, its drift velocity, the damper's last impulse and
// its loss still owed.
template <int D>
void writeHistory(Writer& w, const physics::TangentialHistory<D>& h) {
  w.vec<D>(h.spring);
  w.vec<D>(h.drift);
  w.f64(h.damperImpulse);
  w.f64(h.damperPending);
}

// Returns the bytes writeHistory wrote in r's format (version 2 kept no drift velocity).
template <int D>
size_t historyBytes(const Reader& r) {
  return r.version >= 3 ? 16 * D + 16 : 8 * D;
}

// Reads a tangential history (a version 2 scene has no drift velocities: NaN, which the laws
// restart from the contact's velocity). Throws {LOAD FORMAT} for a non-finite spring or a
// drift velocity neither finite nor unknown (all NaN).
template <int D>
physics::TangentialHistory<D> readHistory(Reader& r) {
  physics::TangentialHistory<D> h;
  h.spring = r.vec<D>();
  if (!h.spring.allFinite()) Reader::bad("spring");
  if (r.version >= 3) {
    h.drift = r.vec<D>();
    if (!h.drift.allFinite() && !h.drift.array().isNaN().all()) {
      Reader::bad("spring drift velocity");
    }
    h.damperImpulse = r.f64();
    h.damperPending = r.f64();
    if (!std::isfinite(h.damperImpulse) || !std::isfinite(h.damperPending)) {
      Reader::bad("spring damper loss");
    }
  }
  return h;
}

// A mesh's triangles as corner coordinates, which TriangleMesh::build turns back into the same
// mesh (corners numbered alike).
std::vector<std::array<double, 9>> meshCorners(const physics::TriangleMesh& m) {
  std::vector<std::array<double, 9>> out;
  out.reserve(m.triangles.size());
  for (const auto& t : m.triangles) {
    std::array<double, 9> c;
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) c[3 * k + d] = m.vertices[t[k]][d];
    out.push_back(c);
  }
  return out;
}

// Writes a wall's geometry; a mesh is written whole unless it is same (the wall's geometry at
// creation, written just before), then only its pose.
template <int D>
void writeShape(Writer& w, const WallGeometry<D>& g, const physics::TriangleMesh* same = nullptr) {
  w.u8(static_cast<uint8_t>(g.index()));
  std::visit(
      [&](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, physics::PlaneShape<D>>) {
          w.vec<D>(s.point);
          w.vec<D>(s.normal);
        } else if constexpr (std::is_same_v<S, physics::FlatWallShape<D>>) {
          w.vec<D>(s.centre);
          for (int k = 0; k < D - 1; ++k) w.vec<D>(s.axes[k]);
          for (int k = 0; k < D - 1; ++k) w.f64(s.halfExtents[k]);
        } else if constexpr (std::is_same_v<S, physics::BoxShape<D>>) {
          w.vec<D>(s.centre);
          for (int c = 0; c < D; ++c) w.vec<D>(s.axes.col(c));
          w.vec<D>(s.halfExtents);
        } else if constexpr (std::is_same_v<S, physics::MeshShape<D>>) {
          for (int c = 0; c < 3; ++c) w.vec<3>(s.rotation.col(c));
          w.vec<3>(s.offset);
          w.u8(s.mesh.get() != same);
          if (s.mesh.get() != same) {
            w.str(s.mesh->source);
            w.list(meshCorners(*s.mesh), [&](const std::array<double, 9>& c) {
              for (double x : c) w.f64(x);
            });
          }
        } else {
          w.vec<D>(s.centre);
          w.vec<D>(s.axis);
          w.f64(s.radius);
          w.f64(s.halfLength);
        }
      },
      g);
}

template <int D>
WallGeometry<D> readShape(Reader& r, const WallGeometry<D>* same = nullptr) {
  switch (r.u8()) {
    case 0: {
      physics::PlaneShape<D> s;
      s.point = r.vec<D>();
      s.normal = r.vec<D>();
      return s;
    }
    case 1: {
      physics::FlatWallShape<D> s;
      s.centre = r.vec<D>();
      for (int k = 0; k < D - 1; ++k) s.axes[k] = r.vec<D>();
      for (int k = 0; k < D - 1; ++k) s.halfExtents[k] = r.f64();
      return s;
    }
    case 2: {
      physics::BoxShape<D> s;
      s.centre = r.vec<D>();
      for (int c = 0; c < D; ++c) s.axes.col(c) = r.vec<D>();
      s.halfExtents = r.vec<D>();
      return s;
    }
    case 3: {
      physics::DrumShape<D> s;
      s.centre = r.vec<D>();
      s.axis = r.vec<D>();
      s.radius = r.f64();
      s.halfLength = r.f64();
      return s;
    }
    case 4: {
      if (D != 3) Reader::bad("mesh wall in 2D");
      physics::MeshShape<D> s;
      for (int c = 0; c < 3; ++c) s.rotation.col(c) = r.vec<3>();
      s.offset = r.vec<3>();
      if (!((s.rotation.transpose() * s.rotation - Mat3::Identity()).norm() < 1e-9) ||
          !(s.rotation.determinant() > 0) || !s.offset.allFinite()) {
        Reader::bad("mesh pose");
      }
      if (r.u8() == 0) {
        const auto* first = same == nullptr ? nullptr : std::get_if<physics::MeshShape<D>>(same);
        if (first == nullptr) Reader::bad("mesh");
        s.mesh = first->mesh;
        return s;
      }
      const std::string source = r.str();
      std::vector<std::array<double, 9>> corners(r.count(72));
      for (auto& c : corners)
        for (double& x : c) x = r.f64();
      try {
        auto mesh = physics::TriangleMesh::build(corners, source);
        if (mesh.triangles.size() != corners.size()) Reader::bad("mesh triangles");
        s.mesh = std::make_shared<const physics::TriangleMesh>(std::move(mesh));
      } catch (const Error& e) {
        if (e.code().size() > 1 && e.code()[1] == "LOAD") throw;
        Reader::bad("mesh triangles");
      }
      return s;
    }
    default:
      Reader::bad("unknown wall shape");
  }
}

template <class Kind>
void writePool(Writer& w, const HandlePool<Kind>& p) {
  const auto st = p.saveState();
  w.list(st.generations, [&](uint32_t g) { w.u32(g); });
  w.list(st.freeSlots, [&](uint32_t g) { w.u32(g); });
  w.list(st.dense, [&](Handle<Kind> h) { w.u64(h.bits()); });
}

template <class Kind>
void readPool(Reader& r, HandlePool<Kind>& p) {
  typename HandlePool<Kind>::State st;
  st.generations.resize(r.count(4));
  for (auto& g : st.generations) g = r.u32();
  st.freeSlots.resize(r.count(4));
  for (auto& g : st.freeSlots) g = r.u32();
  st.dense.resize(r.count(8));
  for (auto& h : st.dense) h = Handle<Kind>::fromBits(r.u64());
  try {
    p.restoreState(st);
  } catch (const Error& e) {
    Reader::bad(e.what());
  }
}

template <class Kind>
void writeNamesTags(Writer& w, const NameLookup<Handle<Kind>>& names, const TagTable<Kind>& tags) {
  w.u64(names.size());
  names.forEach([&](std::string_view n, Handle<Kind> h) {
    w.str(std::string(n));
    w.u64(h.bits());
  });
  const auto tagList = tags.tags();
  w.u64(tagList.size());
  for (std::string_view t : tagList) {
    w.str(std::string(t));
    const auto members = tags.objects(t);
    w.list(members, [&](Handle<Kind> h) { w.u64(h.bits()); });
  }
}

template <class Kind>
void readNamesTags(Reader& r, const HandlePool<Kind>& pool, NameLookup<Handle<Kind>>& names,
                   TagTable<Kind>& tags) {
  try {
    const size_t nn = r.count(9);
    for (size_t k = 0; k < nn; ++k) {
      const std::string n = r.str();
      const auto h = Handle<Kind>::fromBits(r.u64());
      if (!pool.valid(h)) Reader::bad("a name refers to no object");
      names.add(n, h);
    }
    const size_t nt = r.count(9);
    for (size_t k = 0; k < nt; ++k) {
      const std::string t = r.str();
      const size_t m = r.count(8);
      for (size_t j = 0; j < m; ++j) {
        const auto h = Handle<Kind>::fromBits(r.u64());
        if (!pool.valid(h)) Reader::bad("a tag refers to no object");
        tags.add(h, t);
      }
    }
  } catch (const Error& e) {
    // The reader's own errors and Ctrl-C (its poll) pass; a name or tag the tables refuse is
    // a bad checkpoint.
    if (e.code().size() > 1 && (e.code()[1] == "LOAD" || e.code()[1] == "INTERRUPTED")) throw;
    Reader::bad(e.what());
  }
}

void writeMaterial(Writer& w, const physics::MaterialDef& m) {
  for (double x : {m.density, m.young, m.poisson, m.restitution, m.friction, m.rollingFriction,
                   m.normalStiffness, m.shearStiffness}) {
    w.f64(x);
  }
}

physics::MaterialDef readMaterial(Reader& r) {
  physics::MaterialDef m;
  m.density = r.f64();
  m.young = r.f64();
  m.poisson = r.f64();
  m.restitution = r.f64();
  m.friction = r.f64();
  m.rollingFriction = r.f64();
  m.normalStiffness = r.f64();
  m.shearStiffness = r.f64();
  return m;
}

// A behavior's record. Gravity and loads keep the record they had before behaviors were open
// (code 0 or 1, then positional fields), so digests and older checkpoints stay as they were;
// every other type is code kNamedBehavior, its type name, and its named parameters, read back
// through the registry (an unknown name is an error, never a guess).
constexpr uint8_t kNamedBehavior = 0xff;

template <int D>
void writeBehavior(Writer& w, const Behavior<D>& b) {
  const auto* load = dynamic_cast<const LoadBehavior<D>*>(&b);
  const auto* gravity = dynamic_cast<const GravityBehavior<D>*>(&b);
  if (!load && !gravity) {
    w.u8(kNamedBehavior);
    w.str(std::string(b.type()));
    const std::vector<BehaviorParam> ps = b.params();
    w.u64(ps.size());
    for (const BehaviorParam& p : ps) {
      w.str(p.name);
      w.list(p.numbers, [&](double x) { w.f64(x); });
      w.str(p.text);
      w.u64(p.grain.bits());
    }
    return;
  }
  w.u8(gravity ? 0 : 1);
  w.vec<D>(gravity ? gravity->g() : VecD<D>::Zero());
  w.u64(load ? load->grain.bits() : ElementId().bits());
  w.str(load ? load->tag : std::string());
  for (int k = 0; k < 3; ++k) {
    w.f64(load ? load->force[k] : 0.0);
    w.f64(load ? load->torque[k] : 0.0);
    // A flag set here means a clone (the caller copies the behaviors) or a digest.
    w.u8(load && static_cast<bool>(load->forceFn[k]));
    w.u8(load && static_cast<bool>(load->torqueFn[k]));
  }
}

template <int D>
std::unique_ptr<Behavior<D>> readBehavior(Reader& r) {
  const uint8_t code = r.u8();
  if (code == kNamedBehavior) {
    const std::string type = r.str();
    std::vector<BehaviorParam> ps(r.count(32));
    for (BehaviorParam& p : ps) {
      p.name = r.str();
      p.numbers.resize(r.count(8));
      for (double& x : p.numbers) x = r.f64();
      p.text = r.str();
      p.grain = ElementId::fromBits(r.u64());
    }
    try {
      return makeBehavior<D>(type, ps);
    } catch (const Error& e) {
      Reader::bad("behavior: " + std::string(e.what()));
    }
  }
  if (code > 1) Reader::bad("unknown behavior record");
  const VecD<D> g = r.vec<D>();
  const ElementId grain = ElementId::fromBits(r.u64());
  const std::string tag = r.str();
  Vec3d force{}, torque{};
  for (int c = 0; c < 3; ++c) {
    force[c] = r.f64();
    torque[c] = r.f64();
    r.u8();
    r.u8();
  }
  if (code == 0) return std::make_unique<GravityBehavior<D>>(g);
  auto b = std::make_unique<LoadBehavior<D>>();
  b->grain = grain;
  b->tag = tag;
  b->force = force;
  b->torque = torque;
  return b;
}

}  // namespace

namespace {

// Appends a section that says its length: tag, u64 byte count, body's bytes. Changes w.
void writeSection(Writer& w, const char* tag, const Writer& body) {
  w.bytes.append(tag, 4);
  w.u64(body.bytes.size());
  w.bytes.append(body.bytes);
}

// Reads the blocked section's body into s.blocked, checking every handle against the grain
// pool (read before) and every mask against the dimension. Throws {LOAD FORMAT}.
template <int D>
void readBlocked(Reader& r, Scene<D>& s) {
  s.blocked.resize(r.count(9));
  for (BlockedElement& b : s.blocked) {
    b.id.index = r.u32();
    b.id.generation = r.u32();
    b.dofs = r.u8();
    if (!s.elements.pool().valid(b.id)) Reader::bad("blocked element handle");
    if (b.dofs == 0 || (b.dofs & ~dof::all(D)) != 0) Reader::bad("blocked degrees of freedom");
  }
}

// Reads the placed section's body into s.placedElements and s.placedWalls, checking every
// handle against its pool (read before). Throws {LOAD FORMAT}.
template <int D>
void readPlaced(Reader& r, Scene<D>& s) {
  const auto read = [&](auto& ids, const auto& pool) {
    ids.resize(r.count(8));
    for (auto& id : ids) {
      id.index = r.u32();
      id.generation = r.u32();
      if (!pool.valid(id)) Reader::bad("placed handle");
    }
  };
  read(s.placedElements, s.elements.pool());
  read(s.placedWalls, s.walls.pool());
}

// Reads the pair section's body into s.pairOverrides, checking indices and ranges (NaN:
// unset). Throws {LOAD FORMAT}.
template <int D>
void readPairOverrides(Reader& r, Scene<D>& s) {
  s.pairOverrides.resize(r.count(40));
  const auto fine = [](double x, bool ok) { return std::isnan(x) || ok; };
  for (PairOverride& o : s.pairOverrides) {
    o.a = r.u32();
    o.b = r.u32();
    if (o.a > o.b || o.b >= s.nMat()) Reader::bad("pair coefficients' materials");
    PairCoefficients& c = o.c;
    c.restitution = r.f64();
    c.friction = r.f64();
    c.rolling = r.f64();
    c.cohesion = r.f64();
    const bool ok = fine(c.restitution, c.restitution > 0 && c.restitution <= 1) &&
                    fine(c.friction, c.friction >= 0 && std::isfinite(c.friction)) &&
                    fine(c.rolling, c.rolling >= 0 && std::isfinite(c.rolling)) &&
                    fine(c.cohesion, c.cohesion >= 0 && std::isfinite(c.cohesion));
    if (!ok) Reader::bad("pair coefficients");
  }
}

// Writes a region (sim/packing.hpp) as kind, corners, centre, radius, axis, half length.
void writeRegion(Writer& w, const Region& r) {
  w.u8(static_cast<uint8_t>(r.kind));
  for (const Vec3d* v : {&r.lo, &r.hi, &r.centre, &r.axis}) {
    for (double x : *v) w.f64(x);
  }
  w.f64(r.radius);
  w.f64(r.halfLength);
}

Region readRegion(Reader& r) {
  Region g;
  const uint8_t kind = r.u8();
  if (kind > Region::Cylinder) Reader::bad("region kind");
  g.kind = static_cast<Region::Kind>(kind);
  for (Vec3d* v : {&g.lo, &g.hi, &g.centre, &g.axis}) {
    for (double& x : *v) x = r.f64();
  }
  g.radius = r.f64();
  g.halfLength = r.f64();
  return g;
}

Vec3d readVec3(Reader& r) {
  Vec3d v;
  for (double& x : v) x = r.f64();
  return v;
}

template <int D>
void writeSources(Writer& w, const Scene<D>& s) {
  w.list(s.sources, [&](const SourceState& src) {
    const SourceDef& d = src.def;
    w.str(d.name);
    writeRegion(w, d.region);
    w.str(d.size.kind);
    w.list(d.size.p, [&](double x) { w.f64(x); });
    w.u32(src.material);
    w.list(d.tags, [&](const std::string& t) { w.str(t); });
    for (double x : {d.massRate, d.countRate, d.targetMass}) w.f64(x);
    w.u64(d.targetCount);
    for (double x : d.velocity) w.f64(x);
    w.f64(d.jitter);
    w.f64(d.tolerance);
    w.u64(d.seed);
    w.u32(d.tries);
    w.f64(src.start);
    w.u64(src.count);
    w.f64(src.mass);
    w.u64(src.rng);
    w.f64(src.pendingRadius);
  });
}

template <int D>
void readSources(Reader& r, Scene<D>& s) {
  const size_t n = r.count(8);
  for (size_t k = 0; k < n; ++k) {
    SourceState src;
    SourceDef& d = src.def;
    d.name = r.str();
    d.region = readRegion(r);
    d.size.kind = r.str();
    const size_t np = r.count(8);
    for (size_t j = 0; j < np; ++j) d.size.p.push_back(r.f64());
    static const char* kinds[] = {"constant", "uniform", "normal", "powerlaw", "discrete"};
    if (std::none_of(std::begin(kinds), std::end(kinds),
                     [&](const char* x) { return d.size.kind == x; }) ||
        d.size.p.empty()) {
      Reader::bad("source size distribution");
    }
    src.material = r.u32();
    if (src.material >= s.materials.size()) Reader::bad("source material");
    const size_t nt = r.count(8);
    for (size_t j = 0; j < nt; ++j) d.tags.push_back(r.str());
    d.massRate = r.f64();
    d.countRate = r.f64();
    d.targetMass = r.f64();
    d.targetCount = r.u64();
    d.velocity = readVec3(r);
    d.jitter = r.f64();
    d.tolerance = r.f64();
    d.seed = r.u64();
    d.tries = r.u32();
    d.material = s.materialNames[src.material];
    src.start = r.f64();
    src.count = r.u64();
    src.mass = r.f64();
    src.rng = r.u64();
    src.pendingRadius = r.f64();
    s.sources.push_back(std::move(src));
  }
}

template <int D>
void writeSinks(Writer& w, const Scene<D>& s) {
  w.list(s.sinks, [&](const SinkState& k) {
    w.str(k.def.name);
    w.u8(k.def.kind);
    writeRegion(w, k.def.region);
    w.u8(k.def.outside);
    for (double x : k.def.point) w.f64(x);
    for (double x : k.def.normal) w.f64(x);
    w.f64(k.start);
    w.u64(k.count);
    w.f64(k.mass);
  });
}

template <int D>
void readSinks(Reader& r, Scene<D>& s) {
  const size_t n = r.count(8);
  for (size_t j = 0; j < n; ++j) {
    SinkState k;
    k.def.name = r.str();
    const uint8_t kind = r.u8();
    if (kind > SinkDef::Plane) Reader::bad("sink kind");
    k.def.kind = static_cast<SinkDef::Kind>(kind);
    k.def.region = readRegion(r);
    k.def.outside = r.u8() != 0;
    k.def.point = readVec3(r);
    k.def.normal = readVec3(r);
    k.start = r.f64();
    k.count = r.u64();
    k.mass = r.f64();
    s.sinks.push_back(std::move(k));
  }
}

// Writes the periodic section's body: axes, cell, Lees-Edwards state, and the unwrap offsets of
// the live elements that have one (slot, generation, offset).
template <int D>
void writePeriodic(Writer& w, const Scene<D>& s) {
  const PeriodicBox<D>& p = s.periodic;
  w.u8(p.axes);
  for (int k = 0; k < D; ++k) w.f64(p.lo[k]);
  for (int k = 0; k < D; ++k) w.f64(p.hi[k]);
  w.f64(p.shearRate);
  w.u8(static_cast<uint8_t>(p.flow));
  w.u8(static_cast<uint8_t>(p.gradient));
  w.f64(p.offset);
  w.f64(p.offsetTravel);
  std::vector<uint32_t> slots;
  for (uint32_t i = 0; i < p.unwrap.size(); ++i) {
    if (s.elements.pool().valid(ElementId{i, p.unwrapGeneration[i]})) slots.push_back(i);
  }
  w.list(slots, [&](uint32_t i) {
    w.u32(i);
    w.u32(p.unwrapGeneration[i]);
    for (int k = 0; k < D; ++k) w.f64(p.unwrap[i][k]);
  });
}

// Reads the periodic section's body (after the elements), checking it as setPeriodic would.
// Throws {LOAD FORMAT}.
template <int D>
void readPeriodic(Reader& r, Scene<D>& s) {
  PeriodicBox<D>& p = s.periodic;
  p.axes = r.u8();
  if (p.axes == 0 || (p.axes >> D) != 0) Reader::bad("periodic axes");
  for (int k = 0; k < D; ++k) p.lo[k] = r.f64();
  for (int k = 0; k < D; ++k) p.hi[k] = r.f64();
  for (int k = 0; k < D; ++k) {
    if (!p.periodic(k)) continue;
    if (!(std::abs(p.lo[k]) <= validity::kMaxCoordinate && std::abs(p.hi[k]) <= validity::kMaxCoordinate &&
          p.lo[k] < p.hi[k])) {
      Reader::bad("periodic cell");
    }
  }
  p.shearRate = r.f64();
  p.flow = r.u8();
  p.gradient = r.u8();
  p.offset = r.f64();
  p.offsetTravel = r.f64();
  if (!std::isfinite(p.shearRate) || !(p.offsetTravel >= 0 && std::isfinite(p.offsetTravel)))
    Reader::bad("periodic shear");
  if (p.shearRate != 0) {
    if (p.flow >= D || p.gradient >= D || p.flow == p.gradient || !p.periodic(p.flow) ||
        !p.periodic(p.gradient) || !(p.offset >= 0 && p.offset < p.length(p.flow))) {
      Reader::bad("periodic shear");
    }
  }
  const size_t n = r.count(8 + 8 * D);
  for (size_t j = 0; j < n; ++j) {
    const uint32_t slot = r.u32(), generation = r.u32();
    VecD<D> off;
    for (int k = 0; k < D; ++k) off[k] = r.f64();
    if (!s.elements.pool().valid(ElementId{slot, generation}) || !off.allFinite())
      Reader::bad("periodic unwrap offset");
    if (p.unwrap.size() <= slot) {
      p.unwrap.resize(slot + 1, VecD<D>::Zero());
      p.unwrapGeneration.resize(slot + 1, 0);
    }
    p.unwrap[slot] = off;
    p.unwrapGeneration[slot] = generation;
  }
}

// Returns true if some element's global id is not its slot, or the next id not the slot count:
// what the GIDS section is written for.
template <int D>
bool globalIdsDiffer(const Scene<D>& s) {
  const ElementArrays<D>& a = s.elements.a;
  if (s.elements.nextGlobalId() != s.elements.pool().slotCount()) return true;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a.globalId[i] != a.slot[i]) return true;
  }
  return false;
}

// Reads the GIDS section's body: the next id, then one id per element, each below the next id
// and none twice. Throws {LOAD FORMAT}.
template <int D>
void readGlobalIds(Reader& r, Scene<D>& s) {
  const uint64_t next = r.u64();
  if (next > kMaxGlobalId + 1) Reader::bad("next global id");
  std::vector<uint64_t>& ids = s.elements.a.globalId;
  if (r.count(8) != ids.size()) Reader::bad("global id count");
  for (uint64_t& id : ids) {
    id = r.u64();
    if (id >= next) Reader::bad("global id");
  }
  std::vector<uint64_t> sorted = ids;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) Reader::bad("global id twice");
  s.elements.setNextGlobalId(next);
}

// Returns true if some wall has state beyond the fixed wall record (the WALX section).
template <int D>
bool wallsHaveExtra(const Scene<D>& s) {
  for (const Wall<D>& x : s.walls.items) {
    Writer turned, none;
    turned.rot(x.turnedBefore);
    none.rot(Wall<D>::identity());
    if (x.work != 0 || x.servo || turned.bytes != none.bytes) return true;
  }
  return false;
}

template <int D>
void writeWallExtra(Writer& w, const Scene<D>& s) {
  w.list(s.walls.items, [&](const Wall<D>& x) {
    w.f64(x.work);
    w.rot(x.turnedBefore);
    w.u8(x.servo);
    w.f64(x.servoTarget);
    w.f64(x.servoGain);
    w.f64(x.servoMaxSpeed);
  });
}

template <int D>
void readWallExtra(Reader& r, Scene<D>& s) {
  if (r.count(8) != s.walls.items.size()) Reader::bad("wall count");
  for (Wall<D>& x : s.walls.items) {
    x.work = r.f64();
    x.turnedBefore = r.rot<RotationD<D>>();
    x.servo = r.u8() != 0;
    x.servoTarget = r.f64();
    x.servoGain = r.f64();
    x.servoMaxSpeed = r.f64();
  }
}

// Returns the hole of wall x (0 when it has none or is not a finite wall).
template <int D>
double wallHole(const Wall<D>& x) {
  const auto* f = std::get_if<physics::FlatWallShape<D>>(&x.shape0);
  return f ? f->hole : 0;
}

template <int D>
bool wallsHaveHoles(const Scene<D>& s) {
  return std::any_of(s.walls.items.begin(), s.walls.items.end(),
                     [](const Wall<D>& x) { return wallHole(x) != 0; });
}

template <int D>
void writeWallHoles(Writer& w, const Scene<D>& s) {
  w.list(s.walls.items, [&](const Wall<D>& x) { w.f64(wallHole(x)); });
}

// Reads the holes into the walls' reference and current shapes, checked as `wall add finite
// -hole` checks them.
template <int D>
void readWallHoles(Reader& r, Scene<D>& s) {
  if (r.count(8) != s.walls.items.size()) Reader::bad("wall hole count");
  for (Wall<D>& x : s.walls.items) {
    const double hole = r.f64();
    auto* f0 = std::get_if<physics::FlatWallShape<D>>(&x.shape0);
    auto* f = std::get_if<physics::FlatWallShape<D>>(&x.shape);
    if (f0 == nullptr || f == nullptr || x.kind != WallShape::Finite) {
      if (hole != 0) Reader::bad("a hole in a wall that is not finite");
      continue;
    }
    try {
      checkWallHole<D>(*f0, hole);
      checkWallHole<D>(*f, hole);
    } catch (const Error& e) {
      Reader::bad(e.what());
    }
    f0->hole = f->hole = hole;
  }
}

// Writes the shape section's body: geometries, per-element indices, the shape candidates and
// the shape springs.
template <int D>
void writeShapes(Writer& w, const Scene<D>& s) {
  const ShapeTable<D>& t = ShapeTable<D>::get();
  w.list(s.geometries, [&](const Shareable<Geometry<D>>& g) {
    w.str(std::string(t.type(g->shape).name()));
    w.list(g->params, [&](double x) { w.f64(x); });
  });
  w.list(s.elements.a.geometry, [&](uint32_t g) { w.u32(g); });
  w.u8(s.anyShapes);
  w.list(s.shapeCandidates, [&](const CandidatePair& c) {
    w.u32(c.i);
    w.u32(c.j);
  });
  w.list(s.shapeWallCandidates, [&](const std::pair<uint32_t, uint32_t>& c) {
    w.u32(c.first);
    w.u32(c.second);
  });
  w.u64(s.shapeSprings.size());
  for (const auto& [k, h] : s.shapeSprings.sorted()) {
    w.u32(k.a);
    w.u32(k.b);
    w.u32(k.point);
    writeHistory<D>(w, h);
  }
}

// Reads the shape section's body (after the grains). Throws {LOAD FORMAT}, or {LOAD SHAPE} for
// a shape type this process has not registered.
template <int D>
void readShapes(Reader& r, Scene<D>& s) {
  const ShapeTable<D>& t = ShapeTable<D>::get();
  s.geometries.resize(r.count(9));
  if (s.geometries.empty()) Reader::bad("shape geometries");
  for (size_t k = 0; k < s.geometries.size(); ++k) {
    const std::string name = r.str();
    std::vector<double> params(r.count(8));
    for (double& x : params) x = r.f64();
    if (t.find(name) == nullptr) {
      throw Error("can't load a checkpoint with elements of shape type \"" + name +
                      "\": it is not registered in this demlab",
                  {"LOAD", "SHAPE"});
    }
    try {
      s.geometries[k] = Shareable<Geometry<D>>::make(t.makeGeometry(name, params));
    } catch (const Error&) {
      Reader::bad("shape parameters");
    }
    if ((k == 0) != (s.geometries[k]->shape == ShapeTable<D>::ball())) Reader::bad("shape table");
  }
  s.indexGeometries();
  if (s.geometryLookup.size() + 1 != s.geometries.size()) Reader::bad("shape table");
  std::vector<uint32_t>& g = s.elements.a.geometry;
  if (r.count(4) != g.size()) Reader::bad("shape count");
  for (uint32_t& x : g) {
    x = r.u32();
    if (x >= s.geometries.size()) Reader::bad("shape index");
  }
  s.anyShapes = r.u8() != 0;
  s.shapeCandidates.resize(r.count(8));
  for (CandidatePair& c : s.shapeCandidates) {
    c.i = r.u32();
    c.j = r.u32();
    if (c.i >= g.size() || c.j >= g.size() || c.i == c.j) Reader::bad("shape candidate index");
  }
  s.shapeWallCandidates.resize(r.count(8));
  for (auto& c : s.shapeWallCandidates) {
    c.first = r.u32();
    c.second = r.u32();
    if (c.first >= g.size() || c.second >= s.walls.size()) Reader::bad("shape candidate index");
  }
  const uint64_t n = r.count(12 + historyBytes<D>(r));
  for (uint64_t k = 0; k < n; ++k) {
    ShapeSpringKey key;
    key.a = r.u32();
    key.b = r.u32();
    key.point = r.u32();
    s.shapeSprings.put(key, readHistory<D>(r));
  }
}

}  // namespace

template <int D>
void writeScene(Writer& w, const Scene<D>& s, IoMode mode, const BehaviorManager<D>* behaviors) {
  const BehaviorManager<D>& bm = behaviors ? *behaviors : s.behaviors;
  w.bytes.append(kMagic, 8);
  w.u32(kFormatVersion);
  w.u32(D);
  // Materials and laws.
  w.u64(s.materials.size());
  for (size_t m = 0; m < s.materials.size(); ++m) {
    w.str(s.materialNames[m]);
    writeMaterial(w, s.materials[m]);
  }
  w.u8(static_cast<uint8_t>(s.defaultLaw));
  w.list(s.pairLawOverride, [&](int8_t x) { w.u8(static_cast<uint8_t>(x)); });
  w.u8(static_cast<uint8_t>(s.coulomb));
  // Options and time.
  w.f64(s.dt);
  w.f64(s.autoFraction);
  writeHeaderOptions(w, s);  // the integrator, rotation, detection (sim/option_table.hpp)
  w.f64(s.time);
  w.u64(s.steps);
  w.f64(s.stepDt);
  // Grains.
  const ElementArrays<D>& a = s.elements.a;
  writePool(w, s.elements.pool());
  for (size_t i = 0; i < a.size(); ++i) {
    w.vec<D>(a.x[i]);
    w.vec<D>(a.v[i]);
    w.vec<D>(a.f[i]);
    w.vec<D>(a.fPrev[i]);
    w.rot(a.q[i]);
    w.ang(a.w[i]);
    w.ang(a.t[i]);
    w.ang(a.tPrev[i]);
    w.f64(a.r[i]);
    w.f64(a.invMass[i]);
    w.f64(a.invInertia[i]);
    w.u32(a.material[i]);
  }
  writeNamesTags(w, s.elements.names(), s.elements.tags());
  // Walls.
  writePool(w, s.walls.pool());
  for (const Wall<D>& x : s.walls.items) {
    w.u8(static_cast<uint8_t>(x.kind));
    w.u32(x.material);
    writeShape<D>(w, x.shape0);
    const auto* m0 = std::get_if<physics::MeshShape<D>>(&x.shape0);
    writeShape<D>(w, x.shape, m0 != nullptr ? m0->mesh.get() : nullptr);
    w.u8(x.moving);
    w.vec<D>(x.velocity);
    w.vec<D>(x.amplitude);
    w.ang(x.omega);
    w.f64(x.frequency);
    w.f64(x.phase);
    w.f64(x.t0);
    w.vec<D>(x.point);
    w.vec<D>(x.point0);
    w.vec<D>(x.pointVelocity);
    w.rot(x.turned);
    w.vec<D>(x.pointAtBuild);
    w.f64(x.timeAtBuild);
    w.vec<D>(x.force);
  }
  writeNamesTags(w, s.walls.names(), s.walls.tags());
  // Behaviors.
  writePool(w, bm.pool());
  for (const auto& b : bm.items()) {
    if (mode == IoMode::Checkpoint && b->hasCallbacks()) {
      throw Error("internal: a behavior with callbacks reached the checkpoint writer",
                  {"SAVE", "CALLBACK"});
    }
    writeBehavior(w, *b);
  }
  // Pair histories, in iteration order, with the table size that reproduces the layout.
  auto& hist = const_cast<InstanceInteractionManager<physics::TangentialHistory<D>>&>(s.histories);
  w.u8(s.keepHistory);
  w.u8(s.rotating);
  w.u64(hist.bucketCount());
  w.u64(hist.size());
  hist.forEach([&](const auto& p, const physics::TangentialHistory<D>& h) {
    w.u32(p.first);
    w.u32(p.second);
    writeHistory<D>(w, h);
  });
  // Contact detection state, with the springs of the candidate pairs.
  w.list(s.candidates, [&](const CandidatePair& c) {
    w.u32(c.i);
    w.u32(c.j);
  });
  // One spring per candidate (zero for those without a slot): the format predates the pool.
  // Written straight from the pool: a vector of them made first (millions of candidates) was
  // a long stretch that neither polled nor wrote.
  w.u64(s.pairSprings.size());
  for (size_t k = 0; k < s.pairSprings.size(); ++k) writeHistory<D>(w, s.pairSprings.history(k));
  w.u64(s.wallSprings.size());
  for (const auto& l : s.wallSprings) {
    w.list(l, [&](const physics::TangentialHistory<D>& h) { writeHistory<D>(w, h); });
  }
  w.u64(s.wallCandidates.size());
  for (const auto& l : s.wallCandidates) w.list(l, [&](uint32_t i) { w.u32(i); });
  w.list(s.xAtBuild, [&](const VecD<D>& x) { w.vec<D>(x); });
  w.f64(s.skin);
  w.f64(s.maxDisp2);
  // A scripted wall saved without its scripts moves on at constant rates: its skin test cannot
  // count what it turned before, so the loaded scene searches anew.
  const bool scriptedWalls = anyScripted(s.walls.items);
  w.u8(s.needRebuild || (mode == IoMode::Checkpoint && scriptedWalls));
  w.u8(s.forcesReady);
  w.u64(s.rebuilds);
  // Outputs of the last step and the ledger.
  w.list(s.contacts, [&](const ContactRecord<D>& c) {
    w.u32(c.a);
    w.u32(c.b);
    w.u8(c.wall);
    w.vec<D>(c.force);
  });
  const LedgerSums& l = s.ledger;
  for (double x : {l.dampingLoss, l.frictionLoss, l.wallWork, l.behaviorWork, l.springWork,
                   l.elastic, l.reference, l.gravityReference, l.scale}) {
    w.f64(x);
  }
  w.u8(l.started);
  // The watchdog's options and the touch correction, each only when not the defaults: a
  // default scene writes the bytes it wrote before they existed (same digest, and older
  // checkpoints load as scenes with the defaults).
  writeTaggedOptions(w, s);
  // And the calibrated Hertz damping (scene_io.hpp says why its absence means liggghts).
  if (s.hertzDamping == physics::HertzDamping::Calibrated) w.bytes.append(kDampingTag, 4);
  if (!s.blocked.empty()) {
    Writer body;
    body.list(s.blocked, [&](const BlockedElement& b) {
      body.u32(b.id.index);
      body.u32(b.id.generation);
      body.u8(b.dofs);
    });
    writeSection(w, kBlockedTag, body);
  }
  const bool cohesive = std::any_of(s.materials.begin(), s.materials.end(),
                                    [](const physics::MaterialDef& m) { return m.cohesion != 0; });
  if (cohesive) {
    Writer body;
    body.list(s.materials, [&](const physics::MaterialDef& m) { body.f64(m.cohesion); });
    writeSection(w, kCohesionTag, body);
  }
  if (!s.pairOverrides.empty()) {
    Writer body;
    body.list(s.pairOverrides, [&](const PairOverride& o) {
      body.u32(o.a);
      body.u32(o.b);
      for (double x : {o.c.restitution, o.c.friction, o.c.rolling, o.c.cohesion}) body.f64(x);
    });
    writeSection(w, kPairTag, body);
  }
  // The pairs' own moduli, after the pairs they belong to, only when one is set (the PAIR
  // record's layout is fixed).
  if (std::any_of(s.pairOverrides.begin(), s.pairOverrides.end(),
                  [](const PairOverride& o) { return !std::isnan(o.c.young); })) {
    Writer body;
    body.list(s.pairOverrides, [&](const PairOverride& o) { body.f64(o.c.young); });
    writeSection(w, kPairYoungTag, body);
  }
  // Also for balls alone when they meet a mesh wall through the shape pass (its candidates and
  // springs).
  if (s.geometries.size() > 1 || s.anyShapes) {
    Writer body;
    writeShapes(body, s);
    writeSection(w, kShapeTag, body);
  }
  if (!s.sources.empty()) {
    Writer body;
    writeSources(body, s);
    writeSection(w, kSourceTag, body);
  }
  if (!s.sinks.empty()) {
    Writer body;
    writeSinks(body, s);
    writeSection(w, kSinkTag, body);
  }
  if (std::any_of(s.sources.begin(), s.sources.end(), [](const auto& x) { return x.def.every != 1; }) ||
      std::any_of(s.sinks.begin(), s.sinks.end(), [](const auto& x) { return x.def.every != 1; })) {
    Writer body;
    body.list(s.sources, [&](const SourceState& x) { body.u32(x.def.every); });
    body.list(s.sinks, [&](const SinkState& x) { body.u32(x.def.every); });
    writeSection(w, kEveryTag, body);
  }
  if (std::isfinite(s.contactStep)) {
    Writer body;
    body.f64(s.contactStep);
    writeSection(w, kContactStepTag, body);
  }
  if (std::isfinite(s.motionStep) || s.motionSpeed != 0 ||
      s.stepsPerContact != kDefaultStepsPerContact) {
    Writer body;
    body.f64(s.stepsPerContact);
    body.f64(s.motionStep);
    body.f64(s.motionSpeed);
    writeSection(w, kMotionStepTag, body);
  }
  if (std::any_of(s.sources.begin(), s.sources.end(),
                  [](const auto& x) { return x.def.randomOrientation; })) {
    Writer body;
    body.list(s.sources, [&](const SourceState& x) { body.u8(x.def.randomOrientation); });
    writeSection(w, kSourceOrientationTag, body);
  }
  if (std::any_of(s.sources.begin(), s.sources.end(),
                  [](const auto& x) { return !x.def.shape.empty(); })) {
    Writer body;
    body.list(s.sources, [&](const SourceState& x) {
      body.str(x.def.shape);
      body.list(x.def.shapeParams, [&](double v) { body.f64(v); });
    });
    writeSection(w, kSourceShapeTag, body);
  }
  if (s.periodic.any()) {
    Writer body;
    writePeriodic(body, s);
    writeSection(w, kPeriodicTag, body);
  }
  if (wallsHaveExtra(s)) {
    Writer body;
    writeWallExtra(body, s);
    writeSection(w, kWallExtraTag, body);
  }
  if (wallsHaveHoles(s)) {
    Writer body;
    writeWallHoles(body, s);
    writeSection(w, kWallHoleTag, body);
  }
  if (!s.marginWeight.empty()) {
    Writer body;
    body.list(s.marginWeight, [&](Real x) { body.f64(x); });
    writeSection(w, kMarginTag, body);
  }
  const bool grainStates = s.touchNowCurrent(), wallStates = s.wallTouchNowCurrent();
  if (s.touchCorrection && s.forcesReady && (grainStates || wallStates)) {
    Writer body;
    body.u8(static_cast<uint8_t>((grainStates ? 1 : 0) | (wallStates ? 2 : 0)));
    const auto states = [&](const std::vector<uint8_t>& v) {
      body.list(v, [&](uint8_t x) { body.u8(x); });
    };
    if (grainStates) states(s.touchNow);
    if (wallStates) body.list(s.wallTouchNow, states);
    writeSection(w, kTouchStateTag, body);
  }
  if (mode == IoMode::Digest && scriptedWalls) {
    Writer body;
    body.list(s.walls.items, [&](const Wall<D>& x) {
      for (int k = 0; k < 3; ++k) body.u8((x.velocityFn[k] ? 1 : 0) | (x.omegaFn[k] ? 2 : 0));
      body.f64(x.scriptedAngle);
    });
    writeSection(w, kScriptedWallTag, body);
  }
  if (Writer body; writeOptionSection(body, s)) writeSection(w, kOptionTag, body);
  if (!s.bonds.empty()) {
    const size_t at = w.beginSection(kBondTag);
    writeBonds(w, s);
    w.endSection(at);
  }
  if (globalIdsDiffer(s)) {
    Writer body;
    body.u64(s.elements.nextGlobalId());
    body.list(s.elements.a.globalId, [&](uint64_t id) { body.u64(id); });
    writeSection(w, kGlobalIdTag, body);
  }
  if (!s.placedElements.empty() || !s.placedWalls.empty()) {
    Writer body;
    const auto handle = [&](auto id) {
      body.u32(id.index);
      body.u32(id.generation);
    };
    body.list(s.placedElements, handle);
    body.list(s.placedWalls, handle);
    writeSection(w, kPlacedTag, body);
  }
}

uint64_t hashBytes(std::string_view b) {
  uint64_t h = 0xcbf29ce484222325ull;
  size_t k = 0;
  for (; k + 8 <= b.size(); k += 8) {
    if ((k & ((size_t(1) << 22) - 1)) == 0) pollInterrupt("checkpoint");  // every 4 MiB
    uint64_t x;
    std::memcpy(&x, b.data() + k, 8);
    h = (h ^ x) * 0x100000001b3ull;
    h ^= h >> 29;
  }
  for (; k < b.size(); ++k) h = (h ^ static_cast<unsigned char>(b[k])) * 0x100000001b3ull;
  return h;
}

namespace {
constexpr char kChecksumTag[8] = {'C', 'H', 'E', 'C', 'K', 'S', 'U', 'M'};
constexpr size_t kTrailer = sizeof kChecksumTag + sizeof(uint64_t);
}  // namespace

std::string sealCheckpoint(std::string sceneBytes) {
  const FreeAsideOnThrow aside(sceneBytes);  // stopped in the hash
  const uint64_t sum = hashBytes(sceneBytes);
  sceneBytes.append(kChecksumTag, sizeof kChecksumTag);
  sceneBytes.append(reinterpret_cast<const char*>(&sum), sizeof sum);
  return sceneBytes;
}

int checkpointDimension(std::string_view b) {
  if (b.size() < 16 || std::memcmp(b.data(), kMagic, 8) != 0) return 0;
  uint32_t dim;
  std::memcpy(&dim, b.data() + 12, sizeof dim);
  return dim == 2 || dim == 3 ? int(dim) : 0;
}

std::string unsealCheckpoint(std::string b) {
  const FreeAsideOnThrow aside(b);  // stopped in the hash, or damaged
  if (b.size() < kTrailer || std::memcmp(b.data() + b.size() - kTrailer, kChecksumTag, 8) != 0) {
    if (b.size() < 8 || std::memcmp(b.data(), kMagic, 8) != 0) Reader::bad("not a demlab checkpoint");
    Reader::bad("no checksum at the end (the file is truncated or damaged)");
  }
  uint64_t sum;
  std::memcpy(&sum, b.data() + b.size() - sizeof sum, sizeof sum);
  b.resize(b.size() - kTrailer);
  if (hashBytes(b) != sum) Reader::bad("checksum mismatch (the file is damaged)");
  return b;
}

template <int D>
void readScene(Reader& r, Scene<D>& s) {
  char magic[8];
  for (char& c : magic) c = static_cast<char>(r.u8());
  if (std::memcmp(magic, kMagic, 8) != 0) Reader::bad("not a demlab checkpoint");
  r.version = r.u32();
  if (r.version < kOldestFormatVersion || r.version > kFormatVersion) {
    Reader::bad("unknown format version");
  }
  const uint32_t dim = r.u32();
  if (dim != D) {
    throw Error("can't load a " + std::to_string(dim) + "D checkpoint into a " + std::to_string(D) +
                    "D simulation",
                {"LOAD", "DIMENSION"});
  }
  const size_t nm = r.count(9);
  for (size_t m = 0; m < nm; ++m) {
    s.materialNames.push_back(r.str());
    s.materials.push_back(readMaterial(r));
  }
  s.defaultLaw = static_cast<physics::LawKind>(r.u8());
  s.pairLawOverride.resize(r.count(1));
  for (auto& x : s.pairLawOverride) x = static_cast<int8_t>(r.u8());
  if (s.pairLawOverride.size() != nm * nm) Reader::bad("pair law table size");
  const uint8_t coulomb = r.u8();
  if (coulomb > static_cast<uint8_t>(physics::CoulombCriterion::Spring))
    Reader::bad("coulomb criterion");
  s.coulomb = static_cast<physics::CoulombCriterion>(coulomb);
  s.dt = r.f64();
  s.autoFraction = r.f64();
  readHeaderOptions(r, s);
  s.time = r.f64();
  s.steps = r.u64();
  s.stepDt = r.f64();
  readPool(r, s.elements.pool());
  ElementArrays<D>& a = s.elements.a;
  const uint32_t n = s.elements.pool().size();
  // Made to size and filled as read (Reader polls): grown by doubling, the arrays were copied
  // whole in single calls (0.14 s at the last doubling of half a million). A damaged count
  // reserves no more than the bytes left can hold.
  constexpr size_t kGrainBytes = 4 * sizeof(VecD<D>) + sizeof(RotationD<D>) +
                                 3 * sizeof(AngularD<D>) + 3 * sizeof(Real) + sizeof(uint32_t);
  a.reserve(std::min<size_t>(n, r.remaining() / kGrainBytes));
  for (uint32_t i = 0; i < n; ++i) {
    const VecD<D> x = r.vec<D>(), v = r.vec<D>(), f = r.vec<D>(), fp = r.vec<D>();
    const RotationD<D> q = r.rot<RotationD<D>>();
    const AngularD<D> w = r.ang<AngularD<D>>(), t = r.ang<AngularD<D>>(), tp = r.ang<AngularD<D>>();
    const Real rad = r.f64(), im = r.f64(), ii = r.f64();
    const uint32_t mat = r.u32();
    if (mat >= nm) Reader::bad("grain material index");
    a.push(x, v, w, rad, im, ii, mat, s.elements.pool().handleAt(i).index);
    a.f.back() = f;
    a.fPrev.back() = fp;
    a.q.back() = q;
    a.t.back() = t;
    a.tPrev.back() = tp;
  }
  // Each element's global id is its slot unless the GIDS section says otherwise.
  s.elements.setNextGlobalId(s.elements.pool().slotCount());
  readNamesTags(r, s.elements.pool(), s.elements.names(), s.elements.tags());
  readPool(r, s.walls.pool());
  const uint32_t nw = s.walls.pool().size();
  for (uint32_t k = 0; k < nw; ++k) {
    Wall<D> x;
    x.kind = static_cast<WallShape>(r.u8());
    x.material = r.u32();
    if (x.material >= nm) Reader::bad("wall material index");
    x.shape0 = readShape<D>(r);
    x.shape = readShape<D>(r, &x.shape0);
    if (x.shape0.index() != x.shape.index() || static_cast<size_t>(x.kind) != x.shape.index()) {
      Reader::bad("wall shape");
    }
    x.moving = r.u8();
    x.velocity = r.vec<D>();
    x.amplitude = r.vec<D>();
    x.omega = r.ang<AngularD<D>>();
    x.frequency = r.f64();
    x.phase = r.f64();
    x.t0 = r.f64();
    x.point = r.vec<D>();
    x.point0 = r.vec<D>();
    x.pointVelocity = r.vec<D>();
    x.turned = r.rot<RotationD<D>>();
    x.pointAtBuild = r.vec<D>();
    x.timeAtBuild = r.f64();
    x.force = r.vec<D>();
    s.walls.items.push_back(std::move(x));
  }
  readNamesTags(r, s.walls.pool(), s.walls.names(), s.walls.tags());
  readPool(r, s.behaviors.pool());
  const uint32_t nb = s.behaviors.pool().size();
  for (uint32_t k = 0; k < nb; ++k) s.behaviors.items().push_back(readBehavior<D>(r));
  s.keepHistory = r.u8();
  s.rotating = r.u8();
  // The table's size is kept so it rebuilds the same layout; a power of two, bounded by what
  // the scene's pairs can need (a damaged size must not allocate terabytes).
  const size_t buckets = r.u64();
  const size_t mostBuckets = std::bit_ceil(64 * std::max<size_t>(n, 16));
  if (buckets > mostBuckets || (buckets & (buckets - 1)) != 0) Reader::bad("history table size");
  const size_t nh = r.count(8 + historyBytes<D>(r));
  s.histories.reserveBuckets(buckets);
  for (size_t k = 0; k < nh; ++k) {
    const uint32_t p = r.u32(), q = r.u32();
    s.histories.touch(p, q).state = readHistory<D>(r);
  }
  s.histories.sweep();
  const size_t nCandidates = r.count(8);
  s.candidates.clear();
  s.touchNowValid = s.wallTouchNowValid = false;  // (unless the touch state section follows)
  s.candidates.reserve(nCandidates);  // made as read (Reader polls), not zeroed in one call
  for (size_t k = 0; k < nCandidates; ++k) {
    CandidatePair& c = s.candidates.emplace_back();
    c.i = r.u32();
    c.j = r.u32();
    if (c.i >= n || c.j >= n) Reader::bad("candidate pair index");
  }
  // The candidates in the threaded pass's order (a scene written by this version has it
  // already); the springs follow their pairs.
  std::vector<uint32_t> moved;
  groupCandidates(s.candidates, &s.contactGroups, &moved,
                  [] { pollInterrupt("sorting the candidate pairs"); });
  const size_t nSprings = r.count(historyBytes<D>(r));
  if (nSprings != 0 && nSprings != s.candidates.size()) Reader::bad("pair springs");
  std::vector<physics::TangentialHistory<D>> springsRead;
  springsRead.reserve(nSprings);  // made as read (Reader polls), not zeroed in one call
  for (size_t k = 0; k < nSprings; ++k) springsRead.push_back(readHistory<D>(r));
  s.pairSprings.reset(nSprings, true);
  InterruptPoll poll("reading the scene");  // no bytes read here: a third of a second at 3 10^6
  // An empty history is no slot (PairSprings::set), except a zero spring with a -0.0 in it:
  // only a slot holds that (a law's rounding), and keeping it there makes the scene write its
  // bytes.
  const auto signedZero = [](const VecD<D>& sp) {
    bool any = false;
    for (int c = 0; c < D; ++c) any |= std::signbit(sp[c]);
    return sp.squaredNorm() == 0 && any;
  };
  // The pool made to size first: grown an eighth at a time as slots were handed out below, it
  // was copied whole, unpolled, at each growth (nine times its size in all).
  size_t slots = 0;
  for (const auto& h : springsRead) {
    poll();
    slots += !h.empty() || signedZero(h.spring);
  }
  s.pairSprings.reserve(slots);
  for (size_t k = 0; k < nSprings; ++k) {
    poll();
    const physics::TangentialHistory<D>& h = springsRead[moved.empty() ? k : moved[k]];
    if (signedZero(h.spring)) {
      *s.pairSprings.at(k) = h;
    } else {
      s.pairSprings.set(k, h);
    }
  }
  s.wallSprings.resize(r.count(8));
  for (auto& l : s.wallSprings) {
    l.resize(r.count(historyBytes<D>(r)));
    for (auto& h : l) h = readHistory<D>(r);
  }
  s.wallCandidates.resize(r.count(8));
  if (s.wallCandidates.size() > nw) Reader::bad("wall candidate lists");
  for (auto& l : s.wallCandidates) {
    l.resize(r.count(4));
    for (auto& i : l) {
      i = r.u32();
      if (i >= n) Reader::bad("wall candidate index");
    }
  }
  for (size_t w = 0; w < s.wallSprings.size(); ++w) {
    if (w >= s.wallCandidates.size() || s.wallSprings[w].size() != s.wallCandidates[w].size()) {
      Reader::bad("wall springs");
    }
  }
  s.xAtBuild.resize(r.count(8 * D));
  for (auto& x : s.xAtBuild) x = r.vec<D>();
  s.skin = r.f64();
  s.maxDisp2 = r.f64();
  s.needRebuild = r.u8();
  s.forcesReady = r.u8();
  s.rebuilds = r.u64();
  const size_t nRecords = r.count(9 + 8 * D);
  s.contacts.clear();
  s.contacts.reserve(nRecords);  // made as read (Reader polls), not zeroed in one call
  for (size_t k = 0; k < nRecords; ++k) {
    ContactRecord<D>& c = s.contacts.emplace_back();
    const uint32_t a = r.u32(), b = r.u32();
    const bool wall = r.u8() != 0;
    c.force = r.vec<D>();
    if (a >= n || (wall ? b >= nw : b >= n)) Reader::bad("contact index");
    c.a = a;
    c.b = b;  // < n or nw: fits the record's 31 bits (HandlePool::kMaxSlots)
    c.wall = wall;
  }
  LedgerSums& l = s.ledger;
  for (double* x : {&l.dampingLoss, &l.frictionLoss, &l.wallWork, &l.behaviorWork, &l.springWork,
                    &l.elastic, &l.reference, &l.gravityReference, &l.scale}) {
    *x = r.f64();
  }
  l.started = r.u8();
  char tag[4] = {};
  const auto readTag = [&] {
    if (r.atEnd()) return false;
    for (char& c : tag) c = static_cast<char>(r.u8());
    return true;
  };
  bool tagged = readTag();
  clearTagAloneOptions(s);
  while (tagged && readTaggedOptions(r, s, tag)) tagged = readTag();
  const bool calibrated = tagged && std::memcmp(tag, kDampingTag, 4) == 0;
  s.hertzDamping = calibrated ? physics::HertzDamping::Calibrated : physics::HertzDamping::Liggghts;
  if (calibrated) tagged = readTag();
  while (tagged) {
    const std::string_view body = r.bytesOf(r.count(1));
    Reader b(body);
    b.version = r.version;
    if (std::memcmp(tag, kBlockedTag, 4) == 0) {
      readBlocked(b, s);
    } else if (std::memcmp(tag, kPairTag, 4) == 0) {
      readPairOverrides(b, s);
    } else if (std::memcmp(tag, kPairYoungTag, 4) == 0) {
      if (b.count(8) != s.pairOverrides.size()) Reader::bad("pair moduli count");
      for (PairOverride& o : s.pairOverrides) {
        o.c.young = b.f64();
        if (!(std::isnan(o.c.young) || (o.c.young > 0 && std::isfinite(o.c.young)))) {
          Reader::bad("pair modulus");
        }
      }
    } else if (std::memcmp(tag, kShapeTag, 4) == 0) {
      readShapes(b, s);
    } else if (std::memcmp(tag, kPlacedTag, 4) == 0) {
      readPlaced(b, s);
    } else if (std::memcmp(tag, kGlobalIdTag, 4) == 0) {
      readGlobalIds(b, s);
    } else if (std::memcmp(tag, kBondTag, 4) == 0) {
      readBonds(b, s);
    } else if (std::memcmp(tag, kSourceTag, 4) == 0) {
      readSources(b, s);
    } else if (std::memcmp(tag, kSinkTag, 4) == 0) {
      readSinks(b, s);
    } else if (std::memcmp(tag, kEveryTag, 4) == 0) {
      // After the sources' and sinks' sections: one interval for each, checked as addSource's.
      const auto readEvery = [&](auto& list) {
        if (b.count(4) != list.size()) Reader::bad("source or sink interval count");
        for (auto& x : list) {
          x.def.every = b.u32();
          if (x.def.every < 1 || x.def.every > kMaxBoundaryEvery) Reader::bad("source or sink interval");
        }
      };
      readEvery(s.sources);
      readEvery(s.sinks);
    } else if (std::memcmp(tag, kSourceOrientationTag, 4) == 0) {
      if (b.count(1) != s.sources.size()) Reader::bad("source orientation count");
      for (SourceState& x : s.sources) {
        const uint8_t v = b.u8();
        if (v > 1) Reader::bad("source orientation");
        x.def.randomOrientation = v != 0;
      }
    } else if (std::memcmp(tag, kSourceShapeTag, 4) == 0) {
      if (b.count(1) != s.sources.size()) Reader::bad("source shape count");
      for (SourceState& x : s.sources) {
        x.def.shape = b.str();
        x.def.shapeParams.resize(b.count(8));
        for (double& v : x.def.shapeParams) v = b.f64();
        if (x.def.shape.empty()) Reader::bad("source shape");
        try {
          const Geometry<D> g = ShapeTable<D>::get().makeGeometry(x.def.shape, x.def.shapeParams);
          if (g.boundRadius == 0 || !ShapeTable<D>::get().type(g.shape).scaled(x.def.shapeParams, 1)) {
            Reader::bad("source shape");
          }
        } catch (const Error& e) {
          if (e.code().size() > 1 && e.code()[1] == "LOAD") throw;
          Reader::bad("source shape");
        }
      }
    } else if (std::memcmp(tag, kPeriodicTag, 4) == 0) {
      readPeriodic(b, s);
    } else if (std::memcmp(tag, kWallExtraTag, 4) == 0) {
      readWallExtra(b, s);
    } else if (std::memcmp(tag, kWallHoleTag, 4) == 0) {
      readWallHoles(b, s);
    } else if (std::memcmp(tag, kMarginTag, 4) == 0) {
      // One weight per position at the last search, each in (0, 1] (a margin at least half
      // the skin).
      s.marginWeight.resize(b.count(8));
      if (s.marginWeight.size() != s.xAtBuild.size()) Reader::bad("margin count");
      for (Real& x : s.marginWeight) {
        x = b.f64();
        if (!(x > 0 && x <= 1)) Reader::bad("margin weight");
      }
    } else if (std::memcmp(tag, kTouchStateTag, 4) == 0) {
      // One state per candidate, each a touch and perhaps its force cut off.
      const uint8_t flags = b.u8();
      if (flags == 0 || flags > 3) Reader::bad("touch state flags");
      const auto states = [&](size_t n) {
        if (b.count(1) != n) Reader::bad("touch state count");
        std::vector<uint8_t> read(n);
        for (uint8_t& x : read) {
          x = b.u8();
          if (x != 0 && x != kernel::kTouching && x != (kernel::kTouching | kernel::kCutOff)) {
            Reader::bad("touch state");
          }
        }
        return read;
      };
      if (flags & 1) {
        // In the order the candidates were sorted into above.
        const std::vector<uint8_t> read = states(s.candidates.size());
        s.touchNow.resize(read.size());
        for (size_t k = 0; k < read.size(); ++k) s.touchNow[k] = read[moved.empty() ? k : moved[k]];
        s.touchNowValid = true;
      }
      if (flags & 2) {
        if (b.count(8) != s.walls.size()) Reader::bad("touch state wall count");
        s.wallTouchNow.resize(s.walls.size());
        for (size_t k = 0; k < s.walls.size(); ++k) {
          s.wallTouchNow[k] = states(k < s.wallCandidates.size() ? s.wallCandidates[k].size() : 0);
        }
        s.wallTouchNowValid = true;
      }
    } else if (std::memcmp(tag, kOptionTag, 4) == 0) {
      readOptionSection(b, s);
    } else if (std::memcmp(tag, kContactStepTag, 4) == 0) {
      s.contactStep = b.f64();
      if (!(s.contactStep > 0 && std::isfinite(s.contactStep))) Reader::bad("contact step");
    } else if (std::memcmp(tag, kMotionStepTag, 4) == 0) {
      s.stepsPerContact = b.f64();
      s.motionStep = b.f64();
      s.motionSpeed = b.f64();
      if (!(s.stepsPerContact >= 0 && std::isfinite(s.stepsPerContact)))
        Reader::bad("steps per contact");
      if (!(s.motionStep > 0)) Reader::bad("motion step");  // +inf: no bound
      if (!(s.motionSpeed >= 0 && std::isfinite(s.motionSpeed))) Reader::bad("motion speed");
    } else if (std::memcmp(tag, kCohesionTag, 4) == 0) {
      if (b.count(8) != s.materials.size()) Reader::bad("cohesion count");
      for (physics::MaterialDef& m : s.materials) {
        m.cohesion = b.f64();
        if (!(m.cohesion >= 0 && std::isfinite(m.cohesion))) Reader::bad("cohesion");
      }
    } else {
      throw Error("can't load a checkpoint with a \"" + std::string(tag, 4) +
                      "\" section: it was written by a later demlab",
                  {"LOAD", "SECTION"});
    }
    if (!b.atEnd()) Reader::bad("section length");
    tagged = readTag();
  }
  // Each element's inverse inertia says which integrator turns it (0: the rigid-body one,
  // sim/rigid_body.hpp): it must agree with its Geometry, or a corrupt file would send a ball
  // down the rigid path with no principal moments.
  const ElementArrays<D>& e = s.elements.a;
  for (size_t i = 0; i < e.size(); ++i) {
    const Geometry<D>& g = *s.geometries[e.geometry[i]];
    const bool rigid = D == 3 && g.boundRadius > 0 && !g.isotropic;
    const bool ok = e.invMass[i] > 0 && std::isfinite(e.invMass[i]) &&
                    (rigid ? e.invInertia[i] == 0
                           : e.invInertia[i] > 0 && std::isfinite(e.invInertia[i]));
    if (!ok) Reader::bad("element mass or inertia");
  }
  // Every value as the commands would check it (core/validity.hpp): a file made by hand or by
  // another program must not bring in what `element add` or `material add` refuses.
  try {
    for (size_t m = 0; m < s.materials.size(); ++m) s.materials[m].check();
    for (size_t i = 0; i < e.size(); ++i) {
      checkRadiusRange(e.r[i]);
      checkPositionRange<D>(e.x[i], e.r[i]);
      checkVelocityRange<D>(e.v[i]);
      checkAngularRange(e.w[i], e.r[i], D);
      checkMassRange(e.invMass[i], e.r[i]);
    }
  } catch (const Error& err) {
    Reader::bad(err.what());
  }
}

template void writeScene<2>(Writer&, const Scene<2>&, IoMode, const BehaviorManager<2>*);
template void writeScene<3>(Writer&, const Scene<3>&, IoMode, const BehaviorManager<3>*);
template void readScene<2>(Reader&, Scene<2>&);
template void readScene<3>(Reader&, Scene<3>&);

}  // namespace demlab::sim
