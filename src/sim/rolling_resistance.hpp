// The "rolling" module: rolling resistance as a constant directional torque (Ai, Chen, Rotter
// and Ooi, Powder Technology 206 (2011) 269, model A; LIGGGHTS's rolling_friction cdt). At a
// contact with normal force Fn and effective radius R*, the torque on A is
//   M = -mu_r R* Fn w_r / |w_r|,  w_r = the rolling part of A's angular velocity relative to B
// (the relative angular velocity less its part along the normal, which is twisting, not
// rolling), and B receives -M. mu_r is the pair's rolling friction, the smaller of the two
// materials' (the rule of the sliding friction, pair_params.hpp): a length per unit radius,
// the lever arm of the resisting couple.
//
// A constant torque would overshoot once w_r is small, flipping sign every step (the chatter
// model A is known for); the torque is capped at the one that stops the relative rolling
// within the step, |w_r| / (dt (1/I_a + 1/I_b)), so a rolling grain comes to rest and stays.
// The dissipated |M| |w_r| dt goes to the ledger's friction loss.
//
// It reads the step's contact records (SimModule::readsContactRecords), so it runs after the
// contact passes; a scene with no rolling friction runs no such module. A shape's contact point
// comes from its row (sim/record_geometry.hpp), R* is the row's effective radius and the cap
// uses the rigid body's inertia about the rolling axis.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/pair_table.hpp"
#include "sim/record_geometry.hpp"
#include "sim/scene.hpp"
#include "sim/shape_contacts.hpp"
#include "sim/sim_loop.hpp"

namespace demlab::sim {

// Returns true if some material or pair of s has a rolling friction.
template <int D>
bool anyRollingFriction(const Scene<D>& s) {
  return anyPositive(s, &physics::MaterialDef::rollingFriction, &PairCoefficients::rolling);
}

template <int D>
class RollingResistanceModule final : public SimModule<D> {
 public:
  // Mixes the pairs' coefficients of s (the module is rebuilt when the materials change).
  explicit RollingResistanceModule(const Scene<D>& s)
      : mu_(s, &physics::MaterialDef::rollingFriction) {}
  std::string_view name() const override { return "rolling"; }
  SimLevel level() const override { return SimLevel::Contacts; }
  bool readsContactRecords() const override { return true; }

  void run(Scene<D>& s) override {
    if (!s.rotating || !(s.stepDt > 0)) return;
    ElementArrays<D>& a = s.elements.a;
    const Real dt = s.stepDt;
    double loss = 0;
    RecordGeometryReader<D> reader;
    for (const ContactRecord<D>& c : s.contacts) {
      const auto rg = reader.next(s, c);
      if (!rg) continue;
      const uint32_t i = c.a;
      const VecD<D>& n = rg->g.normal;
      const uint32_t matB = rg->materialB;
      const Real radius =
          c.wall ? rg->radiusA : rg->radiusA * rg->radiusB / (rg->radiusA + rg->radiusB);
      const AngularD<D> wOther = c.wall ? s.walls.items[c.b].omega : a.w[c.b];
      const Real mu = mu_.at(a.material[i], matB);
      const Real fn = c.force.dot(n);
      if (!(mu > 0 && fn > 0)) continue;
      AngularD<D> wr = a.w[i] - wOther;
      if constexpr (D == 3) wr -= wr.dot(n) * n;
      const Real speed = std::sqrt(squaredNorm(wr));
      if (!(speed > 0)) continue;
      // The inverse inertia about the rolling axis (a rigid body's from its tensor).
      const AngularD<D> axis = wr / speed;
      const auto invAlong = [&](uint32_t e) {
        return a.invInertia[e] != 0 ? a.invInertia[e] : inverseInertiaAlong(s, e, axis);
      };
      const Real invI = invAlong(i) + (c.wall ? 0 : invAlong(c.b));
      const Real torque = std::min(mu * radius * fn, speed / (dt * invI));
      const AngularD<D> m = (-torque / speed) * wr;
      a.t[i] += m;
      if (!c.wall) a.t[c.b] -= m;
      loss += torque * speed * dt;
    }
    s.ledger.frictionLoss += loss;
  }

 private:
  PairTable<D> mu_;
};

}  // namespace demlab::sim
