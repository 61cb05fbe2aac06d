// Narrow phase and bounds against a brute-force numerical oracle: each wall shape's surface is
// given as parametrised patches, the closest surface point to a grain's centre is found by
// dense sampling of every patch refined around the best sample, and intersect() must agree on
// contact or not, overlap, normal and point, for random grains in 2D and 3D. Bounds must hold
// every sampled surface point and touch the extreme ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "core/type_interaction.hpp"
#include "physics/narrow_phase.hpp"
#include "physics/shapes.hpp"

namespace demlab::physics {
namespace physics_narrow_phase_test {

constexpr Real kPi = std::numbers::pi;

template <int D>
using Patch = std::function<VecD<D>(Real, Real)>;  // (u, v) in [0,1]^2 -> surface point

// The surface of a shape, and which side of it a grain centre is on: signedDistance > 0 on the
// side where grains live (outside a solid, inside a drum), so overlap = r - signedDistance.
template <int D>
struct Surface {
  std::vector<Patch<D>> patches;
  bool flat1D = D == 2;    // patches depend on u only
  bool periodicU = false;  // u is an angle: refine across u = 0 = 1 instead of clamping
  Real margin = 0;         // grains are drawn near patch points with u, v in [margin, 1-margin]
  std::function<bool(const VecD<D>&)> onGrainSide;  // centre on the grains' side
};

// Returns the surface point nearest to x: a grid over each patch, then twelve rounds of a
// five times finer grid around the best sample.
template <int D>
VecD<D> closestPoint(const Surface<D>& s, const VecD<D>& x) {
  const int nu = s.flat1D ? 400 : 32, nv = s.flat1D ? 1 : 32;
  Real best = std::numeric_limits<Real>::infinity();
  VecD<D> bestPoint = VecD<D>::Zero();
  for (const Patch<D>& p : s.patches) {
    Real bu = 0, bv = 0, bd = std::numeric_limits<Real>::infinity();
    for (int i = 0; i <= nu; ++i) {
      for (int j = 0; j <= (s.flat1D ? 0 : nv); ++j) {
        const Real u = Real(i) / nu, v = s.flat1D ? 0 : Real(j) / nv;
        const Real d = (p(u, v) - x).squaredNorm();
        if (d < bd) bd = d, bu = u, bv = v;
      }
    }
    Real su = 1.0 / nu, sv = s.flat1D ? 0 : 1.0 / nv;
    for (int round = 0; round < 12; ++round) {
      const Real cu = bu, cv = bv;
      for (int i = -10; i <= 10; ++i) {
        for (int j = (s.flat1D ? 0 : -10); j <= (s.flat1D ? 0 : 10); ++j) {
          const Real u = s.periodicU ? cu + i * su / 5 : std::clamp(cu + i * su / 5, 0.0, 1.0);
          const Real v = std::clamp(cv + j * sv / 5, 0.0, 1.0);
          const Real d = (p(u, v) - x).squaredNorm();
          if (d < bd) bd = d, bu = u, bv = v;
        }
      }
      su /= 5, sv /= 5;
    }
    if (bd < best) best = bd, bestPoint = p(bu, bv);
  }
  return bestPoint;
}

template <int D>
Real signedDistance(const Surface<D>& s, const VecD<D>& x) {
  const Real d = (closestPoint(s, x) - x).norm();
  return s.onGrainSide(x) ? d : -d;
}

template <int D>
VecD<D> randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<Real> g;
  VecD<D> v;
  for (int k = 0; k < D; ++k) v[k] = g(rng);
  return v.normalized();
}

// Returns an orthonormal basis (columns) with first column `a` (3D) or a random rotation.
template <int D>
MatD<D> randomRotation(std::mt19937_64& rng) {
  if constexpr (D == 2) {
    const Real t = std::uniform_real_distribution<Real>(0, 2 * kPi)(rng);
    return Rotation2{t}.matrix();
  } else {
    const Vec3 axis = randomUnit<3>(rng);
    return AngleAxis(std::uniform_real_distribution<Real>(0, 2 * kPi)(rng), axis)
        .toRotationMatrix();
  }
}

// Returns a random point near the surface: a random surface point moved by up to `reach` in a
// random direction, so that about half the grains drawn around it touch.
template <int D>
VecD<D> nearSurface(const Surface<D>& s, std::mt19937_64& rng, Real reach) {
  std::uniform_real_distribution<Real> u01(0, 1), uv(s.margin, 1 - s.margin);
  const Patch<D>& p =
      s.patches[std::uniform_int_distribution<size_t>(0, s.patches.size() - 1)(rng)];
  return p(uv(rng), uv(rng)) + randomUnit<D>(rng) * reach * u01(rng);
}

// Checks intersect(grain, shape) against the oracle for `cases` random grains near the shape.
template <int D, class Shape>
void checkAgainstOracle(const Shape& shape, const Surface<D>& surface, std::mt19937_64& rng,
                        int cases) {
  std::uniform_real_distribution<Real> radius(0.05, 0.5);
  const Real tol = 1e-6;
  int contacts = 0, misses = 0;
  for (int c = 0; c < cases; ++c) {
    const VecD<D> x = nearSurface(surface, rng, 0.8);
    const SphereShape<D> grain{x, radius(rng)};
    const Real sd = signedDistance(surface, x);
    const Real want = grain.radius - sd;  // oracle overlap
    const auto got = intersect(grain, shape);
    if (std::abs(want) < 10 * tol) continue;  // grazing: either answer is right
    if (want < 0) {
      EXPECT_FALSE(got.has_value()) << "case " << c << " overlap " << want;
      ++misses;
      continue;
    }
    ++contacts;
    ASSERT_TRUE(got.has_value()) << "case " << c << " overlap " << want;
    EXPECT_NEAR(got->overlap, want, tol) << "case " << c;
    EXPECT_NEAR(got->normal.norm(), 1, 1e-12);
    // The normal points from the centre to the closest surface point (away from it when the
    // centre is on the wrong side): that point is centre + n (r - overlap).
    const VecD<D> q = x + got->normal * (grain.radius - got->overlap);
    if (std::abs(sd) > 1e-3) {
      EXPECT_LT((closestPoint(surface, q) - q).norm(), tol) << "case " << c;
    }
    const VecD<D> point = x + got->normal * (grain.radius - 0.5 * got->overlap);
    EXPECT_LT((got->point - point).norm(), 1e-12) << "case " << c;
  }
  // Random inputs must exercise both outcomes.
  EXPECT_GE(contacts, 3);
  EXPECT_GE(misses, 3);
}

// Checks that bounds hold every surface sample and that each face of the box is touched.
template <int D>
void checkBounds(const Bounds<D>& b, const Surface<D>& s) {
  const int n = s.flat1D ? 2000 : 200;
  VecD<D> lo = VecD<D>::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (const Patch<D>& p : s.patches) {
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; j <= (s.flat1D ? 0 : n); ++j) {
        const VecD<D> x = p(Real(i) / n, s.flat1D ? 0 : Real(j) / n);
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
      }
    }
  }
  for (int k = 0; k < D; ++k) {
    EXPECT_LE(b.lo[k], lo[k] + 1e-12);
    EXPECT_GE(b.hi[k], hi[k] - 1e-12);
    // Tight: the extreme samples are within the sampling step of the box (curved surfaces).
    EXPECT_NEAR(b.lo[k], lo[k], 1e-3);
    EXPECT_NEAR(b.hi[k], hi[k], 1e-3);
  }
}

