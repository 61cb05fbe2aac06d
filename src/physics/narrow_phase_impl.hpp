// Inline bodies of the intersect() routines declared in narrow_phase.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>

#include "physics/contact.hpp"
#include "physics/shapes.hpp"

namespace demlab::physics {

namespace detail {

// Returns the contact of grain a whose centre is at distance `dist` from the nearest point of
// B along the unit normal n (grain to B), overlap = radius - dist.
template <int D>
inline ContactGeometry<D> makeContact(const SphereShape<D>& a, const VecD<D>& n, Real overlap) {
  return ContactGeometry<D>{n, overlap, a.centre + (a.radius - 0.5 * overlap) * n};
}

// Returns a unit vector normal to the flat wall w (for a grain centred exactly on it).
template <int D>
inline VecD<D> flatWallNormal(const FlatWallShape<D>& w) {
  if constexpr (D == 2) {
    return perp(w.axes[0]);
  } else {
    return w.axes[0].cross(w.axes[1]).normalized();
  }
}

// Returns the contact of grain a with the point q (the nearest point of a wall), or nothing;
// fallback: the normal used if the centre lies exactly at q.
template <int D>
inline std::optional<ContactGeometry<D>> touchPoint(const SphereShape<D>& a, const VecD<D>& q,
                                                    const VecD<D>& fallback) {
  const VecD<D> e = q - a.centre;
  const Real d2 = e.squaredNorm();
  if (d2 >= a.radius * a.radius) return std::nullopt;
  if (d2 == 0) return makeContact(a, fallback, a.radius);
  const Real d = std::sqrt(d2);
  return makeContact<D>(a, e / d, a.radius - d);
}

}  // namespace detail

template <int D>
inline std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a,
                                                   const SphereShape<D>& b) {
  const VecD<D> e = b.centre - a.centre;
  const Real rs = a.radius + b.radius;
  const Real d2 = e.squaredNorm();
  if (d2 >= rs * rs) return std::nullopt;
  // Coincident centres: any direction separates them; the first axis, deterministically.
  if (d2 == 0) return detail::makeContact<D>(a, VecD<D>::Unit(0), rs);
  const Real d = std::sqrt(d2);
  return detail::makeContact<D>(a, e / d, rs - d);
}

template <int D>
inline std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a,
                                                   const PlaneShape<D>& b) {
  const Real h = (a.centre - b.point).dot(b.normal);
  if (h >= a.radius) return std::nullopt;
  return detail::makeContact<D>(a, -b.normal, a.radius - h);
}

template <int D>
inline std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a,
                                                   const FlatWallShape<D>& b) {
  const VecD<D> v = a.centre - b.centre;
  if (b.hole > 0) {
    // Over the hole the nearest point is on its rim, straight out from the axis: the grain is
    // pushed away from that rim point, never by the face as well (one nearest point, one
    // contact). Outside the hole the nearest point of the whole wall is also the holed wall's.
    VecD<D> inPlane = VecD<D>::Zero();
    for (int i = 0; i < D - 1; ++i) inPlane += v.dot(b.axes[i]) * b.axes[i];
    const Real rho2 = inPlane.squaredNorm();
    if (rho2 < b.hole * b.hole) {
      if (rho2 > 0)
        return detail::touchPoint<D>(a, b.centre + inPlane * (b.hole / std::sqrt(rho2)),
                                     -detail::flatWallNormal(b));
      // On the hole's axis every rim point is as near: the rim's net push is along the axis.
      const VecD<D> n = detail::flatWallNormal(b);
      const Real h = v.dot(n);
      const Real dist = std::sqrt(b.hole * b.hole + h * h);
      if (dist >= a.radius) return std::nullopt;
      return detail::makeContact<D>(a, h >= 0 ? VecD<D>(-n) : n, a.radius - dist);
    }
  }
  VecD<D> q = b.centre;
  for (int i = 0; i < D - 1; ++i) {
    const Real s = std::clamp(v.dot(b.axes[i]), -b.halfExtents[i], b.halfExtents[i]);
    q += s * b.axes[i];
  }
  // A grain centred on the wall is pushed out along +wall normal (arbitrary but fixed).
  return detail::touchPoint<D>(a, q, -detail::flatWallNormal(b));
}

template <int D>
inline std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a, const BoxShape<D>& b) {
  const VecD<D> p = b.axes.transpose() * (a.centre - b.centre);  // centre in box coordinates
  bool inside = true;
  VecD<D> q;
  for (int k = 0; k < D; ++k) {
    q[k] = std::clamp(p[k], -b.halfExtents[k], b.halfExtents[k]);
    inside = inside && q[k] == p[k];
  }
  if (!inside) {
    const VecD<D> e = q - p;  // from the centre to the nearest surface point, box coordinates
    const Real d2 = e.squaredNorm();
    if (d2 >= a.radius * a.radius) return std::nullopt;
    const Real d = std::sqrt(d2);
    return detail::makeContact<D>(a, b.axes * (e / d), a.radius - d);
  }
  // Centre inside the solid: push the grain out through the nearest face.
  int best = 0;
  Real depth = b.halfExtents[0] - std::abs(p[0]);
  for (int k = 1; k < D; ++k) {
    const Real dk = b.halfExtents[k] - std::abs(p[k]);
    if (dk < depth) depth = dk, best = k;
  }
  const VecD<D> outward = (p[best] < 0 ? -1.0 : 1.0) * b.axes.col(best);
  return detail::makeContact<D>(a, -outward, a.radius + depth);
}

template <int D>
inline std::optional<ContactGeometry<D>> intersect(const SphereShape<D>& a, const DrumShape<D>& b) {
  VecD<D> e = a.centre - b.centre;
  if constexpr (D == 3) {
    const Real z = e.dot(b.axis);
    if (std::abs(z) > b.halfLength) return std::nullopt;
    e -= z * b.axis;
  }
  const Real rho2 = e.squaredNorm();
  const Real inner = b.radius - a.radius;  // the grain touches once its centre is beyond this
  if (inner > 0 && rho2 <= inner * inner) return std::nullopt;
  if (rho2 == 0) {
    // A grain as wide as the drum, centred on its axis: any radial direction.
    VecD<D> n = VecD<D>::Unit(0);
    if constexpr (D == 3) {
      n -= n.dot(b.axis) * b.axis;
      if (n.squaredNorm() < 0.25) n = VecD<D>::Unit(1) - b.axis[1] * b.axis;
      n.normalize();
    }
    return detail::makeContact<D>(a, n, a.radius - b.radius);
  }
  const Real rho = std::sqrt(rho2);
  return detail::makeContact<D>(a, e / rho, rho + a.radius - b.radius);
}

}  // namespace demlab::physics
