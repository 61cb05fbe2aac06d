#!/usr/bin/env python3
"""The stable step of a damped oscillator (x'' = -omega^2 x - 2 zeta omega x', omega = 1) under
the two integrators, found by bisection on long runs, against the closed forms of
physics::dampedStepFactor (src/physics/critical_step.cpp):
  verlet        the damper sees the half-step velocity v(n-1/2): 2 (sqrt(1 + z^2) - z)
  synchronized  it sees v(n-1/2) + a(n-1) dt/2 (src/sim/integrator.hpp): the same with 2 zeta
Prints one CSV row a zeta.
  python3 scripts/damped-stability.py"""
import math


def unstable(zeta, dt, synchronized, steps=20000):
    c = 2 * zeta
    x, vh, a = 1.0, 0.3, 0.0
    for _ in range(steps):
        v = vh + 0.5 * a * dt if synchronized else vh
        a = -x - c * v
        vh += a * dt
        x += vh * dt
        if abs(x) > 1e6:
            return True
    return False


def limit(zeta, synchronized):
    lo, hi = 1e-3, 4.0
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if unstable(zeta, mid, synchronized):
            hi = mid
        else:
            lo = mid
    return lo


print("zeta,verlet_bisected,verlet_formula,synchronized_bisected,synchronized_formula")
for zeta in (0.0, 0.1, 0.2155, 0.4, 0.59, 0.8, 1.6):
    f = lambda z: 2 * (math.sqrt(1 + z * z) - z)
    print("%g,%.4f,%.4f,%.4f,%.4f" % (zeta, limit(zeta, False), f(zeta), limit(zeta, True), f(2 * zeta)))
