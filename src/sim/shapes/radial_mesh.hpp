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

}  // namespace demlab::sim
