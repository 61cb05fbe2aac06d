// The "bonds" module: every intact bond's force and moment, after the contact passes (a bond
// acts in parallel with the pair's contact law). It runs serially over the bonds in creation
// order, so each element receives its bonds' forces in the same order for any thread count: the
// bits do not depend on the threads. A bond whose strength is exceeded still acts for this step
// and is queued to break at the step's end (Scene::deferred); the manager then marks it broken,
// books the energy it held as released and computes the forces of the changed scene.
//
// The increments a model receives are taken with the half-step velocities the drift used, so
// a step's relative displacement is the drift's exactly; the accumulated shear force and
// bending moment are carried into the current bond plane (projected and rescaled to their
// magnitude) before the increment is added. With a zero step (the forces of a scene after an
// edit) no increment is added and the state stays as it was, bit for bit.
#pragma once

#include "sim/bond_model.hpp"
#include "sim/integrator.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Returns v with its component along the unit n removed and its length kept (v itself when it
// is zero or along n). Changes nothing.
template <int D>
inline VecD<D> carryIntoPlane(const VecD<D>& v, const VecD<D>& n) {
  const Real len2 = v.squaredNorm();
  if (len2 == 0) return v;
  const VecD<D> p = v - v.dot(n) * n;
  const Real p2 = p.squaredNorm();
  if (p2 == 0) return p;
  return p * std::sqrt(len2 / p2);
}
inline Real carryIntoPlane(Real m, const Vec2&) {
  return m;  // 2D: a bending moment is along the plane's normal, always normal to the axis
}

// The geometry of one bond now: axis, length and the centre the force acts at (the middle of
// the gap between the two surfaces). Changes nothing.
template <int D>
struct BondFrame {
  VecD<D> n, centre;
  Real length;
};
template <int D>
inline BondFrame<D> bondFrame(const ElementArrays<D>& a, uint32_t i, uint32_t j) {
  const VecD<D> d = a.x[j] - a.x[i];
  BondFrame<D> f;
  f.length = d.norm();
  f.n = d / f.length;
  f.centre = a.x[i] + (a.r[i] + 0.5 * (f.length - a.r[i] - a.r[j])) * f.n;
  return f;
}

template <int D>
class BondModule final : public SimModule<D> {
 public:
  std::string_view name() const override { return "bonds"; }
  SimLevel level() const override { return SimLevel::Contacts; }

  void run(Scene<D>& s) override {
    ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt;
    const auto& types = bondModelTypes();
    double energy = 0;
    std::vector<Bond<D>>& bonds = s.bonds.bonds;
    for (size_t k = 0; k < bonds.size(); ++k) {
      Bond<D>& bond = bonds[k];
      if (!bond.intact) continue;
      const uint32_t i = s.elements.pool().findDense(bond.a);
      const uint32_t j = s.elements.pool().findDense(bond.b);
      const BondModel& model = s.bonds.models[bond.model];
      const BondFrame<D> f = bondFrame(a, i, j);
      BondKinematics<D> kin{f.n,    f.length,        a.r[i],
                            a.r[j], VecD<D>::Zero(), ElementArrays<D>::zeroAngular()};
      BondState<D> st = bond.state;
      if (dt > 0) {
        VecD<D> vi = halfStepVelocity(s, i), vj = halfStepVelocity(s, j);
        if (s.rotating) {
          const AngularD<D> wi = halfStepAngularVelocity(s, i);
          const AngularD<D> wj = halfStepAngularVelocity(s, j);
          vi += cross(wi, VecD<D>(f.centre - a.x[i]));
          vj += cross(wj, VecD<D>(f.centre - a.x[j]));
          kin.dRot = (wj - wi) * dt;
        }
        const VecD<D> du = (vj - vi) * dt;
        kin.dShear = du - du.dot(f.n) * f.n;
        st.shearForce = carryIntoPlane<D>(st.shearForce, f.n);
        st.bendMoment = carryIntoPlane(st.bendMoment, f.n);
      }
      const BondResponse<D> r = bondStep<D>(types[model.type])(model.values, bond, kin, st);
      bond.state = st;
      a.f[j] += r.force;
      a.f[i] -= r.force;
      if (s.rotating) {
        a.t[j] += cross(VecD<D>(f.centre - a.x[j]), r.force) + r.moment;
        a.t[i] -= cross(VecD<D>(f.centre - a.x[i]), r.force) + r.moment;
      }
      energy += st.energy;
      if (dt > 0 && r.breaks)
        s.deferred.breakBonds.push_back({static_cast<uint32_t>(k), *r.breaks});
    }
    s.ledger.elastic += energy;
  }
};

}  // namespace demlab::sim
