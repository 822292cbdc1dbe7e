#!/usr/bin/python3
"""Writes the PLY test files: run from this folder.

With VTK's vtkPLYWriter (python3-vtk9): box_ascii.ply, box_binary_le.ply, box_binary_be.ply,
  the 20 x 30 x 40 m box centred at (500100.5, 7000200.5, 350) (volume 24000 m3) in ASCII,
  binary little-endian and binary big-endian (VTK writes float32 coordinates, exact here).
Two boxes and an open sheet in one triangle list, face region 1 = a 10 m cube at the origin
  corner, 2 = a 2 x 4 x 8 m box at (100, 0, 0), 7 = an open 10 x 10 m sheet at z = -5:
  regions_meshio.ply by meshio (python3-meshio, binary little-endian, no region property:
  meshio 5.0's PLY writer drops cell data), regions_ascii.ply and regions_binary_be.ply with
  the int32 face property "region", written with struct (see below).
"""
import vtk  # before meshio: the other order crashed in vtkPLYWriter here

import meshio
import numpy as np


def vtk_box():
    s = vtk.vtkCubeSource()
    s.SetCenter(500100.5, 7000200.5, 350.0)
    s.SetXLength(20.0)
    s.SetYLength(30.0)
    s.SetZLength(40.0)
    t = vtk.vtkTriangleFilter()
    t.SetInputConnection(s.GetOutputPort())
    c = vtk.vtkCleanPolyData()  # shared corners, as PLY writers usually give
    c.SetInputConnection(t.GetOutputPort())
    c.Update()
    out = vtk.vtkPolyData()
    out.DeepCopy(c.GetOutput())
    return out


for name, binary, big in (("box_ascii.ply", False, False), ("box_binary_le.ply", True, False),
                          ("box_binary_be.ply", True, True)):
    w = vtk.vtkPLYWriter()
    w.SetInputData(vtk_box())
    w.SetFileName(name)
    if binary:
        w.SetFileTypeToBinary()
        if big:
            w.SetDataByteOrderToBigEndian()
        else:
            w.SetDataByteOrderToLittleEndian()
    else:
        w.SetFileTypeToASCII()
    w.Write()

# Boxes as 8 corners and 12 outward triangles.
QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (0, 4, 7, 3), (1, 2, 6, 5)]


def box(o, size, base):
    x0, y0, z0 = o
    dx, dy, dz = size
    pts = [(x0, y0, z0), (x0 + dx, y0, z0), (x0 + dx, y0 + dy, z0), (x0, y0 + dy, z0),
           (x0, y0, z0 + dz), (x0 + dx, y0, z0 + dz), (x0 + dx, y0 + dy, z0 + dz), (x0, y0 + dy, z0 + dz)]
    tris = []
    for a, b, c, d in QUADS:
        tris += [(base + a, base + b, base + c), (base + a, base + c, base + d)]
    return pts, tris


points, tris, region = [], [], []
for o, size, r in (((0.0, 0.0, 0.0), (10.0, 10.0, 10.0), 1), ((100.0, 0.0, 0.0), (2.0, 4.0, 8.0), 2)):
    p, t = box(o, size, len(points))
    points += p
    tris += t
    region += [r] * len(t)
b = len(points)
points += [(0.0, 0.0, -5.0), (10.0, 0.0, -5.0), (10.0, 10.0, -5.0), (0.0, 10.0, -5.0)]
tris += [(b, b + 1, b + 2), (b, b + 2, b + 3)]
region += [7, 7]
# meshio 5.0's PLY writer drops cell data, so it writes the geometry only (regions_meshio.ply,
# read as one part) and the region files are written below with Python's struct module, by
# the PLY 1.0 grammar: vertex x y z (double) and a float "nx" skipped by the reader; face
# "vertex_indices" (uchar count, int32 indices), then "region" (int32) and "quality" (float32,
# skipped), ASCII and binary big-endian.
mesh = meshio.Mesh(np.array(points, dtype=np.float64), [("triangle", np.array(tris, dtype=np.int32))])
meshio.write("regions_meshio.ply", mesh, binary=True)

import struct

header = ["ply", None, "comment written by make_ply.py", "element vertex %d" % len(points),
          "property double x", "property double y", "property double z", "property float nx",
          "element face %d" % len(tris), "property list uchar int vertex_indices", "property int region",
          "property float quality", "end_header"]
with open("regions_ascii.ply", "w") as f:
    header[1] = "format ascii 1.0"
    f.write("\n".join(header) + "\n")
    for p in points:
        f.write("%r %r %r 0.5\n" % p)
    for t, r in zip(tris, region):
        f.write("3 %d %d %d %d 1.25\n" % (t[0], t[1], t[2], r))
with open("regions_binary_be.ply", "wb") as f:
    header[1] = "format binary_big_endian 1.0"
    f.write(("\n".join(header) + "\n").encode())
    for p in points:
        f.write(struct.pack(">dddf", p[0], p[1], p[2], 0.5))
    for t, r in zip(tris, region):
        f.write(struct.pack(">Biiiif", 3, t[0], t[1], t[2], r, 1.25))
