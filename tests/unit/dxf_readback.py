#!/usr/bin/python3
"""Reads a DXF written by geoslice back with ezdxf (python3-ezdxf, the real client) and prints
what a CAD user would see, as JSON: the DXF version, ezdxf's audit errors, the layers with their
true colours, per layer the hatched area (outer loops minus holes, shoelace over the boundary
edges) and the number of closed polylines, the TEXT labels, and every polyline vertex's
bounds (x, y, z).

usage: dxf_readback.py FILE.dxf
"""
import json
import sys

import ezdxf


def shoelace(points):
    a = 0.0
    for i in range(len(points)):
        x0, y0 = points[i][0], points[i][1]
        x1, y1 = points[(i + 1) % len(points)][0], points[(i + 1) % len(points)][1]
        a += x0 * y1 - x1 * y0
    return 0.5 * a


def main():
    doc = ezdxf.readfile(sys.argv[1])
    auditor = doc.audit()
    msp = doc.modelspace()
    out = {
        "version": doc.dxfversion,
        "audit_errors": len(auditor.errors),
        "layers": {},
        "hatch_area": {},
        "polylines": {},
        "texts": [],
        "bounds": None,
    }
    for layer in doc.layers:
        if layer.dxf.name == "0":
            continue
        rgb = layer.rgb if layer.has_dxf_attrib("true_color") else None
        out["layers"][layer.dxf.name] = list(rgb) if rgb else None
    lo, hi = [1e300] * 3, [-1e300] * 3

    def extend(p):
        for k in range(3):
            lo[k] = min(lo[k], p[k])
            hi[k] = max(hi[k], p[k])

    for e in msp:
        kind = e.dxftype()
        layer = e.dxf.layer
        if kind == "HATCH":
            areas = []
            for path in e.paths:
                if hasattr(path, "edges"):
                    pts = [edge.start for edge in path.edges]
                else:
                    pts = [v[:2] for v in path.vertices]
                areas.append(abs(shoelace(pts)))
            # One hatch per polygon, filled by odd parity: the largest loop is the outer
            # boundary, every other one a hole in it.
            total = max(areas) - (sum(areas) - max(areas)) if areas else 0.0
            out["hatch_area"][layer] = out["hatch_area"].get(layer, 0.0) + total
        elif kind == "LWPOLYLINE":
            out["polylines"][layer] = out["polylines"].get(layer, 0) + (1 if e.closed else 0)
            for x, y in e.get_points("xy"):
                extend((x, y, e.dxf.elevation))
        elif kind == "POLYLINE":
            out["polylines"][layer] = out["polylines"].get(layer, 0) + (1 if e.is_closed else 0)
            for v in e.vertices:
                extend(tuple(v.dxf.location))
        elif kind == "TEXT":
            out["texts"].append({"layer": layer, "text": e.dxf.text})
    if lo[0] <= hi[0]:
        out["bounds"] = {"min": lo, "max": hi}
    print(json.dumps(out))


if __name__ == "__main__":
    main()
