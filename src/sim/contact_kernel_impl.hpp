// The body of the SIMD kernels (contact_kernel.hpp), written once over a lane count W (2 or 4
// doubles per register). Included by contact_kernel_sse2.cpp,
// contact_kernel_avx2.cpp and contact_kernel_avx512.cpp only, each inside its own namespace
// (DEMLAB_KERNEL_NS), so no function here is shared between translation units compiled for
// different instruction sets. Nothing from Eigen or the standard library's templates.
//
// The arithmetic is BallContactModule::pass's (contacts.hpp) and hertzMindlinContactWith's
// with coulombSpringStep<Project> (law_hertz_mindlin.hpp, tangential.hpp), operation by
// operation, each lane one contact; the law's branches become selects (both sides computed,
// one kept, which changes no bit of the kept side), except three that are rarely taken and
// test the whole register: coincident centres, sliding contacts (a sqrt and a division) and
// the half-step velocity lag (a division).
//
// Per batch of kBatch candidates:
//  1. W candidates at a time, the touching ones (|x_j - x_i|^2 < (r_i + r_j)^2) are listed
//     without a branch; with history, a pair that stopped touching gives its spring's slot
//     back, one that started gets one (sim/pair_springs.hpp; both rare, one test per W).
//  2. W touching contacts at a time (one per lane), their grains' positions, velocities, radii
//     and inverse masses gathered into registers: the geometry, the law's roots, the lever arms
//     and the relative velocity, stored by lanes into the batch's structure-of-arrays buffer.
//  3. W contacts at a time from the buffer, and their springs: the law; then the forces and
//     torques added to the grains, the springs and records stored and the energies summed lane
//     by lane in candidate order (so two lanes that share a grain add in the Eigen loop's
//     order). Stages 2 and 3 apart need fewer registers each than in one (16 with AVX2).
// The touching candidates fewer than W left at the end of a batch wait for the next; the last
// group of the pass repeats its last contact in the lanes it lacks, which are then dropped.
//
// Further on: the static walls' contacts (the narrow phase's geometry given, the same law),
// and the rotation update, the drift and the kick over W grains at a time.
#include <immintrin.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "sim/contact_kernel.hpp"

#ifndef DEMLAB_KERNEL_NS
#error "define DEMLAB_KERNEL_NS before including contact_kernel_impl.hpp"
#endif

namespace demlab::sim::kernel::DEMLAB_KERNEL_NS {

template <int W>
struct VT;
template <>
struct VT<2> {
  typedef double d __attribute__((vector_size(16)));
  typedef long long m __attribute__((vector_size(16)));
};
template <>
struct VT<4> {
  typedef double d __attribute__((vector_size(32)));
  typedef long long m __attribute__((vector_size(32)));
};
template <int W>
using vd = typename VT<W>::d;  // W doubles
template <int W>
using vm = typename VT<W>::m;  // W lane masks (all ones or zero)

#define DEMLAB_KI [[gnu::always_inline]] inline

template <int W>
DEMLAB_KI vd<W> splat(double s) {
  vd<W> v;
  for (int l = 0; l < W; ++l) v[l] = s;
  return v;
}

template <int W>
DEMLAB_KI vd<W> vsqrt(vd<W> x) {
  if constexpr (W == 2) {
    return (vd<2>)_mm_sqrt_pd((__m128d)x);
  } else {
    return (vd<4>)_mm256_sqrt_pd((__m256d)x);
  }
}

// Returns bit l set where lane l of m is set.
template <int W>
DEMLAB_KI unsigned bitsOf(vm<W> m) {
  if constexpr (W == 2) {
    return static_cast<unsigned>(_mm_movemask_pd((__m128d)m));
  } else {
    return static_cast<unsigned>(_mm256_movemask_pd((__m256d)m));
  }
}

// Returns true if some bit of m is set.
template <int W>
DEMLAB_KI bool anyBits(vm<W> m) {
  if constexpr (W == 2) {
    const __m128i z = _mm_cmpeq_epi32((__m128i)m, _mm_setzero_si128());
    return _mm_movemask_epi8(z) != 0xffff;
  } else {
    return !_mm256_testz_si256((__m256i)m, (__m256i)m);
  }
}

// ---- lanes from the grain arrays --------------------------------------------------------------

// Returns lane l = p[o[l]].
template <int W>
DEMLAB_KI vd<W> gather1(const double* p, const size_t* o) {
  if constexpr (W == 2) {
    return (vd<2>)_mm_loadh_pd(_mm_load_sd(p + o[0]), p + o[1]);
  } else {
    const __m128d lo = _mm_loadh_pd(_mm_load_sd(p + o[0]), p + o[1]);
    const __m128d hi = _mm_loadh_pd(_mm_load_sd(p + o[2]), p + o[3]);
    return (vd<4>)_mm256_insertf128_pd(_mm256_castpd128_pd256(lo), hi, 1);
  }
}

// The components of W 3-vectors, lane l the vector at p + o[l].
template <int W>
struct V3 {
  vd<W> x, y, z;
};

template <int W>
DEMLAB_KI V3<W> gather3(const double* p, const size_t* o) {
  if constexpr (W == 2) {
    const __m128d a = _mm_loadu_pd(p + o[0]), b = _mm_loadu_pd(p + o[1]);
    return {(vd<2>)_mm_unpacklo_pd(a, b), (vd<2>)_mm_unpackhi_pd(a, b),
            (vd<2>)_mm_loadh_pd(_mm_load_sd(p + o[0] + 2), p + o[1] + 2)};
  } else {
    // a = (x0 y0 x2 y2), b = (x1 y1 x3 y3)
    const __m256d a = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p + o[0])),
                                           _mm_loadu_pd(p + o[2]), 1);
    const __m256d b = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p + o[1])),
                                           _mm_loadu_pd(p + o[3]), 1);
    const __m128d zlo = _mm_loadh_pd(_mm_load_sd(p + o[0] + 2), p + o[1] + 2);
    const __m128d zhi = _mm_loadh_pd(_mm_load_sd(p + o[2] + 2), p + o[3] + 2);
    return {(vd<4>)_mm256_unpacklo_pd(a, b), (vd<4>)_mm256_unpackhi_pd(a, b),
            (vd<4>)_mm256_insertf128_pd(_mm256_castpd128_pd256(zlo), zhi, 1)};
  }
}

// The same W 3-vectors one per lane again: xy[l] = (x_l, y_l), z[l] = (z_l, -).
template <int W>
struct Lanes3 {
  __m128d xy[W], z[W];
};

template <int W>
DEMLAB_KI void split(const V3<W>& v, Lanes3<W>& out) {
  if constexpr (W == 2) {
    const __m128d x = (__m128d)v.x, y = (__m128d)v.y, z = (__m128d)v.z;
    out.xy[0] = _mm_unpacklo_pd(x, y);
    out.xy[1] = _mm_unpackhi_pd(x, y);
    out.z[0] = z;
    out.z[1] = _mm_unpackhi_pd(z, z);
  } else {
    const __m256d x = (__m256d)v.x, y = (__m256d)v.y, z = (__m256d)v.z;
    const __m256d t0 = _mm256_unpacklo_pd(x, y);  // x0 y0 x2 y2
    const __m256d t1 = _mm256_unpackhi_pd(x, y);  // x1 y1 x3 y3
    out.xy[0] = _mm256_castpd256_pd128(t0);
    out.xy[1] = _mm256_castpd256_pd128(t1);
    out.xy[2] = _mm256_extractf128_pd(t0, 1);
    out.xy[3] = _mm256_extractf128_pd(t1, 1);
    const __m128d zlo = _mm256_castpd256_pd128(z), zhi = _mm256_extractf128_pd(z, 1);
    out.z[0] = zlo;
    out.z[1] = _mm_unpackhi_pd(zlo, zlo);
    out.z[2] = zhi;
    out.z[3] = _mm_unpackhi_pd(zhi, zhi);
  }
}

// q[0..2] += lane. (q -= v is q += -v: IEEE 754 defines the difference as that sum, so the
// bits are the same, and the sum takes q from memory in the instruction.)
DEMLAB_KI void add3(double* q, __m128d xy, __m128d z) {
  _mm_storeu_pd(q, _mm_add_pd(_mm_loadu_pd(q), xy));
  q[2] = q[2] + _mm_cvtsd_f64(z);
}
// Returns -v, bit for bit (the sign flipped).
DEMLAB_KI __m128d neg(__m128d v) {
  return _mm_xor_pd(v, _mm_set1_pd(-0.0));
}
DEMLAB_KI void store3(double* q, __m128d xy, __m128d z) {
  _mm_storeu_pd(q, xy);
  _mm_store_sd(q + 2, z);
}

// A contact's slot (kSpringStride doubles, physics::TangentialHistory<3>): the spring and its
// drift velocity (6 doubles), the damper's last impulse and the part of its loss still owed
// (2 doubles); lane l at p + o[l].

