#!/usr/bin/python3
"""Writes the DXF test files with ezdxf (python3-ezdxf): run from this folder.

solids.dxf (DXF R2010), one layer per object:
  box_faces     a 20 x 30 x 40 m box centred at (500100.5, 7000200.5, 350) as six 3DFACE quads
                (volume 24000 m3)
  box_polyface  a 10 x 10 x 10 m cube at (500200, 7000200, 300) as a POLYLINE polyface mesh
                (ezdxf add_polyface, six quads; volume 1000 m3)
  box_mesh      a 4 x 6 x 8 m box at (500300, 7000200, 300) as a MESH entity (add_mesh;
                volume 192 m3)
  topo          an open 3 x 3 grid of triangles as 3DFACEs at z = 320 over 100 x 100 m: a surface
  grid          an open 4 x 3 POLYLINE polygon mesh (add_polymesh), z = 280: a surface
  contours      an LWPOLYLINE (closed, elevation 330) and a 3D POLYLINE: lines
  a CIRCLE on layer contours, which the reader skips and counts.
solids_r12.dxf: the same box_faces and box_polyface in DXF R12 (POLYLINE/VERTEX/SEQEND
  without subclass markers).
"""
import ezdxf

QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (0, 4, 7, 3), (1, 2, 6, 5)]


def corners(o, size):
    x0, y0, z0 = o
    dx, dy, dz = size
    return [(x0, y0, z0), (x0 + dx, y0, z0), (x0 + dx, y0 + dy, z0), (x0, y0 + dy, z0),
            (x0, y0, z0 + dz), (x0 + dx, y0, z0 + dz), (x0 + dx, y0 + dy, z0 + dz), (x0, y0 + dy, z0 + dz)]


def add_common(msp):
    c = corners((500090.5, 7000185.5, 330.0), (20.0, 30.0, 40.0))
    for q in QUADS:
        msp.add_3dface([c[i] for i in q], dxfattribs={"layer": "box_faces"})
    c = corners((500200.0, 7000200.0, 300.0), (10.0, 10.0, 10.0))
    pf = msp.add_polyface(dxfattribs={"layer": "box_polyface"})
    for q in QUADS:
        pf.append_face([c[i] for i in q])
    pf.optimize()  # shared vertices, as CAD programs write them


def solids():
    doc = ezdxf.new("R2010")
    msp = doc.modelspace()
    add_common(msp)
    c = corners((500300.0, 7000200.0, 300.0), (4.0, 6.0, 8.0))
    mesh = msp.add_mesh(dxfattribs={"layer": "box_mesh"})
    with mesh.edit_data() as data:
        data.vertices = c
        data.faces = QUADS
    for i in range(3):
        for j in range(3):
            x0, y0 = 500050.0 + 100.0 / 3 * i, 7000150.0 + 100.0 / 3 * j
            x1, y1 = x0 + 100.0 / 3, y0 + 100.0 / 3
            msp.add_3dface([(x0, y0, 320.0), (x1, y0, 320.0), (x1, y1, 320.0)], dxfattribs={"layer": "topo"})
            msp.add_3dface([(x0, y0, 320.0), (x1, y1, 320.0), (x0, y1, 320.0)], dxfattribs={"layer": "topo"})
    pm = msp.add_polymesh(size=(4, 3), dxfattribs={"layer": "grid"})
    for m in range(4):
        for n in range(3):
            pm.set_mesh_vertex((m, n), (500050.0 + 25.0 * m, 7000150.0 + 25.0 * n, 280.0))
    msp.add_lwpolyline([(500050.0, 7000150.0), (500150.0, 7000150.0), (500150.0, 7000250.0)], close=True,
                       dxfattribs={"layer": "contours", "elevation": 330.0})
    msp.add_polyline3d([(500050.0, 7000150.0, 300.0), (500100.0, 7000200.0, 350.0), (500150.0, 7000250.0, 400.0)],
                       dxfattribs={"layer": "contours"})
    msp.add_circle((500100.0, 7000200.0), 5.0, dxfattribs={"layer": "contours"})
    doc.saveas("solids.dxf")


def solids_r12():
    doc = ezdxf.new("R12")
    add_common(doc.modelspace())
    doc.saveas("solids_r12.dxf")


solids()
solids_r12()
