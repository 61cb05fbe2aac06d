#!/usr/bin/env python3
"""A stuck tangential spring (a unit mass on a spring, no slip, no dashpot) under the
synchronized integrator (src/sim/integrator.hpp: the laws see v(t+dt/2) + a(t) dt/2), with
three ways to lengthen the spring each step:
  sync   s += v_sync dt                      (demlab's default today)
  trap   s += (v_sync + last v_sync)/2 dt    (tried, not committed: doc/plans/ledger-tangential.md)
  drift  s += v(t+dt/2) dt                   (the drift's displacement, as plain Verlet)
Prints the energy left (start = 1) after 200/(omega dt) steps (about 32 periods) at several
omega dt: below 1 the scheme damps the stuck mode numerically, above 1 it is unstable.
  python3 scripts/tangential-schemes.py"""


def energy_left(wdt, scheme):
    dt, w2 = 1.0, wdt * wdt
    s, v, vs_last, a = 1.0, 0.0, 0.0, -wdt * wdt
    first = True
    e0 = 0.5 * w2 * s * s
    for _ in range(int(200 / wdt)):
        vs = v + a * dt  # v(t+dt/2) + a(t) dt/2
        if scheme == "sync":
            u = vs * dt
        elif scheme == "trap":
            u = vs * dt if first else 0.5 * (vs + vs_last) * dt
        else:
            u = (v + 0.5 * a * dt) * dt
        first = False
        s += u
        a_new = -w2 * s
        v = vs + 0.5 * (a_new - a) * dt  # the second kick: v(t+dt)
        a, vs_last = a_new, vs
    return (0.5 * v * v + 0.5 * w2 * s * s) / e0


print("omega_dt,sync,trap,drift")
for wdt in (0.05, 0.1, 0.2, 0.5, 1.0):
    print(",".join([str(wdt)] + ["%.4g" % energy_left(wdt, k) for k in ("sync", "trap", "drift")]))
