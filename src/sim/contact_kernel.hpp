// SIMD kernels of the 3D step: the grain-grain contact pass of Hertz-Mindlin beds over
// structure-of-arrays batches (several contacts per register, 2 with SSE2, 4 with AVX2 or
// AVX-512, instead of one 3-vector per register), and the rotation update, the drift and the
// kick over several grains per register. BallContactModule (contacts.hpp) calls the contact
// pass for the scenes it covers (3D, every pair Hertz-Mindlin), the integrator modules
// (integrator.hpp) the others for every 3D scene; 2D scenes and the other laws keep the
// Eigen loops.
//
// One source (contact_kernel_impl.hpp), compiled once per instruction set in its own
// translation unit (contact_kernel_sse2.cpp: baseline x86-64; contact_kernel_avx2.cpp with
// -mavx2; contact_kernel_avx512.cpp with -mavx512f/dq/vl; all with -mno-fma and
// -ffp-contract=off). The best one the CPU supports is chosen once, at the first call of
// activeIsa() (__builtin_cpu_supports); the build itself targets any x86-64. Every lane does the
// Eigen loop's operations in the Eigen loop's order (IEEE add, sub, mul, div and sqrt are
// correctly rounded on every path, and nothing is fused), and the forces, torques, springs and
// energy sums are accumulated contact by contact in candidate order: every kernel gives the
// Eigen loop's bits (sim_kernel_test.cpp checks each against the Eigen loops on random
// batches and grains, and through whole runs).
//
// This header holds only plain types (no Eigen): the kernels' translation units are compiled
// for other instruction sets and must not emit inline functions the rest of the build shares.
#pragma once

#include <cstddef>
#include <cstdint>