// Loads lane l's spring a and drift b: one 256-bit load (sx sy sz dx) and one 128-bit (dy dz).
template <int W>
DEMLAB_KI void loadSpringsAndDrifts(const double* p, const size_t* o, V3<W>& a, V3<W>& b) {
  if constexpr (W == 2) {
    const __m128d xy0 = _mm_loadu_pd(p + o[0]), zx0 = _mm_loadu_pd(p + o[0] + 2),
                  yz0 = _mm_loadu_pd(p + o[0] + 4);
    const __m128d xy1 = _mm_loadu_pd(p + o[1]), zx1 = _mm_loadu_pd(p + o[1] + 2),
                  yz1 = _mm_loadu_pd(p + o[1] + 4);
    a = {(vd<2>)_mm_unpacklo_pd(xy0, xy1), (vd<2>)_mm_unpackhi_pd(xy0, xy1),
         (vd<2>)_mm_unpacklo_pd(zx0, zx1)};
    b = {(vd<2>)_mm_unpackhi_pd(zx0, zx1), (vd<2>)_mm_unpacklo_pd(yz0, yz1),
         (vd<2>)_mm_unpackhi_pd(yz0, yz1)};
  } else {
    const __m256d r0 = _mm256_loadu_pd(p + o[0]), r1 = _mm256_loadu_pd(p + o[1]);
    const __m256d r2 = _mm256_loadu_pd(p + o[2]), r3 = _mm256_loadu_pd(p + o[3]);
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    const __m256d u0 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p + o[0] + 4)),
                                            _mm_loadu_pd(p + o[2] + 4), 1);
    const __m256d u1 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p + o[1] + 4)),
                                            _mm_loadu_pd(p + o[3] + 4), 1);
    a = {(vd<4>)_mm256_permute2f128_pd(t0, t2, 0x20), (vd<4>)_mm256_permute2f128_pd(t1, t3, 0x20),
         (vd<4>)_mm256_permute2f128_pd(t0, t2, 0x31)};
    b = {(vd<4>)_mm256_permute2f128_pd(t1, t3, 0x31), (vd<4>)_mm256_unpacklo_pd(u0, u1),
         (vd<4>)_mm256_unpackhi_pd(u0, u1)};
  }
}

// Stores lane l's whole slot at p + o[l]: spring a, drift b, then the two damper figures c
// and e; as two 256-bit stores a lane (W = 4).
template <int W>
DEMLAB_KI void storeSlots(double* p, const size_t* o, const V3<W>& a, const V3<W>& b, vd<W> c,
                          vd<W> e) {
  if constexpr (W == 2) {
    const __m128d ax = (__m128d)a.x, ay = (__m128d)a.y, az = (__m128d)a.z;
    const __m128d bx = (__m128d)b.x, by = (__m128d)b.y, bz = (__m128d)b.z;
    const __m128d cc = (__m128d)c, ee = (__m128d)e;
    _mm_storeu_pd(p + o[0], _mm_unpacklo_pd(ax, ay));
    _mm_storeu_pd(p + o[0] + 2, _mm_unpacklo_pd(az, bx));
    _mm_storeu_pd(p + o[0] + 4, _mm_unpacklo_pd(by, bz));
    _mm_storeu_pd(p + o[0] + 6, _mm_unpacklo_pd(cc, ee));
    _mm_storeu_pd(p + o[1], _mm_unpackhi_pd(ax, ay));
    _mm_storeu_pd(p + o[1] + 2, _mm_unpackhi_pd(az, bx));
    _mm_storeu_pd(p + o[1] + 4, _mm_unpackhi_pd(by, bz));
    _mm_storeu_pd(p + o[1] + 6, _mm_unpackhi_pd(cc, ee));
  } else {
    const __m256d xy0 = _mm256_unpacklo_pd((__m256d)a.x, (__m256d)a.y);  // lanes 0, 2
    const __m256d xy1 = _mm256_unpackhi_pd((__m256d)a.x, (__m256d)a.y);  // lanes 1, 3
    const __m256d zx0 = _mm256_unpacklo_pd((__m256d)a.z, (__m256d)b.x);
    const __m256d zx1 = _mm256_unpackhi_pd((__m256d)a.z, (__m256d)b.x);
    const __m256d yz0 = _mm256_unpacklo_pd((__m256d)b.y, (__m256d)b.z);
    const __m256d yz1 = _mm256_unpackhi_pd((__m256d)b.y, (__m256d)b.z);
    const __m256d ce0 = _mm256_unpacklo_pd((__m256d)c, (__m256d)e);
    const __m256d ce1 = _mm256_unpackhi_pd((__m256d)c, (__m256d)e);
    _mm256_storeu_pd(p + o[0], _mm256_permute2f128_pd(xy0, zx0, 0x20));
    _mm256_storeu_pd(p + o[2], _mm256_permute2f128_pd(xy0, zx0, 0x31));
    _mm256_storeu_pd(p + o[1], _mm256_permute2f128_pd(xy1, zx1, 0x20));
    _mm256_storeu_pd(p + o[3], _mm256_permute2f128_pd(xy1, zx1, 0x31));
    _mm256_storeu_pd(p + o[0] + 4, _mm256_permute2f128_pd(yz0, ce0, 0x20));
    _mm256_storeu_pd(p + o[2] + 4, _mm256_permute2f128_pd(yz0, ce0, 0x31));
    _mm256_storeu_pd(p + o[1] + 4, _mm256_permute2f128_pd(yz1, ce1, 0x20));
    _mm256_storeu_pd(p + o[3] + 4, _mm256_permute2f128_pd(yz1, ce1, 0x31));
  }
}

// Loads lane l's two doubles at p + o[l] into a and b.
template <int W>
DEMLAB_KI void loadPairs(const double* p, const size_t* o, vd<W>& a, vd<W>& b) {
  if constexpr (W == 2) {
    const __m128d r0 = _mm_loadu_pd(p + o[0]), r1 = _mm_loadu_pd(p + o[1]);
    a = (vd<2>)_mm_unpacklo_pd(r0, r1);
    b = (vd<2>)_mm_unpackhi_pd(r0, r1);
  } else {
    const __m256d u0 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p + o[0])),
                                            _mm_loadu_pd(p + o[2]), 1);
    const __m256d u1 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p + o[1])),
                                            _mm_loadu_pd(p + o[3]), 1);
    a = (vd<4>)_mm256_unpacklo_pd(u0, u1);
    b = (vd<4>)_mm256_unpackhi_pd(u0, u1);
  }
}

// damperCatchUp (tangential.hpp) for the lanes of a law's output lo, with the slots' store:
// returns the damper's loss owed for the last step (from the slots' last two doubles at
// p + o[l] + 6), and stores each lane's slot: the new spring and drift and this step's damper
// figures.
template <int W, class Out>
DEMLAB_KI vd<W> storeHistories(double* p, const size_t* o, const Out& lo, double dt) {
  vd<W> impulse, pending;
  loadPairs<W>(p + 6, o, impulse, pending);
  const vd<W> owed = pending + impulse * (0.5 * lo.vnDrift);
  const vd<W> now = lo.damperForce * dt;
  storeSlots<W>(p, o, lo.sNew, lo.dNew, now, now * (0.5 * lo.vnDrift - lo.vn));
  return owed;
}

