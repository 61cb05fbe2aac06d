// The superquadric's geometry in its body frame (the shape type is sim/shapes/superquadric.cpp).
//
// 3D: the points with F(x) = (|x/a|^n2 + |y/b|^n2)^(n1/n2) + |z/c|^n1 <= 1: half axes a, b, c,
// blockiness n1 from the xy plane to the z axis and n2 within the xy plane (2 and 2: an
// ellipsoid; large: a box with rounded edges). 2D: the superellipse |x/a|^n + |y/b|^n <= 1.
// Exponents of at least 2 keep the shape convex and its surface twice differentiable.
//
// The contact routines read the shape through its gauge phi = F^(1/n1): phi is 1 on the surface,
// convex and homogeneous of degree 1 (phi(t x) = t phi(x)), so t = phi(x) is the factor by which
// the shape must be scaled about its centre to reach x. The sphere of radius r is the
// superquadric (r, r, r, 2, 2), which is how a ball meets a superquadric.
#pragma once

#include "core/math.hpp"
#include "sim/shape.hpp"

namespace demlab::sim {

template <int D>
struct Superquadric {
  Real a = 1, b = 1, c = 1;  // half axes (m); c unused in 2D
  Real n1 = 2, n2 = 2;       // blockiness exponents, >= 2; 2D: n1 (n2 unused)

  // Returns phi(x), the gauge: < 1 inside, 1 on the surface, > 1 outside. Changes nothing.
  Real gauge(const VecD<D>& x) const;
  // Returns F(x) = phi(x)^n1, which orders points as the gauge does without its root or any
  // derivative: what a search for the deepest point compares. Changes nothing.
  Real level(const VecD<D>& x) const;
  // Returns the gradient of phi at x (x != 0).
  VecD<D> gaugeGradient(const VecD<D>& x) const;
  // Returns the gradient of phi at x and writes phi(x) to phi: both for the cost of one.
  VecD<D> gaugeAndGradient(const VecD<D>& x, Real& phi) const;
  // Returns psi = phi^2 at x and writes its gradient and Hessian (psi is convex and smooth:
  // the midway-point solver's objective).
  Real squaredGauge(const VecD<D>& x, VecD<D>& grad, MatD<D>& hess) const;
  // Returns the point of the surface farthest along the direction d (d != 0): the support
  // point, in closed form (Hoelder's inequality applied twice).
  VecD<D> support(const VecD<D>& d) const;
};

// Returns true and writes the contact of a ball (centre, radius) with the superquadric element
// sq, the normal from the ball to it and the Hertz radius the pair's (the contact of a clump's
// member, sim/shapes/clump.cpp). Changes nothing else.
template <int D>
bool ballSuperquadricContact(const VecD<D>& centre, Real radius, const ElementRef<D>& sq,
                             ContactPoint<D>& out);

}  // namespace demlab::sim
