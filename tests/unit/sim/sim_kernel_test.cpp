// The SIMD kernels (sim/contact_kernel.hpp: the grain contact pass, the rotation update, the
// drift and the kick) against the Eigen loops they replace: every kernel
// the CPU runs (SSE2, the portable x86-64 one, always; AVX2 and AVX-512 where present) must
// give the Eigen loop's bits on the same random contact batches and grains, and whole runs the
// same state digest.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "sim/contact_kernel.hpp"
#include "sim/contacts.hpp"
#include "sim/integrator.hpp"
#include "sim/scene.hpp"
#include "sim/watchdog.hpp"
#include "sim_test_util.hpp"

namespace demlab::sim {
namespace sim_kernel_test {

using testing::material;

constexpr int kHertz = static_cast<int>(physics::LawKind::HertzMindlin);

// The kernels to compare with the Eigen loop: those this CPU runs.
std::vector<kernel::Isa> kernels() {
  std::vector<kernel::Isa> out;
  for (kernel::Isa isa : {kernel::Isa::Sse2, kernel::Isa::Avx2, kernel::Isa::Avx512}) {
    if (kernel::supported(isa)) out.push_back(isa);
  }
  return out;
}

using testing::KernelChoice;

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}
bool sameBits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

struct BatchOptions {
  bool mixed = false;   // three materials, one pair of them frictionless; else one material
  bool spring = false;  // the Coulomb criterion (else Total)
  bool verlet = false;  // half-step velocities (a velocity lag)
  unsigned seed = 1;
  // No springs yet: every contact takes a slot from an empty pool, which grows (and moves)
  // in the middle of the pass.
  bool fresh = false;
};

// A random contact batch: grains packed closely enough that about half of the candidate pairs
// touch, random velocities and spins (some grains still), springs of every size (zero, within
// the Coulomb limit, far beyond it), two grains on one point, a few pairs listed twice.
Scene<3> randomBatch(const BatchOptions& o) {
  Scene<3> s;
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u(0, 1);
  const int nMat = o.mixed ? 3 : 1;
  for (int m = 0; m < nMat; ++m) {
    s.materials.push_back(material(1e7 * (1 + m), 0.3 + 0.2 * m, m == 2 ? 0.0 : 0.5 - 0.2 * m));
  }
  const auto coulomb =
      o.spring ? physics::CoulombCriterion::Spring : physics::CoulombCriterion::Total;
  s.coulomb = coulomb;
  for (int m = 0; m < nMat; ++m) {
    for (int k = 0; k < nMat; ++k) {
      physics::PairParams p =
          physics::mixPair(physics::LawKind::HertzMindlin, s.materials[m], s.materials[k]);
      p.coulomb = coulomb;
      s.pairParams.push_back(p);
      s.pairLawFn.push_back(physics::contactLawFor<3>(physics::LawKind::HertzMindlin));
    }
  }
  s.integrator = o.verlet ? IntegratorKind::Verlet : IntegratorKind::Synchronized;
  s.stepDt = 2e-6;
  s.keepHistory = true;
  const int n = 260;
  const double r0 = 1e-3, side = 0.0085;
  for (int i = 0; i < n; ++i) {
    Vec3 x(side * u(rng), side * u(rng), side * u(rng));
    if (i == 1) x = s.elements.a.x[0];  // coincident centres
    const double r = r0 * (0.7 + 0.6 * u(rng));
    const double mass = 2500 * 4.0 / 3.0 * std::numbers::pi * r * r * r;
    Vec3 v(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    Vec3 w = 200 * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
    if (i % 7 == 3) v.setZero();
    if (i % 5 == 2) w.setZero();
    s.elements.a.push(x, 0.3 * v, w, r, 1 / mass, 1 / (0.4 * mass * r * r),
                    static_cast<uint32_t>(i % nMat), static_cast<uint32_t>(i));
  }
  // Nonzero forces and torques to add to.
  for (int i = 0; i < n; ++i) {
    s.elements.a.f[i] = Vec3(u(rng), u(rng), u(rng)) * 1e-3;
    s.elements.a.t[i] = Vec3(u(rng), u(rng), u(rng)) * 1e-7;
  }
  const ElementArrays<3>& a = s.elements.a;
  for (uint32_t i = 0; i < static_cast<uint32_t>(n); ++i) {
    for (uint32_t j = i + 1; j < static_cast<uint32_t>(n); ++j) {
      const double reach = 1.15 * (a.r[i] + a.r[j]);
      if ((a.x[j] - a.x[i]).squaredNorm() < reach * reach) s.candidates.push_back({i, j});
    }
  }
  // A few pairs twice (the same grain in neighbouring lanes).
  for (size_t k = 0; k < 12 && k < s.candidates.size(); ++k)
    s.candidates.push_back(s.candidates[3 * k]);
  s.pairSprings.reset(s.candidates.size(), true);
  // Their drift velocities (which the synchronized integrator's springs follow) unknown for
  // the shortest springs (NaN: a scene saved without them), of the contacts' size for the
  // others.
  for (size_t k = 0; k < s.candidates.size() && !o.fresh; ++k) {
    const int kind = static_cast<int>(k % 4);
    if (kind > 0) {
      const double len = kind == 1 ? 1e-9 : kind == 2 ? 1e-7 : 1e-4;
      const Vec3 spring = len * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      if (kind == 1) {
        s.pairSprings.set(k, spring);
      } else {
        s.pairSprings.set(k, physics::TangentialHistory<3>{
                                 spring, 0.6 * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)});
      }
    }
  }
  s.recordContacts = true;
  // Odd seeds keep the candidates' touch states (the touch correction's).
  s.touchCorrection = o.seed % 2 == 1;
  return s;
}

// Runs one grain contact pass of the batch, through the Eigen loop (use = false) or isa.
template <bool History, bool Rotation>
Scene<3> contactPass(const BatchOptions& o, bool use, kernel::Isa isa) {
  Scene<3> s = randomBatch(o);
  EXPECT_TRUE(kernel::setActive(use, isa));
  const long onePair = o.mixed ? -1 : 0;
  BallContactModule<3, kHertz, History, Rotation> module(onePair);
  module.run(s);
  return s;
}

template <bool History, bool Rotation>
void compareContactPasses(const BatchOptions& o) {
  KernelChoice restore;
  const Scene<3> ref = contactPass<History, Rotation>(o, false, kernel::Isa::Sse2);
  // The batch exercises what it should: contacts, sliding and sticking springs; with touch
  // states, some forces cut off.
  ASSERT_GT(ref.contacts.size(), 100u);
  if (ref.touchCorrection) {
    EXPECT_EQ(ref.touchNow.size(), ref.candidates.size());
    EXPECT_EQ(std::count(ref.touchNow.begin(), ref.touchNow.end(), kernel::kTouching) +
                  std::count(ref.touchNow.begin(), ref.touchNow.end(),
                             kernel::kTouching | kernel::kCutOff),
              static_cast<std::ptrdiff_t>(ref.contacts.size()));
    EXPECT_GT(std::count(ref.touchNow.begin(), ref.touchNow.end(),
                         kernel::kTouching | kernel::kCutOff),
              0);
  }
  if (History && !o.fresh) {
    EXPECT_GT(ref.ledger.frictionLoss, 0);
    EXPECT_GT(ref.ledger.dampingLoss, 0);
  }
  for (kernel::Isa isa : kernels()) {
    SCOPED_TRACE(kernel::isaName(isa));
    const Scene<3> s = contactPass<History, Rotation>(o, true, isa);
    const ElementArrays<3>& a = s.elements.a;
    const ElementArrays<3>& b = ref.elements.a;
    EXPECT_TRUE(sameBits(a.f, b.f));
    EXPECT_TRUE(sameBits(a.t, b.t));
    EXPECT_TRUE(sameBits(s.pairSprings.perCandidate(), ref.pairSprings.perCandidate()));
    EXPECT_EQ(s.touchNow, ref.touchNow);
    // A slot for each contact and none for the others (the pool's count, the spring values
    // aside: a contact's new spring may be zero).
    if (History) {
      EXPECT_EQ(s.pairSprings.live(), ref.contacts.size());
    }
    ASSERT_EQ(s.contacts.size(), ref.contacts.size());
    for (size_t c = 0; c < s.contacts.size(); ++c) {
      EXPECT_EQ(s.contacts[c].a, ref.contacts[c].a);
      EXPECT_EQ(s.contacts[c].b, ref.contacts[c].b);
      EXPECT_FALSE(s.contacts[c].wall);
      EXPECT_EQ(std::memcmp(s.contacts[c].force.data(), ref.contacts[c].force.data(), sizeof(Vec3)),
                0)
          << c;
    }
    EXPECT_TRUE(sameBits(s.ledger.elastic, ref.ledger.elastic));
    EXPECT_TRUE(sameBits(s.ledger.dampingLoss, ref.ledger.dampingLoss));
    EXPECT_TRUE(sameBits(s.ledger.frictionLoss, ref.ledger.frictionLoss));
    EXPECT_TRUE(sameBits(s.ledger.springWork, ref.ledger.springWork));
  }
}

TEST(SimKernel, ContactBatchesMatchTheEigenLoopBitForBit) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    for (int variant = 0; variant < 8; ++variant) {
      const BatchOptions o{(variant & 1) != 0, (variant & 2) != 0, (variant & 4) != 0, seed};
      SCOPED_TRACE("seed " + std::to_string(seed) + " mixed " + std::to_string(o.mixed) +
                   " spring " + std::to_string(o.spring) + " verlet " + std::to_string(o.verlet));
      compareContactPasses<true, true>(o);
      compareContactPasses<true, false>(o);
      compareContactPasses<false, true>(o);
      compareContactPasses<false, false>(o);
    }
    BatchOptions fresh;
    fresh.seed = seed;
    fresh.fresh = true;
    SCOPED_TRACE("fresh pool");
    compareContactPasses<true, true>(fresh);
    compareContactPasses<true, false>(fresh);
  }
}