template <int W>
DEMLAB_KI vd<W> dot(const V3<W>& a, const V3<W>& b) {
  return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
// Eigen's cross product (core/math.hpp cross): (a1 b2 - a2 b1, a2 b0 - a0 b2, a0 b1 - a1 b0).
template <int W>
DEMLAB_KI V3<W> cross(const V3<W>& a, const V3<W>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <int W>
DEMLAB_KI V3<W> select(vm<W> m, const V3<W>& a, const V3<W>& b) {
  return {m ? a.x : b.x, m ? a.y : b.y, m ? a.z : b.z};
}

// What every stage reads: passed by value into the inlined functions below, so the compiler
// keeps it in registers. (The kernel's loads and stores use the intrinsics' may-alias vector
// types: anything reached through memory would be reloaded after each of them.)
struct Consts {
  const double* x;
  const double* v;
  const double* w;
  double* force;
  double* torque;
  const double* r;
  const double* invMass;
  const uint32_t* material;
  const uint32_t* cand;
  SpringSlots* springs;  // grain pairs with history
  const HertzPair* pairs;
  size_t nMat;
  double dt, lagDt;
  bool lag, total;
  HertzPair one;
  const PeriodicCell* periodic;  // null: not periodic
  uint8_t* touchState;           // null: not kept (HertzPassArgs::touchState)
  double deepLimit;              // HertzPassArgs::deepLimit (0: the deepest is not tracked)
};

// The pass's deepest contact so far (HertzPassArgs::deepRatio, deepCand).
struct Deepest {
  double ratio;
  size_t cand;
};

struct Sums {
  double elastic, damping, friction, springWork;
};

// Returns the energy sums a pass starts from (HertzPassArgs or WallPassArgs).
template <class Args>
Sums sumsOf(const Args& A) {
  return {A.elastic, A.damping, A.friction, A.springWork};
}

// Writes the sums e back into the pass's arguments. Changes A's four sums.
template <class Args>
void storeSums(const Sums& e, Args& A) {
  A.elastic = e.elastic;
  A.damping = e.damping;
  A.friction = e.friction;
  A.springWork = e.springWork;
}

// The records of contacts not yet handed to HertzPassArgs::record.
struct Records {
  static constexpr size_t kSize = 256;
  uint32_t cand[kSize];
  double force[3 * kSize];
};

// Hands the n buffered records to the pass's record callback, if any are buffered, and sets n
// to 0.
template <class Args>
void flushRecords(const Args& A, const Records& records, size_t& n) {
  if (n > 0) A.record(A.recordContext, records.cand, records.force, n);
  n = 0;
}

constexpr size_t kBatch = 128;  // candidates per touch pass
constexpr size_t kAhead = 64;   // how far ahead positions are prefetched (in candidates)

// Stage 2's results, by field and contact (lane) of the batch.
enum Field : int {
  kNx,
  kNy,
  kNz,
  kOverlap,
  kEffMass,
  kEffRadius,
  kA,
  kSqrtAm,
  kVx,
  kVy,
  kVz,
  kArmA,
  kArmB,
  kKn,
  kKt,
  kGn,
  kGt,
  kMu,  // the pair's constants (mixed materials only)
  kFields
};
template <int W>
struct alignas(64) Stage {
  static constexpr size_t kSize = kBatch + W;  // the batch's contacts and those carried over
  double f[kFields][kSize];
  DEMLAB_KI void put(int field, size_t c, vd<W> value) {
    std::memcpy(&f[field][c], &value, sizeof value);
  }
  DEMLAB_KI vd<W> get(int field, size_t c) const {
    vd<W> value;
    std::memcpy(&value, &f[field][c], sizeof value);
    return value;
  }
};

// Returns component k of v.
template <int W>
DEMLAB_KI vd<W>& component(V3<W>& v, int k) {
  return k == 0 ? v.x : (k == 1 ? v.y : v.z);
}

// Returns 1 where x > half, -1 where x < -half, else 0.
template <int W>
DEMLAB_KI vd<W> crossings(vd<W> x, vd<W> half) {
  const vd<W> zero = splat<W>(0.0), one = splat<W>(1.0);
  return ((x > half) ? one : zero) - ((x < -half) ? one : zero);
}
// Returns x less L where above L/2, plus L where below -L/2 (PeriodicBox::wrapOnce).
template <int W>
DEMLAB_KI vd<W> wrapOnce(vd<W> x, double L) {
  const vd<W> half = splat<W>(0.5 * L);
  return x - L * crossings<W>(x, half);
}

// Reduces the lanes' pair vectors d to the nearest image (PeriodicBox::nearest, operation by
// operation); returns the cells crossed along the gradient axis (0 without shear).
template <int W>
DEMLAB_KI vd<W> nearestImage(const PeriodicCell& p, V3<W>& d) {
  vd<W> n = splat<W>(0.0);
  if (p.speed != 0) {
    vd<W>& g = component<W>(d, p.gradient);
    vd<W>& f = component<W>(d, p.flow);
    const double L = p.length[p.gradient];
    n = crossings<W>(g, splat<W>(0.5 * L));
    g -= n * L;
    f -= n * p.offset;
    f = wrapOnce<W>(f, p.length[p.flow]);
  }
  for (int k = 0; k < 3; ++k) {
    if (p.length[k] > 0) component<W>(d, k) = wrapOnce<W>(component<W>(d, k), p.length[k]);
  }
  return n;
}

// The lanes' candidates: k[l] for l < valid, then the last one repeated.
template <int W>
DEMLAB_KI void laneCandidates(const uint32_t* k, size_t valid, size_t* kc) {
  // Every caller has at least one candidate; saying so keeps GCC from warning about k[-1].
  if (valid == 0) __builtin_unreachable();
  for (int l = 0; l < W; ++l) kc[l] = k[static_cast<size_t>(l) < valid ? l : valid - 1];
}

// Stage 2 for the contacts of candidates k[0 .. valid - 1], into stage lanes c ...
template <int W, bool Rotation, bool OnePair>
DEMLAB_KI void geometry(const Consts C, const uint32_t* k, size_t valid, Stage<W>& st, size_t c,
                        Deepest& deep) {
  size_t kc[W], si[W], sj[W], oi[W], oj[W];
  laneCandidates<W>(k, valid, kc);
  for (int l = 0; l < W; ++l) {
    si[l] = C.cand[2 * kc[l]];
    sj[l] = C.cand[2 * kc[l] + 1];
    oi[l] = 3 * si[l];
    oj[l] = 3 * sj[l];
  }
  const vd<W> zero = splat<W>(0.0);
  // The module's inline narrow phase.
  const V3<W> xi = gather3<W>(C.x, oi), xj = gather3<W>(C.x, oj);
  const vd<W> ri = gather1<W>(C.r, si), rj = gather1<W>(C.r, sj);
  V3<W> d{xj.x - xi.x, xj.y - xi.y, xj.z - xi.z};
  vd<W> crossed = zero;
  if (C.periodic != nullptr) [[unlikely]] crossed = nearestImage<W>(*C.periodic, d);
  const vd<W> rs = ri + rj;
  const vd<W> d2 = dot<W>(d, d);
  const vd<W> sumInvMass = gather1<W>(C.invMass, si) + gather1<W>(C.invMass, sj);
  const vd<W> dist = vsqrt<W>(d2);
  const vd<W> srs = sumInvMass * rs;
  const vd<W> q = 1.0 / (dist * srs);
  const vd<W> qs = q * srs;
  V3<W> n{d.x * qs, d.y * qs, d.z * qs};
  vd<W> overlap = rs - dist;
  vd<W> effMass = q * dist * rs;
  vd<W> effRadius = ri * rj * sumInvMass * dist * q;
  const vm<W> apart = d2 > 0.0;
  if (bitsOf<W>(apart) != (1u << W) - 1) [[unlikely]] {
    // Coincident centres: the first axis, as physics::intersect.
    n = select<W>(apart, n, V3<W>{splat<W>(1.0), zero, zero});
    overlap = apart ? overlap : rs;
    effMass = apart ? effMass : 1.0 / sumInvMass;
    effRadius = apart ? effRadius : ri * rj / rs;
  }
  if (C.deepLimit > 0) {
    // The watchdog's measure (recordOverlapRatio, operation by operation): the lanes whose
    // overlap exceeds deepLimit of the smaller radius, in candidate order (rare).
    const vd<W> small = rj < ri ? rj : ri;
    const vd<W> t = rs - C.deepLimit * small;
    unsigned over = bitsOf<W>((t > 0.0) & (d2 < t * t)) & ((1u << valid) - 1);
    if (over != 0) [[unlikely]] {
      double ov[W], sm[W];
      std::memcpy(ov, &overlap, sizeof ov);
      std::memcpy(sm, &small, sizeof sm);
      for (size_t l = 0; l < valid; ++l) {
        if (((over >> l) & 1) == 0) continue;
        const double ratio = ov[l] / sm[l];
        if (ratio > deep.ratio) deep = {ratio, kc[l]};
      }
    }
  }
  // The law's roots (hertzMindlinRoots).
  const vd<W> a = vsqrt<W>(effRadius * overlap);
  st.put(kA, c, a);
  st.put(kSqrtAm, c, vsqrt<W>(a * effMass));
  st.put(kNx, c, n.x);
  st.put(kNy, c, n.y);
  st.put(kNz, c, n.z);
  st.put(kOverlap, c, overlap);
  st.put(kEffMass, c, effMass);
  st.put(kEffRadius, c, effRadius);
  // The relative velocity at the contact.
  const V3<W> vi = gather3<W>(C.v, oi), vj = gather3<W>(C.v, oj);
  V3<W> vrel{vj.x - vi.x, vj.y - vi.y, vj.z - vi.z};
  if (C.periodic != nullptr && C.periodic->speed != 0) [[unlikely]] {
    // Through the sliding boundary the other's image moves with -n U along the flow axis.
    vd<W>& vf = component<W>(vrel, C.periodic->flow);
    vf = crossed != zero ? vf - crossed * C.periodic->speed : vf;
  }
  if constexpr (Rotation) {
    const vd<W> armA = ri - 0.5 * overlap, armB = rj - 0.5 * overlap;
    const V3<W> wi = gather3<W>(C.w, oi), wj = gather3<W>(C.w, oj);
    const V3<W> ws{armA * wi.x + armB * wj.x, armA * wi.y + armB * wj.y, armA * wi.z + armB * wj.z};
    const V3<W> cr = cross<W>(ws, n);
    vrel = V3<W>{vrel.x - cr.x, vrel.y - cr.y, vrel.z - cr.z};
    st.put(kArmA, c, armA);
    st.put(kArmB, c, armB);
  }
  st.put(kVx, c, vrel.x);
  st.put(kVy, c, vrel.y);
  st.put(kVz, c, vrel.z);
  if constexpr (!OnePair) {
    // The pair's constants.
    size_t op[W];
    for (int l = 0; l < W; ++l) {
      op[l] =
          (C.material[si[l]] * C.nMat + C.material[sj[l]]) * (sizeof(HertzPair) / sizeof(double));
    }
    const double* pp = &C.pairs[0].kn;
    st.put(kKn, c, gather1<W>(pp + 0, op));
    st.put(kKt, c, gather1<W>(pp + 1, op));
    st.put(kGn, c, gather1<W>(pp + 2, op));
    st.put(kGt, c, gather1<W>(pp + 3, op));
    st.put(kMu, c, gather1<W>(pp + 4, op));
  }
}

// The law's inputs for W contacts: geometry, roots, kinematics, the spring before the step and
// the pair's constants.
template <int W>
struct LawIn {
  V3<W> n;
  vd<W> overlap, a, sqrtAm, effMass, effRadius;
  V3<W> vrel;
  V3<W> sOld, dOld;  // with history: the spring; Drift: its drift velocity
  vd<W> kn, kt, gammaN, gammaT, mu;
};
// What it gives: the force on B, the step's energies and (with history) the spring after it.
template <int W>
struct LawOut {
  V3<W> F;
  vd<W> damping, elastic, friction, springWork;
  V3<W> sNew;
  // Drift: the drift velocity after the step, its normal part, the damper's force (spring -
  // fn) and the synchronized normal velocity, for damperCatchUp.
  V3<W> dNew;
  vd<W> vnDrift, damperForce, vn;
  vd<W> fn;  // the normal force's magnitude (0: cut off)
};

// hertzMindlinContactWith with driftDisplacement and coulombSpringStep<Project>
// (law_hertz_mindlin.hpp, tangential.hpp), lane by lane. Drift: synchronized velocities (the
// springs' drift velocities are read and written); else half-step ones (C.lag).
template <int W, bool History, bool Drift>
DEMLAB_KI LawOut<W> hertzLaw(const Consts& C, const LawIn<W>& in) {
  const double dt = C.dt;
  const vd<W> zero = splat<W>(0.0);
  LawOut<W> out;
  const V3<W>& n = in.n;
  const vd<W> overlap = in.overlap, a = in.a, sqrtAm = in.sqrtAm;
  const V3<W>& vrel = in.vrel;
  const vd<W> pKn = in.kn, pKt = in.kt, pGn = in.gammaN, pGt = in.gammaT, pMu = in.mu;
  // Normal force (hertzMindlinContactWith).
  const vd<W> kn = pKn * a;
  const vd<W> gn = pGn * sqrtAm;
  const vd<W> vn = dot<W>(vrel, n);
  const vd<W> spring = kn * overlap;
  vd<W> fn = spring - gn * vn;
  fn = fn < 0.0 ? zero : fn;
  vd<W> vForce = vn;
  if constexpr (!Drift) {
    if (C.lag) vForce = vn + C.lagDt * fn / in.effMass;  // (Drift: synchronized, no lag)
  }
  vd<W> damping = (spring - fn) * vForce * dt;
  V3<W> F{fn * n.x, fn * n.y, fn * n.z};
  vd<W> elastic = 0.4 * spring * overlap;
  vd<W> friction = zero;
  vd<W> springWork = zero;
  if constexpr (History) {
    const vm<W> rough = pMu > 0.0;
    const V3<W> vt{vrel.x - vn * n.x, vrel.y - vn * n.y, vrel.z - vn * n.z};
    const vd<W> kt = pKt * a;
    const V3<W> s0 = in.sOld;
    const vd<W> ct = pGt * sqrtAm;
    const vd<W> cap = pMu * fn;
    // advanceDrift and damperCatchUp (every pair with history), driftDisplacement.
    V3<W> u{vt.x * dt, vt.y * dt, vt.z * dt};
    vd<W> vnDrift = vn;
    V3<W> d = vrel;
    if constexpr (Drift) {
      const V3<W>& d0 = in.dOld;
      const vm<W> known = d0.x == d0.x;  // (no drift yet: NaN)
      const double third = 1.0 / 3;
      d = select<W>(known,
                    V3<W>{(2.0 * vrel.x + d0.x) * third, (2.0 * vrel.y + d0.y) * third,
                          (2.0 * vrel.z + d0.z) * third},
                    vrel);
      vnDrift = dot<W>(d, n);
      u = V3<W>{(d.x - vnDrift * n.x) * dt, (d.y - vnDrift * n.y) * dt, (d.z - vnDrift * n.z) * dt};
      if (bitsOf<W>(known) != (1u << W) - 1) [[unlikely]] {
        // A contact's first step: its increment from the touch on (touchingFraction).
        const vd<W> before = overlap + vnDrift * dt;
        const vd<W> one = splat<W>(1.0);
        vd<W> theta = before < 0.0 ? overlap / (overlap - before) : one;
        theta = known ? one : theta;
        u = V3<W>{u.x * theta, u.y * theta, u.z * theta};
      }
    }
    // kt at the overlap before the step's normal displacement.
    const vd<W> reach = overlap + vnDrift * dt;
    const vd<W> kt0 = pKt * vsqrt<W>(in.effRadius * (zero < reach ? reach : zero));
    // coulombSpringStep<Project>.
    V3<W> s{s0.x + u.x, s0.y + u.y, s0.z + u.z};
    const vd<W> sn = dot<W>(s, n);
    s = V3<W>{s.x - sn * n.x, s.y - sn * n.y, s.z - sn * n.z};
    const vd<W> s2 = dot<W>(s, s);
    // What the booking needs of the last spring (it is then dead: fewer live registers).
    const vd<W> s0n = dot<W>(s0, n), s0s = dot<W>(s0, s);
    const vd<W> f2 = kt * kt * s2;
    const vd<W> cap2 = cap * cap;
    const V3<W> stickF{kt * s.x + ct * vt.x, kt * s.y + ct * vt.y, kt * s.z + ct * vt.z};
    const vm<W> slide = f2 > cap2;
    // Sticking: force -= kt s + ct vt; the dashpot's loss; the spring's energy.
    V3<W> Ft{F.x - stickF.x, F.y - stickF.y, F.z - stickF.z};
    vd<W> dampT = damping + ct * dot<W>(vt, vt) * dt;
    vd<W> elT = 0.5 * kt * s2;
    V3<W> sT = s;
    vd<W> r = splat<W>(1.0);  // sT = r s
    if (C.total) {
      // Sliding on a short spring (Total criterion): force -= kt s.
      const vm<W> shortSlide = (f2 <= cap2) & (dot<W>(stickF, stickF) > cap2);
      const V3<W> Fs{F.x - kt * s.x, F.y - kt * s.y, F.z - kt * s.z};
      Ft = select<W>(shortSlide, Fs, Ft);
      dampT = shortSlide ? damping : dampT;
    }
    if (bitsOf<W>(slide) != 0) {
      // Sliding: the spring scaled to the Coulomb limit.
      const vd<W> len = vsqrt<W>(s2);
      const vd<W> ratio = cap / (kt * len);
      const V3<W> sc{s.x * ratio, s.y * ratio, s.z * ratio};
      const vd<W> capEnergy = 0.5 * cap * cap / kt;
      const V3<W> Fc{F.x - kt * sc.x, F.y - kt * sc.y, F.z - kt * sc.z};
      Ft = select<W>(slide, Fc, Ft);
      dampT = slide ? damping : dampT;
      elT = slide ? capEnergy : elT;
      sT = select<W>(slide, sc, sT);
      r = slide ? ratio : r;
    }
    // The loss by the trapezoid identity and the stiffening work (tangential.hpp).
    const vd<W> flT = zero + 0.5 * (kt0 * sn * s0n + (1.0 - r) * (kt0 * s0s + kt * r * s2));
    const vd<W> swT = zero + 0.5 * (kt - kt0) * r * s0s;
    // A pair without friction: normal force only, its spring zeroed.
    F = select<W>(rough, Ft, F);
    damping = rough ? dampT : damping;
    elastic = rough ? elastic + elT : elastic;
    friction = rough ? flT : zero;
    springWork = rough ? swT : zero;
    out.sNew = select<W>(rough, sT, V3<W>{zero, zero, zero});
    if constexpr (Drift) {
      out.dNew = d;
      out.vnDrift = vnDrift;
      out.damperForce = spring - fn;
      out.vn = vn;
    }
  }
  out.F = F;
  out.damping = damping;
  out.elastic = elastic;
  out.friction = friction;
  out.springWork = springWork;
  out.fn = fn;
  return out;
}

// Stage 3 for the contacts of candidates k[0 .. valid - 1], from stage lanes c ...
template <int W, bool History, bool Rotation, bool OnePair, bool Drift>
DEMLAB_KI void law(const Consts C, const uint32_t* k, size_t valid, const Stage<W>& st, size_t c,
                   Sums& e, Records* rec, size_t& nRec) {
  size_t kc[W], ok[W];
  laneCandidates<W>(k, valid, kc);
  // (Stage 1 gave every touching candidate a slot; it may have moved the pool since.)
  double* springs = nullptr;
  if constexpr (History) {
    springs = C.springs->data;
    for (int l = 0; l < W; ++l) ok[l] = kSpringStride * size_t{C.springs->slotOf[kc[l]]};
  }
  vd<W> pKn, pKt, pGn, pGt, pMu;
  if constexpr (OnePair) {
    pKn = splat<W>(C.one.kn);
    pKt = splat<W>(C.one.kt);
    pGn = splat<W>(C.one.gammaN);
    pGt = splat<W>(C.one.gammaT);
    pMu = splat<W>(C.one.friction);
  } else {
    pKn = st.get(kKn, c);
    pKt = st.get(kKt, c);
    pGn = st.get(kGn, c);
    pGt = st.get(kGt, c);
    pMu = st.get(kMu, c);
  }
  LawIn<W> in;
  in.n = V3<W>{st.get(kNx, c), st.get(kNy, c), st.get(kNz, c)};
  in.overlap = st.get(kOverlap, c);
  in.a = st.get(kA, c);
  in.sqrtAm = st.get(kSqrtAm, c);
  in.effMass = st.get(kEffMass, c);
  in.effRadius = st.get(kEffRadius, c);
  in.vrel = V3<W>{st.get(kVx, c), st.get(kVy, c), st.get(kVz, c)};
  if constexpr (Drift) {
    loadSpringsAndDrifts<W>(springs, ok, in.sOld, in.dOld);
  } else if constexpr (History) {
    in.sOld = gather3<W>(springs, ok);
  }
  in.kn = pKn;
  in.kt = pKt;
  in.gammaN = pGn;
  in.gammaT = pGt;
  in.mu = pMu;
  const LawOut<W> lo = hertzLaw<W, History, Drift>(C, in);
  const V3<W>& n = in.n;
  const V3<W>& F = lo.F;
  vd<W> damping = lo.damping;
  const vd<W> elastic = lo.elastic, friction = lo.friction, springWork = lo.springWork;
  // (A repeated lane stores its last lane's spring again: the same values, as the lanes'
  // stores go in lane order.)
  if constexpr (Drift) {
    damping = damping + storeHistories<W>(springs, ok, lo, C.dt);
  } else if constexpr (History) {
    Lanes3<W> sl;
    split<W>(lo.sNew, sl);
    for (int l = 0; l < W; ++l) store3(springs + ok[l], sl.xy[l], sl.z[l]);
  }
  if (C.touchState != nullptr) {
    // (Rare: a damped force cut off while the grains still overlap.)
    const unsigned cut = bitsOf<W>(lo.fn == 0.0) & ((1u << valid) - 1);
    if (cut != 0) [[unlikely]] {
      for (size_t l = 0; l < valid; ++l) {
        if ((cut >> l) & 1) C.touchState[kc[l]] |= kCutOff;
      }
    }
  }
  // The grains' forces and torques, lane by lane in candidate order: f_j += F, f_i -= F,
  // t_i -= armA (n x F), t_j -= armB (n x F); -(a b) is (-a) b exactly.
  size_t oi[W], oj[W];
  for (int l = 0; l < W; ++l) {
    oi[l] = 3 * size_t{C.cand[2 * kc[l]]};
    oj[l] = 3 * size_t{C.cand[2 * kc[l] + 1]};
  }
  Lanes3<W> fl3;
  split<W>(F, fl3);
  for (size_t l = 0; l < valid; ++l) {
    add3(C.force + oj[l], fl3.xy[l], fl3.z[l]);
    add3(C.force + oi[l], neg(fl3.xy[l]), neg(fl3.z[l]));
  }
  if (rec != nullptr) {
    // The caller leaves room for W: all W lanes are written.
    for (int l = 0; l < W; ++l) {
      rec->cand[nRec + l] = static_cast<uint32_t>(kc[l]);
      store3(rec->force + 3 * (nRec + l), fl3.xy[l], fl3.z[l]);
    }
    nRec += valid;
  }
  if constexpr (Rotation) {
    const V3<W> cn = cross<W>(n, F);
    const vd<W> armA = -st.get(kArmA, c), armB = -st.get(kArmB, c);
    Lanes3<W> ta, tb;
    split<W>(V3<W>{armA * cn.x, armA * cn.y, armA * cn.z}, ta);
    split<W>(V3<W>{armB * cn.x, armB * cn.y, armB * cn.z}, tb);
    for (size_t l = 0; l < valid; ++l) {
      add3(C.torque + oi[l], ta.xy[l], ta.z[l]);
      add3(C.torque + oj[l], tb.xy[l], tb.z[l]);
    }
  }
  {
    double e0[W], e1[W], e2[W], e3[W];
    std::memcpy(e0, &elastic, sizeof e0);
    std::memcpy(e1, &damping, sizeof e1);
    std::memcpy(e2, &friction, sizeof e2);
    std::memcpy(e3, &springWork, sizeof e3);
    for (size_t l = 0; l < valid; ++l) {
      e.elastic += e0[l];
      e.damping += e1[l];
      e.friction += e2[l];
      e.springWork += e3[l];
    }
  }
}

// For each 4-bit pattern: the byte shuffle that packs the 32-bit lanes whose bit is set to the
// front, and their number.
struct Pack4 {
  __m128i shuffle[16];
  unsigned count[16];
};
constexpr Pack4 makePack4() {
  Pack4 p{};
  for (unsigned bits = 0; bits < 16; ++bits) {
    unsigned char b[16] = {};
    unsigned n = 0;
    for (unsigned l = 0; l < 4; ++l) {
      if ((bits >> l) & 1) {
        for (unsigned k = 0; k < 4; ++k) b[4 * n + k] = static_cast<unsigned char>(4 * l + k);
        ++n;
      }
    }
    unsigned long long lo = 0, hi = 0;
    for (int k = 7; k >= 0; --k) {
      lo = (lo << 8) | b[k];
      hi = (hi << 8) | b[8 + k];
    }
    p.shuffle[bits] = __m128i{static_cast<long long>(lo), static_cast<long long>(hi)};
    p.count[bits] = n;
  }
  return p;
}
inline constexpr Pack4 kPack4 = makePack4();

// Stage 1 for candidates kc .. kc + valid - 1 (valid <= W; W in the main loop): appends the
// touching ones to bk[m...] without a branch; with history, gives the slots of the others back
// and gives a slot to touching ones without (both rare: a pair starts or stops touching).
template <int W, bool History, bool Rotation, int Prefetch>
DEMLAB_KI void touch(const Consts C, size_t kc, size_t valid, uint32_t* bk, size_t& m) {
  size_t si[W], sj[W], oi[W], oj[W];
  for (int l = 0; l < W; ++l) {
    const size_t k = kc + (static_cast<size_t>(l) < valid ? l : valid - 1);
    si[l] = C.cand[2 * k];
    sj[l] = C.cand[2 * k + 1];
    oi[l] = 3 * si[l];
    oj[l] = 3 * sj[l];
  }
  const V3<W> xi = gather3<W>(C.x, oi), xj = gather3<W>(C.x, oj);
  const vd<W> rs = gather1<W>(C.r, si) + gather1<W>(C.r, sj);
  V3<W> d{xj.x - xi.x, xj.y - xi.y, xj.z - xi.z};
  if (C.periodic != nullptr) [[unlikely]] nearestImage<W>(*C.periodic, d);
  unsigned hit = bitsOf<W>(dot<W>(d, d) < rs * rs);
  if (valid < W) hit &= (1u << valid) - 1;
  if constexpr (Prefetch > 0) {
    // Beds larger than the caches: the positions of the candidates kAhead on, and (dense beds,
    // where most candidates touch) the lines stages 2 and 3 read and write for these candidates
    // a few hundred cycles from now.
    for (int l = 0; l < W; ++l) {
      if constexpr (Prefetch > 1) {
        for (int g = 0; g < 2; ++g) {
          const size_t o = g == 0 ? oi[l] : oj[l];
          __builtin_prefetch(C.v + o);
          __builtin_prefetch(C.force + o, 1);
          if constexpr (Rotation) {
            __builtin_prefetch(C.w + o);
            __builtin_prefetch(C.torque + o, 1);
          }
        }
      }
      const size_t ahead = kc + l + kAhead;
      __builtin_prefetch(C.x + 3 * size_t{C.cand[2 * ahead]});
      __builtin_prefetch(C.x + 3 * size_t{C.cand[2 * ahead + 1]});
    }
  }
  if constexpr (W == 4) {
    // The lanes hit, packed to the front with one shuffle; bk has room for W past the end.
    const __m128i lanes =
        _mm_add_epi32(_mm_set1_epi32(static_cast<int>(kc)), _mm_setr_epi32(0, 1, 2, 3));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(bk + m),
                     _mm_shuffle_epi8(lanes, kPack4.shuffle[hit]));
    m += kPack4.count[hit];
  } else {
    for (int l = 0; l < W; ++l) {
      bk[m] = static_cast<uint32_t>(kc + l);
      m += (hit >> l) & 1;
    }
  }
  if constexpr (History) {
    SpringSlots& sp = *C.springs;
    unsigned none = 0;
    for (int l = 0; l < W; ++l) {
      none |= static_cast<unsigned>(sp.slotOf[kc + (static_cast<size_t>(l) < valid ? l : 0)] ==
                                    SpringSlots::kNoSlot)
              << l;
    }
    const unsigned lanes = (1u << valid) - 1;
    const unsigned change = (none ^ ~hit) & lanes;  // touching without a slot, or the reverse
    if (change != 0) [[unlikely]] {
      for (size_t l = 0; l < valid; ++l) {
        if (!((change >> l) & 1)) continue;
        if ((hit >> l) & 1) {
          sp.data = sp.acquire(sp.owner, sp.base + kc + l);
        } else {
          sp.release(sp.owner, sp.base + kc + l);
        }
      }
    }
  }
}

// The prefetch level (A.prefetch) only selects stage 1's variant, in the loop below: stages 2
// and 3, the bulk of the code, are compiled once per History x Rotation x OnePair, not three
// times more (it was most of the kernels' build time).
template <int W, bool History, bool Rotation, bool OnePair, bool Drift>
void hertzRun(HertzPassArgs& A) {
  const Consts C{
      A.x,       A.v,       A.w,     A.f,    A.t,  A.r,          A.invMass,  A.material,
      A.cand,    A.springs, A.pairs, A.nMat, A.dt, A.lag * A.dt, A.lag != 0, !A.springCriterion,
      A.pairs[0], A.periodic, A.touchState, A.deepLimit};
  const size_t nc = A.nCand;
  Deepest deep{A.deepRatio, A.deepCand};
  Sums e = sumsOf(A);
  Records records;
  Records* rec = A.record != nullptr ? &records : nullptr;
  size_t nRec = 0;
  auto flush = [&] { flushRecords(A, records, nRec); };
  Stage<W> st;
  size_t contacts = 0;
  // The touching candidates not yet run: fewer than W carry over to the next batch.
  uint32_t bk[kBatch + 2 * W];
  size_t m = 0;
  for (size_t k0 = 0; k0 < nc; k0 += kBatch) {
    const size_t kEnd = nc < k0 + kBatch ? nc : k0 + kBatch;
    size_t kc = k0;
    const size_t mBatch = m;  // (bk[0 .. mBatch - 1]: the last batch's, carried over)
    // (Prefetching looks kAhead candidates on: the last ones go without it.)
    const size_t kFast =
        A.prefetch > 0 ? (nc > kAhead ? (kEnd < nc - kAhead ? kEnd : nc - kAhead) : 0) : kEnd;
    if (A.prefetch == 2) {
      for (; kc + W <= kFast; kc += W) touch<W, History, Rotation, 2>(C, kc, W, bk, m);
    } else if (A.prefetch == 1) {
      for (; kc + W <= kFast; kc += W) touch<W, History, Rotation, 1>(C, kc, W, bk, m);
    }
    for (; kc + W <= kEnd; kc += W) touch<W, History, Rotation, 0>(C, kc, W, bk, m);
    if (kc < kEnd) touch<W, History, Rotation, 0>(C, kc, kEnd - kc, bk, m);
    if (C.touchState != nullptr) {
      // Here, once a batch, not in stage 1: a byte store there may alias anything, and the
      // loop would reload what it keeps in registers.
      std::memset(C.touchState + k0, 0, kEnd - k0);
      for (size_t j = mBatch; j < m; ++j) C.touchState[bk[j]] = kTouching;
    }
    const size_t full = m - m % W;
    for (size_t c = 0; c < full; c += W) {
      geometry<W, Rotation, OnePair>(C, bk + c, W, st, c, deep);
    }
    for (size_t c = 0; c < full; c += W) {
      if (rec != nullptr && nRec + W > Records::kSize) flush();
      law<W, History, Rotation, OnePair, Drift>(C, bk + c, W, st, c, e, rec, nRec);
    }
    contacts += full;
    for (size_t j = full; j < m; ++j) bk[j - full] = bk[j];
    m -= full;
  }
  if (m > 0) {
    if (rec != nullptr && nRec + W > Records::kSize) flush();
    geometry<W, Rotation, OnePair>(C, bk, m, st, 0, deep);
    law<W, History, Rotation, OnePair, Drift>(C, bk, m, st, 0, e, rec, nRec);
    contacts += m;
  }
  if (rec != nullptr) flush();
  A.contacts = contacts;
  A.deepRatio = deep.ratio;
  A.deepCand = deep.cand;
  storeSums(e, A);
}

// Calls run.template operator()<OnePair, Drift>() with the pass's variant: one material pair or
// several, and with history and synchronized velocities (lag 0) the springs following their
// drift velocities (hertzLaw).
template <bool History, class Args, class Run>
void byVariant(const Args& a, Run&& run) {
  if constexpr (History) {
    if (a.lag == 0) {
      a.onePair ? run.template operator()<true, true>() : run.template operator()<false, true>();
      return;
    }
  }
  a.onePair ? run.template operator()<true, false>() : run.template operator()<false, false>();
}

template <int W, bool History, bool Rotation>
void hertzPass(HertzPassArgs& a) {
  byVariant<History>(a, [&]<bool OnePair, bool Drift>() {
    hertzRun<W, History, Rotation, OnePair, Drift>(a);
  });
}

template <int W>
HertzPassFn hertzPassFor(bool history, bool rotation) {
  if (history) return rotation ? &hertzPass<W, true, true> : &hertzPass<W, true, false>;
  return rotation ? &hertzPass<W, false, true> : &hertzPass<W, false, false>;
}

// ---- walls ------------------------------------------------------------------------------------

// WallContactModule's loop for contacts c0 .. c0 + valid - 1 of one static wall (valid <= W; the
// lanes from valid on repeat the last contact and are dropped): the grain is A, the wall B;
// vWall = 0, so vrel = 0 - v_i - w_i x arm with arm = point - x_i; m* = 1 / invMass_i, R* = r_i.
template <int W, bool History, bool Rotation, bool OnePair, bool Drift>
DEMLAB_KI void wallGroup(const Consts& C, const WallPassArgs& A, size_t c0, size_t valid,
                         double* wf, Sums& e, Records* rec, size_t& nRec) {
  size_t cs[W], gi[W], oi[W], og[W], os[W];
  for (int l = 0; l < W; ++l) {
    const size_t c = c0 + (static_cast<size_t>(l) < valid ? l : valid - 1);
    cs[l] = c;
    gi[l] = A.grain[c];
    oi[l] = 3 * gi[l];
    og[l] = 7 * c;
    if constexpr (History) os[l] = kSpringStride * size_t{A.slot[c]};
  }
  const vd<W> zero = splat<W>(0.0);
  LawIn<W> in;
  in.n = gather3<W>(A.geometry, og);
  in.overlap = gather1<W>(A.geometry + 3, og);
  in.effMass = 1.0 / gather1<W>(A.invMass, gi);
  in.effRadius = gather1<W>(A.r, gi);
  in.a = vsqrt<W>(in.effRadius * in.overlap);
  in.sqrtAm = vsqrt<W>(in.a * in.effMass);
  const V3<W> vi = gather3<W>(A.v, oi);
  in.vrel = V3<W>{zero - vi.x, zero - vi.y, zero - vi.z};
  V3<W> arm;
  if constexpr (Rotation) {
    const V3<W> point = gather3<W>(A.geometry + 4, og);
    const V3<W> xi = gather3<W>(A.x, oi);
    arm = V3<W>{point.x - xi.x, point.y - xi.y, point.z - xi.z};
    const V3<W> cr = cross<W>(gather3<W>(A.w, oi), arm);
    in.vrel = V3<W>{in.vrel.x - cr.x, in.vrel.y - cr.y, in.vrel.z - cr.z};
  }
  if constexpr (Drift) {
    loadSpringsAndDrifts<W>(A.springs, os, in.sOld, in.dOld);
  } else if constexpr (History) {
    in.sOld = gather3<W>(A.springs, os);
  }
  if constexpr (OnePair) {
    in.kn = splat<W>(C.one.kn);
    in.kt = splat<W>(C.one.kt);
    in.gammaN = splat<W>(C.one.gammaN);
    in.gammaT = splat<W>(C.one.gammaT);
    in.mu = splat<W>(C.one.friction);
  } else {
    size_t op[W];
    for (int l = 0; l < W; ++l) op[l] = A.material[gi[l]] * (sizeof(HertzPair) / sizeof(double));
    const double* pp = &A.pairs[0].kn;
    in.kn = gather1<W>(pp + 0, op);
    in.kt = gather1<W>(pp + 1, op);
    in.gammaN = gather1<W>(pp + 2, op);
    in.gammaT = gather1<W>(pp + 3, op);
    in.mu = gather1<W>(pp + 4, op);
  }
  LawOut<W> lo = hertzLaw<W, History, Drift>(C, in);
  if (A.cutOff != nullptr) {
    const unsigned cut = bitsOf<W>(lo.fn == 0.0) & ((1u << valid) - 1);
    if (cut != 0) [[unlikely]] {
      for (size_t l = 0; l < valid; ++l) {
        if ((cut >> l) & 1) A.cutOff[cs[l]] = 1;
      }
    }
  }
  if constexpr (Drift) {
    lo.damping = lo.damping + storeHistories<W>(A.springs, os, lo, C.dt);
  } else if constexpr (History) {
    Lanes3<W> sl;
    split<W>(lo.sNew, sl);
    for (int l = 0; l < W; ++l) store3(A.springs + os[l], sl.xy[l], sl.z[l]);
  }
  // The grain's force and torque (f_i -= F, t_i -= arm x F), the wall's force, lane by lane.
  Lanes3<W> fl3;
  split<W>(lo.F, fl3);
  for (size_t l = 0; l < valid; ++l) add3(A.f + oi[l], neg(fl3.xy[l]), neg(fl3.z[l]));
  if constexpr (Rotation) {
    const V3<W> tc = cross<W>(arm, lo.F);
    Lanes3<W> tl;
    split<W>(V3<W>{-tc.x, -tc.y, -tc.z}, tl);
    for (size_t l = 0; l < valid; ++l) add3(A.t + oi[l], tl.xy[l], tl.z[l]);
  }
  for (size_t l = 0; l < valid; ++l) add3(wf, fl3.xy[l], fl3.z[l]);
  {
    double e0[W], e1[W], e2[W], e3[W];
    std::memcpy(e0, &lo.elastic, sizeof e0);
    std::memcpy(e1, &lo.damping, sizeof e1);
    std::memcpy(e2, &lo.friction, sizeof e2);
    std::memcpy(e3, &lo.springWork, sizeof e3);
    for (size_t l = 0; l < valid; ++l) {
      e.elastic += e0[l];
      e.damping += e1[l];
      e.friction += e2[l];
      e.springWork += e3[l];
    }
  }
  if (rec != nullptr) {
    for (int l = 0; l < W; ++l) {
      rec->cand[nRec + l] = static_cast<uint32_t>(cs[l]);
      store3(rec->force + 3 * (nRec + l), fl3.xy[l], fl3.z[l]);
    }
    nRec += valid;
  }
}

template <int W, bool History, bool Rotation, bool OnePair, bool Drift>
void wallRun(WallPassArgs& A) {
  Consts C{};
  C.dt = A.dt;
  C.lagDt = A.lag * A.dt;
  C.lag = A.lag != 0;
  C.total = !A.springCriterion;
  C.one = A.pairs[0];
  Sums e = sumsOf(A);
  double wf[3] = {A.wallForce[0], A.wallForce[1], A.wallForce[2]};
  Records records;
  Records* rec = A.record != nullptr ? &records : nullptr;
  size_t nRec = 0;
  auto flush = [&] { flushRecords(A, records, nRec); };
  size_t c = 0;
  for (; c + W <= A.n; c += W) {
    if (rec != nullptr && nRec + W > Records::kSize) flush();
    wallGroup<W, History, Rotation, OnePair, Drift>(C, A, c, W, wf, e, rec, nRec);
  }
  if (c < A.n) {
    if (rec != nullptr && nRec + W > Records::kSize) flush();
    wallGroup<W, History, Rotation, OnePair, Drift>(C, A, c, A.n - c, wf, e, rec, nRec);
  }
  if (rec != nullptr) flush();
  for (int k = 0; k < 3; ++k) A.wallForce[k] = wf[k];
  storeSums(e, A);
}

template <int W, bool History, bool Rotation>
void wallPass(WallPassArgs& a) {
  byVariant<History>(a, [&]<bool OnePair, bool Drift>() {
    wallRun<W, History, Rotation, OnePair, Drift>(a);
  });
}

template <int W>
WallPassFn wallPassFor(bool history, bool rotation) {
  if (history) return rotation ? &wallPass<W, true, true> : &wallPass<W, true, false>;
  return rotation ? &wallPass<W, false, true> : &wallPass<W, false, false>;
}

// ---- the rotation update ----------------------------------------------------------------------

// The 3-vectors of grains i .. i + W - 1 (contiguous: 3 W doubles at p) by component, and back.
// Three registers holding 3-vectors one after the other (a = (x0 y0 z0 x1), ... for W = 4)
// by component.
template <int W>
DEMLAB_KI V3<W> toSoA(vd<W> av, vd<W> bv, vd<W> cv) {
  if constexpr (W == 2) {
    const __m128d a = (__m128d)av, b = (__m128d)bv, c = (__m128d)cv;
    // a = (x0 y0), b = (z0 x1), c = (y1 z1)
    return {(vd<2>)_mm_shuffle_pd(a, b, 2), (vd<2>)_mm_shuffle_pd(a, c, 1),
            (vd<2>)_mm_shuffle_pd(b, c, 2)};
  } else {
    static_assert(W == 4);
    const __m256d a = (__m256d)av, b = (__m256d)bv, c = (__m256d)cv;
    // a = (x0 y0 z0 x1), b = (y1 z1 x2 y2), c = (z2 x3 y3 z3)
    const __m256d m0 = _mm256_blend_pd(a, b, 0xc);          // x0 y0 x2 y2
    const __m256d m1 = _mm256_permute2f128_pd(a, c, 0x21);  // z0 x1 z2 x3
    const __m256d m2 = _mm256_blend_pd(b, c, 0xc);          // y1 z1 y3 z3
    return {(vd<4>)_mm256_shuffle_pd(m0, m1, 0xa), (vd<4>)_mm256_shuffle_pd(m0, m2, 0x5),
            (vd<4>)_mm256_shuffle_pd(m1, m2, 0xa)};
  }
}

// The 3 W doubles at p as three registers, and back.
template <int W>
struct Flat3 {
  vd<W> a, b, c;
};
template <int W>
DEMLAB_KI Flat3<W> loadFlat(const double* p) {
  Flat3<W> f;
  std::memcpy(&f.a, p, sizeof f.a);
  std::memcpy(&f.b, p + W, sizeof f.b);
  std::memcpy(&f.c, p + 2 * W, sizeof f.c);
  return f;
}
template <int W>
DEMLAB_KI void storeFlat(double* p, const Flat3<W>& f) {
  std::memcpy(p, &f.a, sizeof f.a);
  std::memcpy(p + W, &f.b, sizeof f.b);
  std::memcpy(p + 2 * W, &f.c, sizeof f.c);
}

// A per-grain scalar of W grains (lane l: grain l) spread over their 3 W components: the
// registers of loadFlat's layout, double k holding grain k / 3's value.
template <int W>
DEMLAB_KI Flat3<W> perComponent(vd<W> m) {
  if constexpr (W == 2) {
    const __m128d v = (__m128d)m;
    return {(vd<2>)_mm_unpacklo_pd(v, v), m, (vd<2>)_mm_unpackhi_pd(v, v)};
  } else {
    static_assert(W == 4);
    const __m256d v = (__m256d)m;
    return {(vd<4>)_mm256_permute4x64_pd(v, 0x40), (vd<4>)_mm256_permute4x64_pd(v, 0xa5),
            (vd<4>)_mm256_permute4x64_pd(v, 0xfe)};
  }
}

// The 3-vectors of grains i .. i + W - 1 (contiguous: 3 W doubles at p) by component, and back.
template <int W>
DEMLAB_KI V3<W> load3c(const double* p) {
  const Flat3<W> f = loadFlat<W>(p);
  return toSoA<W>(f.a, f.b, f.c);
}

template <int W>
DEMLAB_KI void store3c(double* p, const V3<W>& v) {
  if constexpr (W == 2) {
    const __m128d x = (__m128d)v.x, y = (__m128d)v.y, z = (__m128d)v.z;
    _mm_storeu_pd(p, _mm_unpacklo_pd(x, y));
    _mm_storeu_pd(p + 2, _mm_shuffle_pd(z, x, 2));
    _mm_storeu_pd(p + 4, _mm_unpackhi_pd(y, z));
  } else {
    static_assert(W == 4);
    const __m256d x = (__m256d)v.x, y = (__m256d)v.y, z = (__m256d)v.z;
    const __m256d m0 = _mm256_shuffle_pd(x, y, 0x0);  // x0 y0 x2 y2
    const __m256d m1 = _mm256_shuffle_pd(z, x, 0xa);  // z0 x1 z2 x3
    const __m256d m2 = _mm256_shuffle_pd(y, z, 0xf);  // y1 z1 y3 z3
    _mm256_storeu_pd(p, _mm256_permute2f128_pd(m0, m1, 0x20));
    _mm256_storeu_pd(p + 4, _mm256_blend_pd(m2, m0, 0xc));
    _mm256_storeu_pd(p + 8, _mm256_permute2f128_pd(m1, m2, 0x31));
  }
}

// The quaternions of grains i .. i + W - 1 (4 doubles each, x y z w) by coefficient, and back.
template <int W>
struct Q4 {
  vd<W> x, y, z, w;
};
template <int W>
DEMLAB_KI Q4<W> loadQ(const double* p) {
  if constexpr (W == 2) {
    const __m128d a0 = _mm_loadu_pd(p), b0 = _mm_loadu_pd(p + 2);
    const __m128d a1 = _mm_loadu_pd(p + 4), b1 = _mm_loadu_pd(p + 6);
    return {(vd<2>)_mm_unpacklo_pd(a0, a1), (vd<2>)_mm_unpackhi_pd(a0, a1),
            (vd<2>)_mm_unpacklo_pd(b0, b1), (vd<2>)_mm_unpackhi_pd(b0, b1)};
  } else {
    static_assert(W == 4);
    const __m256d q0 = _mm256_loadu_pd(p), q1 = _mm256_loadu_pd(p + 4);
    const __m256d q2 = _mm256_loadu_pd(p + 8), q3 = _mm256_loadu_pd(p + 12);
    const __m256d t0 = _mm256_unpacklo_pd(q0, q1);  // x0 x1 z0 z1
    const __m256d t1 = _mm256_unpackhi_pd(q0, q1);  // y0 y1 w0 w1
    const __m256d t2 = _mm256_unpacklo_pd(q2, q3);
    const __m256d t3 = _mm256_unpackhi_pd(q2, q3);
    return {
        (vd<4>)_mm256_permute2f128_pd(t0, t2, 0x20), (vd<4>)_mm256_permute2f128_pd(t1, t3, 0x20),
        (vd<4>)_mm256_permute2f128_pd(t0, t2, 0x31), (vd<4>)_mm256_permute2f128_pd(t1, t3, 0x31)};
  }
}
template <int W>
DEMLAB_KI void storeQ(double* p, const Q4<W>& q) {
  if constexpr (W == 2) {
    const __m128d x = (__m128d)q.x, y = (__m128d)q.y, z = (__m128d)q.z, w = (__m128d)q.w;
    _mm_storeu_pd(p, _mm_unpacklo_pd(x, y));
    _mm_storeu_pd(p + 2, _mm_unpacklo_pd(z, w));
    _mm_storeu_pd(p + 4, _mm_unpackhi_pd(x, y));
    _mm_storeu_pd(p + 6, _mm_unpackhi_pd(z, w));
  } else {
    static_assert(W == 4);
    const __m256d x = (__m256d)q.x, y = (__m256d)q.y, z = (__m256d)q.z, w = (__m256d)q.w;
    const __m256d t0 = _mm256_unpacklo_pd(x, y);  // x0 y0 x2 y2
    const __m256d t1 = _mm256_unpackhi_pd(x, y);  // x1 y1 x3 y3
    const __m256d t2 = _mm256_unpacklo_pd(z, w);  // z0 w0 z2 w2
    const __m256d t3 = _mm256_unpackhi_pd(z, w);  // z1 w1 z3 w3
    _mm256_storeu_pd(p, _mm256_permute2f128_pd(t0, t2, 0x20));
    _mm256_storeu_pd(p + 4, _mm256_permute2f128_pd(t1, t3, 0x20));
    _mm256_storeu_pd(p + 8, _mm256_permute2f128_pd(t0, t2, 0x31));
    _mm256_storeu_pd(p + 12, _mm256_permute2f128_pd(t1, t3, 0x31));
  }
}

// PredictRotationModule's update of grains 0 .. n - n % W (the caller does the rest), with
// advance()'s series and renormalisation; the quaternion product is Eigen's (its SSE2
// quat_product: res.x = (aw bx + ay bz) - (az by - ax bw), ...), the norm of a 4-vector
// (x^2 + z^2) + (y^2 + w^2) as Eigen's two-packet sum.
template <int W>
void rotationPass(RotationArgs& A) {
  double* __restrict qa = A.q;
  double* __restrict wa = A.w;
  double* __restrict ta = A.t;
  double* __restrict tp = A.tPrev;
  const double* __restrict invI = A.invInertia;
  const double dt = A.dt, h = 0.5 * dt;
  const bool sync = A.sync;
  constexpr double k24 = 1.0 / 24, k48 = 1.0 / 48, k80 = 1.0 / 80, k120 = 1.0 / 120;
  constexpr double k168 = 1.0 / 168;
  const vd<W> zero = splat<W>(0.0);
  const size_t n = A.n - A.n % W;
  for (size_t i = 0; i < n; i += W) {
    const Flat3<W> tf = loadFlat<W>(ta + 3 * i), wf = loadFlat<W>(wa + 3 * i);
    if (!anyBits<W>((vm<W>)tf.a | (vm<W>)tf.b | (vm<W>)tf.c | (vm<W>)wf.a | (vm<W>)wf.b |
                    (vm<W>)wf.c)) {
      // W idle grains (no torque, no spin, all +0 bit for bit): as the module's shortcut, only
      // their last torques become +0 (the update would leave the same bits, at more cost).
      const Flat3<W> p = loadFlat<W>(tp + 3 * i);
      if (anyBits<W>((vm<W>)p.a | (vm<W>)p.b | (vm<W>)p.c)) storeFlat<W>(tp + 3 * i, tf);
      continue;
    }
    const V3<W> t = toSoA<W>(tf.a, tf.b, tf.c);
    const V3<W> w = toSoA<W>(wf.a, wf.b, wf.c);
    vd<W> inv;
    std::memcpy(&inv, invI + i, sizeof inv);
    const V3<W> alpha{t.x * inv, t.y * inv, t.z * inv};
    const V3<W> wh{w.x + h * alpha.x, w.y + h * alpha.y, w.z + h * alpha.z};
    const vm<W> still = (wh.x == 0.0) & (wh.y == 0.0) & (wh.z == 0.0);
    const V3<W> phi{wh.x * dt, wh.y * dt, wh.z * dt};
    const vd<W> t2 = dot<W>(phi, phi);
    const vm<W> big = ~still & (t2 >= 1e-4);
    if (bitsOf<W>(still) != (1u << W) - 1) {
      const vd<W> c = 1.0 - t2 * 0.125 * (1.0 - t2 * k48 * (1.0 - t2 * k120));
      const vd<W> s = 0.5 * (1.0 - t2 * k24 * (1.0 - t2 * k80 * (1.0 - t2 * k168)));
      const vd<W> ax = s * phi.x, ay = s * phi.y, az = s * phi.z, aw = c;
      const Q4<W> b = loadQ<W>(qa + 4 * i);
      Q4<W> r{(aw * b.x + ay * b.z) - (az * b.y - ax * b.w),
              (aw * b.y + ay * b.w) + (az * b.x - ax * b.z),
              (aw * b.z - ay * b.x) + (az * b.w + ax * b.y),
              (aw * b.w - ay * b.y) - (az * b.z + ax * b.x)};
      const vd<W> n2 = (r.x * r.x + r.z * r.z) + (r.y * r.y + r.w * r.w);
      const vd<W> f = 1.5 - 0.5 * n2;
      const vm<W> keep = still | big;
      r = Q4<W>{keep ? b.x : r.x * f, keep ? b.y : r.y * f, keep ? b.z : r.z * f,
                keep ? b.w : r.w * f};
      storeQ<W>(qa + 4 * i, r);
    }
    if (sync) {
      store3c<W>(wa + 3 * i, V3<W>{wh.x + h * alpha.x, wh.y + h * alpha.y, wh.z + h * alpha.z});
    } else {
      store3c<W>(wa + 3 * i, wh);
    }
    // tPrev = t and t = 0, as raw doubles.
    std::memcpy(tp + 3 * i, ta + 3 * i, 3 * W * sizeof(double));
    store3c<W>(ta + 3 * i, V3<W>{zero, zero, zero});
    if (const unsigned bits = bitsOf<W>(big)) [[unlikely]] {
      double whl[3][W];
      std::memcpy(whl[0], &wh.x, sizeof whl[0]);
      std::memcpy(whl[1], &wh.y, sizeof whl[1]);
      std::memcpy(whl[2], &wh.z, sizeof whl[2]);
      for (int l = 0; l < W; ++l) {
        if ((bits >> l) & 1) {
          const double wl[3] = {whl[0][l], whl[1][l], whl[2][l]};
          A.turn(A.turnContext, i + l, wl);
        }
      }
    }
  }
  A.done = n;
}

// ---- the translational integrator -------------------------------------------------------------

template <bool B>
struct Flag {
  static constexpr bool value = B;
};

// PredictModule's drift of grains 0 .. n - n % W (the caller does the rest), over the arrays as
// flat doubles: acc = f invMass, vHalf = v + dt/2 acc, x += dt vHalf, v = vHalf (+ dt/2 acc
// when sync), fPrev = f, f = 0; and the largest |x - x0|^2 (a max picks one of its values:
// kept per lane, then combined, it is the loop's).
template <int W>
void predictPass(PredictArgs& A) {
  double* __restrict x = A.x;
  double* __restrict v = A.v;
  double* __restrict f = A.f;
  double* __restrict fPrev = A.fPrev;
  const double* __restrict invMass = A.invMass;
  const double* __restrict x0 = A.x0;
  const double* __restrict weight = A.weight;
  const double dt = A.dt, h = 0.5 * dt;
  const size_t n = A.n - A.n % W;
  vd<W> maxD2 = splat<W>(A.maxDisp2);
  const Flat3<W> zero{splat<W>(0.0), splat<W>(0.0), splat<W>(0.0)};
  auto run = [&](auto sync, auto track, auto weighted) {
    for (size_t i = 0; i < n; i += W) {
      vd<W> m;
      std::memcpy(&m, invMass + i, sizeof m);
      const Flat3<W> M = perComponent<W>(m);
      const Flat3<W> F = loadFlat<W>(f + 3 * i);
      const Flat3<W> V = loadFlat<W>(v + 3 * i);
      Flat3<W> X = loadFlat<W>(x + 3 * i);
      const Flat3<W> acc{F.a * M.a, F.b * M.b, F.c * M.c};
      const Flat3<W> vh{V.a + h * acc.a, V.b + h * acc.b, V.c + h * acc.c};
      X = Flat3<W>{X.a + dt * vh.a, X.b + dt * vh.b, X.c + dt * vh.c};
      storeFlat<W>(x + 3 * i, X);
      if constexpr (decltype(sync)::value) {
        storeFlat<W>(v + 3 * i, Flat3<W>{vh.a + h * acc.a, vh.b + h * acc.b, vh.c + h * acc.c});
      } else {
        storeFlat<W>(v + 3 * i, vh);
      }
      storeFlat<W>(fPrev + 3 * i, F);
      storeFlat<W>(f + 3 * i, zero);
      if constexpr (decltype(track)::value) {
        const Flat3<W> X0 = loadFlat<W>(x0 + 3 * i);
        const V3<W> d = toSoA<W>(X.a - X0.a, X.b - X0.b, X.c - X0.c);
        vd<W> d2 = dot<W>(d, d);
        if constexpr (decltype(weighted)::value) {
          vd<W> wt;
          std::memcpy(&wt, weight + i, sizeof wt);
          d2 = d2 * wt;
        }
        maxD2 = maxD2 < d2 ? d2 : maxD2;
      }
    }
  };
  using Yes = Flag<true>;
  using No = Flag<false>;
  const auto tracked = [&](auto sync) {
    if (x0 == nullptr) return run(sync, No{}, No{});
    weight != nullptr ? run(sync, Yes{}, Yes{}) : run(sync, Yes{}, No{});
  };
  A.sync ? tracked(Yes{}) : tracked(No{});
  double lanes[W];
  std::memcpy(lanes, &maxD2, sizeof lanes);
  double out = A.maxDisp2;
  for (int l = 0; l < W; ++l) out = out < lanes[l] ? lanes[l] : out;
  A.maxDisp2 = out;
  A.done = n;
}

// CorrectModule's second kick of grains 0 .. n - n % W, over flat doubles: v += (dt/2 invMass)
// (f - fPrev) (synchronized) or v += (dt/2 invMass) f (Verlet); the same for w with t when w
// is not null.
template <int W>
void correctPass(CorrectArgs& A) {
  const double h = A.h;
  const size_t n = A.n - A.n % W;
  auto kick = [&](double* __restrict v, const double* __restrict f, const double* __restrict fp,
                  const double* __restrict inv, auto sync) {
    for (size_t i = 0; i < n; i += W) {
      vd<W> m;
      std::memcpy(&m, inv + i, sizeof m);
      const Flat3<W> M = perComponent<W>(h * m);
      const Flat3<W> F = loadFlat<W>(f + 3 * i);
      const Flat3<W> V = loadFlat<W>(v + 3 * i);
      if constexpr (decltype(sync)::value) {
        const Flat3<W> P = loadFlat<W>(fp + 3 * i);
        storeFlat<W>(v + 3 * i, Flat3<W>{V.a + M.a * (F.a - P.a), V.b + M.b * (F.b - P.b),
                                         V.c + M.c * (F.c - P.c)});
      } else {
        storeFlat<W>(v + 3 * i, Flat3<W>{V.a + M.a * F.a, V.b + M.b * F.b, V.c + M.c * F.c});
      }
    }
  };
  using Yes = Flag<true>;
  using No = Flag<false>;
  if (A.sync) {
    kick(A.v, A.f, A.fPrev, A.invMass, Yes{});
    if (A.w != nullptr) kick(A.w, A.t, A.tPrev, A.invInertia, Yes{});
  } else {
    kick(A.v, A.f, A.fPrev, A.invMass, No{});
    if (A.w != nullptr) kick(A.w, A.t, A.tPrev, A.invInertia, No{});
  }
  A.done = n;
}

// Returns this instruction set's kernels at W lanes.
template <int W>
IsaPasses passesFor() {
  return {&hertzPassFor<W>, &wallPassFor<W>, &rotationPass<W>, &predictPass<W>, &correctPass<W>};
}

#undef DEMLAB_KI

}  // namespace demlab::sim::kernel::DEMLAB_KERNEL_NS
