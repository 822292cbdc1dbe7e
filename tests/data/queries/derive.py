#!/usr/bin/env python3
"""Derives every tests/data/queries/<case>/expected.json, and writes the two query models
(models/), from first principles: nothing here runs or links geoslice.

  python3 tests/data/queries/derive.py          # rewrite models/ and every expected.json
  python3 tests/data/queries/derive.py --check  # exit 1 when a file on disk differs

Where the numbers come from (README.md beside this script says it again, per case):
  * the models are analytic: `layers` is four axis-aligned boxes in CGCS2000 / 3-degree
    Gauss-Kruger zone 35 (EPSG:4523) whose faces are known exactly, with a block grid of
    binary-fraction grades over its orebody; `tets` is 48 tetrahedra (eight jittered cubes,
    six Kuhn tetrahedra each), and the record at a point is the region of the tetrahedron
    that contains it (barycentric signs, below);
  * pixel -> world follows the documented frame rule, written out here by hand from the
    doc comments, not from the code: view/plane.hpp (u = normalize(n x z), v = u x n,
    origin the foot of the perpendicular from world 0), view/view_frame.hpp (pixel centre
    (i + 0.5, j + 0.5); u = u0 + x (u1 - u0) / W, v = v1 - y (v1 - v0) / H; the default
    frame: bounds projected on the plane, 2 % margin, then grown about its centre along one
    axis until metres per pixel along u = stretch x metres per pixel along v),
    view/exaggeration.hpp (z' = pivot + k (z - pivot), pivot the bounds' centre elevation;
    a vertical plane's v is stretched by k), api/view.hpp (tile grid), view/camera.hpp
    (gluPerspective rays through pixel centres);
  * lon/lat come from PROJ's cs2cs (EPSG:4523 -> EPSG:4490), the oracle tests/unit/crs_test.cpp
    already uses; never from geoslice's GeographicLib code.
Every pixel is checked to lie at least GUARD_M from any boundary between different answers
(the point moved by +-GUARD_M along each axis must give the same body), so that the
tolerance band of the engines (a few micrometres) cannot change the expected record.
"""
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
MODELS = os.path.join(HERE, "models")
GUARD_M = 0.05  # metres: pixels closer than this to a body boundary are refused here

# ----------------------------------------------------------------------------- models
# layers: world metres, EPSG:4523 (easting with the zone number 35 in front, northing, z up)
X0, X1 = 35500000.0, 35501000.0
Y0, Y1 = 3390000.0, 3390600.0
LAYERS = [  # (name, (xmin, ymin, zmin), (xmax, ymax, zmax)); the orebody is nested in the sandstone
    ("basement", (X0, Y0, -200.0), (X1, Y1, 0.0)),
    ("sandstone", (X0, Y0, 0.0), (X1, Y1, 150.0)),
    ("shale", (X0, Y0, 150.0), (X1, Y1, 300.0)),
    ("orebody", (35500400.0, 3390200.0, 40.0), (35500600.0, 3390400.0, 110.0)),
]
LAYER_RECORDS = {
    "basement": {"kind": "stratum", "lithology": "granite gneiss", "age": "Archean (Ar)", "colour": "#8c6d5a"},
    "sandstone": {"kind": "stratum", "lithology": "quartz sandstone", "age": "Late Triassic (T3x)",
                  "colour": "#e0c070"},
    "shale": {"kind": "stratum", "lithology": "mudstone and shale", "age": "Early Jurassic (J1z)",
              "colour": "#708090"},
    "orebody": {"kind": "orebody", "lithology": "silica sandstone ore", "age": "Late Triassic (T3x)",
                "colour": "#d04030"},
}
# Block grid over the orebody: 50 x 50 x 35 m cells, 4 x 4 x 2, clipped by the orebody.
# Cell (i, j, k) spans x 35500400 + 50 [i, i+1], y 3390200 + 50 [j, j+1], z 40 + 35 [k, k+1];
# grade = 0.5 + 0.25 i + j + 4 k g/t Au (binary fractions: exact in float and double).
BLOCK_ORIGIN = (35500400.0, 3390200.0, 40.0)
BLOCK_SIZE = (50.0, 50.0, 35.0)
BLOCK_DIMS = (4, 4, 2)


def block_grade(i, j, k):
    return 0.5 + 0.25 * i + 1.0 * j + 4.0 * k


