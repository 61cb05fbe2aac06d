// Contact between convex polytopes by separating axes and face clipping
// (sim/shapes/polytope.hpp), and between a ball and a polytope.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "sim/shapes/convex_contact.hpp"
#include "sim/shapes/polytope.hpp"

namespace demlab::sim {

namespace {

// A feature number from its parts: which body holds the reference face, the two faces, and the
// point's label from the clipping.
uint32_t faceFeature(bool refOnB, size_t ref, size_t inc, uint32_t label) {
  return (refOnB ? 0x40000000u : 0u) | (static_cast<uint32_t>(ref & 63) << 24) |
         (static_cast<uint32_t>(inc & 63) << 18) | (label & 0x3ffffu);
}

// The least separation of b's corners from a's face planes: the deepest face of a.
template <int D>
void faceQuery(const Polytope<D>& a, std::span<const VecD<D>> wa, std::span<const VecD<D>> na,
               std::span<const VecD<D>> wb, Real& best, size_t& face) {
  best = -std::numeric_limits<Real>::infinity();
  face = 0;
  for (size_t f = 0; f < a.faces.size(); ++f) {
    const VecD<D>& n = na[f];
    const Real o = n.dot(wa[a.faces[f].loop[0]]);
    Real s = std::numeric_limits<Real>::infinity();
    for (const VecD<D>& q : wb) s = std::min(s, n.dot(q) - o);
    if (s > best) best = s, face = f;
  }
}

// Returns the lowest and highest projections of pts on axis.
template <int D>
std::pair<Real, Real> project(std::span<const VecD<D>> pts, const VecD<D>& axis) {
  Real lo = std::numeric_limits<Real>::infinity(), hi = -lo;
  for (const VecD<D>& p : pts) {
    const Real s = axis.dot(p);
    lo = std::min(lo, s), hi = std::max(hi, s);
  }
  return {lo, hi};
}

// A point of the clipped incident face, with its label: a corner k of the incident face keeps
// k; a point cut by a side plane gets a label mixed from the plane and the edge's first point.
struct Clipped3 {
  Vec3 p;
  uint32_t label;
};

// Sutherland-Hodgman: keeps the part of poly with side . (x - o) <= 0.
void clipPolygon(std::vector<Clipped3>& poly, const Vec3& side, const Vec3& o, uint32_t plane,
                 std::vector<Clipped3>& out) {
  out.clear();
  const size_t n = poly.size();
  for (size_t k = 0; k < n; ++k) {
    const Clipped3& a = poly[k];
    const Clipped3& b = poly[(k + 1) % n];
    const Real da = side.dot(a.p - o), db = side.dot(b.p - o);
    if (da <= 0) out.push_back(a);
    if ((da <= 0) != (db <= 0)) {
      const Real t = da / (da - db);
      out.push_back({Vec3(a.p + t * (b.p - a.p)),
                     0x20000u | ((a.label * 37u + plane * 7u + 1u) & 0x1ffffu)});
    }
  }
  poly.swap(out);
}

}  // namespace

template <int D>
int polytopeContact(const Polytope<D>& a, std::span<const VecD<D>> wa, std::span<const VecD<D>> na,
                    const Polytope<D>& b, std::span<const VecD<D>> wb, std::span<const VecD<D>> nb,
                    ContactPoint<D>* out) {
  Real sepA, sepB;
  size_t faceA, faceB;
  faceQuery(a, wa, na, wb, sepA, faceA);
  if (sepA > 0) return 0;
  faceQuery(b, wb, nb, wa, sepB, faceB);
  if (sepB > 0) return 0;
  // 3D: the edges' cross products, each the separation of the two sets along it in the
  // direction that separates them best.
  Real sepE = -std::numeric_limits<Real>::infinity();
  size_t edgeA = 0, edgeB = 0;
  VecD<D> axisE = VecD<D>::Zero();
  if constexpr (D == 3) {
    for (size_t i = 0; i < a.edges.size(); ++i) {
      const Vec3 da = wa[a.edges[i].b] - wa[a.edges[i].a];
      for (size_t j = 0; j < b.edges.size(); ++j) {
        const Vec3 db = wb[b.edges[j].b] - wb[b.edges[j].a];
        Vec3 axis = da.cross(db);
        const Real len = axis.norm();
        if (!(len > 1e-6 * da.norm() * db.norm())) continue;  // parallel: a face axis covers it
        axis /= len;
        const auto [loA, hiA] = project<3>(wa, axis);
        const auto [loB, hiB] = project<3>(wb, axis);
        const Real up = loB - hiA, down = loA - hiB;  // b above a along axis; below
        const Real s = std::max(up, down);
        if (s > 0) return 0;
        if (!(s > sepE)) continue;
        // Parallel edges give the same axis: the pair is the contact only if both edges are
        // where the bodies meet (a's at its extreme towards b, b's at its extreme towards a).
        const Real tol = 1e-9 * (hiA - loA + hiB - loB);
        const Real topA = up >= down ? hiA : loA, topB = up >= down ? loB : hiB;
        const auto at = [&](const Vec3& x, Real level) { return std::abs(axis.dot(x) - level) <= tol; };
        if (!(at(wa[a.edges[i].a], topA) && at(wa[a.edges[i].b], topA) &&
              at(wb[b.edges[j].a], topB) && at(wb[b.edges[j].b], topB))) {
          continue;
        }
        sepE = s, edgeA = i, edgeB = j, axisE = up >= down ? axis : Vec3(-axis);
      }
    }
  }
  // The reference: a face unless an edge pair overlaps clearly less (5 %), and b's face over
  // a's only when clearly better (2 %), so the choice does not flip between equal candidates.
  const Real faceBest = std::max(sepA, sepB);
  if constexpr (D == 3) {
    if (sepE > 0.95 * faceBest) {
      const Vec3 p1 = wa[a.edges[edgeA].a], q1 = wb[b.edges[edgeB].a];
      const Vec3 d1 = wa[a.edges[edgeA].b] - p1, d2 = wb[b.edges[edgeB].b] - q1;
      // The closest points of the two segments.
      const Vec3 r = p1 - q1;
      const Real aa = d1.dot(d1), ee = d2.dot(d2), f = d2.dot(r), c = d1.dot(r), bb = d1.dot(d2);
      const Real denom = aa * ee - bb * bb;
      Real s = denom > 0 ? std::clamp((bb * f - c * ee) / denom, Real{0}, Real{1}) : 0;
      Real t = (bb * s + f) / ee;
      if (t < 0) t = 0, s = std::clamp(-c / aa, Real{0}, Real{1});
      else if (t > 1) t = 1, s = std::clamp((bb - c) / aa, Real{0}, Real{1});
      const Vec3 pa = p1 + s * d1, pb = q1 + t * d2;
      out[0].g = {axisE, -sepE, Vec3(0.5 * (pa + pb))};
      out[0].feature = 0x80000000u | static_cast<uint32_t>((edgeA & 0x7fff) << 15 | (edgeB & 0x7fff));
      return 1;
    }
  }
  const bool refOnB = sepB > 0.98 * sepA;  // both <= 0: b's is shallower by 2 %
  const Polytope<D>& rp = refOnB ? b : a;
  const Polytope<D>& ip = refOnB ? a : b;
  const std::span<const VecD<D>> rw = refOnB ? wb : wa, iw = refOnB ? wa : wb;
  const std::span<const VecD<D>> rn = refOnB ? nb : na, in = refOnB ? na : nb;
  const size_t ref = refOnB ? faceB : faceA;
  const VecD<D> n = rn[ref];
  // The incident face: the other body's face most opposed to the reference normal.
  size_t inc = 0;
  Real most = std::numeric_limits<Real>::infinity();
  for (size_t f = 0; f < ip.faces.size(); ++f) {
    const Real d = in[f].dot(n);
    if (d < most) most = d, inc = f;
  }
  const std::vector<uint32_t>& rl = rp.faces[ref].loop;
  const std::vector<uint32_t>& il = ip.faces[inc].loop;
  const Real offset = n.dot(rw[rl[0]]);
  int count = 0;
  const auto emit = [&](const VecD<D>& p, uint32_t label) {
    const Real depth = offset - n.dot(p);
    if (!(depth > 0) || count == kMaxContactPoints) return;
    ContactPoint<D>& c = out[count++];
    c.g = {refOnB ? VecD<D>(-n) : n, depth, VecD<D>(p + 0.5 * depth * n)};
    c.feature = faceFeature(refOnB, ref, inc, label);
  };
  if constexpr (D == 2) {
    // Clip the incident edge to the reference edge's span.
    const Vec2 r0 = rw[rl[0]], r1 = rw[rl[1]], e = r1 - r0;
    Vec2 p0 = iw[il[0]], p1 = iw[il[1]];
    uint32_t l0 = 0, l1 = 1;
    const Real len2 = e.squaredNorm();
    Real t0 = (p0 - r0).dot(e) / len2, t1 = (p1 - r0).dot(e) / len2;
    const Vec2 q0 = p0, q1 = p1;
    const auto at = [&](Real t) {  // the incident edge's point whose projection is t
      return Vec2(q0 + (t - t0) / (t1 - t0) * (q1 - q0));
    };
    if (t0 < 0 && t1 >= 0) p0 = at(0), l0 = 2;
    if (t0 > 1 && t1 <= 1) p0 = at(1), l0 = 3;
    if (t1 < 0 && t0 >= 0) p1 = at(0), l1 = 2;
    if (t1 > 1 && t0 <= 1) p1 = at(1), l1 = 3;
    if ((t0 < 0 && t1 < 0) || (t0 > 1 && t1 > 1)) return 0;
    emit(p0, l0);
    emit(p1, l1);
  } else {
    thread_local std::vector<Clipped3> poly, scratch;
    poly.clear();
    for (uint32_t k = 0; k < il.size(); ++k) poly.push_back({iw[il[k]], k});
    for (size_t k = 0; k < rl.size() && !poly.empty(); ++k) {
      const Vec3 r0 = rw[rl[k]], r1 = rw[rl[(k + 1) % rl.size()]];
      clipPolygon(poly, Vec3((r1 - r0).cross(n)), r0, static_cast<uint32_t>(k), scratch);
    }
    for (const Clipped3& c : poly) emit(c.p, c.label);
  }
  if (count == 0) {
    // The incident face missed the overlap (a corner of the other body poking in beside it):
    // that body's deepest corner along the reference normal.
    size_t deepest = 0;
    for (size_t k = 1; k < iw.size(); ++k) {
      if (n.dot(iw[k]) < n.dot(iw[deepest])) deepest = k;
    }
    emit(iw[deepest], 0x30000u | static_cast<uint32_t>(deepest & 0xffff));
  }
  return count;
}

template <int D>
int polytopeGaugeContact(const Polytope<D>& a, std::span<const VecD<D>> wa,
                         std::span<const VecD<D>> na, const PlacedGauge<D>& g, Real reach,
                         ContactPoint<D>* out) {
  Real best = std::numeric_limits<Real>::infinity();
  VecD<D> normal = VecD<D>::Zero();
  // The overlap along n (from a to g) of the two bodies' extents.
  const auto consider = [&](VecD<D> n) {
    const Real len = n.norm();
    if (!(len > 0)) return;
    n /= len;
    Real hi = -std::numeric_limits<Real>::infinity();
    for (const VecD<D>& x : wa) hi = std::max(hi, n.dot(x));
    const Real d = hi - n.dot(g.support(VecD<D>(-n)));
    if (d < best) best = d, normal = n;
  };
  for (const VecD<D>& n : na) {
    consider(n);
    if (best < 0) return 0;  // a face plane separates them
  }
  // g's normal where a's corners lie, and where each edge's point deepest in g's gauge does
  // (the gauge is convex along the edge: golden-section search). They are also how the pair is
  // found apart when no face plane separates it: a meets g only if some point of a lies where
  // g's gauge is below 1, and the least gauge over a is at a corner, on an edge, or inside a
  // face where g scaled about its centre first touches the face's plane. Only features within
  // reach of g's centre can be inside it.
  Real least = std::numeric_limits<Real>::infinity();
  for (const VecD<D>& x : wa) {
    if (!((x - g.centre).norm() < reach)) continue;
    least = std::min(least, g.gauge(x));
    consider(VecD<D>(-g.gaugeGradient(x)));
  }
  const auto edge = [&](const VecD<D>& p, const VecD<D>& q) {
    const VecD<D> d = q - p;
    const Real t0 = std::clamp((g.centre - p).dot(d) / d.squaredNorm(), Real{0}, Real{1});
    if (!((p + t0 * d - g.centre).norm() < reach)) return;
    Real lo = 0, hi = 1;
    const Real r = (std::sqrt(5.0) - 1) / 2;
    for (int it = 0; it < 60 && hi - lo > 1e-12; ++it) {
      const Real x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo);
      // F orders points as the gauge does, at a fraction of its cost (no root).
      if (g.level(VecD<D>(p + x1 * d)) < g.level(VecD<D>(p + x2 * d))) {
        hi = x2;
      } else {
        lo = x1;
      }
    }
    const VecD<D> at = p + 0.5 * (lo + hi) * d;
    least = std::min(least, g.gauge(at));
    consider(VecD<D>(-g.gaugeGradient(at)));
  };
  if constexpr (D == 3) {
    for (const auto& e : a.edges) edge(wa[e.a], wa[e.b]);
  } else {
    for (const auto& f : a.faces) edge(wa[f.loop[0]], wa[f.loop[1]]);
  }
  for (size_t f = 0; f < a.faces.size() && least >= 1; ++f) {
    const VecD<D>& n = na[f];
    const std::vector<uint32_t>& loop = a.faces[f].loop;
    const VecD<D> s = g.support(VecD<D>(-n));
    const Real lambda = n.dot(VecD<D>(wa[loop[0]] - g.centre)) / n.dot(VecD<D>(s - g.centre));
    if (!(lambda > 0)) continue;
    const VecD<D> x = g.centre + lambda * (s - g.centre);
    bool inside = true;
    if constexpr (D == 3) {
      for (size_t k = 0; k < loop.size() && inside; ++k) {
        const Vec3 r0 = wa[loop[k]], r1 = wa[loop[(k + 1) % loop.size()]];
        inside = (r1 - r0).cross(n).dot(x - r0) <= 0;
      }
    } else {
      const Vec2 e = wa[loop[1]] - wa[loop[0]];
      const Real t = e.dot(x - wa[loop[0]]) / e.squaredNorm();
      inside = t >= 0 && t <= 1;
    }
    if (inside) least = std::min(least, lambda);
  }
  if (!(least < 1)) return 0;
  VecD<D> centre = VecD<D>::Zero();
  for (const VecD<D>& x : wa) centre += x;
  consider(VecD<D>(g.centre - centre / static_cast<Real>(wa.size())));
  if (!(best > 0)) return 0;
  out[0].g = {normal, best, VecD<D>(g.support(VecD<D>(-normal)) + 0.5 * best * normal)};
  return 1;
}

