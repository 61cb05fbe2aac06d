// The bond module's threaded pass (sim/bond_module.hpp) against a plain serial pass over the
// bonds in creation order, the oracle: the same forces, torques, bond states, elastic energy
// and queued breaks, bit for bit, with 1 to 4 threads, on randomized bonded scenes edited
// between passes (elements removed with their bonds, elements added and bonded, bonds
// broken, the dense order sorted anew at every search), one module kept throughout so that
// its cached gather lists must follow every edit.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "core/thread_pool.hpp"
#include "sim/bond_module.hpp"
#include "sim/simulation_manager.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_bond_pass_test {

using testing::latticeGrains;
using testing::material;

template <int D>
Scene<D>& sceneOf(Simulation& s) {
  return const_cast<Scene<D>&>(dynamic_cast<SimulationManager<D>&>(s).scene());
}

// The oracle: one serial pass over the bonds in creation order, each bond's force and
// torques added to its elements as soon as its model has run.
template <int D>
void serialPass(Scene<D>& s) {
  ElementArrays<D>& a = s.elements.a;
  const Real dt = s.stepDt;
  double energy = 0;
  for (size_t k = 0; k < s.bonds.bonds.size(); ++k) {
    Bond<D>& bond = s.bonds.bonds[k];
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
    const BondResponse<D> r = bondStep<D>(bondModelTypes()[model.type])(model.values, bond, kin, st);
    bond.state = st;
    a.f[j] += r.force;
    a.f[i] -= r.force;
    if (s.rotating) {
      a.t[j] += cross(VecD<D>(f.centre - a.x[j]), r.force) + r.moment;
      a.t[i] -= cross(VecD<D>(f.centre - a.x[i]), r.force) + r.moment;
    }
    energy += st.energy;
    if (dt > 0 && r.breaks) s.deferred.breakBonds.push_back({static_cast<uint32_t>(k), *r.breaks});
  }
  s.ledger.elastic += energy;
}

// What a pass changes, to compare bit for bit and to put back.
template <int D>
struct PassState {
  std::vector<VecD<D>> f;
  std::vector<AngularD<D>> t;
  std::vector<BondState<D>> bonds;
  double elastic;
  std::vector<PendingBreak> breaks;

  static PassState of(const Scene<D>& s) {
    PassState p{s.elements.a.f, s.elements.a.t, {}, s.ledger.elastic, s.deferred.breakBonds};
    for (const Bond<D>& b : s.bonds.bonds) p.bonds.push_back(b.state);
    return p;
  }
  void restore(Scene<D>& s) const {
    s.elements.a.f = f;
    s.elements.a.t = t;
    for (size_t k = 0; k < bonds.size(); ++k) s.bonds.bonds[k].state = bonds[k];
    s.ledger.elastic = elastic;
    s.deferred.breakBonds = breaks;
  }
};

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

template <int D>
void checkAgainstTheSerialPass(unsigned seed) {
  std::unique_ptr<Simulation> sim = makeSimulation(D);
  Simulation& s = *sim;
  s.addMaterial("glass", material(5e6, 0.5, 0.5));
  const double r = 0.001;
  std::vector<ElementId> ids = s.addElements(latticeGrains(D, 2400, r, 0.2, 0.02, "glass", seed));
  // Weak and scattered strengths: bonds break throughout the run.
  s.addBondModel("weak", D == 3 ? "parallel" : "pointspring",
                 {{"kn", 1e6}, {"ks", 5e5}, {"tensile", 2e-2}, {"shear", 2e-2}, {"scatter", 0.5}});
  s.addBondsWithin({}, 0.25 * r, "weak");
  sceneOf<D>(s).elements.reorderEvery = 1;  // a new dense order at every search
  std::mt19937_64 rng(seed);
  BondModule<D> module;
  const unsigned before = ThreadPool::global().threads();
  size_t checked = 0;
  for (int round = 0; round < 6; ++round) {
    RunOptions run;
    run.steps = 40;
    s.run(run);
    // An edit: remove a few elements (their bonds go), or add a bonded cluster far away.
    if (round % 3 == 1) {
      for (int k = 0; k < 5; ++k) {
        const size_t at = rng() % ids.size();
        s.removeElement(ids[at]);
        ids.erase(ids.begin() + static_cast<std::ptrdiff_t>(at));
      }
    } else if (round % 3 == 2) {
      std::vector<ElementDef> defs = latticeGrains(D, 30, r, 0.02, 0.02, "glass", seed + round);
      for (ElementDef& d : defs) d.position[0] += 0.5 + 0.05 * round;
      const std::vector<ElementId> added = s.addElements(defs);
      ids.insert(ids.end(), added.begin(), added.end());
      s.addBondsWithin(added, 0.25 * r, "weak");
    }
    Scene<D>& scene = sceneOf<D>(s);
    if (scene.stepDt == 0) scene.stepDt = s.timeStep();
    const PassState<D> start = PassState<D>::of(scene);
    serialPass(scene);
    const PassState<D> expected = PassState<D>::of(scene);
    for (unsigned threads = 1; threads <= 4; ++threads) {
      ThreadPool::global().setThreads(threads);
      start.restore(scene);
      module.run(scene);
      const PassState<D> got = PassState<D>::of(scene);
      EXPECT_TRUE(sameBits(got.f, expected.f)) << "round " << round << ", threads " << threads;
      EXPECT_TRUE(sameBits(got.t, expected.t)) << "round " << round << ", threads " << threads;
      EXPECT_TRUE(sameBits(got.bonds, expected.bonds)) << "round " << round;
      EXPECT_EQ(std::memcmp(&got.elastic, &expected.elastic, sizeof(double)), 0);
      ASSERT_EQ(got.breaks.size(), expected.breaks.size());
      for (size_t k = 0; k < got.breaks.size(); ++k) {
        EXPECT_EQ(got.breaks[k].index, expected.breaks[k].index);
        EXPECT_EQ(got.breaks[k].mode, expected.breaks[k].mode);
      }
      ++checked;
    }
    start.restore(scene);
  }
  ThreadPool::global().setThreads(before);
  EXPECT_EQ(checked, 24u);
  // The scenes did what they are for: bonds broke, so the gather lists had holes to follow.
  const BondCount count = s.bondCount();
  EXPECT_GT(count.tension + count.shear, 0u);
  EXPECT_GT(count.intact, 0u);
}

TEST(SimBondPass, TheThreadedPassGivesTheSerialPassBits2D) {
  for (unsigned seed : {1u, 2u}) checkAgainstTheSerialPass<2>(seed);
}

TEST(SimBondPass, TheThreadedPassGivesTheSerialPassBits3D) {
  for (unsigned seed : {1u, 2u}) checkAgainstTheSerialPass<3>(seed);
}

}  // namespace sim_bond_pass_test
}  // namespace demlab::sim
