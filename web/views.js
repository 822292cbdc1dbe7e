// geoslice web client: pure helpers (no DOM state). World coordinates are the model's CRS:
// x easting, y northing, z elevation, metres. Section coordinates (u, v) follow the server:
// u = normalize(n x up), v = u x n (section/plane.cpp), so for a vertical plane v = z.

// ---- numbers -----------------------------------------------------------------------
export const fmt = (x, digits = 2) => (Number.isFinite(x) ? x.toFixed(digits) : '–');

// A "nice" step (1, 2 or 5 x 10^k) of at least `min`.
export function niceStep(min) {
  const p = Math.pow(10, Math.floor(Math.log10(min)));
  for (const m of [1, 2, 5, 10]) if (m * p >= min) return m * p;
  return 10 * p;
}

// ---- vectors -----------------------------------------------------------------------
export const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
export const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
export const mul = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
export const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
export const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
export const norm = (a) => mul(a, 1 / Math.hypot(a[0], a[1], a[2]));

// The section frame of a plane with unit normal n (as section/plane.cpp makeSectionFrame).
export function planeBasis(n) {
  let u = cross(n, [0, 0, 1]);
  const len = Math.hypot(u[0], u[1], u[2]);
  if (len < 1e-9) {
    u = [1, 0, 0];
    u = norm(sub(u, mul(n, dot(u, n))));
  } else u = mul(u, 1 / len);
  return { u, v: cross(u, n) };
}

// A vertical or dipping plane from a strike azimuth (degrees clockwise from north; the
// section's u axis points that way), a dip (degrees from horizontal, 90 = vertical) and a
// point on it. Returns {n, d}: keeps n.p + d >= 0.
export function planeFrom(azimuthDeg, dipDeg, point) {
  const a = (azimuthDeg * Math.PI) / 180, dp = (dipDeg * Math.PI) / 180;
  let n = [-Math.cos(a) * Math.sin(dp), Math.sin(a) * Math.sin(dp), Math.cos(dp)];
  n = norm(n);
  return { n, d: -dot(n, point) };
}
export const planeText = (p) => p.n.map((x) => +x.toPrecision(15)).concat(+p.d.toPrecision(15)).join(',');

// 8-point compass name of a horizontal direction.
export function compass(dx, dy) {
  const names = ['N', 'NE', 'E', 'SE', 'S', 'SW', 'W', 'NW'];
  const az = (Math.atan2(dx, dy) * 180) / Math.PI;
  return names[((Math.round(az / 45) % 8) + 8) % 8];
}

// Corners of the model's box cut by a plane, ordered around their centroid: the plane's
// visible patch. Empty when the plane misses the box.
export function planeBoxPolygon(plane, min, max) {
  const c = (i) => [i & 1 ? max[0] : min[0], i & 2 ? max[1] : min[1], i & 4 ? max[2] : min[2]];
  const edges = [[0, 1], [2, 3], [4, 5], [6, 7], [0, 2], [1, 3], [4, 6], [5, 7], [0, 4], [1, 5], [2, 6], [3, 7]];
  const pts = [];
  for (const [i, j] of edges) {
    const a = c(i), b = c(j);
    const sa = dot(plane.n, a) + plane.d, sb = dot(plane.n, b) + plane.d;
    if ((sa < 0) !== (sb < 0) || sa === 0) {
      const t = sa / (sa - sb);
      if (t >= 0 && t <= 1) pts.push(add(a, mul(sub(b, a), t)));
    }
  }
  if (pts.length < 3) return [];
  const centre = mul(pts.reduce(add, [0, 0, 0]), 1 / pts.length);
  const { u, v } = planeBasis(plane.n);
  pts.sort((p, q) => Math.atan2(dot(sub(p, centre), v), dot(sub(p, centre), u)) -
                     Math.atan2(dot(sub(q, centre), v), dot(sub(q, centre), u)));
  return pts;
}

// ---- perspective camera (api/view.cpp perspectiveRay, inverted) -----------------------
// Pixel (x right, y down, CSS pixels of a w x h image) of world point p, or null behind the eye.
export function project(cam, w, h, p) {
  const f = norm(sub(cam.target, cam.eye));
  const r = norm(cross(f, cam.up));
  const u = cross(r, f);
  const d = sub(p, cam.eye);
  const z = dot(d, f);
  if (z <= 1e-6) return null;
  const t = Math.tan(((cam.fov * Math.PI) / 180) / 2);
  const nx = dot(d, r) / (z * t * (w / h)), ny = dot(d, u) / (z * t);
  return [((nx + 1) / 2) * w, ((1 - ny) / 2) * h];
}

