"""Reads VTK XML files with VTK's own readers and prints what they hold as a Tcl dict, so the
dump tests check the files as ParaView sees them, not by string comparison.

Usage: vtk_read.py FILE   (.vtp or .vti)
Prints: type T points N verts V lines L polys P connectivity {...} arrays {NAME {ASSOC COMPONENTS
TUPLES {values...}} ...}; ASSOC is point, cell or field; string arrays have COMPONENTS "string".
"""
import sys

import vtk


def tcl(s):
    s = str(s)
    if s and all(c.isalnum() or c in "._-+" for c in s):
        return s
    return "{" + s.replace("\\", "\\\\").replace("{", "\\{").replace("}", "\\}") + "}"


def main(path):
    if path.endswith(".vti"):
        reader = vtk.vtkXMLImageDataReader()
    else:
        reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    if reader.GetErrorCode() != 0:
        sys.exit("VTK could not read " + path)
    d = reader.GetOutput()
    out = ["type", d.GetClassName(), "points", str(d.GetNumberOfPoints())]
    if isinstance(d, vtk.vtkPolyData):
        out += ["verts", str(d.GetNumberOfVerts()), "lines", str(d.GetNumberOfLines()),
                "polys", str(d.GetNumberOfPolys())]
        cells = []
        for k in range(d.GetNumberOfCells()):
            ids = d.GetCell(k).GetPointIds()
            cells.append("{" + " ".join(str(ids.GetId(j)) for j in range(ids.GetNumberOfIds())) + "}")
        out += ["connectivity", "{" + " ".join(cells) + "}"]
        pts = d.GetPoints()
        coords = [] if pts is None else [repr(c) for k in range(pts.GetNumberOfPoints()) for c in pts.GetPoint(k)]
        out += ["coordinates", "{" + " ".join(coords) + "}"]
    else:
        out += ["dims", "{" + " ".join(map(str, d.GetDimensions())) + "}",
                "origin", "{" + " ".join(map(repr, d.GetOrigin())) + "}",
                "spacing", "{" + " ".join(map(repr, d.GetSpacing())) + "}"]
    arrays = []
    for assoc, data in (("point", d.GetPointData()), ("cell", d.GetCellData()), ("field", d.GetFieldData())):
        for i in range(data.GetNumberOfArrays()):
            a = data.GetAbstractArray(i)
            if isinstance(a, vtk.vtkStringArray):
                vals = [tcl(a.GetValue(k)) for k in range(a.GetNumberOfValues())]
                comps = "string"
                tuples = a.GetNumberOfValues()
            else:
                comps = a.GetNumberOfComponents()
                tuples = a.GetNumberOfTuples()
                vals = [repr(a.GetComponent(t, c)) for t in range(tuples) for c in range(comps)]
            arrays.append(tcl(a.GetName()) + " {" + " ".join([assoc, str(comps), str(tuples), "{" + " ".join(vals) + "}"]) + "}")
    out += ["arrays", "{" + " ".join(arrays) + "}"]
    print(" ".join(out))


if __name__ == "__main__":
    main(sys.argv[1])