template <int D>
Surface<D> sphereSurface(const SphereShape<D>& s) {
  Surface<D> out;
  if constexpr (D == 2) {
    out.patches.push_back([s](Real u, Real) {
      return VecD<D>(s.centre + s.radius * Vec2(std::cos(2 * kPi * u), std::sin(2 * kPi * u)));
    });
  } else {
    // Two charts with their poles on different axes, so that every point lies well away from
    // the poles of one of them (near a pole a chart's grid cannot be refined).
    out.patches.push_back([s](Real u, Real v) {
      const Real th = kPi * v, ph = 2 * kPi * u;
      return Vec3(s.centre + s.radius * Vec3(std::sin(th) * std::cos(ph),
                                             std::sin(th) * std::sin(ph), std::cos(th)));
    });
    out.patches.push_back([s](Real u, Real v) {
      const Real th = kPi * v, ph = 2 * kPi * u;
      return Vec3(s.centre + s.radius * Vec3(std::cos(th), std::sin(th) * std::cos(ph),
                                             std::sin(th) * std::sin(ph)));
    });
  }
  out.onGrainSide = [s](const VecD<D>& x) { return (x - s.centre).norm() >= s.radius; };
  out.periodicU = true;
  return out;
}

template <int D>
void grainGrain(uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 6; ++i) {
    const SphereShape<D> b{randomUnit<D>(rng) * 0.3,
                           std::uniform_real_distribution<Real>(0.2, 1)(rng)};
    checkAgainstOracle<D>(b, sphereSurface(b), rng, 40);
    checkBounds<D>(bounds(b), sphereSurface(b));
  }
}

