// Helpers shared by the case files: materials, vectors, and the Runner that steps a scene while
// charging only the simulation loop's own time to the case.
#pragma once

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>

#include "sim/simulation.hpp"
#include "verify/verify.hpp"

namespace demlab::verify {

using sim::Vec3d;

constexpr double kGravity = 9.81;

// Returns a material of density rho (kg/m^3 in 3D, kg/m^2 in 2D), Young's modulus young,
// Poisson 0.3, restitution e and friction mu.
inline sim::MaterialDef material(double young, double e, double mu, double rho = 2500) {
  sim::MaterialDef m;
  m.density = rho;
  m.young = young;
  m.poisson = 0.3;
  m.restitution = e;
  m.friction = mu;
  return m;
}

// Returns E* of a contact between two bodies of material m (Hertz: 1/E* = 2 (1 - nu^2)/E).
inline double youngEff(const sim::MaterialDef& m) {
  return m.young / (2 * (1 - m.poisson * m.poisson));
}

// The "up" axis: y in 2D, z in 3D.
inline int upAxis(int dim) {
  return dim - 1;
}

inline Vec3d axisVec(int axis, double x) {
  Vec3d v{0, 0, 0};
  v[axis] = x;
  return v;
}

inline double dot(const Vec3d& a, const Vec3d& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Returns the unit-radius moment of inertia factor k = I / (m r^2): 2/5 sphere, 1/2 disc.
inline double inertiaFactor(int dim) {
  return dim == 3 ? 0.4 : 0.5;
}

// Returns a plane wall through point with the given normal, of material mat.
inline sim::WallDef planeWall(const Vec3d& point, const Vec3d& normal, const std::string& mat) {
  sim::WallDef w;
  w.shape = sim::WallShape::Plane;
  w.point = point;
  w.normal = normal;
  w.material = mat;
  return w;
}

inline sim::ElementDef grainDef(const Vec3d& x, double r, const std::string& mat, const Vec3d& v = {},
                              const Vec3d& w = {}) {
  sim::ElementDef g;
  g.position = x;
  g.radius = r;
  g.material = mat;
  g.velocity = v;
  g.angularVelocity = w;
  return g;
}

// Steps a scene and books its cost into a CaseResult: steps, the loop's wall time
// (RunReport::wallSeconds), the energy residual at the scene's last step and the largest seen.
class Runner {
 public:
  Runner(sim::Simulation& s, CaseResult& out) : s_(s), out_(out) {}
  // The scene's residual at its last step is its end-of-run figure.
  ~Runner() { out_.energyResidual = std::max(out_.energyResidual, last_); }
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;
  // Runs n steps; returns nothing; changes the scene and the booked cost.
  void run(uint64_t n) {
    if (n == 0) return;
    book(s_.runSteps(n));
  }
  void step() { book(s_.step()); }

 private:
  void book(const sim::RunReport& r) {
    out_.steps += r.steps;
    out_.wallSeconds += r.wallSeconds;
    out_.energyResidualMax = std::max(out_.energyResidualMax, r.energyResidual);
    last_ = r.energyResidual;
  }
  sim::Simulation& s_;
  CaseResult& out_;
  double last_ = 0;
};

// Sets the scene's integrator from a suite integrator name (integrators(): a Simulation
// integrator with the sub-step touch correction on, as by default, or with "-notouch" off).
// Changes the scene.
inline void setIntegrator(sim::Simulation& s, const std::string& name) {
  constexpr std::string_view kOff = "-notouch";
  const bool off = name.size() > kOff.size() && name.ends_with(kOff);
  s.setOptions({{"integrator", "name", off ? name.substr(0, name.size() - kOff.size()) : name},
                {"touch", "on", !off}});
}

// Returns a Quantity.
inline Quantity quantity(std::string name, double measured, double reference, std::string source,
                         double scale = 0) {
  Quantity q;
  q.name = std::move(name);
  q.measured = measured;
  q.reference = reference;
  q.source = std::move(source);
  q.scale = scale;
  return q;
}

// Returns the vertex value of the parabola through (-1, a), (0, b), (1, c) when b is a local
// extremum of the three, else b: the peak of uniformly sampled smooth data, to O(h^3).
inline double parabolicPeak(double a, double b, double c) {
  const double den = a - 2 * b + c;
  if (den == 0) return b;
  const double x = 0.5 * (a - c) / den;
  if (x < -1 || x > 1) return b;
  return b - 0.25 * (a - c) * x;
}

// Returns where, in steps after the sample f1 (> 0), the parabola through the samples f3, f2,
// f1 of three consecutive steps crosses zero: its first root in (0, 1], or the line through f2
// and f1's where the parabola has none there. Changes nothing.
inline double forceZeroAfter(double f3, double f2, double f1) {
  const double line = f2 > f1 ? f1 / (f2 - f1) : 0.0;
  // p(x) = f1 + b x + c x^2 with p(-1) = f2, p(-2) = f3.
  const double c = 0.5 * (f3 - 2 * f2 + f1);
  const double b = f1 + c - f2;
  const double disc = b * b - 4 * c * f1;
  if (c == 0 || disc < 0) return line;
  // The roots f1 / q and q / c, q = -(b + sign(b) sqrt(disc)) / 2 (no cancellation).
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  double best = -1;
  for (double x : {q != 0 ? f1 / q : -1.0, q / c}) {
    if (x > 0 && x <= 1 && (best < 0 || x < best)) best = x;
  }
  return best > 0 ? best : line;
}

}  // namespace demlab::verify
