// Periodic boundaries and Lees-Edwards (sliding periodic) boundaries.
//
// A periodic axis k makes the scene an infinite lattice of copies of the cell [lo_k, hi_k):
// every pair is measured between an element and the nearest image of the other (the minimum
// image convention), which is unique while each periodic length exceeds twice the largest
// reach of a pair (two bounding radii and the skin; checked at every run start). Elements are
// wrapped back into the cell at each neighbour search, never between, so the positions the
// skin bookkeeping compares stay continuous; each element's wraps are kept per slot as the
// offset from its wrapped to its unwrapped position.
//
// Lees-Edwards: with a shear rate g on a flow axis f and a gradient axis y (both periodic),
// the images one cell up along y are displaced along f by the offset delta(t) (advanced by
// U dt each step, U = g L_y, kept within [0, L_f)) and move with +U along f. A pair reaching
// through n cells along y sees the other's image displaced by -n (L_y e_y + delta e_f) and its
// velocity by -n U e_f; an element leaving through the top re-enters at the bottom with
// x_f -= delta and v_f -= U (Lees and Edwards, J. Phys. C 5 (1972) 1921). The work the moving
// images do through the contacts, and the kinetic energy of the velocity jumps, are booked to
// the ledger's wall work, so the energy balance still closes.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/math.hpp"

namespace demlab::sim {

template <int D>
struct PeriodicBox {
  uint8_t axes = 0;  // bit k: axis k is periodic
  VecD<D> lo = VecD<D>::Zero(), hi = VecD<D>::Zero();
  // Lees-Edwards: the shear rate (1/s), its flow and gradient axes, the images' offset now
  // (m, in [0, L_flow)) and how far it has moved since the last search (m, for the skin).
  double shearRate = 0;
  int flow = 0, gradient = 1;
  double offset = 0;
  double offsetTravel = 0;
  // Per element slot: the offset from the wrapped position to the unwrapped one, valid while
  // the slot's generation is unwrapGeneration[slot] (a reused slot starts from zero).
  std::vector<VecD<D>> unwrap;
  std::vector<uint32_t> unwrapGeneration;

  bool any() const { return axes != 0; }
  bool periodic(int k) const { return (axes >> k) & 1u; }
  bool sheared() const { return any() && shearRate != 0; }
  Real length(int k) const { return hi[k] - lo[k]; }
  // The images' speed along the flow axis one cell up (m/s).
  Real shearSpeed() const { return shearRate * length(gradient); }

  // Returns d (the raw vector from one element to another) reduced to the nearest image;
  // *crossings: the cells crossed along the gradient axis (0 without shear). Changes nothing.
  // Elements are within the cell at each search and move less than the skin between, so a raw
  // component is within 1.5 lengths and one comparison each way reduces it (no division or
  // rounding call in the contact pass); the flow axis, shifted by up to one more length by the
  // offset, takes two.
  [[gnu::always_inline]] VecD<D> nearest(VecD<D> d, int* crossings) const {
    int n = 0;
    if (shearRate != 0) {
      n = gradientCrossings(d);
      const Real L = length(gradient);
      d[gradient] -= n * L;
      d[flow] -= n * offset;
      d[flow] = wrapOnce(d[flow], length(flow));
    }
    for (int k = 0; k < D; ++k) {
      if (periodic(k)) d[k] = wrapOnce(d[k], length(k));
    }
    *crossings = n;
    return d;
  }
  // Returns the cells of the gradient axis a raw pair vector d crosses (nearest's n).
  [[gnu::always_inline]] int gradientCrossings(const VecD<D>& d) const {
    const Real L = length(gradient);
    return (d[gradient] > 0.5 * L) - (d[gradient] < -0.5 * L);
  }
  // Returns x less L if above L/2, plus L if below -L/2.
  static Real wrapOnce(Real x, Real L) {
    return x - L * static_cast<Real>((x > 0.5 * L) - (x < -0.5 * L));
  }
  [[gnu::always_inline]] VecD<D> nearest(const VecD<D>& d) const {
    int n;
    return nearest(d, &n);
  }
  // Returns the work (J) the images do in one step dt on a pair through n cells of the
  // sliding boundary with force f (on the image's element) along the flow axis: its image
  // moves with -n U relative to it, so n U f dt.
  double imageWork(int n, Real f, double dt) const { return n * shearSpeed() * f * dt; }

