# yade's side of scripts/peer-bond: rebuilds the bonded sample demlab exported (rock::export in
# examples/rock.tcl: prefix.elements.csv, prefix.bonds.csv, prefix.meta) and loads it the way
# examples/ucs.tcl does, then prints one CSV row on stdout:
#
#   CODE,elements,bonds,steps,seconds,seconds_per_step,us_per_bond_step,peak_MPa,E_GPa,
#   cpu_seconds,cpu_us_per_bond_step
#
# seconds and cpu_seconds: the wall and CPU time (time.process_time, the whole process) of the
# compression alone.
#
# Run by scripts/peer-bond as  yade -j1 -n -x scripts/peer-bond.py PREFIX ?DAMPING? ?MODE?
#
# MODE bond (the default, CODE yade): a bonded pair's springs are the bond's alone. MODE stiff
# (CODE yade-stiff): the contact's normal and shear stiffness are added to the bond's, as in
# demlab once a bonded pair touches (demlab's contact law acts beside the bond when the pair
# overlaps; yade's cohesive interaction has one spring for tension and compression, so neither
# mode is demlab's pair in both).
#
# The model is CohFrictMat (Law2_ScGeom6D_CohFrictPhys_CohesionMoment with its moment law), set
# pair by pair from demlab's parallel bonds: for a bond of radius R = lambda min(Ri, Rj),
# A = pi R^2, I = pi R^4 / 4, J = pi R^4 / 2 and stiffnesses per area kn, ks,
#   kn A, ks A (normal, shear, N/m), kn I (bending), ks J (twist, N m/rad),
#   normalAdhesion = sigma_t A, shearAdhesion = tau_c A (each bond's own drawn strengths),
# and unp = the pair's initial penetration (minus its gap), so that a bond made across a gap
# starts unloaded as demlab's does (yade measures the normal force from touching). Unbonded
# contacts get yade's default stiffness from the material: kn = 2 E R1 R2 / (R1 + R2), which is
# demlab's kn = E* R* with E = E* / 2, and ks = poisson kn, so "poisson" is demlab's ks/kn.
# The platens are yade walls of a stiff FrictMat: kn -> 2 E R, demlab's rigid plate's E* R.
# Stress, strain, peak and E are read and defined as in examples/ucs.tcl, from the same face
# elements, cross-section, initial height and platen speed, every as many steps as demlab's
# readings (its -time interval rounded up to whole steps), at demlab's time step.
import math
import sys
import time

prefix = sys.argv[1]
damping = float(sys.argv[2]) if len(sys.argv) > 2 else 0.2
mode = sys.argv[3] if len(sys.argv) > 3 else 'bond'
if mode not in ('bond', 'stiff'):
    sys.exit('peer-bond.py: bad mode %r: must be bond or stiff' % mode)


def read_csv(path):
    with open(path) as f:
        head = f.readline().strip().split(',')
        return [dict(zip(head, map(float, line.strip().split(',')))) for line in f if line.strip()]


meta = {}
with open(prefix + '.meta') as f:
    for line in f:
        k, _, v = line.strip().partition(' ')
        meta[k] = v
num = lambda k: float(meta[k])
elements = read_csv(prefix + '.elements.csv')
bonds = read_csv(prefix + '.bonds.csv')

axis = int(num('axis'))
ey = num('rock_rock_young') / 2
shear_ratio = 2 * (1 - num('rock_poisson')) / (2 - num('rock_poisson'))  # demlab's 4 G*/E*
rock = O.materials.append(
    CohFrictMat(young=ey, poisson=shear_ratio, density=num('rock_density'),
                frictionAngle=math.atan(num('rock_rock_friction')), isCohesive=True,
                momentRotationLaw=True, alphaKr=0, alphaKtw=0, etaRoll=-1, etaTwist=-1,
                fragile=True, normalCohesion=0, shearCohesion=0))
# A plate far stiffer than the rock: the wall contact's harmonic mean tends to 2 E R.
plate = O.materials.append(
    FrictMat(young=ey * 1e6, poisson=shear_ratio, density=7800,
             frictionAngle=math.atan(num('rock_plate_friction'))))

ids = {}
for e in elements:
    ids[int(e['id'])] = O.bodies.append(
        sphere((e['x'], e['y'], e['z']), e['radius'], material=rock))

