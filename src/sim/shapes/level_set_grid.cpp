// The level set's grid (sim/shapes/level_set.hpp): its parameters checked, its interpolation,
// the surface of its zero level set and the surface nodes.
#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "core/error.hpp"
#include "core/validity.hpp"
#include "sim/shapes/level_set.hpp"
#include "sim/shapes/level_set_internal.hpp"

namespace demlab::sim {

namespace {

[[noreturn]] void bad(const std::string& why) {
  throw Error("bad shape parameters: the level set " + why, {"VALUE", "SHAPE"});
}

}  // namespace

template <int D>
size_t nodeCount(const std::array<int, D>& n) {
  size_t c = 1;
  for (int k : n) c *= static_cast<size_t>(k);
  return c;
}

template <int D>
std::array<int, D> nodeIndex(size_t i, const std::array<int, D>& n) {
  std::array<int, D> ix{};
  for (int d = 0; d < D; ++d) {
    ix[d] = static_cast<int>(i % static_cast<size_t>(n[d]));
    i /= static_cast<size_t>(n[d]);
  }
  return ix;
}

template <int D>
Polytope<D> zeroLevelSurface(Real h, const std::array<int, D>& n, const VecD<D>& origin,
                             std::span<const double> values) {
  Polytope<D> out;
  // One vertex per grid edge (or cell diagonal) the surface crosses, shared by the simplices
  // around it: keyed by its two nodes.
  std::unordered_map<uint64_t, uint32_t> crossing;
  const auto node = [&](size_t i) {
    const std::array<int, D> ix = nodeIndex<D>(i, n);
    VecD<D> p;
    for (int d = 0; d < D; ++d) p[d] = origin[d] + h * ix[d];
    return p;
  };
  const auto vertex = [&](size_t a, size_t b) {  // values[a] < 0 <= values[b]
    const uint64_t key = static_cast<uint64_t>(std::min(a, b)) << 32 | std::max(a, b);
    auto [it, added] = crossing.try_emplace(key, static_cast<uint32_t>(out.vertices.size()));
    if (added) {
      const Real t = values[a] / (values[a] - values[b]);
      out.vertices.push_back(node(a) + t * (node(b) - node(a)));
    }
    return it->second;
  };
  // Adds the face through vertices f, turned so that its normal points from the inside corners'
  // centroid to the outside ones'.
  const auto addFace = [&](std::array<uint32_t, D> f, const VecD<D>& outward) {
    const auto& v = out.vertices;
    VecD<D> normal;
    if constexpr (D == 3) {
      normal = (v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]);
    } else {
      const Vec2 e = v[f[1]] - v[f[0]];
      normal = Vec2(e.y(), -e.x());
    }
    if (normal.dot(outward) < 0) {
      std::swap(f[0], f[1]);
      normal = -normal;
    }
    typename Polytope<D>::Face face;
    face.loop.assign(f.begin(), f.end());
    const Real len = normal.norm();
    face.normal = len > 0 ? VecD<D>(normal / len) : VecD<D>(outward.normalized());
    face.offset = face.normal.dot(v[f[0]]);
    out.faces.push_back(std::move(face));
  };
  // The cells' Kuhn simplices: corners 0, e_a, e_a + e_b (, all) for each order of the axes.
  std::vector<std::array<int, D + 1>> simplices;
  {
    std::array<int, D> axes{};
    for (int d = 0; d < D; ++d) axes[d] = d;
    do {
      std::array<int, D + 1> s{};
      int bits = 0;
      s[0] = 0;
      for (int d = 0; d < D; ++d) s[d + 1] = bits |= 1 << axes[d];
      simplices.push_back(s);
    } while (std::next_permutation(axes.begin(), axes.end()));
  }
  std::array<size_t, D> stride{};
  stride[0] = 1;
  for (int d = 1; d < D; ++d) stride[d] = stride[d - 1] * static_cast<size_t>(n[d - 1]);
  const size_t total = nodeCount<D>(n);
  for (size_t base = 0; base < total; ++base) {
    const std::array<int, D> ix = nodeIndex<D>(base, n);
    bool interior = true;
    for (int d = 0; d < D; ++d) interior = interior && ix[d] + 1 < n[d];
    if (!interior) continue;
    std::array<size_t, 1 << D> corner{};
    bool any = false, all = true;
    for (int c = 0; c < (1 << D); ++c) {
      size_t k = base;
      for (int d = 0; d < D; ++d) {
        if (c >> d & 1) k += stride[d];
      }
      corner[c] = k;
      any = any || values[k] < 0;
      all = all && values[k] < 0;
    }
    if (!any || all) continue;
    for (const auto& s : simplices) {
      std::array<size_t, D + 1> in{}, outs{};
      int ni = 0, no = 0;
      VecD<D> cin = VecD<D>::Zero(), cout = VecD<D>::Zero();
      for (int k = 0; k <= D; ++k) {
        const size_t g = corner[s[k]];
        if (values[g] < 0) {
          in[ni++] = g, cin += node(g);
        } else {
          outs[no++] = g, cout += node(g);
        }
      }
      if (ni == 0 || no == 0) continue;
      const VecD<D> outward = cout / no - cin / ni;
      if constexpr (D == 2) {
        // One inside corner, or one outside: a segment between the two crossings.
        if (ni == 1) {
          addFace({vertex(in[0], outs[0]), vertex(in[0], outs[1])}, outward);
        } else {
          addFace({vertex(in[0], outs[0]), vertex(in[1], outs[0])}, outward);
        }
      } else {
        if (ni == 1) {
          addFace({vertex(in[0], outs[0]), vertex(in[0], outs[1]), vertex(in[0], outs[2])}, outward);
        } else if (no == 1) {
          addFace({vertex(in[0], outs[0]), vertex(in[1], outs[0]), vertex(in[2], outs[0])}, outward);
        } else {
          // Two and two: the quadrilateral i0-o0, i0-o1, i1-o1, i1-o0, as two triangles.
          const uint32_t a = vertex(in[0], outs[0]), b = vertex(in[0], outs[1]);
          const uint32_t c = vertex(in[1], outs[1]), d = vertex(in[1], outs[0]);
          addFace({a, b, c}, outward);
          addFace({a, c, d}, outward);
        }
      }
    }
  }
  return out;
}