// Between records the passes keep only the step's deepest contact for the watchdog: the kernels
// find it themselves, as the first of the largest ratio in candidate order. It must be the
// contact the Eigen loop's sink keeps and the one the watchdog finds among a recording run's
// records, at limits that leave many contacts, a few or none above them.
TEST(SimKernel, DeepestContactIsTheWatchdogsOnTheRecords) {
  KernelChoice restore;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    for (double limit : {0.02, 0.2, 0.6, 1.5, 2.0}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + " limit " + std::to_string(limit));
      BatchOptions o;
      o.seed = seed;
      o.mixed = seed == 2;
      Scene<3> recorded = randomBatch(o);
      recorded.watchdog.overlap = limit;
      ASSERT_TRUE(kernel::setActive(false, kernel::Isa::Sse2));
      BallContactModule<3, kHertz, true, true>(o.mixed ? -1 : 0).run(recorded);
      const auto [worst, ratio] = deepestRecord<false>(recorded, limit);
      if (limit < 1) {
        ASSERT_NE(worst, nullptr);  // the batch overlaps deeply enough
      }
      auto tracked = [&](bool use, kernel::Isa isa) {
        Scene<3> s = randomBatch(o);
        s.watchdog.overlap = limit;
        s.recordContacts = false;
        s.trackDeepest = true;
        EXPECT_TRUE(kernel::setActive(use, isa));
        BallContactModule<3, kHertz, true, true>(o.mixed ? -1 : 0).run(s);
        EXPECT_TRUE(s.contacts.empty());
        return s.deepest;
      };
      std::vector<std::pair<std::string, DeepestContact<3>>> runs{
          {"eigen", tracked(false, kernel::Isa::Sse2)}};
      for (kernel::Isa isa : kernels()) runs.emplace_back(kernel::isaName(isa), tracked(true, isa));
      for (const auto& [name, d] : runs) {
        SCOPED_TRACE(name);
        if (worst == nullptr) {
          EXPECT_EQ(d.ratio, -1);
          continue;
        }
        EXPECT_TRUE(sameBits(d.ratio, ratio));
        EXPECT_EQ(d.record.a, worst->a);
        EXPECT_EQ(d.record.b, worst->b);
        EXPECT_FALSE(d.record.wall);
      }
    }
  }
}