# tets: local metres, no CRS. Vertex (i, j, k) of a 3 x 3 x 3 grid of 10 m spacing, moved by
# a smooth field so that no face is axis-aligned; every cube cut into the six Kuhn
# tetrahedra along its (0,0,0)-(1,1,1) diagonal. Regions (record ids of the 'formation' cell
# array): cubes with k = 0 -> 1, k = 1 -> 2, except cube (1, 0, 1) -> 3.
TET_NAMES = {1: "lower sandstone", 2: "upper shale", 3: "quartz lens"}
TET_RECORDS = {
    1: {"kind": "stratum", "lithology": "sandstone", "age": "Middle Jurassic (J2s)", "colour": "#c8a050"},
    2: {"kind": "stratum", "lithology": "shale", "age": "Late Jurassic (J3p)", "colour": "#607080"},
    3: {"kind": "orebody", "lithology": "vein quartz", "age": "Cretaceous (K)", "colour": "#f0f0f0"},
}


def tet_vertex(i, j, k):
    x, y, z = 10.0 * i, 10.0 * j, 10.0 * k
    return (x + 0.8 * math.sin(0.31 * y + 0.17 * z + 0.4),
            y + 0.7 * math.sin(0.23 * x + 0.29 * z + 1.1),
            z + 1.2 * math.sin(0.19 * x + 0.5) * math.cos(0.27 * y + 0.3))


def tet_region(i, j, k):
    return 3 if (i, j, k) == (1, 0, 1) else (1 if k == 0 else 2)


def tet_cells():
    """[(region, (p0, p1, p2, p3)), ...] with vertex indices into tet_points()."""
    perms = [(0, 1, 2), (1, 2, 0), (2, 0, 1), (0, 2, 1), (2, 1, 0), (1, 0, 2)]
    cells = []
    for k in range(2):
        for j in range(2):
            for i in range(2):
                for p in perms:
                    c = [i, j, k]
                    ids = [vid(*c)]
                    for s in range(3):
                        c[p[s]] += 1
                        ids.append(vid(*c))
                    if signed_volume(*[tet_points()[v] for v in ids]) < 0:
                        ids[2], ids[3] = ids[3], ids[2]
                    cells.append((tet_region(i, j, k), tuple(ids)))
    return cells


def vid(i, j, k):
    return (k * 3 + j) * 3 + i


def tet_halfspaces():
    """Every tetrahedron as its four inner half-spaces (n, d): n . p + d >= 0 inside."""
    pts = tet_points()
    out = []
    for _, ids in tet_cells():
        hs = []
        for k in range(4):
            a = pts[ids[k]]
            b, c, d = (pts[ids[(k + j) % 4]] for j in (1, 2, 3))
            n = cross(sub(c, b), sub(d, b))
            if dot(n, sub(a, b)) < 0:
                n = mul(n, -1.0)
            hs.append((n, -dot(n, b)))
        out.append(hs)
    return out


def tet_points():
    return [tet_vertex(i, j, k) for k in range(3) for j in range(3) for i in range(3)]


# ----------------------------------------------------------------------------- vectors
def add(a, b): return tuple(x + y for x, y in zip(a, b))
def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def mul(a, s): return tuple(x * s for x in a)
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
def norm(a): return math.sqrt(dot(a, a))
def unit(a): return mul(a, 1.0 / norm(a))


def signed_volume(a, b, c, d):
    return dot(sub(b, a), cross(sub(c, a), sub(d, a))) / 6.0


# ----------------------------------------------------------------------------- classify
def classify_layers(p):
    """The deepest box containing p (the orebody is inside the sandstone), or None."""
    hit = None
    for name, lo, hi in LAYERS:
        if all(lo[a] <= p[a] <= hi[a] for a in range(3)):
            hit = name if hit is None or name == "orebody" else hit
    return hit


def classify_tets(p):
    pts = tet_points()
    for region, ids in tet_cells():
        a, b, c, d = (pts[v] for v in ids)
        if (signed_volume(p, b, c, d) >= 0 and signed_volume(a, p, c, d) >= 0 and signed_volume(a, b, p, d) >= 0
                and signed_volume(a, b, c, p) >= 0):
            return TET_NAMES[region]
    return None


