"""What the YADE sides of the peer benchmarks share (clumps_yade.py, polyhedra_yade.py): random
orientations and a packing of bounding spheres apart. Plain Python: imported from the scripts'
folder (sys.argv[0] is the script under `yade -x`)."""
import math
import sys


def random_quaternion(rng):
    """A unit quaternion uniform over the rotations (Shoemake), as (w, x, y, z)."""
    u1, u2, u3 = rng.random(), rng.random(), rng.random()
    a, b = math.sqrt(1 - u1), math.sqrt(u1)
    return (a * math.sin(2 * math.pi * u2), a * math.cos(2 * math.pi * u2),
            b * math.sin(2 * math.pi * u3), b * math.cos(2 * math.pi * u3))


def pack_apart(rng, n, bound, side, height, what):
    """Centres and orientations (unit quaternions) of n bodies whose bounding spheres of radius
    bound are apart and inside the box 0 < x, y < side, 0 < z < height, placed at random on a
    grid of cells of 2 bound; exits naming `what` if one cannot be placed."""
    cell = 2 * bound
    grid = {}
    placed = []
    for i in range(n):
        for attempt in range(100000):
            p = (rng.uniform(bound, side - bound), rng.uniform(bound, side - bound),
                 rng.uniform(bound, height - bound))
            key = tuple(int(v // cell) for v in p)
            ok = all(sum((p[k] - q[k]) ** 2 for k in range(3)) >= cell * cell
                     for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                     for q in grid.get((key[0] + dx, key[1] + dy, key[2] + dz), ()))
            if ok:
                grid.setdefault(key, []).append(p)
                placed.append((p, random_quaternion(rng)))
                break
        else:
            sys.exit("could not place %s %d of %d" % (what, i + 1, n))
    return placed