// Random grains for the rotation update: unit quaternions, torques and spins of every size
// (a few turning by more than the series covers), idle grains, -0 components; n not a
// multiple of any lane count.
Scene<3> randomSpins(unsigned seed, bool verlet) {
  Scene<3> s;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  s.stepDt = 1e-5;
  s.integrator = verlet ? IntegratorKind::Verlet : IntegratorKind::Synchronized;
  const int n = 203;
  for (int i = 0; i < n; ++i) {
    Vec3 w = 300 * Vec3(u(rng), u(rng), u(rng));
    if (i % 9 == 4) w *= 1000;  // |w dt|^2 beyond the series
    if (i % 6 == 1) w.setZero();
    if (i % 11 == 5) w = Vec3(-0.0, 0.0, -0.0);
    s.elements.a.push(Vec3::Zero(), Vec3::Zero(), w, 1e-3, 1e3, 1e9 * (1 + 0.5 * u(rng)), 0,
                    static_cast<uint32_t>(i));
    Quat q(u(rng), u(rng), u(rng), u(rng));
    q.normalize();
    s.elements.a.q[i] = q;
    s.elements.a.t[i] = i % 4 == 2 ? Vec3(Vec3::Zero()) : Vec3(1e-6 * Vec3(u(rng), u(rng), u(rng)));
    s.elements.a.tPrev[i] = i % 3 == 0 ? Vec3(Vec3::Zero()) : Vec3(u(rng), u(rng), u(rng));
    // A run of idle grains (whole registers of them), some with a last torque.
    if (i >= 120 && i < 160) {
      s.elements.a.w[i].setZero();
      s.elements.a.t[i].setZero();
      if (i >= 136) s.elements.a.tPrev[i].setZero();
    }
  }
  return s;
}