def guarded(classify, p, what):
    """classify(p), after checking that p moved by GUARD_M along each axis gives the same."""
    r = classify(p)
    for a in range(3):
        for s in (-GUARD_M, GUARD_M):
            q = list(p)
            q[a] += s
            if classify(tuple(q)) != r:
                sys.exit(f"{what}: {p} lies within {GUARD_M} m of a boundary ({r} vs {classify(tuple(q))}); "
                         "choose another pixel")
    return r


def block_at(p):
    """(cell [i, j, k], grade) of the orebody's block grid at p, or None outside it."""
    idx = []
    for a in range(3):
        g = (p[a] - BLOCK_ORIGIN[a]) / BLOCK_SIZE[a]
        if g < 0 or g >= BLOCK_DIMS[a]:
            return None
        if abs(g - round(g)) * BLOCK_SIZE[a] < GUARD_M:
            sys.exit(f"{p} lies within {GUARD_M} m of a block cell face; choose another pixel")
        idx.append(int(math.floor(g)))
    return idx, block_grade(*idx)


def layers_bounds():
    lo = tuple(min(b[1][a] for b in LAYERS) for a in range(3))
    hi = tuple(max(b[2][a] for b in LAYERS) for a in range(3))
    return lo, hi


def tets_bounds():
    pts = tet_points()
    return tuple(min(p[a] for p in pts) for a in range(3)), tuple(max(p[a] for p in pts) for a in range(3))


# ----------------------------------------------------------------------------- frames
def plane_frame(n, d):
    """view/plane.hpp: u = normalize(n x z) (world x for a horizontal plane), v = u x n,
    origin (u, v) = (0, 0) at the foot of the perpendicular from world 0, -d n."""
    nz = cross(n, (0.0, 0.0, 1.0))
    u = (1.0, 0.0, 0.0) if norm(nz) < 1e-9 else unit(nz)
    v = cross(u, n)
    return u, v, mul(n, -d)


def parse_plane(text):
    a, b, c, d = (float(x) for x in text.split(","))
    length = norm((a, b, c))
    return (a / length, b / length, c / length), d / length


def fit_rect(lo, hi, w, h, stretch, margin=0.02):
    """view/view_frame.hpp fitRect: grow by margin x size on each side, then along one axis
    about the centre until (u metres per pixel) = stretch x (v metres per pixel)."""
    su, sv = max(hi[0] - lo[0], 1e-3), max(hi[1] - lo[1], 1e-3)
    u0, u1 = lo[0] - margin * su, hi[0] + margin * su
    v0, v1 = lo[1] - margin * sv, hi[1] + margin * sv
    pu, pv = (u1 - u0) / w, (v1 - v0) / h
    if pu < stretch * pv:  # widen u
        cu, half = 0.5 * (u0 + u1), 0.5 * stretch * pv * w
        u0, u1 = cu - half, cu + half
    else:  # taller v
        cv, half = 0.5 * (v0 + v1), 0.5 * pu / stretch * h
        v0, v1 = cv - half, cv + half
    return u0, u1, v0, v1


def corners(lo, hi):
    return [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]


def projected_bounds(u, v, origin, lo, hi):
    uv = [(dot(sub(c, origin), u), dot(sub(c, origin), v)) for c in corners(lo, hi)]
    return (min(p[0] for p in uv), min(p[1] for p in uv)), (max(p[0] for p in uv), max(p[1] for p in uv))


def v_stretch(n, k):
    """view/exaggeration.hpp: sqrt(nz^2 + k^2 (1 - nz^2))."""
    return math.sqrt(n[2] ** 2 + k * k * (1.0 - n[2] ** 2))


def pixel_uv(rect, w, h, px, py):
    u0, u1, v0, v1 = rect
    return u0 + (px + 0.5) * (u1 - u0) / w, v1 - (py + 0.5) * (v1 - v0) / h


def parse_size(text):
    w, h = text.split("x")
    return int(w), int(h)


# ----------------------------------------------------------------------------- PROJ
def lonlat_by_proj(points):
    """EPSG:4523 (northing, easting as EPSG orders them) -> EPSG:4490 (lat, lon) by cs2cs."""
    text = "".join(f"{p[1]!r} {p[0]!r}\n" for p in points)
    out = subprocess.run(["cs2cs", "-f", "%.13f", "EPSG:4523", "EPSG:4490"], input=text, capture_output=True,
                         text=True, check=True).stdout.split("\n")
    result = []
    for line in out[:len(points)]:
        lat, lon = (float(x) for x in line.split()[:2])
        result.append((lon, lat))
    return result