// An orbit camera around `target`: azimuth (deg, clockwise from north, where the eye is),
// elevation (deg above horizontal), distance (m).
export function orbitCamera(target, azDeg, elDeg, dist, fov = 40) {
  const a = (azDeg * Math.PI) / 180, e = (elDeg * Math.PI) / 180;
  const dir = [Math.sin(a) * Math.cos(e), Math.cos(a) * Math.cos(e), Math.sin(e)];
  return { eye: add(target, mul(dir, dist)), target, up: [0, 0, 1], fov };
}

// ---- CGCS2000 Gauss-Kruger (transverse Mercator, Krüger series to n^4; Karney 2011) -----
// Used only to draw the lon/lat graticule on the plan; answers carry the server's
// GeographicLib coordinates. Sub-millimetre within a 3-degree zone.
const A_ = 6378137, F_ = 1 / 298.257222101, N_ = F_ / (2 - F_);
const n2 = N_ * N_, n3 = n2 * N_, n4 = n3 * N_;
const AA = (A_ / (1 + N_)) * (1 + n2 / 4 + n4 / 64);
const ALPHA = [N_ / 2 - (2 * n2) / 3 + (5 * n3) / 16 + (41 * n4) / 180, (13 * n2) / 48 - (3 * n3) / 5 + (557 * n4) / 1440,
               (61 * n3) / 240 - (103 * n4) / 140, (49561 * n4) / 161280];
const BETA = [N_ / 2 - (2 * n2) / 3 + (37 * n3) / 96 - n4 / 360, n2 / 48 + n3 / 15 - (437 * n4) / 1440,
              (17 * n3) / 480 - (37 * n4) / 840, (4397 * n4) / 161280];
const DELTA = [2 * N_ - (2 * n2) / 3 - 2 * n3 + (116 * n4) / 45, (7 * n2) / 3 - (8 * n3) / 5 - (227 * n4) / 45,
               (56 * n3) / 15 - (136 * n4) / 35, (4279 * n4) / 630];
const E2N = (2 * Math.sqrt(N_)) / (1 + N_);

// {cm: central meridian deg, fe: false easting m} of an EPSG CGCS2000 Gauss-Kruger code, or null.
export function gaussKruger(epsg) {
  const c = Number(String(epsg).replace(/^EPSG:/, ''));
  if (c >= 4513 && c <= 4533) { const z = 25 + c - 4513; return { cm: 3 * z, fe: z * 1e6 + 500000 }; }
  if (c >= 4534 && c <= 4554) return { cm: 75 + 3 * (c - 4534), fe: 500000 };
  if (c >= 4491 && c <= 4501) { const z = 13 + c - 4491; return { cm: 6 * z - 3, fe: z * 1e6 + 500000 }; }
  if (c >= 4502 && c <= 4512) return { cm: 75 + 6 * (c - 4502), fe: 500000 };
  return null;
}
export function lonLatToGk(gk, lon, lat) {
  const phi = (lat * Math.PI) / 180, dl = ((lon - gk.cm) * Math.PI) / 180;
  const s = Math.sin(phi);
  const t = Math.sinh(Math.atanh(s) - E2N * Math.atanh(E2N * s));
  const xi1 = Math.atan2(t, Math.cos(dl)), eta1 = Math.atanh(Math.sin(dl) / Math.sqrt(1 + t * t));
  let xi = xi1, eta = eta1;
  for (let j = 1; j <= 4; ++j) {
    xi += ALPHA[j - 1] * Math.sin(2 * j * xi1) * Math.cosh(2 * j * eta1);
    eta += ALPHA[j - 1] * Math.cos(2 * j * xi1) * Math.sinh(2 * j * eta1);
  }
  return [gk.fe + AA * eta, AA * xi];
}
export function gkToLonLat(gk, x, y) {
  const xi = y / AA, eta = (x - gk.fe) / AA;
  let xi1 = xi, eta1 = eta;
  for (let j = 1; j <= 4; ++j) {
    xi1 -= BETA[j - 1] * Math.sin(2 * j * xi) * Math.cosh(2 * j * eta);
    eta1 -= BETA[j - 1] * Math.cos(2 * j * xi) * Math.sinh(2 * j * eta);
  }
  const chi = Math.asin(Math.sin(xi1) / Math.cosh(eta1));
  let phi = chi;
  for (let j = 1; j <= 4; ++j) phi += DELTA[j - 1] * Math.sin(2 * j * chi);
  const lon = gk.cm + (Math.atan2(Math.sinh(eta1), Math.cos(xi1)) * 180) / Math.PI;
  return [lon, (phi * 180) / Math.PI];
}

