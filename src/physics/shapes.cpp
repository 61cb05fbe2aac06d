// Bounds of the shapes (shapes.hpp).
#include "physics/shapes.hpp"

#include <cmath>

namespace demlab::physics {

namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();

template <int D>
Bounds<D> around(const VecD<D>& c, const VecD<D>& extent) {
  Bounds<D> b;
  for (int k = 0; k < D; ++k) {
    b.lo[k] = c[k] - extent[k];
    b.hi[k] = c[k] + extent[k];
  }
  return b;
}

}  // namespace

template <int D>
Bounds<D> bounds(const SphereShape<D>& s) {
  return around<D>(s.centre, VecD<D>::Constant(s.radius));
}

template <int D>
Bounds<D> bounds(const PlaneShape<D>& p) {
  Bounds<D> b;
  b.lo.fill(-kInf);
  b.hi.fill(kInf);
  // The back half-space has a finite side only when the normal is along an axis.
  int along = -1, nonzero = 0;
  for (int k = 0; k < D; ++k) {
    if (p.normal[k] != 0) ++nonzero, along = k;
  }
  if (nonzero == 1) {
    if (p.normal[along] > 0) {
      b.hi[along] = p.point[along];
    } else {
      b.lo[along] = p.point[along];
    }
  }
  return b;
}

template <int D>
Bounds<D> bounds(const FlatWallShape<D>& w) {
  VecD<D> ext = VecD<D>::Zero();
  for (int i = 0; i < D - 1; ++i) ext += w.halfExtents[i] * w.axes[i].cwiseAbs();
  return around<D>(w.centre, ext);
}

template <int D>
Bounds<D> bounds(const BoxShape<D>& b) {
  return around<D>(b.centre, b.axes.cwiseAbs() * b.halfExtents);
}

template <int D>
Bounds<D> bounds(const DrumShape<D>& d) {
  if constexpr (D == 2) {
    return around<D>(d.centre, VecD<D>::Constant(d.radius));
  } else {
    VecD<D> ext;
    for (int k = 0; k < D; ++k) {
      const Real ak = std::abs(d.axis[k]);
      const Real radial = d.radius * std::sqrt(std::max<Real>(0, 1 - ak * ak));
      // Avoid inf * 0 = NaN for an infinite drum along an axis.
      ext[k] = (ak == 0 ? 0 : d.halfLength * ak) + radial;
    }
    return around<D>(d.centre, ext);
  }
}

// The box of the mesh's bounds turned and moved: its eight corners' box.
template <int D>
Bounds<D> bounds(const MeshShape<D>& m) {
  Bounds<D> out;
  out.lo.fill(kInf);
  out.hi.fill(-kInf);
  if (!m.mesh) return out;
  for (int c = 0; c < 8; ++c) {
    const Vec3 local((c & 1) ? m.mesh->hi.x() : m.mesh->lo.x(), (c & 2) ? m.mesh->hi.y() : m.mesh->lo.y(),
                     (c & 4) ? m.mesh->hi.z() : m.mesh->lo.z());
    const Vec3 x = m.rotation * local + m.offset;
    for (int k = 0; k < D; ++k) {
      out.lo[k] = std::min(out.lo[k], x[k]);
      out.hi[k] = std::max(out.hi[k], x[k]);
    }
  }
  return out;
}

template <int D>
Bounds<D> boundsWithin(const PlaneShape<D>& p, const Bounds<D>& domain) {
  Bounds<D> out;
  out.lo.fill(kInf);
  out.hi.fill(-kInf);
  auto include = [&](const VecD<D>& x) {
    for (int k = 0; k < D; ++k) {
      out.lo[k] = std::min(out.lo[k], x[k]);
      out.hi[k] = std::max(out.hi[k], x[k]);
    }
  };
  constexpr int kCorners = 1 << D;
  VecD<D> corner[kCorners];
  Real side[kCorners];
  for (int c = 0; c < kCorners; ++c) {
    for (int k = 0; k < D; ++k) corner[c][k] = (c >> k & 1) ? domain.hi[k] : domain.lo[k];
    side[c] = (corner[c] - p.point).dot(p.normal);
    if (side[c] <= 0) include(corner[c]);
  }
  // Where an edge of the domain crosses the plane, the crossing point bounds the clipped part.
  for (int c = 0; c < kCorners; ++c) {
    for (int k = 0; k < D; ++k) {
      const int o = c | (1 << k);
      if (o == c) continue;
      if ((side[c] < 0 && side[o] > 0) || (side[c] > 0 && side[o] < 0)) {
        const Real t = side[c] / (side[c] - side[o]);
        VecD<D> x = corner[c] + t * (corner[o] - corner[c]);
        x[k] = std::clamp(x[k], domain.lo[k], domain.hi[k]);
        include(x);
      }
    }
  }
  return out;
}

#define DEMLAB_PHYSICS_BOUNDS(D)                         \
  template Bounds<D> bounds<D>(const SphereShape<D>&);   \
  template Bounds<D> bounds<D>(const PlaneShape<D>&);    \
  template Bounds<D> bounds<D>(const FlatWallShape<D>&); \
  template Bounds<D> bounds<D>(const BoxShape<D>&);      \
  template Bounds<D> bounds<D>(const DrumShape<D>&);     \
  template Bounds<D> bounds<D>(const MeshShape<D>&);     \
  template Bounds<D> boundsWithin<D>(const PlaneShape<D>&, const Bounds<D>&);
DEMLAB_PHYSICS_BOUNDS(2)
DEMLAB_PHYSICS_BOUNDS(3)
#undef DEMLAB_PHYSICS_BOUNDS

}  // namespace demlab::physics
