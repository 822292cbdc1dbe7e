#!/usr/bin/python3
"""VTK peer of bench/table1: vtkPlaneCutter (sphere tree built once, SMP backend with the
given threads) and vtkCutter on the mesh and planes bench_table1 exported.

usage: vtk_peer.py MODEL.ply PLANES.json OUT.json [--threads 2] [--cutter-budget-s 120]

Writes per plane and per filter the update time (ms), the segment count (line cells) and
the total segment length. vtkCutter is skipped for the remaining planes once its total
time passes the budget (its per-plane cost is O(N); the report says how many were run).
Debian's python3-vtk9 (VTK 9.1); run with /usr/bin/python3 (a pyenv python lacks it).
"""
import json
import resource
import sys
import time

import numpy as np
from vtkmodules.util import numpy_support
from vtkmodules.vtkCommonCore import vtkPoints, vtkSMPTools, vtkVersion
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPlane, vtkPolyData
from vtkmodules.vtkFiltersCore import vtkCutter, vtkPlaneCutter


def read_ply(path):
    with open(path, "rb") as f:
        nv = nf = 0
        while True:
            line = f.readline().decode("ascii").strip()
            if line.startswith("element vertex"):
                nv = int(line.split()[2])
            elif line.startswith("element face"):
                nf = int(line.split()[2])
            elif line == "end_header":
                break
        verts = np.fromfile(f, dtype="<f8", count=3 * nv).reshape(nv, 3)
        faces = np.fromfile(f, dtype=np.dtype([("n", "u1"), ("v", "<i4", (3,)), ("part", "<i4")]), count=nf)
    return verts, faces["v"].astype(np.int64)


def polydata(verts, tris):
    pts = vtkPoints()
    pts.SetData(numpy_support.numpy_to_vtk(verts, deep=True))
    offsets = numpy_support.numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(tris) + 1, 3, dtype=np.int64), deep=True)
    conn = numpy_support.numpy_to_vtkIdTypeArray(np.ascontiguousarray(tris.ravel()), deep=True)
    cells = vtkCellArray()
    cells.SetData(offsets, conn)
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(cells)
    return pd


def pieces(obj):
    """The vtkPolyData leaves of a filter output."""
    if obj is None:
        return []
    if obj.IsA("vtkPolyData"):
        return [obj]
    out = []
    if obj.IsA("vtkPartitionedDataSet"):
        for i in range(obj.GetNumberOfPartitions()):
            out += pieces(obj.GetPartition(i))
    elif obj.IsA("vtkMultiBlockDataSet"):
        for i in range(obj.GetNumberOfBlocks()):
            out += pieces(obj.GetBlock(i))
    elif obj.IsA("vtkPartitionedDataSetCollection"):
        for i in range(obj.GetNumberOfPartitionedDataSets()):
            out += pieces(obj.GetPartitionedDataSet(i))
    return out


def segments_and_length(obj):
    n = 0
    length = 0.0
    for pd in pieces(obj):
        lines = pd.GetLines()
        if lines is None or lines.GetNumberOfCells() == 0:
            continue
        pts = numpy_support.vtk_to_numpy(pd.GetPoints().GetData()).astype(np.float64)
        off = numpy_support.vtk_to_numpy(lines.GetOffsetsArray())
        conn = numpy_support.vtk_to_numpy(lines.GetConnectivityArray())
        sizes = np.diff(off)
        # Each polyline cell: consecutive point pairs are segments.
        mask = np.ones(len(conn), dtype=bool)
        mask[off[1:] - 1] = False  # last point of each cell starts no segment
        a = conn[:-1][mask[:-1]]
        b = conn[1:][mask[:-1]]
        n += int((sizes - 1).clip(min=0).sum())
        length += float(np.linalg.norm(pts[b] - pts[a], axis=1).sum())
    return n, length


def main():
    args = sys.argv[1:]
    threads, budget = 2, 120.0
    if "--threads" in args:
        i = args.index("--threads")
        threads = int(args[i + 1])
        del args[i:i + 2]
    if "--cutter-budget-s" in args:
        i = args.index("--cutter-budget-s")
        budget = float(args[i + 1])
        del args[i:i + 2]
    ply, planes_path, out_path = args
    planes = json.load(open(planes_path))
    vtkSMPTools.Initialize(threads)
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    t = time.perf_counter()
    verts, tris = read_ply(ply)
    pd = polydata(verts, tris)
    del verts, tris
    read_ms = (time.perf_counter() - t) * 1e3
    rss_mesh = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0

    plane = vtkPlane()
    pc = vtkPlaneCutter()
    pc.SetInputData(pd)
    pc.SetPlane(plane)
    pc.BuildTreeOn()
    pc.BuildHierarchyOn()
    pc.ComputeNormalsOff()
    pc.InterpolateAttributesOff()
    cutter = vtkCutter()
    cutter.SetInputData(pd)
    cutter.SetCutFunction(plane)
    cutter.GenerateTrianglesOff()

    def set_plane(p):
        a, b, c, d = p["local"]
        plane.SetNormal(a, b, c)
        plane.SetOrigin(-d * a, -d * b, -d * c)  # unit normal: the foot of the perpendicular

    # The tree is built by the first update; its time is the filter's init (on the last
    # plane, so that the loop's first plane is a change and runs).
    set_plane(planes[-1])
    t = time.perf_counter()
    pc.Update()
    init_ms = (time.perf_counter() - t) * 1e3
    rss_tree = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    rows = []
    cutter_total = 0.0
    for k, p in enumerate(planes):
        set_plane(p)
        t = time.perf_counter()
        pc.Update()
        ms = (time.perf_counter() - t) * 1e3
        n, length = segments_and_length(pc.GetOutputDataObject(0))
        row = {"plane": k, "plane_cutter": {"ms": ms, "segments": n, "length": length}}
        if cutter_total < budget:
            t = time.perf_counter()
            cutter.Update()
            cms = (time.perf_counter() - t) * 1e3
            cutter_total += cms / 1e3
            cn, cl = segments_and_length(cutter.GetOutput())
            row["cutter"] = {"ms": cms, "segments": cn, "length": cl}
        rows.append(row)
    doc = {
        "peer": "vtk",
        "version": vtkVersion.GetVTKVersion(),
        "smp_backend": vtkSMPTools.GetBackend(),
        "threads": threads,
        "read_ms": read_ms,
        "plane_cutter_init_ms": init_ms,
        "mesh_rss_mib": rss_mesh - rss0,
        "plane_cutter_tree_rss_mib": rss_tree - rss_mesh,
        "peak_rss_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "cutter_budget_s": budget,
        "planes": rows,
    }
    json.dump(doc, open(out_path, "w"), indent=1)


if __name__ == "__main__":
    main()