template <int D>
bool LevelSet<D>::sample(const VecD<D>& x, Real& value, VecD<D>& gradient) const {
  std::array<int, D> c{};
  std::array<Real, D> t{};
  for (int d = 0; d < D; ++d) {
    Real u = (x[d] - origin[d]) / h;
    // A point on the grid's border may round to just beyond it.
    if (u < 0 && u > -1e-9) u = 0;
    if (u > n[d] - 1 && u < n[d] - 1 + 1e-9) u = n[d] - 1;
    if (!(u >= 0 && u <= n[d] - 1)) return false;
    c[d] = std::min(static_cast<int>(u), n[d] - 2);
    t[d] = u - c[d];
  }
  size_t base = 0, stride = 1;
  std::array<size_t, D> step{};
  for (int d = 0; d < D; ++d) {
    base += static_cast<size_t>(c[d]) * stride;
    step[d] = stride;
    stride *= static_cast<size_t>(n[d]);
  }
  value = 0;
  gradient = VecD<D>::Zero();
  for (int k = 0; k < (1 << D); ++k) {
    size_t g = base;
    Real w = 1;
    std::array<Real, D> dw{};
    for (int d = 0; d < D; ++d) {
      const bool up = k >> d & 1;
      if (up) g += step[d];
      const Real wd = up ? t[d] : 1 - t[d];
      w *= wd;
    }
    // d w / d x_d: the factor of axis d replaced by its derivative (+-1/h).
    for (int d = 0; d < D; ++d) {
      Real p = (k >> d & 1) ? 1 / h : -1 / h;
      for (int e = 0; e < D; ++e) {
        if (e != d) p *= (k >> e & 1) ? t[e] : 1 - t[e];
      }
      dw[d] = p;
    }
    value += w * phi[g];
    for (int d = 0; d < D; ++d) gradient[d] += dw[d] * phi[g];
  }
  return true;
}