TEST(SimKernel, RotationUpdateMatchesTheEigenLoopBitForBit) {
  KernelChoice restore;
  for (unsigned seed = 1; seed <= 4; ++seed) {
    for (bool verlet : {false, true}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + " verlet " + std::to_string(verlet));
      ASSERT_TRUE(kernel::setActive(false, kernel::Isa::Sse2));
      Scene<3> ref = randomSpins(seed, verlet);
      PredictRotationModule<3>().run(ref);
      for (kernel::Isa isa : kernels()) {
        SCOPED_TRACE(kernel::isaName(isa));
        ASSERT_TRUE(kernel::setActive(true, isa));
        Scene<3> s = randomSpins(seed, verlet);
        PredictRotationModule<3>().run(s);
        EXPECT_TRUE(sameBits(s.elements.a.q, ref.elements.a.q));
        EXPECT_TRUE(sameBits(s.elements.a.w, ref.elements.a.w));
        EXPECT_TRUE(sameBits(s.elements.a.t, ref.elements.a.t));
        EXPECT_TRUE(sameBits(s.elements.a.tPrev, ref.elements.a.tPrev));
      }
    }
  }
}

// Random grains for the translational drift and kick: forces, velocities, masses; positions
// at the last search for the skin's bookkeeping (or none), some grains far from theirs.
Scene<3> randomGrains(unsigned seed, bool verlet, bool track, bool rotating) {
  Scene<3> s;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  s.stepDt = 1e-5;
  s.integrator = verlet ? IntegratorKind::Verlet : IntegratorKind::Synchronized;
  s.rotating = rotating;
  s.maxDisp2 = 1e-12;
  const int n = 205;
  for (int i = 0; i < n; ++i) {
    s.elements.a.push(Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)),
                    Vec3(u(rng), u(rng), u(rng)) * 100, 1e-3, 1e3 * (1 + 0.5 * u(rng)),
                    1e9 * (1 + 0.5 * u(rng)), 0, static_cast<uint32_t>(i));
    s.elements.a.f[i] = Vec3(u(rng), u(rng), u(rng)) * 1e-3;
    s.elements.a.fPrev[i] = Vec3(u(rng), u(rng), u(rng)) * 1e-3;
    s.elements.a.t[i] = Vec3(u(rng), u(rng), u(rng)) * 1e-7;
    s.elements.a.tPrev[i] = Vec3(u(rng), u(rng), u(rng)) * 1e-7;
    if (track) {
      s.xAtBuild.push_back(s.elements.a.x[i] +
                           Vec3(u(rng), u(rng), u(rng)) * (i % 17 == 3 ? 1e-3 : 1e-6));
    }
  }
  return s;
}

