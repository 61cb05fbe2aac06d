#!/usr/bin/env python3
"""A stuck tangential spring (a unit mass on a spring, no slip, no dashpot) under the
synchronized integrator (src/sim/integrator.hpp: the laws see v(t+dt/2) + a(t) dt/2), with
three ways to lengthen the spring each step:
  sync   s += v_sync dt                      (demlab's default today)
  trap   s += (v_sync + last v_sync)/2 dt    (tried, not committed: doc/plans/ledger-tangential.md)
  drift  s += v(t+dt/2) dt                   (the drift's displacement, as plain Verlet)
  recursion  s += (vS - A) dt, A = (vS - vS_last + A_last) / 3, A = 0 at the contact's first
         step (the drift's displacement recovered from the synchronized velocities alone:
         vS_{n+1} - vS_n = 3 A_n - A_{n-1} with A = a dt/2; doc/plans/ledger-tangential.md)
Prints the energy left (start = 1) after 200/(omega dt) steps (about 32 periods) at several
omega dt, for a loaded spring let go (s = 1, v = 0) and for a contact that starts (s = 0,
v = 1): below 1 the scheme damps the stuck mode numerically, above 1 it gains energy (the drift's
scheme, Verlet's, oscillates about 1 by O((omega dt)^2) and is measured at one phase).
  python3 scripts/tangential-schemes.py"""


def energy_left(wdt, scheme, s=1.0, v=0.0):
    dt, w2 = 1.0, wdt * wdt
    a = -w2 * s
    vs_last, a_last = None, 0.0
    e0 = 0.5 * v * v + 0.5 * w2 * s * s
    for _ in range(int(200 / wdt)):
        vs = v + a * dt  # v(t+dt/2) + a(t) dt/2
        if scheme == "sync":
            u = vs * dt
        elif scheme == "trap":
            u = vs * dt if vs_last is None else 0.5 * (vs + vs_last) * dt
        elif scheme == "recursion":
            if vs_last is None:
                u, big_a = vs * dt, 0.0
            else:
                big_a = (vs - vs_last + a_last) / 3
                u = (vs - big_a) * dt
            a_last = big_a
        else:
            u = (v + 0.5 * a * dt) * dt
        vs_last = vs
        s += u
        a_new = -w2 * s
        v = vs + 0.5 * (a_new - a) * dt  # the second kick: v(t+dt)
        a = a_new
    return (0.5 * v * v + 0.5 * w2 * s * s) / e0


schemes = ("sync", "trap", "recursion", "drift")
for name, s0, v0 in (("loaded spring let go", 1.0, 0.0), ("a contact that starts", 0.0, 1.0)):
    print("# " + name)
    print("omega_dt," + ",".join(schemes))
    for wdt in (0.05, 0.1, 0.2, 0.5, 1.0):
        print(",".join([str(wdt)] + ["%.4g" % energy_left(wdt, k, s0, v0) for k in schemes]))