# ----------------------------------------------------------------------------- views
def profile_points(req, bounds):
    """[(px, py, world, section)] of a profile view (plane, elevation or tile)."""
    view = req["view"]
    if "elevation" in view:  # keeps what lies below z: normal -z, d = z
        n, d = (0.0, 0.0, -1.0), float(view["elevation"])
    else:
        n, d = parse_plane(view["plane"])
    u, v, origin = plane_frame(n, d)
    k = float(view.get("vx", "1"))
    lo, hi = projected_bounds(u, v, origin, *bounds)
    if "tile" in req:
        t = req["tile"]
        s_k = v_stretch(n, k)
        size0 = 2.0 ** math.ceil(math.log2(max(hi[0] - lo[0], (hi[1] - lo[1]) * s_k, 1e-3)))
        s = size0 / 2 ** t["z"]
        rect = (lo[0] + t["x"] * s, lo[0] + (t["x"] + 1) * s, hi[1] - (t["y"] + 1) * s / s_k, hi[1] - t["y"] * s / s_k)
        w = h = 256
    else:
        w, h = parse_size(view["size"])
        if "frame" in view:
            f = [float(x) for x in view["frame"].split(",")]
            rect = (f[0], f[1], f[2], f[3])
        else:
            rect = fit_rect(lo, hi, w, h, v_stretch(n, k))
    out = []
    for px, py in req["pixels"]:
        uu, vv = pixel_uv(rect, w, h, px, py)
        world = add(origin, add(mul(u, uu), mul(v, vv)))
        out.append((px, py, world, {"u": uu, "v": vv, "distanceAlong": uu - rect[0]}))
    return out, rect


def line_points(req, bounds):
    """[(px, py, world, section)] of a vertical section along a map polyline: chainage s from
    the first vertex plays u, elevation plays v; default frame: chainage 0..length by the
    model's elevation range, fitted like a plane's with stretch k."""
    view = req["view"]
    xy = [float(x) for x in view["line"].split(",")]
    verts = list(zip(xy[0::2], xy[1::2]))
    legs = [math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(verts, verts[1:])]
    length = sum(legs)
    w, h = parse_size(view["size"])
    k = float(view.get("vx", "1"))
    if "frame" in view:
        f = [float(x) for x in view["frame"].split(",")]
        rect = (f[0], f[1], f[2], f[3])
    else:
        rect = fit_rect((0.0, bounds[0][2]), (length, bounds[1][2]), w, h, k)
    out = []
    for px, py in req["pixels"]:
        s, z = pixel_uv(rect, w, h, px, py)
        if not 0.0 <= s < length:
            sys.exit(f"pixel {px},{py}: chainage {s} is off the line; the cases keep to it")
        rest = s
        for (a, b), leg in zip(zip(verts, verts[1:]), legs):
            if rest <= leg:
                t = rest / leg
                world = (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), z)
                break
            rest -= leg
        out.append((px, py, world, {"distanceAlong": s, "elevation": z}))
    return out, rect


