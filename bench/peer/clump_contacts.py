#!/usr/bin/env python3
"""Counts the contacts of a bed of clumps the same way for every code of scripts/peer-clumps.

Reads the member spheres written by a code at the end of its timed steps, one sphere a line:
"body x y z r" (SI units; other lines, such as a LAMMPS dump's headers, are skipped), and
prints one line:

    spheres S bodies B pair P wall W contacts C zmean Z ztop T

pair      touching pairs of member spheres of different bodies (centre distance < r1 + r2):
          a clump-clump contact counts once per touching member pair
wall      touching sphere-wall pairs (distance to the plane < r) with the floor z = 0 and the
          four side walls x = 0, x = L, y = 0, y = L
contacts  pair + wall
zmean     the mean height of the member centres (m); 2 zmean is about the bed's height
ztop      the highest point of any member (max z + r, m)

Usage: clump_contacts.py FILE L
"""
import math
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    side = float(sys.argv[2])
    spheres = []
    with open(sys.argv[1]) as f:
        for line in f:
            fields = line.split()
            if len(fields) != 5:
                continue
            try:
                body = int(float(fields[0]))
                x, y, z, r = (float(v) for v in fields[1:])
            except ValueError:
                continue
            spheres.append((body, x, y, z, r))
    if not spheres:
        sys.exit("clump_contacts: no member spheres in " + sys.argv[1])
    rmax = max(s[4] for s in spheres)
    cell = 2 * rmax
    grid = {}
    for i, (_, x, y, z, _) in enumerate(spheres):
        grid.setdefault((int(math.floor(x / cell)), int(math.floor(y / cell)),
                         int(math.floor(z / cell))), []).append(i)
    pair = 0
    for (cx, cy, cz), members in grid.items():
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    other = grid.get((cx + dx, cy + dy, cz + dz))
                    if not other:
                        continue
                    for i in members:
                        bi, xi, yi, zi, ri = spheres[i]
                        for j in other:
                            if j <= i:
                                continue
                            bj, xj, yj, zj, rj = spheres[j]
                            if bi == bj:
                                continue
                            d2 = (xi - xj) ** 2 + (yi - yj) ** 2 + (zi - zj) ** 2
                            if d2 < (ri + rj) ** 2:
                                pair += 1
    wall = 0
    for _, x, y, z, r in spheres:
        wall += (z < r) + (x < r) + (side - x < r) + (y < r) + (side - y < r)
    zmean = sum(s[3] for s in spheres) / len(spheres)
    ztop = max(s[3] + s[4] for s in spheres)
    bodies = len({s[0] for s in spheres})
    print("spheres %d bodies %d pair %d wall %d contacts %d zmean %.6g ztop %.6g"
          % (len(spheres), bodies, pair, wall, pair + wall, zmean, ztop))


if __name__ == "__main__":
    main()
