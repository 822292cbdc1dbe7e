#!/usr/bin/python3
"""Writes the STL test files with VTK's vtkSTLWriter (python3-vtk9): run from this folder.

box_ascii.stl, box_binary.stl: a 20 x 30 x 40 m box centred at (500100.5, 7000200.5, 350)
  (volume 24000 m3; every coordinate is exact in float32, whose step at 7e6 is 0.5 m).
box_binary_solid_header.stl: the box, binary, with its header replaced by "solid box" (a binary file
  that begins with "solid", as several exporters write them).
plane_binary.stl: an open 4 x 4 quad sheet (100 m x 100 m at z = 300): a surface.
two_solids.stl: the ASCII box written with header "ore_lens" followed by the ASCII sheet
  written with header "fault_7": two solids in one file.
"""
import vtk


def box():
    s = vtk.vtkCubeSource()
    s.SetCenter(500100.5, 7000200.5, 350.0)
    s.SetXLength(20.0)
    s.SetYLength(30.0)
    s.SetZLength(40.0)
    t = vtk.vtkTriangleFilter()
    t.SetInputConnection(s.GetOutputPort())
    return t


def sheet():
    p = vtk.vtkPlaneSource()
    p.SetOrigin(500050.0, 7000150.0, 300.0)
    p.SetPoint1(500150.0, 7000150.0, 300.0)
    p.SetPoint2(500050.0, 7000250.0, 300.0)
    p.SetResolution(4, 4)
    t = vtk.vtkTriangleFilter()
    t.SetInputConnection(p.GetOutputPort())
    return t


def write(src, name, binary, header=None):
    w = vtk.vtkSTLWriter()
    w.SetInputConnection(src.GetOutputPort())
    w.SetFileName(name)
    if header:
        w.SetHeader(header)
    if binary:
        w.SetFileTypeToBinary()
    else:
        w.SetFileTypeToASCII()
    w.Write()


write(box(), "box_ascii.stl", False)
write(box(), "box_binary.stl", True)
# vtkSTLWriter refuses a binary header that begins with "solid": the header bytes of its
# binary box are replaced here (the 80 header bytes only; the triangles are VTK's).
with open("box_binary.stl", "rb") as f:
    data = f.read()
with open("box_binary_solid_header.stl", "wb") as f:
    f.write(b"solid box".ljust(80, b" ") + data[80:])
write(sheet(), "plane_binary.stl", True)
write(box(), "part_a.tmp", False, "ore_lens")
write(sheet(), "part_b.tmp", False, "fault_7")
with open("two_solids.stl", "wb") as out:
    for n in ("part_a.tmp", "part_b.tmp"):
        with open(n, "rb") as f:
            out.write(f.read())
import os
os.remove("part_a.tmp")
os.remove("part_b.tmp")
