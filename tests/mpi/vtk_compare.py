"""Compares the VTK files `dump vtk` wrote alone (PREFIX_*.vtp) and on several ranks
(PREFIX_elements.pvtp and PREFIX_contacts.pvtp over one piece a rank, PREFIX_walls.vtp), read
with VTK's own readers as ParaView reads them: the same element ids at the same positions (to
1e-10 m), the same contacts (by the ids of their ends), the same wall forces (to 1e-7 of the
largest). Usage: vtk_compare.py SERIAL_PREFIX RANKS_PREFIX, or vtk_compare.py --series
SERIAL_DIR RANKS_DIR for the elements.pvd series of `dump every`, or vtk_compare.py --png A1 B1
A2 B2 ... for snapshot frames (at most 1 pixel in 1000 differing), or vtk_compare.py --csv A B
for `dump csv -fields {id radius x y z vx vy vz}`, or vtk_compare.py --lammps A B for `dump
lammps`. Exits 1 naming what differs.
"""
import os
import sys
import xml.etree.ElementTree as ET

import vtk


def read(path):
    reader = vtk.vtkXMLPPolyDataReader() if path.endswith(".pvtp") else vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0:
        sys.exit("VTK could not read " + path)
    return reader.GetOutput()


def array(d, assoc, name):
    """Returns the array's tuples: numbers, or tuples of numbers."""
    data = d.GetPointData() if assoc == "point" else d.GetCellData()
    a = data.GetArray(name)
    if a is None:
        sys.exit("no %s array %s" % (assoc, name))
    n = a.GetNumberOfComponents()
    return [a.GetTuple(k) if n > 1 else a.GetTuple(k)[0] for k in range(a.GetNumberOfTuples())]


def points(d):
    return [d.GetPoint(k) for k in range(d.GetNumberOfPoints())]


def compare_elements(file_a, file_b):
    """Returns the number of elements and the largest position difference; exits if they differ."""
    a, b = read(file_a), read(file_b)
    ida, idb = array(a, "point", "id"), array(b, "point", "id")
    if sorted(ida) != sorted(idb):
        sys.exit("%s: the ids differ (%d alone, %d on the ranks)" % (file_b, len(ida), len(idb)))
    xa, xb = dict(zip(ida, points(a))), dict(zip(idb, points(b)))
    worst = max(abs(p - q) for i in ida for p, q in zip(xa[i], xb[i]))
    if not worst <= 1e-10:
        sys.exit("%s: positions differ by %g m" % (file_b, worst))
    return len(ida), worst


def compare_series(dir_a, dir_b):
    """The elements.pvd series of `dump every`: the same times, the last frames' elements alike."""
    def frames(d):
        root = ET.parse(os.path.join(d, "elements.pvd")).getroot()
        return [(float(e.get("timestep")), e.get("file")) for e in root.iter("DataSet")]
    fa, fb = frames(dir_a), frames(dir_b)
    if [t for t, _ in fa] != [t for t, _ in fb]:
        sys.exit("series: the frames' times differ: %s / %s" % (fa, fb))
    n, worst = compare_elements(os.path.join(dir_a, fa[-1][1]), os.path.join(dir_b, fb[-1][1]))
    print("vtk series: %d frames (%s), the last one's %d elements within %.1e m"
          % (len(fb), " ".join(f for _, f in fb), n, worst))


def compare_png(file_a, file_b):
    """Two frames of the same scene: at most 1 pixel in 1000 differs (a ball's edge may fall on
    the other side of a pixel's centre with the positions' round-off)."""
    def pixels(path):
        reader = vtk.vtkPNGReader()
        reader.SetFileName(path)
        reader.Update()
        d = reader.GetOutput()
        a = d.GetPointData().GetScalars()
        if a is None:
            sys.exit("VTK could not read " + path)
        return d.GetDimensions(), [a.GetTuple(k) for k in range(a.GetNumberOfTuples())]
    (da, pa), (db, pb) = pixels(file_a), pixels(file_b)
    if da != db:
        sys.exit("%s: %s pixels, %s alone" % (file_b, db, da))
    differ = sum(1 for x, y in zip(pa, pb) if x != y)
    if differ > len(pa) // 1000:
        sys.exit("%s: %d of %d pixels differ" % (file_b, differ, len(pa)))
    return differ, len(pa)


def compare_csv(file_a, file_b):
    """`dump csv` alone (the scene's order) and distributed (by id): the same rows by id, the
    radii exactly, positions within 1e-10 m and velocities within 1e-7 m/s."""
    def rows(path):
        with open(path) as f:
            lines = f.read().split("\n")
        head = lines[0].split(",")
        return head, {int(r.split(",")[0]): [float(x) for x in r.split(",")[1:]] for r in lines[1:] if r}
    (ha, ra), (hb, rb) = rows(file_a), rows(file_b)
    if ha != hb or sorted(ra) != sorted(rb):
        sys.exit("%s: other columns or ids than alone" % file_b)
    order = [int(r.split(",")[0]) for r in open(file_b).read().split("\n")[1:] if r]
    if order != sorted(order):
        sys.exit("%s: the rows are not in the order of the ids" % file_b)
    worst = [0.0] * (len(ha) - 1)
    for i in ra:
        for k, (x, y) in enumerate(zip(ra[i], rb[i])):
            worst[k] = max(worst[k], abs(x - y))
    tol = [0.0, 1e-10, 1e-10, 1e-10, 1e-7, 1e-7, 1e-7]
    if any(not w <= t for w, t in zip(worst, tol)):
        sys.exit("%s: columns differ by %s" % (file_b, worst))
    print("csv: %d rows agree (largest differences %s)" % (len(ra), " ".join("%.1e" % w for w in worst)))