def perspective_hit(view, bounds, x, y, model):
    """(world point, distance from the eye) of the first visible point on the ray through
    pixel coordinates (x, y) of a perspective view of `model`, or (None, None).

    The ray (view/camera.hpp, gluPerspective): ndc = (2 x / W - 1, 1 - 2 y / H), direction
    f + ndc.x tan(fov / 2) aspect r + ndc.y tan(fov / 2) t with f, r, t the camera's forward,
    right and true-up axes, in display space (eye and target are world points mapped by the
    exaggeration, about the bounds' centre elevation), mapped back to world (the map is
    affine: a line stays a line; distances are world metres). What is visible: the first
    point of any box on the kept side of the cut, i.e. the smallest entry parameter over the
    convex sets box (or tetrahedron) ∩ kept half-spaces: one plane, or a cut-out where 'union' keeps what is
    on the kept side of every plane and 'intersection' takes out only what is on the removed
    side of every plane (what stays is box ∩ (H1 ∪ H2 ...): one convex set per plane)."""
    w, h = parse_size(view["size"])
    k = float(view.get("vx", "1"))
    pivot = 0.5 * (bounds[0][2] + bounds[1][2])
    to_display = lambda p: (p[0], p[1], pivot + k * (p[2] - pivot))
    to_world = lambda p: (p[0], p[1], pivot + (p[2] - pivot) / k)
    eye_w = tuple(float(v) for v in view["eye"].split(","))
    target_w = tuple(float(v) for v in view["target"].split(","))
    up = tuple(float(v) for v in view.get("up", "0,0,1").split(","))
    fov = float(view.get("fov", "45"))
    eye, target = to_display(eye_w), to_display(target_w)
    f = unit(sub(target, eye))
    r = unit(cross(f, up))
    t_up = cross(r, f)
    tan_half = math.tan(math.radians(fov) / 2.0)
    planes = [parse_plane(p) for p in (view["planes"].split(";") if "planes" in view else [view["plane"]])]
    groups = [[p] for p in planes] if view.get("cut", "union") == "intersection" else [planes]
    nx, ny = 2.0 * x / w - 1.0, 1.0 - 2.0 * y / h
    dd = unit(add(f, add(mul(r, nx * tan_half * w / h), mul(t_up, ny * tan_half))))
    o = eye_w
    dw = unit(sub(to_world(add(eye, dd)), eye_w))  # the world ray, unit: t in world metres
    best = None
    # Convex pieces: the boxes as slabs, or every tetrahedron as its four inner half-spaces.
    pieces = [("slabs", lo, hi) for _, lo, hi in LAYERS] if model == "layers" else \
        [("halfspaces", hs, None) for hs in tet_halfspaces()]
    for kind, lo, hi in pieces:
        for group in groups:
            t0, t1 = 0.0, math.inf
            if kind == "slabs":
                for a in range(3):  # the box's slabs
                    if dw[a] == 0.0:
                        if not lo[a] <= o[a] <= hi[a]:
                            t0, t1 = 1.0, 0.0
                        continue
                    ta, tb = (lo[a] - o[a]) / dw[a], (hi[a] - o[a]) / dw[a]
                    t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
            for n, d in (lo if kind == "halfspaces" else []) + group:  # kept: n . p + d >= 0
                s0, s1 = dot(n, o) + d, dot(n, dw)
                if s1 == 0.0:
                    if s0 < 0:
                        t0, t1 = 1.0, 0.0
                elif s1 > 0:
                    t0 = max(t0, -s0 / s1)
                else:
                    t1 = min(t1, -s0 / s1)
            if t0 < t1 and (best is None or t0 < best):
                best = t0
    if best is None:
        return None, None, dw
    return add(o, mul(dw, best)), best, dw


def on_cut_plane(view, p):
    """Whether world point p lies on one of the view's cut planes (within 1e-6 m: rounding at
    Gauss-Kruger eastings is ~1e-8 m)."""
    planes = [parse_plane(t) for t in (view["planes"].split(";") if "planes" in view else [view["plane"]])]
    return any(abs(dot(n, p) + d) < 1e-6 for n, d in planes)


def perspective_body(view, bounds, x, y, model):
    """The body the ray through (x, y) enters first (the deepest box, or the tetrahedron's
    formation, holding the point 1 mm past the visible point along the ray), or None."""
    p, _, dw = perspective_hit(view, bounds, x, y, model)
    classify = classify_layers if model == "layers" else classify_tets
    return None if p is None else classify(add(p, mul(dw, 1e-3)))


def perspective_points(req, bounds, case):
    """[(px, py, world or None, eye distance, body)] of the pixel centres; each pixel's body
    must be the same for rays 0.1 pixel to either side (no pixel on an edge)."""
    out = []
    for px, py in req["pixels"]:
        x, y = px + 0.5, py + 0.5
        p, dist, _ = perspective_hit(req["view"], bounds, x, y, req["model"])
        body = perspective_body(req["view"], bounds, x, y, req["model"])
        for ox, oy in ((-0.1, 0), (0.1, 0), (0, -0.1), (0, 0.1)):
            if perspective_body(req["view"], bounds, x + ox, y + oy, req["model"]) != body:
                sys.exit(f"{case} pixel {px},{py}: an edge between bodies lies within 0.1 pixel; choose another")
        out.append((px, py, p, dist, body))
    return out


# ----------------------------------------------------------------------------- cases
def record_of(model, name):
    if name is None:
        return None
    if model == "layers":
        r = dict(LAYER_RECORDS[name])
        return {"name": name, "kind": r["kind"], "lithology": r["lithology"], "age": r["age"]}
    rid = next(i for i, n in TET_NAMES.items() if n == name)
    return {"id": rid, "name": name, "kind": TET_RECORDS[rid]["kind"], "lithology": TET_RECORDS[rid]["lithology"],
            "age": TET_RECORDS[rid]["age"]}