template <int D>
bool ballPolytopeContact(const VecD<D>& centre, Real radius, const ElementRef<D>& e,
                         ContactPoint<D>& out) {
  if (!((e.x - centre).norm() < radius + e.r)) return false;
  const Polytope<D>& p = *static_cast<const Polytope<D>*>(e.g->data.get());
  const VecD<D> c = rotateInverse(e.q, VecD<D>(centre - e.x));  // the centre in e's frame
  Real deepest = -std::numeric_limits<Real>::infinity();
  size_t face = 0;
  for (size_t f = 0; f < p.faces.size(); ++f) {
    const Real s = p.faces[f].normal.dot(c) - p.faces[f].offset;
    if (s > deepest) deepest = s, face = f;
  }
  if (deepest >= radius) return false;
  VecD<D> closest, normal;  // in e's frame; normal from e to the ball
  Real dist;
  if (deepest <= 0) {
    normal = p.faces[face].normal;
    dist = deepest;
    closest = c - deepest * normal;
  } else {
    // Outside: the nearest point of the surface, on a face whose plane the centre is above
    // (its projection inside the face) or on an edge (3D) or a side (2D).
    dist = std::numeric_limits<Real>::infinity();
    const auto consider = [&](const VecD<D>& q) {
      const Real d = (c - q).norm();
      if (d < dist) dist = d, closest = q;
    };
    const auto onSegment = [&](const VecD<D>& s0, const VecD<D>& s1) {
      const VecD<D> d = s1 - s0;
      const Real t = std::clamp((c - s0).dot(d) / d.squaredNorm(), Real{0}, Real{1});
      consider(VecD<D>(s0 + t * d));
    };
    for (size_t f = 0; f < p.faces.size(); ++f) {
      const auto& fc = p.faces[f];
      const Real s = fc.normal.dot(c) - fc.offset;
      if (s <= 0) continue;
      if constexpr (D == 3) {
        const Vec3 q = c - s * fc.normal;
        bool inside = true;
        for (size_t k = 0; k < fc.loop.size() && inside; ++k) {
          const Vec3 r0 = p.vertices[fc.loop[k]], r1 = p.vertices[fc.loop[(k + 1) % fc.loop.size()]];
          inside = (r1 - r0).cross(fc.normal).dot(q - r0) <= 0;
        }
        if (inside) consider(q);
      } else {
        onSegment(p.vertices[fc.loop[0]], p.vertices[fc.loop[1]]);
      }
    }
    if constexpr (D == 3) {
      for (const auto& ed : p.edges) onSegment(p.vertices[ed.a], p.vertices[ed.b]);
    }
    if (!(dist < radius) || !(dist > 0)) return false;
    normal = (c - closest) / dist;
  }
  const Real depth = radius - dist;
  const VecD<D> n = rotate(e.q, normal), at = e.x + rotate(e.q, closest);
  // From the ball to e: the reverse of e's outward normal.
  out.g = {VecD<D>(-n), depth, VecD<D>(at - 0.5 * depth * n)};
  const Real rb = volumeEquivalentRadius(*e.g);
  out.effRadius = radius * rb / (radius + rb);
  out.feature = 0;
  return true;
}

template int polytopeContact<2>(const Polytope<2>&, std::span<const Vec2>, std::span<const Vec2>,
                                const Polytope<2>&, std::span<const Vec2>, std::span<const Vec2>,
                                ContactPoint<2>*);
template int polytopeContact<3>(const Polytope<3>&, std::span<const Vec3>, std::span<const Vec3>,
                                const Polytope<3>&, std::span<const Vec3>, std::span<const Vec3>,
                                ContactPoint<3>*);
template int polytopeGaugeContact<2>(const Polytope<2>&, std::span<const Vec2>, std::span<const Vec2>,
                                     const PlacedGauge<2>&, Real, ContactPoint<2>*);
template int polytopeGaugeContact<3>(const Polytope<3>&, std::span<const Vec3>, std::span<const Vec3>,
                                     const PlacedGauge<3>&, Real, ContactPoint<3>*);
template bool ballPolytopeContact<2>(const Vec2&, Real, const ElementRef<2>&, ContactPoint<2>&);
template bool ballPolytopeContact<3>(const Vec3&, Real, const ElementRef<3>&, ContactPoint<3>&);

}  // namespace demlab::sim