// ---- polylines -----------------------------------------------------------------------
// Chainages (m) of the vertices of a map polyline [[x, y], ...].
export function chainages(pts) {
  const out = [0];
  for (let i = 1; i < pts.length; ++i) out.push(out[i - 1] + Math.hypot(pts[i][0] - pts[i - 1][0], pts[i][1] - pts[i - 1][1]));
  return out;
}
// Map point at chainage s along the polyline.
export function pointAt(pts, s) {
  const ch = chainages(pts);
  for (let i = 1; i < pts.length; ++i) {
    if (s <= ch[i] || i === pts.length - 1) {
      const t = (s - ch[i - 1]) / Math.max(1e-12, ch[i] - ch[i - 1]);
      return [pts[i - 1][0] + t * (pts[i][0] - pts[i - 1][0]), pts[i - 1][1] + t * (pts[i][1] - pts[i - 1][1])];
    }
  }
  return pts[0];
}
export const letter = (i) => String.fromCharCode(65 + (i % 26)) + (i >= 26 ? String(Math.floor(i / 26)) : '');

// ---- measuring -------------------------------------------------------------------------
// A plan leg's grid distance (m) and grid bearing (degrees clockwise from grid north, 0..360).
export const legLength = (a, b) => Math.hypot(b[0] - a[0], b[1] - a[1]);
export const legBearing = (a, b) => ((Math.atan2(b[0] - a[0], b[1] - a[1]) * 180) / Math.PI + 360) % 360;
// A line drawn on a section, between section points [u, v] in true metres (u along the
// section, v up it): its true length, and on a vertical section its apparent dip (degrees
// below the horizontal, 0..90), whatever the vertical exaggeration on screen.
export function sectionMeasure(a, b, vertical) {
  const du = b[0] - a[0], dv = b[1] - a[1];
  return { length: Math.hypot(du, dv), dip: vertical ? (Math.atan2(Math.abs(dv), Math.abs(du)) * 180) / Math.PI : null };
}

// The length of segment a-b (section [u, v] metres) inside each region, by the even-odd rule
// over each region's rings: regions [{record, name, rings: [[[u, v], ...], ...]}] -> [{record,
// name, length, from, to}] in order along the segment (from/to: fractions of its length), one
// entry per stretch. The apparent thickness of a unit along a drawn line.
export function lengthsAlong(a, b, regions) {
  const du = b[0] - a[0], dv = b[1] - a[1], len = Math.hypot(du, dv);
  const out = [];
  if (!(len > 0)) return out;
  for (const r of regions) {
    const ts = [0, 1];
    for (const ring of r.rings)
      for (let i = 0, n = ring.length; i < n; ++i) {
        const p = ring[i], q = ring[(i + 1) % n];
        const ex = q[0] - p[0], ey = q[1] - p[1], den = du * ey - dv * ex;
        if (den === 0) continue;
        const t = ((p[0] - a[0]) * ey - (p[1] - a[1]) * ex) / den, s = ((p[0] - a[0]) * dv - (p[1] - a[1]) * du) / den;
        if (t > 0 && t < 1 && s >= 0 && s <= 1) ts.push(t);
      }
    ts.sort((x, y) => x - y);
    const inside = (u, v) => {
      let c = false;
      for (const ring of r.rings)
        for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) {
          const [xi, yi] = ring[i], [xj, yj] = ring[j];
          if ((yi > v) !== (yj > v) && u < ((xj - xi) * (v - yi)) / (yj - yi) + xi) c = !c;
        }
      return c;
    };
    for (let k = 0; k + 1 < ts.length; ++k) {
      const t0 = ts[k], t1 = ts[k + 1], tm = 0.5 * (t0 + t1);
      if (t1 - t0 > 1e-12 && inside(a[0] + tm * du, a[1] + tm * dv)) {
        const last = out.length && out[out.length - 1];
        if (last && last.record === r.record && Math.abs(last.to - t0) < 1e-12) { last.to = t1; last.length += (t1 - t0) * len; }
        else out.push({ record: r.record, name: r.name, from: t0, to: t1, length: (t1 - t0) * len });
      }
    }
  }
  return out.sort((x, y) => x.from - y.from);
}