TEST(PhysicsNarrowPhase, SphereSphere) {
  grainGrain<2>(1);
  grainGrain<3>(2);
}

template <int D>
void plane(uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 6; ++i) {
    const PlaneShape<D> p{randomUnit<D>(rng) * 0.5, randomUnit<D>(rng)};
    const MatD<D> basis = [&] {
      MatD<D> m;
      m.col(0) = p.normal;
      if constexpr (D == 2) {
        m.col(1) = perp(p.normal);
      } else {
        const Vec3 t = p.normal.unitOrthogonal();
        m.col(1) = t;
        m.col(2) = p.normal.cross(t);
      }
      return m;
    }();
    Surface<D> s;
    s.patches.push_back([p, basis](Real u, Real v) {
      VecD<D> x = p.point + (u - 0.5) * 20 * basis.col(1);
      if constexpr (D == 3) x += (v - 0.5) * 20 * basis.col(2);
      return x;
    });
    s.onGrainSide = [p](const VecD<D>& x) { return (x - p.point).dot(p.normal) >= 0; };
    s.margin = 0.3;  // the patch is a finite piece of the plane: stay away from its rim
    // Grains on both sides: a grain below a one-sided plane is pushed back out.
    checkAgainstOracle<D>(p, s, rng, 40);
  }
}

TEST(PhysicsNarrowPhase, Plane) {
  plane<2>(3);
  plane<3>(4);
}

template <int D>
FlatWallShape<D> randomFlatWall(std::mt19937_64& rng) {
  const MatD<D> r = randomRotation<D>(rng);
  FlatWallShape<D> w;
  w.centre = randomUnit<D>(rng) * 0.2;
  for (int i = 0; i < D - 1; ++i) {
    w.axes[i] = r.col(i);
    w.halfExtents[i] = std::uniform_real_distribution<Real>(0.1, 1.5)(rng);
  }
  return w;
}

template <int D>
void flatWall(uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 6; ++i) {
    const FlatWallShape<D> w = randomFlatWall<D>(rng);
    Surface<D> s;
    s.patches.push_back([w](Real u, Real v) {
      VecD<D> x = w.centre + (2 * u - 1) * w.halfExtents[0] * w.axes[0];
      if constexpr (D == 3) x += (2 * v - 1) * w.halfExtents[1] * w.axes[1];
      return x;
    });
    s.onGrainSide = [](const VecD<D>&) { return true; };  // two-sided, zero thickness
    checkAgainstOracle<D>(w, s, rng, 40);
    checkBounds<D>(bounds(w), s);
  }
}

TEST(PhysicsNarrowPhase, FlatWall) {
  flatWall<2>(5);
  flatWall<3>(6);
}

