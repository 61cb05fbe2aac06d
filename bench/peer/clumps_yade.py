# Rigid clumps (dumbbells) settling in a box: the YADE side of scripts/peer-clumps (which see).
# YADE 2023.02a (Debian yade), one thread:
#
#   yade -j 1 -n -x bench/peer/clumps_yade.py N SIDE HEIGHT SETTLE_STEPS TIMED_STEPS MEMBERS_FILE
#
# A clump is two spheres of radius 1 mm whose centres are 1.5 mm apart (O.bodies.appendClumped).
# Hertz-Mindlin: Ip2_FrictMat_FrictMat_MindlinPhys with en = 0.5 (its damping ratio from
# Thornton et al. 2013, for a rebound of 0.5 with the attractive force cut off; es = en) and
# Law2_ScGeom_MindlinPhys_Mindlin; E = 5e6 Pa, nu = 0.3, mu = 0.5 (friction angle atan 0.5),
# 2500 kg/m^3; the same law against the five walls (Wall bodies: floor z = 0, sides x, y = 0
# and SIDE), whose contacts are Hertz contacts of a sphere on a half-space
# (Ig2_Wall_Sphere_ScGeom hertzian=True; without it YADE takes the wall's radius equal to the
# sphere's). No numerical damping (NewtonIntegrator damping = 0). Time step 1e-5 s.
#
# Three things are set by hand to match the other codes:
# - the clump's mass and principal inertia are those of the union of its spheres (YADE's
#   appendClumped sums the spheres, counting the lens where they overlap twice: 4.5 % too much
#   mass), integrated here in slices along the axis;
# - each member's mass is the clump's, so the dashpots' effective mass of a contact is that of
#   the bodies, as in LIGGGHTS ("if I or J part of rigid body, use body mass") and demlab (a
#   member's own mass is used by nothing else: the clump carries gravity and the integration);
# - the clumps are placed by random sequential addition: centres uniform in the box, bounding
#   spheres (1.75 mm) apart and inside it, orientations uniform over the rotations.
#
# Prints on stdout a line "RESULT cpu_seconds contacts": the CPU time (time.process_time) of
# O.run(TIMED_STEPS, True), and the touching interactions after it (real, penetration > 0).
# Writes the member spheres to MEMBERS_FILE, a line "body x y z r" each.
import math
import os
import random
import sys
import time

from yade import utils

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from peer_packing import pack_apart  # noqa: E402

n = int(sys.argv[1])
side = float(sys.argv[2])
height = float(sys.argv[3])
settle = int(sys.argv[4])
timed = int(sys.argv[5])
members_file = sys.argv[6]

radius = 1e-3
half = 0.75e-3
bound = half + radius
density = 2500.0


def union_mass_inertia():
    """Mass and principal inertia (axial, transverse) of the two-sphere union, by slices."""
    slices = 20000
    mass = axial = transverse = 0.0
    dx = 2 * bound / slices
    for k in range(slices):
        x = -bound + (k + 0.5) * dx
        rho2 = max(radius ** 2 - (x - c) ** 2 for c in (-half, half))
        if rho2 <= 0:
            continue
        dm = density * math.pi * rho2 * dx
        mass += dm
        axial += dm * rho2 / 2
        transverse += dm * (rho2 / 4 + x * x)
    return mass, axial, transverse


mat = O.materials.append(FrictMat(young=5e6, poisson=0.3, density=density,
                                  frictionAngle=math.atan(0.5)))
for axis, pos, sense in ((2, 0.0, 1), (0, 0.0, 1), (0, side, -1), (1, 0.0, 1), (1, side, -1)):
    O.bodies.append(utils.wall(pos, axis=axis, sense=sense, material=mat))

clump_mass, i_axial, i_transverse = union_mass_inertia()
rng = random.Random(1)
for centre, (w, x, y, z) in pack_apart(rng, n, bound, side, height, "clump"):
    # The clump's axis: the first column of its rotation.
    axis = (1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y))
    spheres = [utils.sphere(tuple(centre[k] + s * half * axis[k] for k in range(3)), radius,
                            material=mat) for s in (-1, 1)]
    cid, ids = O.bodies.appendClumped(spheres)
    st = O.bodies[cid].state
    # appendClumped diagonalised the summed spheres' inertia: the smallest moment is the axis's
    inertia = list(st.inertia)
    k_axial = inertia.index(min(inertia))
    st.inertia = Vector3(*[i_axial if k == k_axial else i_transverse for k in range(3)])
    st.mass = clump_mass
    for i in ids:
        O.bodies[i].state.mass = clump_mass

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom(hertzian=True)],
        [Ip2_FrictMat_FrictMat_MindlinPhys(en=0.5)],
        [Law2_ScGeom_MindlinPhys_Mindlin()],
    ),
    NewtonIntegrator(damping=0.0, gravity=(0, 0, -9.81)),
]
O.dt = 1e-5
print("clumps_yade: %d clumps, mass %.6e, inertia %.6e %.6e, %d bodies"
      % (n, clump_mass, i_axial, i_transverse, len(O.bodies)), file=sys.stderr)

O.run(settle, True)
kinetic = sum(0.5 * b.state.mass * b.state.vel.squaredNorm() for b in O.bodies if b.isClump)
print("clumps_yade: after settling: translational kinetic energy %.6e J" % kinetic,
      file=sys.stderr)
c0 = time.process_time()
O.run(timed, True)
cpu = time.process_time() - c0

contacts = sum(1 for i in O.interactions if i.isReal and i.geom.penetrationDepth > 0)
with open(members_file, "w") as f:
    for b in O.bodies:
        if b.isClumpMember:
            p = b.state.pos
            f.write("%d %.12g %.12g %.12g %.12g\n" % (b.clumpId, p[0], p[1], p[2], b.shape.radius))
print("RESULT %.2f %d" % (cpu, contacts))
sys.stdout.flush()
