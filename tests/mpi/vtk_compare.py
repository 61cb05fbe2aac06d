"""Compares the VTK files `dump vtk` wrote alone (PREFIX_*.vtp) and on several ranks
(PREFIX_elements.pvtp and PREFIX_contacts.pvtp over one piece a rank, PREFIX_walls.vtp), read
with VTK's own readers as ParaView reads them: the same element ids at the same positions (to
1e-10 m), the same contacts (by the ids of their ends), the same wall forces (to 1e-7 of the
largest). Usage: vtk_compare.py SERIAL_PREFIX RANKS_PREFIX. Exits 1 naming what differs.
"""
import sys

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


def main(serial, ranks):
    a, b = read(serial + "_elements.vtp"), read(ranks + "_elements.pvtp")
    ida, idb = array(a, "point", "id"), array(b, "point", "id")
    if sorted(ida) != sorted(idb):
        sys.exit("elements: the ids differ (%d alone, %d on the ranks)" % (len(ida), len(idb)))
    xa, xb = dict(zip(ida, points(a))), dict(zip(idb, points(b)))
    worst = max(abs(p - q) for i in ida for p, q in zip(xa[i], xb[i]))
    if not worst <= 1e-10:
        sys.exit("elements: positions differ by %g m" % worst)

    a, b = read(serial + "_contacts.vtp"), read(ranks + "_contacts.pvtp")
    def pairs(d):
        ea, eb, w = (array(d, "cell", n) for n in ("a", "b", "wall"))
        return sorted((min(x, y), max(x, y), z) if y >= 0 else (x, y, z) for x, y, z in zip(ea, eb, w))
    if pairs(a) != pairs(b):
        sys.exit("contacts differ (%d alone, %d on the ranks)" % (a.GetNumberOfCells(), b.GetNumberOfCells()))

    a, b = read(serial + "_walls.vtp"), read(ranks + "_walls.vtp")
    fa, fb = array(a, "cell", "force"), array(b, "cell", "force")
    largest = max(abs(x) for f in fa for x in f)
    if len(fa) != len(fb) or not max(abs(x - y) for f, g in zip(fa, fb) for x, y in zip(f, g)) <= 1e-7 * largest:
        sys.exit("walls: forces differ")
    contacts = read(serial + "_contacts.vtp").GetNumberOfCells()
    print("vtk: %d elements within %.1e m, %d contacts, %d wall cells agree"
          % (len(ida), worst, contacts, len(fa)))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
