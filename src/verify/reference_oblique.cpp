// The oblique-impact reference: normal and tangential motion of a grain on a floor by RK4.
#include "verify/reference_oblique.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace demlab::verify {

namespace {

struct State {
  double delta, u;  // overlap and its rate
  double s;         // shear spring elongation (m)
  double v, omega;  // tangential velocity of the centre, spin
};

struct Rates {
  State d;
  bool stuck;
};

double normalForce(const ObliqueLaw& law, const State& x) {
  return x.delta > 0 ? std::max(0.0, impactForce(law.normal, x.delta, x.u)) : 0.0;
}

// Returns the time derivatives at x and whether the contact sticks there.
Rates rates(const ObliqueLaw& law, const State& x) {
  const double fn = normalForce(law, x), cap = law.friction * fn;
  const double r = law.normal.radius, arm = r - 0.5 * x.delta;
  const double w = x.v - x.omega * arm;
  double ft = law.kt * x.s + law.ct * w;
  bool stuck = std::abs(ft) <= cap && law.kt * std::abs(x.s) <= cap;
  if (!stuck) ft = std::clamp(law.kt * x.s, -cap, cap);
  Rates out;
  out.stuck = stuck && fn > 0;
  out.d = {x.u, -fn / law.normal.mass, fn > 0 ? w : 0, -ft / law.normal.mass,
           ft * arm / law.inertia};
  return out;
}

State axpy(const State& x, double h, const State& d) {
  return {x.delta + h * d.delta, x.u + h * d.u, x.s + h * d.s, x.v + h * d.v,
          x.omega + h * d.omega};
}

// Returns the state after one RK4 step of length h, the spring then held to the cap (the law
// scales a spring beyond mu Fn / kt down to it).
State step(const ObliqueLaw& law, const State& x, double h) {
  const State k1 = rates(law, x).d, k2 = rates(law, axpy(x, h / 2, k1)).d,
              k3 = rates(law, axpy(x, h / 2, k2)).d, k4 = rates(law, axpy(x, h, k3)).d;
  State n = x;
  n.delta += h / 6 * (k1.delta + 2 * k2.delta + 2 * k3.delta + k4.delta);
  n.u += h / 6 * (k1.u + 2 * k2.u + 2 * k3.u + k4.u);
  n.s += h / 6 * (k1.s + 2 * k2.s + 2 * k3.s + k4.s);
  n.v += h / 6 * (k1.v + 2 * k2.v + 2 * k3.v + k4.v);
  n.omega += h / 6 * (k1.omega + 2 * k2.omega + 2 * k3.omega + k4.omega);
  const double sCap = law.friction * normalForce(law, n) / law.kt;
  n.s = std::clamp(n.s, -sCap, sCap);
  return n;
}

}  // namespace

ObliqueAnswer solveOblique(const ObliqueLaw& law, double v0, double vt0, double stepsPerContact) {
  const double tc = std::numbers::pi * std::sqrt(law.normal.mass / law.normal.kn);
  const double hMax = tc / stepsPerContact;
  ObliqueAnswer out;
  State x{0, v0, 0, vt0, 0};
  double h = hMax * 1e-7, t = 0;
  for (long k = 0; k < 100000000; ++k) {
    const State n = step(law, x, h);
    if (normalForce(law, n) <= 0) {
      // The end: bisect for the step length at which the normal force vanishes.
      double lo = 0, hi = h;
      for (int i = 0; i < 200 && hi - lo > 1e-15 * h; ++i) {
        const double mid = 0.5 * (lo + hi);
        (normalForce(law, step(law, x, mid)) > 0 ? lo : hi) = mid;
      }
      const State e = step(law, x, 0.5 * (lo + hi));
      out.normal.duration = t + 0.5 * (lo + hi);
      out.normal.exitSpeed = -e.u;
      out.normal.endOverlap = e.delta;
      out.tangential = e.v;
      out.spin = e.omega * law.normal.radius;
      return out;
    }
    if (rates(law, x).stuck) out.stuckTime += h;
    x = n;
    t += h;
    h = std::min(hMax, h * 1.05);
  }
  return out;
}

}  // namespace demlab::verify
