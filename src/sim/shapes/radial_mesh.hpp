// The renderer's mesh of a star-shaped body (ShapeType::renderTriangles): a latitude-longitude
// grid of directions mapped to surface points.
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include "core/math.hpp"

namespace demlab::sim {

// Appends the triangles of the surface pointAt(u) over unit directions u on an nu x nt grid of
// polar and azimuthal angles (the poles' rows as fans).
template <class F>
void appendRadialMesh(std::vector<Vec3>& out, int nu, int nt, F&& pointAt) {
  const Real pi = std::numbers::pi;
  const auto at = [&](int i, int j) {
    const Real u = pi * i / nu, t = 2 * pi * j / nt;
    return Vec3(pointAt(Vec3(std::cos(t) * std::sin(u), std::sin(t) * std::sin(u), std::cos(u))));
  };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nt; ++j) {
      const Vec3 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      if (i > 0) out.insert(out.end(), {a, b, d});
      if (i + 1 < nu) out.insert(out.end(), {b, c, d});
    }
  }
}

// Appends the triangles of a ball of radius r about c: a fan of 32 in 2D (z = 0), a radial mesh
// in 3D. What snapshots draw for a ball inside another shape (a clump's or an assembly's).
template <int D>
void appendBallTriangles(std::vector<Vec3>& out, const VecD<D>& c, Real r) {
  const Real pi = std::numbers::pi;
  if constexpr (D == 2) {
    const int n = 32;
    for (int i = 0; i < n; ++i) {
      const Real a0 = 2 * pi * i / n, a1 = 2 * pi * (i + 1) / n;
      out.emplace_back(c.x(), c.y(), 0);
      out.emplace_back(c.x() + r * std::cos(a0), c.y() + r * std::sin(a0), 0);
      out.emplace_back(c.x() + r * std::cos(a1), c.y() + r * std::sin(a1), 0);
    }
  } else {
    appendRadialMesh(out, 8, 16, [&](const Vec3& d) { return Vec3(c + r * d); });
  }
}

}  // namespace demlab::sim