  // Advances the Lees-Edwards offset by one step dt. Changes offset, offsetTravel.
  void advance(double dt) {
    if (shearRate == 0 || !(dt > 0)) return;
    const double move = shearSpeed() * dt;
    offsetTravel += std::abs(move);
    const double L = length(flow);
    offset = std::fmod(offset + move, L);
    if (offset < 0) offset += L;
  }

  // Wraps one element (position x, velocity v, inverse mass invMass, handle h: its slot
  // index and generation) into the cell. Returns the kinetic energy its velocity jump changed (0 without shear). Changes x,
  // v and the slot's unwrap offset.
  template <class H>
  double wrap(VecD<D>& x, VecD<D>& v, Real invMass, H h) {
    VecD<D> moved = VecD<D>::Zero();
    double energy = 0;
    if (shearRate != 0) {
      const int g = gradient;
      const Real m = cellsFrom(x[g], g);
      if (m != 0) {
        x[g] -= m * length(g);
        x[flow] -= m * offset;
        moved[g] += m * length(g);
        moved[flow] += m * offset;
        const Real du = m * shearSpeed();
        if (invMass > 0) energy = 0.5 / invMass * ((v[flow] - du) * (v[flow] - du) - v[flow] * v[flow]);
        v[flow] -= du;
      }
    }
    for (int k = 0; k < D; ++k) {
      if (!periodic(k) || (shearRate != 0 && k == gradient)) continue;
      const Real m = cellsFrom(x[k], k);
      if (m == 0) continue;
      x[k] -= m * length(k);
      moved[k] += m * length(k);
    }
    if (moved != VecD<D>::Zero()) {
      if (unwrap.size() <= h.index) {
        unwrap.resize(h.index + 1, VecD<D>::Zero());
        unwrapGeneration.resize(h.index + 1, 0);
      }
      if (unwrapGeneration[h.index] != h.generation) {
        unwrap[h.index].setZero();
        unwrapGeneration[h.index] = h.generation;
      }
      unwrap[h.index] += moved;
    }
    return energy;
  }

  // Returns the whole cell lengths m such that c - m L lies in [lo, hi) along periodic axis k
  // (a c a rounding below lo would come to hi exactly with floor's m alone).
  Real cellsFrom(Real c, int k) const {
    const Real L = length(k);
    Real m = std::floor((c - lo[k]) / L);
    if (c - m * L >= hi[k]) m += 1;
    return m;
  }

  // Returns the offset from element h's wrapped position to its unwrapped one.
  template <class H>
  VecD<D> unwrapOffset(H h) const {
    if (h.index < unwrap.size() && unwrapGeneration[h.index] == h.generation) return unwrap[h.index];
    return VecD<D>::Zero();
  }

  // Calls fn(image) for every image of a point at x (inside the cell) that comes within reach
  // of the cell, over half the shifts (the first non-zero shift, the gradient axis's first, is
  // positive): each pair of elements within reach through the boundaries is then found once,
  // between one element and the other's image. Changes nothing.
  template <class Fn>
  void forEachImage(const VecD<D>& x, Real reach, Fn&& fn) const {
    int order[D], np = 0;
    if (shearRate != 0) order[np++] = gradient;
    for (int k = 0; k < D; ++k)
      if (periodic(k) && !(shearRate != 0 && k == gradient)) order[np++] = k;
    int total = 1;
    for (int q = 0; q < np; ++q) total *= 3;
    for (int code = 1; code < total; ++code) {
      int s[D] = {}, c = code, first = 0;
      for (int q = 0; q < np; ++q) {
        s[q] = c % 3 - 1;
        c /= 3;
      }
      for (int q = 0; q < np; ++q) {
        if (s[q] != 0) {
          first = s[q];
          break;
        }
      }
      if (first <= 0) continue;
      VecD<D> p = x;
      for (int q = 0; q < np; ++q) {
        const int k = order[q];
        if (shearRate != 0 && k == gradient && s[q] != 0) {
          p[k] += s[q] * length(k);
          p[flow] += s[q] * offset;
          const Real L = length(flow);
          p[flow] -= std::floor((p[flow] - lo[flow]) / L) * L;
        }
      }
      for (int q = 0; q < np; ++q) {
        const int k = order[q];
        if (!(shearRate != 0 && k == gradient)) p[k] += s[q] * length(k);
      }
      bool near = true;
      for (int k = 0; k < D && near; ++k) {
        if (periodic(k)) near = p[k] > lo[k] - reach && p[k] < hi[k] + reach;
      }
      if (near) fn(p);
    }
  }
};

}  // namespace demlab::sim