def derive_case(case):
    req = json.load(open(os.path.join(HERE, case, "request.json")))
    model = req["model"]
    bounds = layers_bounds() if model == "layers" else tets_bounds()
    classify = classify_layers if model == "layers" else classify_tets
    view = req["view"]
    answers = []
    extra = {}
    if view.get("view") == "perspective":
        for px, py, world, dist, name in perspective_points(req, bounds, case):
            if world is None:
                answers.append({"px": px, "py": py, "hit": False, "record": None, "world": None})
                continue
            answers.append({"px": px, "py": py, "hit": True, "body": name, "record": record_of(model, name),
                            "world": list(world), "distanceFromEye": dist})
    else:
        if "line" in view:
            pts, rect = line_points(req, bounds)
        else:
            pts, rect = profile_points(req, bounds)
        if "tile" in req:
            extra["tileFrame"] = list(rect)
        for px, py, world, section in pts:
            name = guarded(classify, world, f"{case} pixel {px},{py}")
            a = {"px": px, "py": py, "hit": name is not None}
            if name is not None:
                a["body"] = name
            a["record"] = record_of(model, name)
            a["world"] = list(world)
            a["section"] = section
            answers.append(a)
    if model == "layers":
        hits = [a for a in answers if a["world"] is not None]
        for a, ll in zip(hits, lonlat_by_proj([a["world"] for a in hits])):
            a["lonlat"] = list(ll)
        for a in answers:
            # The block cell of a pixel whose body clips the grid (the orebody), else none; in a
            # perspective view only on a cut face (the point on a cut plane), where it is coloured.
            on_cut = view.get("view") != "perspective" or (a["world"] is not None and on_cut_plane(view, a["world"]))
            b = block_at(a["world"]) if a.get("body") == "orebody" and on_cut else None
            a["block"] = None if b is None else {"cell": b[0], "properties": {"grade": b[1]}}
    else:
        for a in answers:
            a["lonlat"] = None  # a local model: no geodetic coordinates
    expected = {"case": case, "derivation": req["derivation"], "tolerances": req_tolerances(req, view)}
    expected.update(extra)
    expected["pixels"] = answers
    return expected


def req_tolerances(req, view):
    t = {
        "world_m": {"value": 1e-6, "reason": "pixel centre -> world in double: u/v of 3.5e7 m carry 7e-9 m steps; "
                                             "1 um is far above that and far below a pixel"},
        "section_m": {"value": 1e-6, "reason": "plane u/v or chainage/elevation of the pixel centre, double, as world_m"},
        "lonlat_deg": {"value": 1e-9, "reason": "GeographicLib vs PROJ's cs2cs (printed to 13 decimals): both are "
                                                "nm-accurate in the zone; 1e-9 deg is 0.1 mm, far below any parameter "
                                                "error (tests/unit/crs_test.cpp)"},
        "grade": {"value": 0.0, "reason": "binary-fraction grades read from CSV: exact in float and double"},
    }
    if view.get("view") == "perspective":
        t["world_m"] = {"value": 1e-4, "reason": "the ray hit comes from Embree in the model's float32 local frame: "
                                                 "float steps up to 6e-5 m in the layers model (|local| < 1 km), "
                                                 "2e-6 m over the 20 m tets model; 0.1 mm bounds a hit that is only "
                                                 "float-accurate (measured: under 1e-6 m in both models)"}
        t["eye_m"] = {"value": 1e-4, "reason": "distance from the eye to the hit: as world_m"}
    return t


