// The reference impact: closed forms and the RK4 integration of the one-degree-of-freedom law.
#include "verify/reference_ode.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "physics/pair_params.hpp"

namespace demlab::verify {

namespace {

struct State {
  double delta, u;
};

// Returns the acceleration d u / dt at (delta, u): the cut-off force plus gravity.
double accel(const ImpactLaw& law, const State& s) {
  const double f = s.delta > 0 ? std::max(0.0, impactForce(law, s.delta, s.u)) : 0.0;
  return -f / law.mass + law.gravity;
}

// Returns the state after one classical RK4 step of length h.
State rk4(const ImpactLaw& law, const State& s, double h) {
  const double k1x = s.u, k1v = accel(law, s);
  const State s2{s.delta + 0.5 * h * k1x, s.u + 0.5 * h * k1v};
  const double k2x = s2.u, k2v = accel(law, s2);
  const State s3{s.delta + 0.5 * h * k2x, s.u + 0.5 * h * k2v};
  const double k3x = s3.u, k3v = accel(law, s3);
  const State s4{s.delta + h * k3x, s.u + h * k3v};
  const double k4x = s4.u, k4v = accel(law, s4);
  return {s.delta + h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x),
          s.u + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)};
}

// Returns the unclamped force at s (0 when not touching).
double forceAt(const ImpactLaw& law, const State& s) {
  return s.delta > 0 ? impactForce(law, s.delta, s.u) : 0.0;
}

// Returns the step length tau in (0, h] at which g(rk4(s, tau)) changes sign (g(s) > 0 >=
// g(rk4(s, h))), by bisection to rounding.
template <class G>
double locate(const ImpactLaw& law, const State& s, double h, G g) {
  double lo = 0, hi = h;
  for (int k = 0; k < 200 && hi - lo > 1e-15 * h; ++k) {
    const double mid = 0.5 * (lo + hi);
    (g(rk4(law, s, mid)) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double impactForce(const ImpactLaw& law, double delta, double u) {
  if (!law.hertz) return law.kn * delta + law.cn * u;
  const double a = std::sqrt(law.radius * delta);
  const double le = std::log(law.restitution);
  const double beta = law.liggghtsDamping
                          ? le / std::sqrt(le * le + std::numbers::pi * std::numbers::pi)
                          : -physics::hertzDampingFactor(law.restitution) / std::sqrt(5.0);
  const double gn = 2 * std::sqrt(5.0 / 6.0) * (-beta) * std::sqrt(2 * law.youngEff * a * law.mass);
  return 4.0 / 3.0 * law.youngEff * a * delta + gn * u;
}

ImpactAnswer solveImpact(const ImpactLaw& law, double v0, double stepsPerContact) {
  // The contact time scale, for the step: Hertz's elastic duration or pi/omega.
  const double tc =
      law.hertz ? hertzElastic(law, v0).duration : std::numbers::pi * std::sqrt(law.mass / law.kn);
  const double hMax = tc / stepsPerContact;
  ImpactAnswer out;
  State s{0, v0};
  double h = hMax * 1e-7, t = 0;
  // Forces at the last three steps, for the golden-section search of the peak force.
  std::array<State, 3> hist{s, s, s};
  std::array<double, 3> histH{0, 0, 0};
  double fPrev = forceAt(law, {1e-300, v0});
  double bestF = std::max(0.0, fPrev);
  State bestFrom = s;
  double bestSpan = 0;
  bool peakDone = false;
  for (long k = 0; k < 100000000; ++k) {
    const State n = rk4(law, s, h);
    if (!peakDone && n.u <= 0) {
      const double tau = locate(law, s, h, [](const State& x) { return x.u; });
      out.peakOverlap = rk4(law, s, tau).delta;
      peakDone = true;
    }
    const double fn = forceAt(law, n);
    if (fn <= 0 || n.delta <= 0) {
      const double tau = locate(law, s, h, [&](const State& x) {
        return x.delta > 0 ? impactForce(law, x.delta, x.u) : -1.0;
      });
      const State e = rk4(law, s, tau);
      out.duration = t + tau;
      out.exitSpeed = -e.u;
      out.endOverlap = e.delta;
      break;
    }
    hist = {hist[1], hist[2], s};
    histH = {histH[1], histH[2], h};
    if (fn > bestF) {
      bestF = fn;
      bestFrom = hist[1];
      bestSpan = histH[1] + histH[2] + h;
    }
    fPrev = fn;
    s = n;
    t += h;
    h = std::min(hMax, h * 1.05);
  }
  // Peak force: golden section over [bestFrom, bestFrom + bestSpan] unless the peak is the
  // touch itself (the linear damper's jump).
  out.peakForce = bestF;
  if (bestSpan > 0) {
    const double gr = (std::sqrt(5.0) - 1) / 2;
    double a = 0, b = bestSpan;
    auto f = [&](double x) { return forceAt(law, rk4(law, bestFrom, x)); };
    double c = b - gr * (b - a), d = a + gr * (b - a);
    double fc = f(c), fd = f(d);
    for (int k = 0; k < 200 && b - a > 1e-14 * bestSpan; ++k) {
      if (fc > fd) {
        b = d;
        d = c;
        fd = fc;
        c = b - gr * (b - a);
        fc = f(c);
      } else {
        a = c;
        c = d;
        fc = fd;
        d = a + gr * (b - a);
        fd = f(d);
      }
    }
    out.peakForce = std::max(out.peakForce, std::max(fc, fd));
  }
  return out;
}

ImpactAnswer hertzElastic(const ImpactLaw& law, double v0) {
  ImpactAnswer out;
  const double es = law.youngEff * std::sqrt(law.radius);
  out.peakOverlap = std::pow(15 * law.mass * v0 * v0 / (16 * es), 0.4);
  // integral_0^1 (1 - x^(5/2))^(-1/2) dx = (2/5) B(2/5, 1/2)
  const double integral = 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  out.duration = 2 * integral * out.peakOverlap / v0;
  out.peakForce = 4.0 / 3.0 * es * std::pow(out.peakOverlap, 1.5);
  out.exitSpeed = v0;
  out.endOverlap = 0;
  return out;
}

ImpactAnswer linearDamped(const ImpactLaw& law, double v0) {
  ImpactAnswer out;
  const double wn = std::sqrt(law.kn / law.mass);
  const double zeta = law.cn / (2 * std::sqrt(law.mass * law.kn));
  const double s = std::sqrt(1 - zeta * zeta), wd = wn * s;
  const double phi = 2 * std::acos(zeta);  // the force zero: tan(wd t) = -2 zeta s / (1 - 2 zeta^2)
  out.duration = phi / wd;
  out.peakOverlap = v0 / wn * std::exp(-zeta * std::acos(zeta) / s);
  out.exitSpeed = v0 * std::exp(-zeta * wn * out.duration);
  out.endOverlap = v0 / wd * std::exp(-zeta * wn * out.duration) * std::sin(phi);
  out.peakForce = 0;
  return out;
}

}  // namespace demlab::verify