lo, hi, v = num('lo'), num('hi'), num('velocity')
bottom = O.bodies.append(wall(lo, axis=axis, sense=1, material=plate))
top = O.bodies.append(wall(hi, axis=axis, sense=-1, material=plate))
for w, s in ((bottom, 1), (top, -1)):
    vel = Vector3(0, 0, 0)
    vel[axis] = s * v
    O.bodies[w].state.vel = vel

law = Law2_ScGeom6D_CohFrictPhys_CohesionMoment(useIncrementalForm=True)
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
    InteractionLoop([Ig2_Sphere_Sphere_ScGeom6D(), Ig2_Wall_Sphere_ScGeom()],
                    [Ip2_CohFrictMat_CohFrictMat_CohFrictPhys(), Ip2_FrictMat_FrictMat_FrictPhys()],
                    [law, Law2_ScGeom_FrictPhys_CundallStrack()]),
    NewtonIntegrator(damping=damping),
]
O.dt = num('dt')

lam = num('bond_radius')
kn, ks = num('bond_kn'), num('bond_ks')
for b in bonds:
    i = createInteraction(ids[int(b['a'])], ids[int(b['b'])])
    r = lam * min(O.bodies[i.id1].shape.radius, O.bodies[i.id2].shape.radius)
    area = math.pi * r * r
    p = i.phys
    kc = 0
    if mode == 'stiff':  # the contact's kn = E* R* of demlab's linear law, its ks = ratio kn
        ra, rb = O.bodies[i.id1].shape.radius, O.bodies[i.id2].shape.radius
        kc = 2 * ey * ra * rb / (ra + rb)
    p.kn, p.ks = kn * area + kc, ks * area + shear_ratio * kc
    p.kr, p.ktw = kn * area * r * r / 4, ks * area * r * r / 2
    p.normalAdhesion, p.shearAdhesion = b['tensile'] * area, b['shear'] * area
    p.cohesionBroken, p.fragile, p.cohesionDisablesFriction = False, True, True
    p.momentRotationLaw = True
    p.maxRollPl = p.maxTwistPl = -1
    p.unp = i.geom.penetrationDepth


def intact():
    return sum(1 for i in O.interactions if i.isReal and isinstance(i.phys, CohFrictPhys)
               and not i.phys.cohesionBroken)


nbonds = intact()
lo_face = [ids[int(k)] for k in meta['lo_face'].split()]
hi_face = [ids[int(k)] for k in meta['hi_face'].split()]
h0, area = num('h0'), num('area')
every = math.ceil(num('interval') / O.dt - 1e-9)
strain_end = num('strain_end')
O.engines = O.engines + [PyRunner(iterPeriod=every, command='reading()')]


def mean(face):
    return sum(O.bodies[k].state.pos[axis] for k in face) / len(face)


curve = []
peak = [0.0, 0.0]


def reading():
    strain = 1 - (mean(hi_face) - mean(lo_face)) / h0
    stress = (O.forces.f(top)[axis] - O.forces.f(bottom)[axis]) / 2 / area
    curve.append((strain, stress))
    if stress > peak[0]:
        peak[:] = [stress, strain]
    if stress < 0.6 * peak[0] or strain > strain_end:
        O.pause()


start_iter = O.iter
t0, c0 = time.perf_counter(), time.process_time()
O.run()
O.wait()
seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
steps = O.iter - start_iter

# The least-squares slope of stress against strain between 25 % and 50 % of the peak, before it.
pts = [(e, s) for e, s in curve if e <= peak[1] and 0.25 * peak[0] <= s <= 0.5 * peak[0]]
modulus = 0.0
if len(pts) > 1:
    mx = sum(e for e, _ in pts) / len(pts)
    my = sum(s for _, s in pts) / len(pts)
    modulus = sum((e - mx) * (s - my) for e, s in pts) / sum((e - mx)**2 for e, _ in pts)
print('%s,%d,%d,%d,%.3f,%.4g,%.4g,%.4g,%.4g,%.3f,%.4g' %
      ('yade' if mode == 'bond' else 'yade-stiff', len(elements), nbonds, steps, seconds, seconds / steps, 1e6 * seconds / steps / nbonds,
       peak[0] / 1e6, modulus / 1e9, cpu, 1e6 * cpu / steps / nbonds))
print('peer-bond.py: %d bonds intact at the end; damping %g; every %d steps; peak at strain %.4g' %
      (intact(), damping, every, peak[1]), file=sys.stderr)
sys.stdout.flush()