// A flat wall with a hole (an orifice plate in 3D, a slot in 2D): the surface as patches, and
// the rim (3D) or the gap's ends (2D) once more as patches of their own, so that half the
// grains are drawn near the rim, where the nearest point leaves the face for the rim.
template <int D>
void flatWallWithHole(uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 6; ++i) {
    FlatWallShape<D> w = randomFlatWall<D>(rng);
    // Not too elongated: the patches' rays from the rim to a far edge would be too sparse for
    // the oracle's grid.
    for (Real& h : w.halfExtents) h = std::uniform_real_distribution<Real>(0.5, 1.5)(rng);
    const Real smallest = *std::min_element(w.halfExtents.begin(), w.halfExtents.end());
    w.hole = std::uniform_real_distribution<Real>(0.2, 0.9)(rng) * smallest;
    Surface<D> s;
    if constexpr (D == 2) {
      for (int side : {-1, 1}) {
        s.patches.push_back([w, side](Real u, Real) {
          return VecD<D>(w.centre + side * (w.hole + u * (w.halfExtents[0] - w.hole)) * w.axes[0]);
        });
        s.patches.push_back(
            [w, side](Real, Real) { return VecD<D>(w.centre + side * w.hole * w.axes[0]); });
      }
    } else {
      // One patch per side of the rectangle: u runs along the side, v along the straight line
      // from the rim point at the same angle out to it (the corners are patch corners).
      for (int side = 0; side < 4; ++side) {
        s.patches.push_back([w, side](Real u, Real v) {
          const Real sx[4] = {1, -1, -1, 1}, sy[4] = {1, 1, -1, -1};
          const int next = (side + 1) % 4;
          const Real ex = (1 - u) * sx[side] + u * sx[next], ey = (1 - u) * sy[side] + u * sy[next];
          const Vec3 edge = ex * w.halfExtents[0] * w.axes[0] + ey * w.halfExtents[1] * w.axes[1];
          const Vec3 rim = w.hole * edge.normalized();
          return VecD<D>(w.centre + rim + v * (edge - rim));
        });
      }
      s.patches.push_back([w](Real u, Real) {
        return VecD<D>(w.centre + w.hole * (std::cos(2 * kPi * u) * w.axes[0] +
                                            std::sin(2 * kPi * u) * w.axes[1]));
      });
    }
    s.onGrainSide = [](const VecD<D>&) { return true; };  // two-sided, zero thickness
    checkAgainstOracle<D>(w, s, rng, 60);
    checkBounds<D>(bounds(w), s);
  }
}

TEST(PhysicsNarrowPhase, FlatWallWithHole) {
  flatWallWithHole<2>(15);
  flatWallWithHole<3>(16);
}

// A grain over the hole's axis: every rim point is as near, and the rim pushes it along the
// axis, away from the plate, with the overlap of a ring contact.
TEST(PhysicsNarrowPhase, FlatWallHoleAxis) {
  FlatWallShape<3> w{Vec3(0, 0, 0), {Vec3::UnitX(), Vec3::UnitY()}, {1, 1}, 0.3};
  const auto above = intersect(SphereShape<3>{Vec3(0, 0, 0.4), 0.6}, w);
  ASSERT_TRUE(above.has_value());
  EXPECT_NEAR(above->overlap, 0.1, 1e-12);
  EXPECT_NEAR((above->normal - Vec3(0, 0, -1)).norm(), 0, 1e-12);
  const auto below = intersect(SphereShape<3>{Vec3(0, 0, -0.4), 0.6}, w);
  ASSERT_TRUE(below.has_value());
  EXPECT_NEAR((below->normal - Vec3(0, 0, 1)).norm(), 0, 1e-12);
  // Smaller than the hole, in its plane: no contact (it passes through).
  EXPECT_FALSE(intersect(SphereShape<3>{Vec3(0, 0, 0), 0.29}, w).has_value());
}

template <int D>
Surface<D> boxSurface(const BoxShape<D>& b) {
  Surface<D> s;
  // One patch per face: axis k at side +-1, the other axes spanning the face.
  for (int k = 0; k < D; ++k) {
    for (int side : {-1, 1}) {
      s.patches.push_back([b, k, side](Real u, Real v) {
        VecD<D> local;
        const Real t[2] = {u, v};
        int m = 0;
        for (int j = 0; j < D; ++j) {
          local[j] = j == k ? side * b.halfExtents[j] : (2 * t[m++] - 1) * b.halfExtents[j];
        }
        return VecD<D>(b.centre + b.axes * local);
      });
    }
  }
  s.onGrainSide = [b](const VecD<D>& x) {
    const VecD<D> p = b.axes.transpose() * (x - b.centre);
    return (p.cwiseAbs() - b.halfExtents).maxCoeff() > 0;
  };
  return s;
}

template <int D>
void box(uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 6; ++i) {
    BoxShape<D> b;
    b.centre = randomUnit<D>(rng) * 0.2;
    b.axes = randomRotation<D>(rng);
    for (int k = 0; k < D; ++k)
      b.halfExtents[k] = std::uniform_real_distribution<Real>(0.3, 1.2)(rng);
    const Surface<D> s = boxSurface(b);
    // Centres inside the solid too: pushed out through the nearest face.
    checkAgainstOracle<D>(b, s, rng, 40);
    checkBounds<D>(bounds(b), s);
  }
}