def compare_lammps(file_a, file_b):
    """`dump lammps` alone and distributed (rank 0 writes the gathered scene): the same lines,
    the rows of a section by atom id, word by word: words and integers (counts, atom ids and
    types) equal; before the Velocities section (box, diameters, densities, positions) numbers
    within 1e-10; in it velocities within 1e-7 m/s (as --csv) and angular velocities within
    1e-5 of the row's largest (round-off grows through stick and slip: ~1e-6 after the
    edits of falling_bed.tcl on 3 ranks)."""
    def lines(path):
        # The sections' rows by atom id (alone they come in the scene's order, gathered by id).
        out, rows = [], []
        for line in open(path).read().split("\n") + [""]:
            if line and line[0].isdigit() and len(line.split()) > 4:
                rows.append(line)
                continue
            out += sorted(rows, key=lambda r: int(r.split()[0]))
            rows = []
            out.append(line)
        return out
    la, lb = lines(file_a), lines(file_b)
    if len(la) != len(lb):
        sys.exit("%s: %d lines, %d alone" % (file_b, len(lb), len(la)))
    velocities, worst = False, [0.0, 0.0, 0.0]
    for a, b in zip(la, lb):
        velocities = velocities or a.startswith("Velocities")
        wa, wb = a.split(), b.split()
        if len(wa) != len(wb):
            sys.exit("%s: line %r, alone %r" % (file_b, b, a))
        spin = max([abs(float(x)) for x in wa[4:7]] or [0]) if velocities and len(wa) == 7 else 0
        for k, (x, y) in enumerate(zip(wa, wb)):
            try:
                fx, fy = float(x), float(y)
            except ValueError:
                fx = fy = None
            if fx is None or x.lstrip("-").isdigit():
                if x != y:
                    sys.exit("%s: %r where alone %r" % (file_b, y, x))
                continue
            which = 0 if not velocities else (1 if k < 4 else 2)
            tol = (1e-10, 1e-7, 1e-5 * spin)[which]
            if not abs(fx - fy) <= tol:
                sys.exit("%s: %s where alone %s (line %r)" % (file_b, y, x, a))
            # (A grain that does not turn, a fixed one, must agree exactly: tolerance 0.)
            if which != 2 or spin > 0:
                worst[which] = max(worst[which], abs(fx - fy) / (spin if which == 2 else 1))
    print("lammps: %d lines agree (largest differences %.1e, %.1e m/s, %.1e of the spin)"
          % (len(la), *worst))


def main(serial, ranks):
    n, worst = compare_elements(serial + "_elements.vtp", ranks + "_elements.pvtp")
    a, b = read(serial + "_contacts.vtp"), read(ranks + "_contacts.pvtp")
    def pairs(d):
        ea, eb, w = (array(d, "cell", n) for n in ("a", "b", "wall"))
        return sorted((min(x, y), max(x, y), z) if y >= 0 else (x, y, z) for x, y, z in zip(ea, eb, w))
    if pairs(a) != pairs(b):
        sys.exit("contacts differ (%d alone, %d on the ranks)" % (a.GetNumberOfCells(), b.GetNumberOfCells()))

    a, b = read(serial + "_walls.vtp"), read(ranks + "_walls.vtp")
    fa, fb = array(a, "cell", "force"), array(b, "cell", "force")
    largest = max(abs(x) for f in fa for x in f)
    # (Within 1e-6 of the largest, as compare_runs.tcl: a sum of stiff contacts' forces.)
    if len(fa) != len(fb):
        sys.exit("walls: %d alone, %d on the ranks" % (len(fa), len(fb)))
    diff = max(abs(x - y) for f, g in zip(fa, fb) for x, y in zip(f, g))
    if not diff <= 1e-6 * largest:
        sys.exit("walls: forces differ by %.3g N (largest %.3g N)" % (diff, largest))
    contacts = read(serial + "_contacts.vtp").GetNumberOfCells()
    print("vtk: %d elements within %.1e m, %d contacts, %d wall cells agree"
          % (n, worst, contacts, len(fa)))


if __name__ == "__main__":
    if sys.argv[1] == "--series":
        compare_series(sys.argv[2], sys.argv[3])
    elif sys.argv[1] == "--csv":
        compare_csv(sys.argv[2], sys.argv[3])
    elif sys.argv[1] == "--lammps":
        compare_lammps(sys.argv[2], sys.argv[3])
    elif sys.argv[1] == "--png":
        for a, b in zip(sys.argv[2::2], sys.argv[3::2]):
            differ, total = compare_png(a, b)
            print("png %s: %d of %d pixels differ" % (os.path.basename(b), differ, total))
    else:
        main(sys.argv[1], sys.argv[2])