def write_models(check):
    files = {}
    # layers.obj: one group per box, outward counter-clockwise triangles.
    lines = ["# tests/data/queries/models/layers.obj: written by ../derive.py (four analytic boxes, EPSG:4523)"]
    base = 1
    for name, lo, hi in LAYERS:
        lines.append(f"o {name}")
        c = corners(lo, hi)  # index = 4 xbit + 2 ybit + zbit
        for p in c:
            lines.append("v {!r} {!r} {!r}".format(*p))
        centre = mul(add(lo, hi), 0.5)
        quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
        for q in quads:
            a, b, cc, d = (c[i] for i in q)
            nrm = cross(sub(b, a), sub(cc, a))
            if dot(nrm, sub(a, centre)) < 0:
                q = tuple(reversed(q))
            lines.append("f {} {} {}".format(*(base + i for i in (q[0], q[1], q[2]))))
            lines.append("f {} {} {}".format(*(base + i for i in (q[0], q[2], q[3]))))
        base += 8
    files["layers.obj"] = "\n".join(lines) + "\n"
    files["layers.crs"] = "EPSG:4523\n"
    recs = [{"id": i + 1, "name": n, **LAYER_RECORDS[n]} for i, (n, _, _) in enumerate(LAYERS)]
    files["layers.attributes.json"] = json.dumps({"records": recs}, indent=2, ensure_ascii=False) + "\n"
    files["layers.blocks.json"] = json.dumps(
        {"source": "layers_blocks.csv", "clip": ["orebody"], "units": {"grade": "g/t Au"}}, indent=2) + "\n"
    rows = ["x,y,z,dx,dy,dz,grade"]
    for kk in range(BLOCK_DIMS[2]):
        for jj in range(BLOCK_DIMS[1]):
            for ii in range(BLOCK_DIMS[0]):
                cx = BLOCK_ORIGIN[0] + (ii + 0.5) * BLOCK_SIZE[0]
                cy = BLOCK_ORIGIN[1] + (jj + 0.5) * BLOCK_SIZE[1]
                cz = BLOCK_ORIGIN[2] + (kk + 0.5) * BLOCK_SIZE[2]
                rows.append(f"{cx!r},{cy!r},{cz!r},50,50,35,{block_grade(ii, jj, kk)!r}")
    files["layers_blocks.csv"] = "\n".join(rows) + "\n"
    # tets.vtu: VTK XML UnstructuredGrid, ascii (docs.vtk.org "VTK File Formats"); type 10 = tetra.
    pts = tet_points()
    cells = tet_cells()
    conn = " ".join(str(v) for _, ids in cells for v in ids)
    offs = " ".join(str(4 * (i + 1)) for i in range(len(cells)))
    files["tets.vtu"] = (
        '<?xml version="1.0"?>\n<!-- tests/data/queries/models/tets.vtu: written by ../derive.py -->\n'
        '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">\n'
        ' <UnstructuredGrid>\n'
        f'  <Piece NumberOfPoints="{len(pts)}" NumberOfCells="{len(cells)}">\n'
        '   <Points>\n    <DataArray type="Float64" NumberOfComponents="3" format="ascii">\n'
        + "".join("     {!r} {!r} {!r}\n".format(*p) for p in pts)
        + '    </DataArray>\n   </Points>\n   <Cells>\n'
        f'    <DataArray type="Int64" Name="connectivity" format="ascii">{conn}</DataArray>\n'
        f'    <DataArray type="Int64" Name="offsets" format="ascii">{offs}</DataArray>\n'
        f'    <DataArray type="UInt8" Name="types" format="ascii">{" ".join("10" for _ in cells)}</DataArray>\n'
        '   </Cells>\n   <CellData Scalars="formation">\n'
        f'    <DataArray type="Int32" Name="formation" format="ascii">{" ".join(str(r) for r, _ in cells)}'
        '</DataArray>\n   </CellData>\n  </Piece>\n </UnstructuredGrid>\n</VTKFile>\n')
    recs = [{"id": i, "name": TET_NAMES[i], **TET_RECORDS[i]} for i in sorted(TET_NAMES)]
    files["tets.attributes.json"] = json.dumps({"records": recs}, indent=2) + "\n"
    return {os.path.join(MODELS, k): v for k, v in files.items()}


def main():
    check = "--check" in sys.argv
    out = write_models(check)
    for case in sorted(os.listdir(HERE)):
        if os.path.isfile(os.path.join(HERE, case, "request.json")):
            out[os.path.join(HERE, case, "expected.json")] = json.dumps(derive_case(case), indent=2,
                                                                        ensure_ascii=False) + "\n"
    bad = 0
    for path, text in sorted(out.items()):
        old = open(path).read() if os.path.exists(path) else None
        if old == text:
            continue
        if check:
            print(f"differs: {os.path.relpath(path, HERE)}")
            bad += 1
        else:
            os.makedirs(os.path.dirname(path), exist_ok=True)
            open(path, "w").write(text)
            print(f"wrote {os.path.relpath(path, HERE)}")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