TEST(PhysicsNarrowPhase, OrientedBox) {
  box<2>(7);
  box<3>(8);
}

template <int D>
void drum(uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (int i = 0; i < 6; ++i) {
    DrumShape<D> d;
    d.centre = randomUnit<D>(rng) * 0.2;
    d.radius = std::uniform_real_distribution<Real>(0.8, 1.5)(rng);
    Surface<D> s;
    s.periodicU = true;
    if constexpr (D == 2) {
      s.patches.push_back([d](Real u, Real) {
        return Vec2(d.centre + d.radius * Vec2(std::cos(2 * kPi * u), std::sin(2 * kPi * u)));
      });
      s.onGrainSide = [d](const Vec2& x) { return (x - d.centre).norm() <= d.radius; };
    } else {
      d.axis = randomUnit<3>(rng);
      d.halfLength = std::uniform_real_distribution<Real>(0.5, 1.5)(rng);
      const Vec3 e1 = d.axis.unitOrthogonal(), e2 = d.axis.cross(e1);
      s.patches.push_back([d, e1, e2](Real u, Real v) {
        const Real ph = 2 * kPi * u;
        return Vec3(d.centre + (2 * v - 1) * d.halfLength * d.axis +
                    d.radius * (std::cos(ph) * e1 + std::sin(ph) * e2));
      });
      s.onGrainSide = [d](const Vec3& x) {
        const Vec3 e = x - d.centre;
        return (e - e.dot(d.axis) * d.axis).norm() <= d.radius;
      };
    }
    // The mantle only: grains whose centres lie beyond the ends are not its business (the
    // caps are separate walls), so the 3D oracle draws centres within the length.
    std::uniform_real_distribution<Real> u(-1, 1), radius(0.05, 0.6);
    const Real tol = 1e-6;
    int contacts = 0, misses = 0;
    for (int c = 0; c < 60; ++c) {
      VecD<D> x = nearSurface(s, rng, 0.8);
      if constexpr (D == 3) x += 0.3 * u(rng) * d.axis;  // some beyond the ends
      if constexpr (D == 3) {
        const Real z = (x - d.centre).dot(d.axis);
        if (std::abs(z) > d.halfLength) {
          const SphereShape<D> grain{x, 0.3};
          EXPECT_FALSE(intersect(grain, d).has_value());
          continue;
        }
      }
      const SphereShape<D> grain{x, radius(rng)};
      // The nearest mantle point for a centre within the length is on the same cross-section.
      const Real sd = signedDistance(s, x);
      const Real want = grain.radius - sd;
      const auto got = intersect(grain, d);
      if (std::abs(want) < 10 * tol) continue;
      if (want < 0) {
        EXPECT_FALSE(got.has_value()) << c;
        ++misses;
        continue;
      }
      ++contacts;
      ASSERT_TRUE(got.has_value()) << c;
      EXPECT_NEAR(got->overlap, want, tol);
      const VecD<D> q = x + got->normal * (grain.radius - got->overlap);
      if (std::abs(sd) > 1e-3) {
        EXPECT_LT(std::abs(signedDistance(s, q)), tol);
      }
    }
    EXPECT_GE(contacts, 3);
    EXPECT_GE(misses, 3);
    checkBounds<D>(bounds(d), s);
  }
}

TEST(PhysicsNarrowPhase, Drum) {
  drum<2>(9);
  drum<3>(10);
}