template <int D>
LevelSet<D> buildLevelSet(std::span<const double> p) {
  LevelSet<D> ls;
  if (p.size() < static_cast<size_t>(1 + 2 * D)) {
    bad("needs h, " + std::to_string(D) + " node counts, the first node's " + std::to_string(D) +
        " coordinates, then a value per node (got " + std::to_string(p.size()) + " numbers)");
  }
  ls.h = p[0];
  if (!(ls.h >= validity::kMinRadius && ls.h <= validity::kMaxRadius)) {
    bad("spacing must lie in [" + std::to_string(validity::kMinRadius) + ", " +
        std::to_string(validity::kMaxRadius) + "] m");
  }
  size_t total = 1;
  for (int d = 0; d < D; ++d) {
    const double c = p[1 + d];
    if (!(c == std::floor(c) && c >= kLevelSetMinNodes && c <= kLevelSetMaxNodesPerAxis)) {
      bad("node counts must be whole numbers from " + std::to_string(kLevelSetMinNodes) + " to " +
          std::to_string(kLevelSetMaxNodesPerAxis));
    }
    ls.n[d] = static_cast<int>(c);
    total *= static_cast<size_t>(ls.n[d]);
    const double o = p[1 + D + d];
    if (!(std::abs(o) <= validity::kMaxCoordinate)) bad("first node's position must be finite");
    ls.origin[d] = o;
  }
  if (total > kLevelSetMaxNodes) {
    bad("grid has " + std::to_string(total) + " nodes, more than " +
        std::to_string(kLevelSetMaxNodes));
  }
  if (p.size() != 1 + 2 * D + total) {
    bad("grid of " + std::to_string(total) + " nodes needs " + std::to_string(total) +
        " values (got " + std::to_string(p.size() - 1 - 2 * D) + ")");
  }
  Real diagonal = 0;
  for (int d = 0; d < D; ++d) diagonal += std::pow(ls.h * (ls.n[d] - 1), 2);
  diagonal = std::sqrt(diagonal);
  ls.phi.assign(p.begin() + 1 + 2 * D, p.end());
  bool inside = false;
  for (size_t i = 0; i < total; ++i) {
    const Real v = ls.phi[i];
    if (!(std::abs(v) <= 2 * diagonal)) {
      bad("value " + std::to_string(v) + " at node " + std::to_string(i) +
          " is not a finite distance within the grid");
    }
    inside = inside || v < 0;
    const std::array<int, D> ix = nodeIndex<D>(i, ls.n);
    bool border = false;
    for (int d = 0; d < D; ++d) border = border || ix[d] == 0 || ix[d] == ls.n[d] - 1;
    if (border && !(v > 0)) {
      bad("touches its grid's border at node " + std::to_string(i) +
          " (every border node must be outside, phi > 0)");
    }
  }
  if (!inside) bad("has no node inside (phi < 0 nowhere)");
  ls.surface = zeroLevelSurface<D>(ls.h, ls.n, ls.origin, ls.phi);
  // The surface nodes: where each grid line crosses the surface, in grid order.
  size_t stride = 1;
  for (int d = 0; d < D; ++d) {
    for (size_t i = 0; i < total; ++i) {
      const std::array<int, D> ix = nodeIndex<D>(i, ls.n);
      if (ix[d] + 1 >= ls.n[d]) continue;
      const Real a = ls.phi[i], b = ls.phi[i + stride];
      if ((a < 0) == (b < 0)) continue;
      VecD<D> x;
      for (int e = 0; e < D; ++e) x[e] = ls.origin[e] + ls.h * ix[e];
      x[d] += ls.h * a / (a - b);
      ls.nodes.push_back(x);
    }
    stride *= static_cast<size_t>(ls.n[d]);
  }
  return ls;
}

#define DEMLAB_LEVEL_SET(D)                                                                   \
  template size_t nodeCount<D>(const std::array<int, D>&);                                    \
  template std::array<int, D> nodeIndex<D>(size_t, const std::array<int, D>&);                \
  template Polytope<D> zeroLevelSurface<D>(Real, const std::array<int, D>&, const VecD<D>&,   \
                                           std::span<const double>);                          \
  template struct LevelSet<D>;                                                                \
  template LevelSet<D> buildLevelSet<D>(std::span<const double>);
DEMLAB_LEVEL_SET(2)
DEMLAB_LEVEL_SET(3)
#undef DEMLAB_LEVEL_SET

}  // namespace demlab::sim
