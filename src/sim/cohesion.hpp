// The "cohesion" module: a constant cohesion model (the simplified JKR of LIGGGHTS's
// cohesion sjkr): while two surfaces overlap they attract with a force k_c A along the normal,
// A the area of the surfaces' intersection (sphere-sphere: the circle where the two spheres
// cut, pi a^2 with a^2 = (d^2 - (ri - rj)^2) ((ri + rj)^2 - d^2) / (4 d^2); sphere-wall: the cap's
// base, pi delta (2r - delta), taken flat for every wall shape). In 2D too A is pi a^2: discs
// touch as spheres in a plane, as they do in the normal laws (and in LIGGGHTS's 2D). k_c (Pa,
// an energy per volume) is the pair's cohesion, the smaller of the two materials' (as the
// friction).
//
// It runs after the contact passes and adds its force to each contact's record, so queries
// show the net force. The force is conservative, a function of the overlap; its work on the
// grains, -k_c A (relative normal velocity) dt per step, goes to the ledger's behaviour work
// (first order in the step, like the tangential ledger). Pull-off: with the repulsive law F_n,
// the pair separates under the largest k_c A - F_n over the overlaps (0 at first touch: the
// model holds only what is in contact, unlike JKR's pull-off at negative overlap).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "sim/pair_table.hpp"
#include "sim/record_geometry.hpp"
#include "sim/scene.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Returns true if some material or pair of s has a cohesion.
template <int D>
bool anyCohesion(const Scene<D>& s) {
  return anyPositive(s, &physics::MaterialDef::cohesion, &PairCoefficients::cohesion);
}

// Returns the area of the circle where a sphere of radius ri cuts one of radius rj at centre
// distance dist, or, for rj = 0, where it cuts a flat wall at overlap delta.
inline Real cohesionArea(Real ri, Real rj, Real dist, Real delta) {
  Real a2;
  if (rj == 0) {
    a2 = delta * (2 * ri - delta);
  } else {
    const Real d2 = dist * dist;
    a2 = (d2 - (ri - rj) * (ri - rj)) * ((ri + rj) * (ri + rj) - d2) / (4 * d2);
  }
  return std::numbers::pi * std::max<Real>(a2, 0);
}

template <int D>
class CohesionModule final : public SimModule<D> {
 public:
  // Mixes the pairs' coefficients of s (the module is rebuilt when the materials change).
  explicit CohesionModule(const Scene<D>& s) : kc_(s, &physics::MaterialDef::cohesion) {}
  std::string_view name() const override { return "cohesion"; }
  SimLevel level() const override { return SimLevel::Contacts; }
  bool readsContactRecords() const override { return true; }

  void run(Scene<D>& s) override {
    ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt;
    double work = 0;
    for (ContactRecord<D>& c : s.contacts) {
      const auto rg = recordGeometry(s, c);
      if (!rg) continue;
      const Real kc = kc_.at(a.material[c.a], rg->materialB);
      if (!(kc > 0)) continue;
      const uint32_t i = c.a;
      const VecD<D>& n = rg->g.normal;
      const Real delta = rg->g.overlap;
      const Real dist = rg->radiusA + rg->radiusB - delta;
      const Real f = kc * cohesionArea(rg->radiusA, rg->radiusB, dist, delta);
      // On b (or the wall) -f n, towards a; on a +f n.
      const VecD<D> onB = -f * n;
      a.f[i] -= onB;
      VecD<D> vRel;
      if (c.wall) {
        vRel = s.walls.items[c.b].surfaceVelocity(rg->g.point) - a.v[i];
      } else {
        a.f[c.b] += onB;
        vRel = a.v[c.b] - a.v[i];
      }
      work += onB.dot(vRel) * dt;
      c.force += onB;
    }
    s.ledger.behaviorWork += work;
  }

 private:
  PairTable<D> kc_;
};

}  // namespace demlab::sim