TEST(SimKernel, IntegratorMatchesTheEigenLoopBitForBit) {
  KernelChoice restore;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    for (int variant = 0; variant < 8; ++variant) {
      const bool verlet = (variant & 1) != 0, track = (variant & 2) != 0,
                 rotating = (variant & 4) != 0;
      SCOPED_TRACE("seed " + std::to_string(seed) + " variant " + std::to_string(variant));
      ASSERT_TRUE(kernel::setActive(false, kernel::Isa::Sse2));
      Scene<3> ref = randomGrains(seed, verlet, track, rotating);
      PredictModule<3>().run(ref);
      // (The kick after a drift: the forces are those the drift left, and new ones.)
      for (size_t i = 0; i < ref.elements.a.size(); ++i)
        ref.elements.a.f[i] = ref.elements.a.fPrev[i] * 0.75;
      CorrectModule<3>().run(ref);
      for (kernel::Isa isa : kernels()) {
        SCOPED_TRACE(kernel::isaName(isa));
        ASSERT_TRUE(kernel::setActive(true, isa));
        Scene<3> s = randomGrains(seed, verlet, track, rotating);
        PredictModule<3>().run(s);
        EXPECT_TRUE(sameBits(s.maxDisp2, ref.maxDisp2));
        for (size_t i = 0; i < s.elements.a.size(); ++i) s.elements.a.f[i] = s.elements.a.fPrev[i] * 0.75;
        CorrectModule<3>().run(s);
        EXPECT_TRUE(sameBits(s.elements.a.x, ref.elements.a.x));
        EXPECT_TRUE(sameBits(s.elements.a.v, ref.elements.a.v));
        EXPECT_TRUE(sameBits(s.elements.a.w, ref.elements.a.w));
        EXPECT_TRUE(sameBits(s.elements.a.f, ref.elements.a.f));
        EXPECT_TRUE(sameBits(s.elements.a.fPrev, ref.elements.a.fPrev));
      }
    }
  }
}

