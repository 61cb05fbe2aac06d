# Boxes (convex polyhedra) settling in a box: the YADE side of scripts/peer-polyhedra (which
# see). YADE 2023.02a (Debian yade), one thread:
#
#   yade -j 1 -n -x bench/peer/polyhedra_yade.py N SIDE HEIGHT SETTLE_STEPS TIMED_STEPS KN KS DAMPING
#
# A box is 4 x 3 x 2 mm (polyhedra_utils.polyhedra with its 8 corners; PolyhedraMat, 2500
# kg/m^3). YADE's polyhedra contact (Ig2_Polyhedra_Polyhedra_PolyhedraGeom, the intersection
# polyhedron by CGAL; Ig2_Wall_Polyhedra_PolyhedraGeom against the walls) feeds its only law,
# Law2_PolyhedraGeom_PolyhedraPhys_Volumetric: a normal force kn * (overlap volume), a tangential
# spring ks (N/m) on the increments of the contact point's slip, Coulomb's limit; the law has no
# dashpot. Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys makes kn = 1/(1/Y1 + 1/Y2) and
# ks = 1/(1/(Y1 P1) + 1/(Y2 P2)) from the materials' young Y and poisson P (here not Poisson's
# ratio but ks/kn), so one material with young = 2 KN, poisson = KS / KN gives kn = KN (N/m^3)
# and ks = KS (N/m) for box-box and box-wall contacts alike. Friction 0.5 (frictionAngle
# atan 0.5). Damping: NewtonIntegrator's (Cundall's non-viscous, per body and axis) DAMPING.
# It damps the whole acceleration, gravity's too (dampGravity = True), which slows a free fall
# to (1 - DAMPING) g; with dampGravity = False the fall is free but a body at rest flips the
# damping's sign every step and rests on the wrong force (a box on the floor on twice its
# weight with 0.6). So the first half of the settling steps runs with dampGravity = False (the
# fall, as in demlab), the second half and the timed steps with dampGravity = True. Walls:
# five Wall bodies of the same material (floor z = 0, sides x, y = 0 and SIDE). Time step 1e-5 s.
#
# The boxes are placed by random sequential addition: centres uniform in the box, bounding
# spheres (the half diagonal, 2.693 mm) apart and inside it, orientations uniform over the
# rotations (Shoemake's quaternion).
#
# Prints on stdout a line "RESULT cpu_seconds pairs wall_pairs zmean ztop": the CPU time
# (time.process_time) of O.run(TIMED_STEPS, True); after it the contacting pairs (real
# interactions with overlap volume > 0: one per touching box-box or box-wall pair) and of those
# the box-wall pairs; the mean height of the box centres and the highest corner (m).
import math
import os
import random
import sys
import time

from yade import polyhedra_utils

sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[0])))
from peer_packing import pack_apart  # noqa: E402

n = int(sys.argv[1])
side = float(sys.argv[2])
height = float(sys.argv[3])
settle = int(sys.argv[4])
timed = int(sys.argv[5])
kn = float(sys.argv[6])
ks = float(sys.argv[7])
damping = float(sys.argv[8])

half = (2e-3, 1.5e-3, 1e-3)
bound = math.sqrt(sum(h * h for h in half))
density = 2500.0
corners = [Vector3(sx * half[0], sy * half[1], sz * half[2])
           for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]


mat = O.materials.append(PolyhedraMat(young=2 * kn, poisson=ks / kn, density=density,
                                      frictionAngle=math.atan(0.5)))
for axis, pos, sense in ((2, 0.0, 1), (0, 0.0, 1), (0, side, -1), (1, 0.0, 1), (1, side, -1)):
    O.bodies.append(utils.wall(pos, axis=axis, sense=sense, material=mat))

rng = random.Random(1)
for centre, (w, x, y, z) in pack_apart(rng, n, bound, side, height, "box"):
    b = polyhedra_utils.polyhedra(O.materials[mat], v=corners)
    b.state.pos = Vector3(*centre)
    b.state.ori = Quaternion(w, x, y, z)
    O.bodies.append(b)

O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Polyhedra_Aabb(), Bo1_Wall_Aabb()]),
    InteractionLoop(
        [Ig2_Polyhedra_Polyhedra_PolyhedraGeom(), Ig2_Wall_Polyhedra_PolyhedraGeom()],
        [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
        [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()],
    ),
    NewtonIntegrator(damping=damping, dampGravity=False, gravity=(0, 0, -9.81)),
]
O.dt = 1e-5
boxes = [b for b in O.bodies if isinstance(b.shape, Polyhedra)]
print("polyhedra_yade: %d boxes, mass %.6e, inertia %s, kn %.4g N/m^3, ks %.4g N/m, damping %g"
      % (len(boxes), boxes[0].state.mass, boxes[0].state.inertia, kn, ks, damping),
      file=sys.stderr)

O.run(settle // 2, True)
O.engines[-1].dampGravity = True
O.run(settle - settle // 2, True)
kinetic = sum(0.5 * b.state.mass * b.state.vel.squaredNorm() for b in boxes)
print("polyhedra_yade: after settling: translational kinetic energy %.6e J" % kinetic,
      file=sys.stderr)
c0 = time.process_time()
O.run(timed, True)
cpu = time.process_time() - c0

pairs = wall_pairs = 0
for i in O.interactions:
    if i.isReal and i.geom.penetrationVolume > 0:
        pairs += 1
        if not (isinstance(O.bodies[i.id1].shape, Polyhedra)
                and isinstance(O.bodies[i.id2].shape, Polyhedra)):
            wall_pairs += 1
zmean = sum(b.state.pos[2] for b in boxes) / len(boxes)
ztop = max((b.state.pos + b.state.ori * v)[2] for b in boxes for v in b.shape.v)
print("polyhedra_yade: %d real interactions (with or without overlap volume)"
      % sum(1 for i in O.interactions if i.isReal), file=sys.stderr)
print("RESULT %.2f %d %d %.6g %.6g" % (cpu, pairs, wall_pairs, zmean, ztop))
sys.stdout.flush()
