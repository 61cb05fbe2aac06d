// The checkpoint section of the bonds (scene_io.hpp, kBondTag): the models by type name and
// values, every bond (intact or broken) with its accumulated state, the breaks, the next id and
// the ledger's released energy.
#include <cmath>

#include "sim/bond_model.hpp"
#include "sim/scene_io.hpp"

namespace demlab::sim {

namespace {

void writeHandle(Writer& w, ElementId id) {
  w.u32(id.index);
  w.u32(id.generation);
}

template <int D>
ElementId readHandle(Reader& r, const Scene<D>& s) {
  ElementId id;
  id.index = r.u32();
  id.generation = r.u32();
  if (!s.elements.pool().valid(id)) Reader::bad("bond element handle");
  return id;
}

}  // namespace

template <int D>
void writeBonds(Writer& w, const Scene<D>& s) {
  const BondSet<D>& set = s.bonds;
  const auto& types = bondModelTypes();
  w.list(set.models, [&](const BondModel& m) {
    w.str(m.name);
    w.str(types[m.type].name);
    w.list(m.values, [&](double x) { w.f64(x); });
  });
  w.list(set.bonds, [&](const Bond<D>& b) {
    w.u32(b.id);
    writeHandle(w, b.a);
    writeHandle(w, b.b);
    w.u32(b.model);
    for (double x : {b.restLength, b.tensile, b.shear}) w.f64(x);
    w.u8(b.intact);
    const BondState<D>& st = b.state;
    w.vec<D>(st.shearForce);
    w.ang(st.bendMoment);
    for (double x : {st.twistMoment, st.normalForce, st.sigma, st.tau, st.energy}) w.f64(x);
  });
  w.list(set.breaks, [&](const BondBreak<D>& r) {
    w.u32(r.bond);
    writeHandle(w, r.a);
    writeHandle(w, r.b);
    w.u8(static_cast<uint8_t>(r.mode));
    w.f64(r.time);
    w.u64(r.step);
    w.vec<D>(r.point);
    w.f64(r.energy);
    w.f64(r.measure);
  });
  w.u32(set.nextId);
  w.f64(s.ledger.bondReleased);
}

template <int D>
void readBonds(Reader& r, Scene<D>& s) {
  BondSet<D>& set = s.bonds;
  const auto& types = bondModelTypes();
  set.models.resize(r.count(24));
  for (BondModel& m : set.models) {
    m.name = r.str();
    const std::string type = r.str();
    m.type = static_cast<uint32_t>(types.size());
    for (size_t k = 0; k < types.size(); ++k) {
      if (types[k].name == type) m.type = static_cast<uint32_t>(k);
    }
    if (m.type == types.size()) Reader::bad("unknown bond type \"" + type + "\"");
    m.values.resize(r.count(8));
    if (m.values.size() != types[m.type].options.size()) Reader::bad("bond model values");
    for (double& x : m.values) x = r.f64();
  }
  // Reserved, then made one by one as they are read: a resize would zero and fault in the
  // pages of a million bonds (hundreds of megabytes) in one call that Ctrl-C cannot stop.
  const size_t nb = r.count(40);
  set.bonds.clear();
  set.bonds.reserve(nb);
  for (size_t k = 0; k < nb; ++k) {
    Bond<D>& b = set.bonds.emplace_back();
    b.id = r.u32();
    b.a = readHandle(r, s);
    b.b = readHandle(r, s);
    b.model = r.u32();
    if (b.model >= set.models.size()) Reader::bad("bond model index");
    for (Real* x : {&b.restLength, &b.tensile, &b.shear}) *x = r.f64();
    b.intact = r.u8() != 0;
    BondState<D>& st = b.state;
    st.shearForce = r.vec<D>();
    st.bendMoment = r.ang<AngularD<D>>();
    for (Real* x : {&st.twistMoment, &st.normalForce, &st.sigma, &st.tau, &st.energy}) *x = r.f64();
    if (!(b.restLength > 0)) Reader::bad("bond rest length");
  }
  set.breaks.resize(r.count(40));
  for (BondBreak<D>& k : set.breaks) {
    k.bond = r.u32();
    k.a.index = r.u32();  // the elements of a break may be gone: not checked
    k.a.generation = r.u32();
    k.b.index = r.u32();
    k.b.generation = r.u32();
    const uint8_t mode = r.u8();
    if (mode != 1 && mode != 2) Reader::bad("bond break mode");
    k.mode = static_cast<BondBreakMode>(mode);
    k.time = r.f64();
    k.step = r.u64();
    k.point = r.vec<D>();
    k.energy = r.f64();
    k.measure = r.f64();
  }
  set.nextId = r.u32();
  s.ledger.bondReleased = r.f64();
}

template void writeBonds<2>(Writer&, const Scene<2>&);
template void writeBonds<3>(Writer&, const Scene<3>&);
template void readBonds<2>(Reader&, Scene<2>&);
template void readBonds<3>(Reader&, Scene<3>&);

}  // namespace demlab::sim
