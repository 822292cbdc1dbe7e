#!/usr/bin/env python3
"""Writes the .vtu files of tests/unit/vtu_names_test.cpp with VTK's own writer
(vtkXMLUnstructuredGridWriter, Debian's python3-vtk9): three formations of hexahedra (a 10 m
cube each, side by side along x from x = 1000 m) whose names come as
  - names_cell_<mode>.vtu: a CellData string array "formation_name" beside the Int32 array
    "formation" (values 0, 1, 2), in ascii, binary (zlib) and appended (raw) modes;
  - names_field_0.vtu: only a FieldData string array "FormationNames" indexed by the value
    (values 0, 1, 2);
  - names_field_1.vtu: the same with values 1, 2, 3 (1-based);
  - names_shared.vtu: cell names where two formations share a name ("Granite").
    python3 tests/data/vtu/make_formation_names.py   (run from anywhere; writes beside itself)
"""
import os

import vtk

HERE = os.path.dirname(os.path.abspath(__file__))
NAMES = ["Nappe de Morcles", "Nappe du Wildhorn", "地层 T3x"]


def grid(values, cell_names=None, field_names=None):
    g = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for k in range(len(values)):
        x0 = 1000.0 + 10.0 * k
        for z in (0.0, 10.0):
            for (x, y) in ((x0, 0.0), (x0 + 10.0, 0.0), (x0 + 10.0, 10.0), (x0, 10.0)):
                pts.InsertNextPoint(x, y, z)
    g.SetPoints(pts)
    for k in range(len(values)):
        b = 8 * k
        g.InsertNextCell(vtk.VTK_HEXAHEDRON, 8, [b + i for i in range(8)])
    f = vtk.vtkIntArray()
    f.SetName("formation")
    for v in values:
        f.InsertNextValue(v)
    g.GetCellData().AddArray(f)
    if cell_names:
        g.GetCellData().AddArray(strings("formation_name", cell_names))
    if field_names:
        g.GetFieldData().AddArray(strings("FormationNames", field_names))
    return g


def strings(name, values):
    s = vtk.vtkStringArray()
    s.SetName(name)
    for v in values:
        s.InsertNextValue(v)
    return s


def write(g, name, mode):
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(os.path.join(HERE, name))
    w.SetInputData(g)
    w.SetDataMode(mode)
    if mode == vtk.vtkXMLWriter.Appended:
        w.SetEncodeAppendedData(False)
        w.SetCompressorTypeToNone()
    if not w.Write():
        raise SystemExit(f"VTK could not write {name}")


for mode, label in ((vtk.vtkXMLWriter.Ascii, "ascii"), (vtk.vtkXMLWriter.Binary, "binary"),
                    (vtk.vtkXMLWriter.Appended, "appended")):
    write(grid([0, 1, 2], cell_names=NAMES), f"names_cell_{label}.vtu", mode)
write(grid([0, 1, 2], field_names=NAMES), "names_field_0.vtu", vtk.vtkXMLWriter.Ascii)
write(grid([1, 2, 3], field_names=NAMES), "names_field_1.vtu", vtk.vtkXMLWriter.Binary)
write(grid([0, 1, 2], cell_names=["Granite", "Schist", "Granite"]), "names_shared.vtu", vtk.vtkXMLWriter.Ascii)