TEST(PhysicsNarrowPhase, PlaneBounds) {
  const Real inf = std::numeric_limits<Real>::infinity();
  const Bounds<3> floor = bounds(PlaneShape<3>{Vec3(0, 0, 2), Vec3(0, 0, 1)});
  EXPECT_EQ(floor.lo[2], -inf);
  EXPECT_EQ(floor.hi[2], 2);
  EXPECT_EQ(floor.lo[0], -inf);
  EXPECT_EQ(floor.hi[1], inf);
  const Bounds<2> wall = bounds(PlaneShape<2>{Vec2(3, 0), Vec2(-1, 0)});
  EXPECT_EQ(wall.lo[0], 3);
  EXPECT_EQ(wall.hi[0], inf);
  const Bounds<2> tilted = bounds(PlaneShape<2>{Vec2(3, 0), Vec2(1, 1).normalized()});
  EXPECT_EQ(tilted.lo[0], -inf);
  EXPECT_EQ(tilted.hi[1], inf);
  // Clipped to a domain: brute force over a grid of the domain.
  std::mt19937_64 rng(11);
  for (int i = 0; i < 20; ++i) {
    const PlaneShape<3> p{randomUnit<3>(rng) * 0.5, randomUnit<3>(rng)};
    const Bounds<3> domain{{-1, -0.5, -2}, {1, 1.5, 0.5}};
    const Bounds<3> got = boundsWithin(p, domain);
    Vec3 lo = Vec3::Constant(inf), hi = -lo;
    const int n = 60;
    for (int a = 0; a <= n; ++a) {
      for (int b = 0; b <= n; ++b) {
        for (int c = 0; c <= n; ++c) {
          Vec3 x;
          const int idx[3] = {a, b, c};
          for (int k = 0; k < 3; ++k)
            x[k] = domain.lo[k] + (domain.hi[k] - domain.lo[k]) * idx[k] / n;
          if ((x - p.point).dot(p.normal) <= 0) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
        }
      }
    }
    if (lo[0] == inf) continue;  // plane misses the domain on the grid
    for (int k = 0; k < 3; ++k) {
      const Real step = (domain.hi[k] - domain.lo[k]) / n;
      EXPECT_LE(got.lo[k], lo[k] + 1e-12);
      EXPECT_GE(got.hi[k], hi[k] - 1e-12);
      EXPECT_GE(got.lo[k], lo[k] - 2 * step - 0.05);
      EXPECT_LE(got.hi[k], hi[k] + 2 * step + 0.05);
    }
  }
}

TEST(PhysicsNarrowPhase, TableRowsAndBatch) {
  for (const NarrowPhaseRow<3>& row : narrowPhaseRows<3>()) EXPECT_EQ(row.a, "sphere");
  TypeRegistry types("geometry type");
  const TypeId plane = types.add("plane");  // an existing type keeps its id
  TypeInteractionManager<NarrowPhaseEntry<3>> table(types, "intersection routine");
  registerNarrowPhase<3>(types, table);
  EXPECT_EQ(types.get("plane"), plane);
  EXPECT_EQ(table.pairs().size(), narrowPhaseRows<3>().size());
  const TypeId sphere = types.get("sphere"), box = types.get("box");
  // Mirror cell: (plane, sphere) is served with the objects swapped back.
  const SphereShape<3> s{Vec3(0, 0, 0.5), 1};
  const PlaneShape<3> p{Vec3::Zero(), Vec3::UnitZ()};
  const auto c =
      table.dispatch(plane, sphere, static_cast<const void*>(&p), static_cast<const void*>(&s));
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(c->overlap, 0.5, 1e-15);
  EXPECT_TRUE(table.find(plane, sphere)->swapped());
  EXPECT_THROW(registerNarrowPhase<3>(types, table), Error);
  // The batch routine equals the single one.
  BoxShape<3> b{Vec3(0.1, 0.2, 0.3), AngleAxis(0.4, Vec3(1, 1, 0).normalized()).toRotationMatrix(),
                Vec3(0.5, 0.7, 0.2)};
  std::mt19937_64 rng(12);
  std::vector<Vec3> centres(200);
  std::vector<Real> radii(200);
  std::vector<uint32_t> which;
  for (size_t i = 0; i < centres.size(); ++i) {
    centres[i] = b.centre + randomUnit<3>(rng) * 0.8;
    radii[i] = 0.2;
    if (i % 3 != 0) which.push_back(uint32_t(i));
  }
  std::vector<ContactGeometry<3>> out(which.size());
  std::vector<uint32_t> touched(which.size());
  const size_t m = table.get(sphere, box)
                       .fn.grains(&b, centres.data(), radii.data(), which.data(), which.size(),
                                  out.data(), touched.data());
  size_t k = 0;
  for (uint32_t i : which) {
    const auto one = intersect(SphereShape<3>{centres[i], radii[i]}, b);
    if (!one) continue;
    ASSERT_LT(k, m);
    EXPECT_EQ(touched[k], i);
    EXPECT_EQ(out[k].overlap, one->overlap);
    ++k;
  }
  EXPECT_EQ(k, m);
  EXPECT_GT(m, 10u);
}

}  // namespace physics_narrow_phase_test
}  // namespace demlab::physics