namespace demlab::sim::kernel {

// The Hertz-Mindlin constants of one material pair (physics::PairParams's hertz fields).
struct HertzPair {
  double kn, kt, gammaN, gammaT, friction;
};

// The doubles of one spring's slot: the spring, its drift velocity, the damper's last impulse
// and the part of its loss still owed (physics::TangentialHistory<3>).
constexpr size_t kSpringStride = 8;

// The grain-pair springs (sim/pair_springs.hpp owns them): candidate k's spring is the 3
// doubles at data + kSpringStride slotOf[k] (its drift the 3 after), or zero when slotOf[k] is
// kNoSlot. A kernel gives a slot back
// when its pair stops touching (release) and asks for a zeroed one when a pair without one
// touches (acquire, which returns data, moved if the pool grew): both go through the owner,
// once per pair that starts or stops touching.
struct SpringSlots {
  static constexpr uint32_t kNoSlot = 0xffffffffu;
  uint32_t* slotOf = nullptr;
  // The candidates a pass sees start at this one of the owner's (a group of the threaded
  // pass): slotOf already points there; acquire and release take the owner's numbering.
  size_t base = 0;
  double* data = nullptr;
  void* owner = nullptr;
  double* (*acquire)(void* owner, size_t k) = nullptr;
  void (*release)(void* owner, size_t k) = nullptr;
};

// A periodic cell (sim/periodic.hpp, PeriodicBox::nearest): the lengths of the periodic axes
// (0 for the others) and the Lees-Edwards shear (speed 0: none). The pass reduces each pair's
// vector to the nearest image and, through the sliding boundary, shifts the other's velocity
// by -n speed along the flow axis, with PeriodicBox's arithmetic.
struct PeriodicCell {
  double length[3] = {0, 0, 0};
  double speed = 0, offset = 0;
  int flow = 0, gradient = 1;
};

// One grain-grain contact pass: what BallContactModule<3, HertzMindlin, ...>::pass reads and
// writes, as plain arrays (3-vectors as 3 consecutive doubles).
struct HertzPassArgs {
  // Grains (dense order). w and t are read and written only with rotation.
  const double* x = nullptr;
  const double* v = nullptr;
  const double* w = nullptr;
  double* f = nullptr;
  double* t = nullptr;
  const double* r = nullptr;
  const double* invMass = nullptr;
  const uint32_t* material = nullptr;
  // Candidate pairs, (i, j) per pair, i the lower global id.
  const uint32_t* cand = nullptr;
  size_t nCand = 0;
  // With history: the candidates' tangential springs.
  SpringSlots* springs = nullptr;
  // The material pair constants: pairs[material[i] * nMat + material[j]], or pairs[0] for every
  // contact when onePair.
  const HertzPair* pairs = nullptr;
  size_t nMat = 0;
  bool onePair = true;
  double dt = 0;
  double lag = 0;                // physics::ContactKinematics::velocityLag
  bool springCriterion = false;  // physics::CoulombCriterion::Spring (else Total)
  // Prefetching, for beds whose grain arrays outgrow the caches: 1, the positions of the
  // candidates further on; 2, also the velocities, spins, forces and torques of the candidates
  // in hand (worth it where most candidates touch).
  int prefetch = 0;
  // When not null, record is called with the contacts in candidate order, a few hundred at a
  // time: cand[c] the candidate index of contact c, force[3 c ...] the force on B.
  void (*record)(void* context, const uint32_t* cand, const double* force, size_t n) = nullptr;
  void* recordContext = nullptr;
  // A periodic scene's cell, else null.
  const PeriodicCell* periodic = nullptr;
  // When not null, one byte per candidate (Scene::touchNow): kTouching and kCutOff below.
  uint8_t* touchState = nullptr;
  // When > 0, the pass keeps its deepest contact as the watchdog measures it (sim/contacts.hpp,
  // recordOverlapRatio): of the contacts whose overlap exceeds deepLimit of the smaller radius,
  // the first of the largest ratio in candidate order, in and out as deepRatio (above the
  // ratio given: -1 for none) and deepCand (its candidate, of this pass's numbering).
  double deepLimit = 0;
  double deepRatio = -1;
  size_t deepCand = 0;
  // Out: the number of contacts; in and out: the energy sums, added contact by contact.
  size_t contacts = 0;
  double elastic = 0, damping = 0, friction = 0, springWork = 0;
};

using HertzPassFn = void (*)(HertzPassArgs&);

// HertzPassArgs::touchState's bits (Scene::touchNow).
constexpr uint8_t kTouching = 1;  // the pair's distance is below its reach
constexpr uint8_t kCutOff = 2;    // touching, and the law clamped the normal force to zero

// The contacts of one static wall with grains (WallContactModule, contacts.hpp), Hertz-Mindlin,
// in the order of the wall's candidates: the narrow phase's geometry given, the law and the
// forces on the grains, the torques, the wall's force, the springs and the energy sums.
struct WallPassArgs {
  const double* x = nullptr;
  const double* v = nullptr;
  const double* w = nullptr;  // with rotation
  double* f = nullptr;
  double* t = nullptr;  // with rotation
  const double* r = nullptr;
  const double* invMass = nullptr;
  const uint32_t* material = nullptr;
  // Contact c: geometry[7 c ...] = physics::ContactGeometry<3> (normal, overlap, point), grain
  // grain[c], spring springs[kSpringStride slot[c] ...] and its drift the 3 after (with
  // history).
  const double* geometry = nullptr;
  const uint32_t* grain = nullptr;
  const uint32_t* slot = nullptr;
  double* springs = nullptr;
  size_t n = 0;
  // The constants of the pair (grain material m, this wall): pairs[m], or pairs[0] for every
  // grain when onePair.
  const HertzPair* pairs = nullptr;
  bool onePair = true;
  double dt = 0;
  double lag = 0;
  bool springCriterion = false;
  // When not null, cutOff[c] is set to 1 where the law clamped contact c's normal force to
  // zero (the caller zeroes it).
  uint8_t* cutOff = nullptr;
  // As HertzPassArgs::record; cand[c] is the contact's index (0 .. n - 1).
  void (*record)(void* context, const uint32_t* cand, const double* force, size_t n) = nullptr;
  void* recordContext = nullptr;
  // In and out: the wall's force (+= the force on the wall), the energy sums.
  double wallForce[3] = {0, 0, 0};
  double elastic = 0, damping = 0, friction = 0, springWork = 0;
};

using WallPassFn = void (*)(WallPassArgs&);

// The rotation update of 3D grains (PredictRotationModule, integrator.hpp) over grains
// 0 .. n - 1, W at a time: alpha = t invInertia, wHalf = w + dt/2 alpha, q advanced by
// advance(q, wHalf, dt) unless wHalf is zero, w = wHalf (+ dt/2 alpha when sync), tPrev = t,
// t = 0 (an idle grain's update leaves the same bits as the module's shortcut).
struct RotationArgs {
  double* q = nullptr;  // 4 per grain: Eigen's coefficient order x, y, z, w
  double* w = nullptr;
  double* t = nullptr;
  double* tPrev = nullptr;
  const double* invInertia = nullptr;
  size_t n = 0;
  double dt = 0;
  bool sync = true;
  // A grain that turns by |w dt|^2 >= 1e-4 in the step keeps its q; turn(context, i, wHalf)
  // must then set q[i] = advance(q[i], wHalf, dt) (the exact map: sin, cos, sqrt).
  void (*turn)(void* context, size_t i, const double* wHalf) = nullptr;
  void* turnContext = nullptr;
  size_t done = 0;  // out: grains 0 .. done - 1 are updated; the caller updates the rest
};

using RotationPassFn = void (*)(RotationArgs&);

// The translational drift of 3D grains (PredictModule, integrator.hpp): acc = f invMass,
// vHalf = v + dt/2 acc, x += dt vHalf, v = vHalf (+ dt/2 acc when sync), fPrev = f, f = 0,
// and maxDisp2 = max(maxDisp2, |x - x0|^2), times weight[i] when weight is not null, when x0
// is not null.
struct PredictArgs {
  double* x = nullptr;
  double* v = nullptr;
  double* f = nullptr;
  double* fPrev = nullptr;
  const double* invMass = nullptr;
  const double* x0 = nullptr;
  const double* weight = nullptr;
  size_t n = 0;
  double dt = 0;
  bool sync = true;
  double maxDisp2 = 0;  // in and out
  size_t done = 0;      // out: grains 0 .. done - 1 are updated; the caller updates the rest
};

// The second kick (CorrectModule): v += (h invMass) (f - fPrev) when sync, else
// v += (h invMass) f; the same for w, t, tPrev, invInertia when w is not null.
struct CorrectArgs {
  double* v = nullptr;
  const double* f = nullptr;
  const double* fPrev = nullptr;
  const double* invMass = nullptr;
  double* w = nullptr;
  const double* t = nullptr;
  const double* tPrev = nullptr;
  const double* invInertia = nullptr;
  size_t n = 0;
  double h = 0;
  bool sync = true;
  size_t done = 0;  // out, as PredictArgs::done
};

using PredictPassFn = void (*)(PredictArgs&);
using CorrectPassFn = void (*)(CorrectArgs&);

// One instruction set's kernels, as its file (contact_kernel_{sse2,avx2,avx512}.cpp) hands
// them to the dispatch below: one row of contact_kernel.cpp's table.
struct IsaPasses {
  HertzPassFn (*hertz)(bool history, bool rotation);
  WallPassFn (*wall)(bool history, bool rotation);
  RotationPassFn rotation;
  PredictPassFn predict;
  CorrectPassFn correct;
};

enum class Isa : uint8_t { Sse2, Avx2, Avx512 };

// Returns the kernel's name as the benchmarks print it: "sse2", "avx2", "avx512".
const char* isaName(Isa isa);

// Returns true if this build has the kernel of `isa` and the CPU runs it. Changes nothing.
bool supported(Isa isa);

// Returns the kernel for isa, history (tangential springs) and rotation (torques, angular
// velocities), or nullptr if !supported(isa).
HertzPassFn hertzPass(Isa isa, bool history, bool rotation);

// Returns the wall kernel for isa, history and rotation, or nullptr if !supported(isa).
WallPassFn wallPass(Isa isa, bool history, bool rotation);

// Returns the rotation update for isa, or nullptr if !supported(isa).
RotationPassFn rotationPass(Isa isa);

// Returns the integrator's passes for isa, or nullptr if !supported(isa).
PredictPassFn predictPass(Isa isa);
CorrectPassFn correctPass(Isa isa);

// Returns true and sets *isa to the instruction set the contact modules use: the widest one
// supported, chosen at the first call, unless $DEMLAB_KERNEL names another ("sse2", "avx2",
// "avx512", or "eigen" for none: the Eigen loop). Returns false when no kernel is used
// (not x86-64, or "eigen"). A test may change the choice with setActive.
bool activeIsa(Isa* isa);

// Sets the kernel activeIsa returns (use = false: none, the Eigen loop), for tests and
// benchmarks; returns false, changing nothing, if use and !supported(isa).
bool setActive(bool use, Isa isa);

}  // namespace demlab::sim::kernel