// A small polydisperse bed of two materials in a box, started from an overlapping jittered
// lattice (every grain touches its neighbours from the first step) and settling under gravity.
std::unique_ptr<Simulation> settlingBed(bool spring, bool verlet, bool rotation) {
  auto s = makeSimulation(3);
  s->addMaterial("glass", material(1e7, 0.5, 0.5));
  s->addMaterial("steel", material(3e7, 0.7, 0.3));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  // The outer layers overlap the walls too.
  const int perAxis = 7;
  const double pitch = 1.8e-3, side = (perAxis - 0.1) * pitch;
  std::vector<ElementDef> grains;
  for (int k = 0; k < perAxis * perAxis * perAxis; ++k) {
    const Vec3d x{pitch * (0.45 + k % perAxis) + 1e-5 * u(rng),
                  pitch * (0.45 + k / perAxis % perAxis) + 1e-5 * u(rng),
                  pitch * (0.45 + k / perAxis / perAxis) + 1e-5 * u(rng)};
    const double r = 1e-3 * (0.9 + 0.12 * std::fmod(0.6180339887 * k, 1.0));
    grains.push_back(testing::grain(x, r, k % 3 == 0 ? "steel" : "glass",
                                    {0.2 * u(rng), 0.2 * u(rng), 0.2 * u(rng)}));
  }
  s->addElements(grains);
  testing::addBox(*s, side, "glass");
  s->addGravity({0, -9.81, 0});
  s->setAutoTimeStep(0.2);
  if (spring) s->setCoulombCriterion(physics::CoulombCriterion::Spring);
  if (verlet) s->setOption("integrator", "name", "verlet");
  s->setOption("rotation", "on", rotation);
  return s;
}

TEST(SimKernel, RunsGiveTheEigenLoopsDigest) {
  KernelChoice restore;
  for (int variant = 0; variant < 3; ++variant) {
    const bool spring = variant == 1, verlet = variant == 2, rotation = variant != 2;
    SCOPED_TRACE("variant " + std::to_string(variant));
    ASSERT_TRUE(kernel::setActive(false, kernel::Isa::Sse2));
    auto ref = settlingBed(spring, verlet, rotation);
    std::vector<uint64_t> digests;
    size_t contacts = 0, wallContacts = 0;
    for (int stretch = 0; stretch < 3; ++stretch) {
      ref->runSteps(300);
      digests.push_back(ref->stateDigest());
      for (const ContactInfo& c : ref->contacts()) (c.wall.isNull() ? contacts : wallContacts) += 1;
    }
    // The kernels ran on grain and wall contacts at every step.
    EXPECT_GT(contacts, 150u);
    EXPECT_GT(wallContacts, 50u);
    for (kernel::Isa isa : kernels()) {
      SCOPED_TRACE(kernel::isaName(isa));
      ASSERT_TRUE(kernel::setActive(true, isa));
      auto s = settlingBed(spring, verlet, rotation);
      for (int stretch = 0; stretch < 3; ++stretch) {
        s->runSteps(300);
        EXPECT_EQ(s->stateDigest(), digests[stretch]) << "after " << 300 * (stretch + 1);
      }
    }
  }
}

TEST(SimKernel, ChoiceAndNames) {
  KernelChoice restore;
#if defined(__x86_64__)
  EXPECT_TRUE(kernel::supported(kernel::Isa::Sse2));
#endif
  EXPECT_STREQ(kernel::isaName(kernel::Isa::Sse2), "sse2");
  EXPECT_STREQ(kernel::isaName(kernel::Isa::Avx2), "avx2");
  EXPECT_STREQ(kernel::isaName(kernel::Isa::Avx512), "avx512");
  for (kernel::Isa isa : {kernel::Isa::Sse2, kernel::Isa::Avx2, kernel::Isa::Avx512}) {
    EXPECT_EQ(kernel::setActive(true, isa), kernel::supported(isa));
    EXPECT_EQ(kernel::hertzPass(isa, true, true) != nullptr, kernel::supported(isa));
    EXPECT_EQ(kernel::rotationPass(isa) != nullptr, kernel::supported(isa));
  }
  ASSERT_TRUE(kernel::setActive(false, kernel::Isa::Avx2));
  kernel::Isa isa;
  EXPECT_FALSE(kernel::activeIsa(&isa));
}

}  // namespace sim_kernel_test
}  // namespace demlab::sim
