// The model's 3D Tiles (GET /v1/models/{id}/3dtiles/tileset.json) in a real CesiumJS page (npm
// `cesium`, pinned in package-lock.json) in Debian's Chromium with SwiftShader WebGL, offline:
// no Cesium ion, no imagery, no terrain; every request the page makes must go to this test's
// own origin (Cesium's files and a proxy to the geoslice server).
//
// Oracles, none of them geoslice's code:
//  - placement: PROJ's cs2cs (EPSG:4523 <-> EPSG:4978, Earth-fixed) for three corners of the
//    model's top. Seen from 120 m straight above each corner, scene.pick must hit the model
//    1 m inside both edges and miss it 1 m outside either edge (so the model lies within 1 m
//    of where PROJ puts the corner, horizontally), and scene.pickPosition 1 m inside, taken
//    back through cs2cs, must be within 1 m of the point asked for (vertically too: its height
//    is the top the server's virtual borehole gives there).
//  - units: 50 pixels of an oblique view (at full detail) where scene.pick returns a feature; the feature's
//    `id` property must be the record the server's virtual borehole (an exact ray query)
//    gives at the picked point moved 3 m into the surface along the view ray (the depth
//    buffer at this range places a pick to about a metre). A pixel whose answer changes
//    between 1.5 and 6 m into the surface lies near a contact, where that precision decides,
//    and is replaced by another (how many is printed).
//  - colours: at each of those pixels the rendered colour is nearest, in chromaticity, to
//    the legend colour of the unit picked there, for at least 90 % of them (lighting shades
//    a colour but keeps its hue; antialiased edges mix two).
// Writes cesium-overview.png and cesium-corner-*.png to the artifacts directory.
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { execFileSync } from 'node:child_process';
import { createRequire } from 'node:module';
import { startServer, launch, loadAverage } from './lib.mjs';

const require = createRequire(import.meta.url);
const binary = process.argv[2];
const out = process.argv[3] || 'cesium-artifacts';
fs.mkdirSync(out, { recursive: true });
const cesiumDir = path.join(path.dirname(require.resolve('cesium/package.json')), 'Build', 'Cesium');
const t0 = Date.now();

function fail(msg) { console.error(`FAIL: ${msg}`); process.exitCode = 1; }

// cs2cs: EPSG:4523 takes northing, easting (EPSG's order); EPSG:4978 is X, Y, Z.
function cs2cs(from, to, rows) {
  const text = rows.map((r) => r.join(' ')).join('\n') + '\n';
  return execFileSync('cs2cs', ['-f', '%.6f', from, to], { input: text }).toString().trim().split('\n')
    .map((l) => l.trim().split(/\s+/).slice(0, 3).map(Number));
}
const toEcef = (pts) => cs2cs('EPSG:4523', 'EPSG:4978', pts.map(([x, y, z]) => [y, x, z]));
const toGk = (pts) => cs2cs('EPSG:4978', 'EPSG:4523', pts).map(([n, e, z]) => [e, n, z]);

// Leaf tiles of about 2,048 triangles: a tree of several levels for a model SwiftShader draws quickly.
const server = await startServer(binary, { models: [{ name: 'mine', triangles: 20000, seed: 3 }],
  extraArgs: ['--3dtiles-triangles', '2048'] });
process.on('exit', () => { try { server.proc.kill('SIGKILL'); } catch (_) { /* gone */ } });
const api = async (p) => {
  const r = await fetch(server.url + p);
  if (!r.ok) throw new Error(`${p}: ${r.status} ${await r.text()}`);
  return r.json();
};
// The server's virtual borehole at (x, y): intervals [from_m, to_m] along `direction` from
// `origin` (straight down), each with its record; as [top z, bottom z, record].
async function boreholeAt(x, y) {
  const r = await fetch(`${server.url}/v1/models/mine/borehole?x=${x}&y=${y}`);
  if (r.status === 400) return null;  // outside the model's map extent
  if (!r.ok) throw new Error(`borehole ${x} ${y}: ${r.status} ${await r.text()}`);
  const b = await r.json();
  const v = (p) => (Array.isArray(p) ? p : [p.x, p.y, p.z]);
  const o = v(b.origin), d = v(b.direction);
  return (b.intervals || []).map((iv) => [o[2] + d[2] * iv.from_m, o[2] + d[2] * iv.to_m, iv.record]);
}
// The unit at a world point: the record of the interval holding z, or null.
async function unitAt([x, y, z]) {
  const ivs = await boreholeAt(x, y);
  if (ivs == null) return 'outside';
  for (const [za, zb, record] of ivs)
    if (z <= Math.max(za, zb) && z >= Math.min(za, zb)) return record;
  return null;
}
async function topAt(x, y) {
  const ivs = await boreholeAt(x, y);
  return ivs && ivs.length ? Math.max(ivs[0][0], ivs[0][1]) : null;
}

const model = await api('/v1/models/mine');

// 0. Every tile passes Khronos' glTF validator (0 errors, 0 warnings; EXT_mesh_features and
// EXT_structural_metadata are reported as extensions it does not check).
const validator = require('gltf-validator');
const tilesetDoc = await api('/v1/models/mine/3dtiles/tileset.json');
const uris = [];
(function walk(t, depth) {
  if (t.content) uris.push(t.content.uri);
  for (const c of t.children || []) walk(c, depth + 1);
})(tilesetDoc.root, 0);
if (uris.length < 5) fail(`the tileset has ${uris.length} tiles with content; expected a tree`);
for (const uri of uris) {
  const r = await fetch(`${server.url}/v1/models/mine/3dtiles/${uri}`);
  if (r.headers.get('content-type') !== 'model/gltf-binary') fail(`${uri}: content type ${r.headers.get('content-type')}`);
  const report = await validator.validateBytes(new Uint8Array(await r.arrayBuffer()), { maxIssues: 20 });
  if (report.issues.numErrors || report.issues.numWarnings)
    fail(`${uri}: glTF validator: ${JSON.stringify(report.issues.messages.filter((m) => m.severity < 2).slice(0, 3))}`);
}
const legend = new Map(model.legend.filter((e) => e.id != null).map((e) => [e.id, e.colour]));

// Cesium's files and the page from here; /v1 proxied to geoslice: one origin.
const page0 = `<!doctype html><html><head><meta charset="utf-8">
<script>window.CESIUM_BASE_URL = '/cesium/';</script>
<script src="/cesium/Cesium.js"></script>
<link rel="stylesheet" href="/cesium/Widgets/widgets.css">
<style>html,body,#c{margin:0;width:100%;height:100%;overflow:hidden}</style></head>
<body><div id="c"></div></body></html>`;
const types = { '.js': 'text/javascript', '.css': 'text/css', '.json': 'application/json', '.png': 'image/png',
  '.jpg': 'image/jpeg', '.svg': 'image/svg+xml', '.wasm': 'application/wasm', '.glb': 'model/gltf-binary' };
const web = http.createServer(async (req, res) => {
  try {
    if (req.url === '/' || req.url === '/index.html') {
      res.writeHead(200, { 'content-type': 'text/html' });
      return res.end(page0);
    }
    if (req.url.startsWith('/v1/')) {
      const r = await fetch(server.url + req.url);
      const body = Buffer.from(await r.arrayBuffer());
      res.writeHead(r.status, { 'content-type': r.headers.get('content-type') || 'application/octet-stream' });
      return res.end(body);
    }
    if (req.url.startsWith('/cesium/')) {
      const rel = decodeURIComponent(req.url.slice('/cesium/'.length).split('?')[0]);
      const file = path.join(cesiumDir, rel);
      if (!file.startsWith(cesiumDir) || !fs.existsSync(file)) { res.writeHead(404); return res.end(); }
      res.writeHead(200, { 'content-type': types[path.extname(file)] || 'application/octet-stream' });
      return res.end(fs.readFileSync(file));
    }
    res.writeHead(404);
    res.end();
  } catch (e) { res.writeHead(500); res.end(String(e)); }
});
await new Promise((r) => web.listen(0, '127.0.0.1', r));
const origin = `http://127.0.0.1:${web.address().port}`;

const browser = await launch({ webgl: true });
const ctx = await browser.newContext({ viewport: { width: 800, height: 600 }, deviceScaleFactor: 1 });
const page = await ctx.newPage();
const foreign = [];
page.on('request', (r) => { if (!r.url().startsWith(origin) && !r.url().startsWith('data:') && !r.url().startsWith('blob:')) foreign.push(r.url()); });
page.on('pageerror', (e) => fail(`page error: ${e.message}`));
await page.goto(origin + '/');
await page.waitForFunction(() => window.Cesium !== undefined, null, { timeout: 60000 });

// The viewer, no ion, no imagery, no globe (the model reaches below the ellipsoid), a
// headlight so colours do not depend on the time of day.
await page.evaluate(async () => {
  const C = window.Cesium;
  C.Ion.defaultAccessToken = '';
  const viewer = new C.Viewer('c', {
    baseLayer: false, baseLayerPicker: false, geocoder: false, timeline: false, animation: false,
    homeButton: false, sceneModePicker: false, navigationHelpButton: false, fullscreenButton: false,
    infoBox: false, selectionIndicator: false, terrainProvider: new C.EllipsoidTerrainProvider(),
    skyBox: false, skyAtmosphere: false, contextOptions: { webgl: { preserveDrawingBuffer: true } },
    // Frames only when asked (settle() and the picks ask): SwiftShader draws on the CPU, and
    // a continuous render loop would take it from the picks.
    requestRenderMode: true, maximumRenderTimeChange: Infinity,
  });
  viewer.scene.globe.show = false;
  viewer.scene.backgroundColor = C.Color.WHITE;
  viewer.scene.light = new C.DirectionalLight({ direction: new C.Cartesian3(0, 0, -1) });
  viewer.scene.preUpdate.addEventListener((scene) => { scene.light.direction = C.Cartesian3.clone(scene.camera.directionWC, scene.light.direction); });
  const tileset = await C.Cesium3DTileset.fromUrl('/v1/models/mine/3dtiles/tileset.json', { maximumScreenSpaceError: 2 });
  viewer.scene.primitives.add(tileset);
  window.viewer = viewer;
  window.tileset = tileset;
  // Frames until every tile the view needs is loaded and stays so over three frames (a frame
  // may ask for more tiles), at most a minute.
  window.settle = async () => {
    let stable = 0;
    for (let i = 0; i < 600 && stable < 3; ++i) {
      viewer.scene.render();
      await new Promise((r) => setTimeout(r, 100));
      stable = tileset.tilesLoaded ? stable + 1 : 0;
    }
    viewer.scene.render();
    return stable >= 3;
  };
  // Look straight down from `h` metres above an Earth-fixed point, north up.
  window.lookDown = (xyz, h) => {
    const p = new C.Cartesian3(...xyz);
    const up = C.Ellipsoid.WGS84.geodeticSurfaceNormal(p, new C.Cartesian3());
    viewer.camera.setView({
      destination: C.Cartesian3.add(p, C.Cartesian3.multiplyByScalar(up, h, new C.Cartesian3()), new C.Cartesian3()),
      orientation: { heading: 0, pitch: -C.Math.PI_OVER_TWO, roll: 0 },
    });
  };
  window.windowOf = (xyz) => {
    const w = C.SceneTransforms.worldToWindowCoordinates(viewer.scene, new C.Cartesian3(...xyz));
    return w ? [w.x, w.y] : null;
  };
  window.pickAt = (x, y) => {
    const f = viewer.scene.pick(new C.Cartesian2(x, y));
    const id = f && f.getProperty ? f.getProperty('id') : null;
    const p = viewer.scene.pickPosition(new C.Cartesian2(x, y));
    return { hit: !!f, id: id ?? null, name: f && f.getProperty ? f.getProperty('name') : null,
      colour: f && f.getProperty ? f.getProperty('colour') : null,
      pos: p ? [p.x, p.y, p.z] : null, eye: [viewer.camera.positionWC.x, viewer.camera.positionWC.y, viewer.camera.positionWC.z] };
  };
});
const loadMs = Date.now() - t0;
const phases = {};

// 1. Three corners of the model's top.
const [x0, y0] = model.bounds.min, [x1, y1] = model.bounds.max;
const corners = [[x0, y0, 1, 1], [x1, y0, -1, 1], [x0, y1, 1, -1]];
let cornerNo = 0;
for (const [cx, cy, sx, sy] of corners) {
  ++cornerNo;
  const inside = [cx + sx * 1, cy + sy * 1];
  const z = await topAt(inside[0], inside[1]);
  if (z == null) { fail(`corner ${cornerNo}: no borehole top at ${inside}`); continue; }
  const pts = [[...inside, z], [cx - sx * 1, cy + sy * 1, z], [cx + sx * 1, cy - sy * 1, z]];
  const ecef = toEcef(pts);
  await page.evaluate(([p]) => window.lookDown(p, 120), [ecef[0]]);
  if (!await page.evaluate(() => window.settle())) fail(`corner ${cornerNo}: tiles did not load`);
  await page.screenshot({ path: path.join(out, `cesium-corner-${cornerNo}.png`) });
  const picks = [];
  for (const e of ecef) {
    const w = await page.evaluate((p) => window.windowOf(p), e);
    picks.push(w ? await page.evaluate(([x, y]) => window.pickAt(x, y), w) : { hit: false, pos: null });
  }
  if (!picks[0].hit) fail(`corner ${cornerNo}: 1 m inside (${pts[0].map((v) => v.toFixed(2))}) the model is not there`);
  if (picks[1].hit) fail(`corner ${cornerNo}: 1 m outside along x the model is there (shifted by more than 1 m)`);
  if (picks[2].hit) fail(`corner ${cornerNo}: 1 m outside along y the model is there (shifted by more than 1 m)`);
  if (picks[0].pos) {
    const [g] = toGk([picks[0].pos]);
    const d = Math.hypot(g[0] - pts[0][0], g[1] - pts[0][1], g[2] - pts[0][2]);
    console.log(`corner ${cornerNo}: picked ${g.map((v) => v.toFixed(3))} vs PROJ ${pts[0].map((v) => v.toFixed(3))}: ${d.toFixed(3)} m`);
    if (!(d < 1.0)) fail(`corner ${cornerNo}: the picked top is ${d.toFixed(3)} m from where PROJ puts it`);
  } else fail(`corner ${cornerNo}: no pick position`);
}

phases.cornersMs = Date.now() - t0 - loadMs;
// 2. 50 pixels of an oblique overview.
await page.evaluate(() => {
  const C = window.Cesium;
  const bs = window.tileset.boundingSphere;
  window.viewer.camera.viewBoundingSphere(bs, new C.HeadingPitchRange(C.Math.toRadians(30), C.Math.toRadians(-35), bs.radius * 1.7));
  // Full detail for the picks: a coarser level lies off the exact surfaces by up to its
  // geometricError (that is what levels of detail are), which would move picked points
  // across contacts. The levels themselves are checked in tests/unit/tiles3d_test.cpp.
  window.tileset.maximumScreenSpaceError = 0;
});
if (!await page.evaluate(() => window.settle())) fail('overview: tiles did not load');
await page.screenshot({ path: path.join(out, 'cesium-overview.png') });
const shot = await page.evaluate(async () => {
  // The canvas as drawn (preserveDrawingBuffer), through a 2D canvas.
  const img = new Image();
  img.src = window.viewer.canvas.toDataURL('image/png');
  await img.decode();
  const c2 = document.createElement('canvas');
  c2.width = img.width;
  c2.height = img.height;
  const g = c2.getContext('2d');
  g.drawImage(img, 0, 0);
  return { w: img.width, h: img.height, px: Array.from(g.getImageData(0, 0, img.width, img.height).data) };
});
const rgbAt = (x, y) => {  // window coordinates, top-left origin like the image rows
  const i = (Math.round(y) * shot.w + Math.round(x)) * 4;
  return [shot.px[i], shot.px[i + 1], shot.px[i + 2]];
};
const hex = (s) => [1, 3, 5].map((i) => parseInt(s.slice(i, i + 2), 16));
const chroma = ([r, g, b]) => { const s = r + g + b + 1e-9; return [r / s, g / s, b / s]; };
let matched = 0, ambiguous = 0, colourOk = 0, tried = 0;
const mismatches = [];
for (let gy = 0; gy < 24 && matched < 50; ++gy) {
  for (let gx = 0; gx < 24 && matched < 50; ++gx) {
    const x = 40 + (gx + 0.5) * (720 / 24), y = 40 + (((gy * 7) % 24) + 0.5) * (520 / 24);
    // Background (white) in the drawn frame: nothing to pick there (a pick is a render in
    // SwiftShader, so only pixels that show the model are picked).
    if (rgbAt(x, y).every((c) => c >= 250)) continue;
    const p = await page.evaluate(([a, b]) => window.pickAt(a, b), [x, y]);
    if (!p.hit || !p.pos || p.id == null) continue;
    ++tried;
    const dir = p.pos.map((v, i) => v - p.eye[i]);
    const len = Math.hypot(...dir);
    const along = (d) => p.pos.map((v, i) => v + dir[i] / len * d);
    const [a, b, c] = toGk([along(1.5), along(3), along(6)]);
    const [ua, ub, uc] = [await unitAt(a), await unitAt(b), await unitAt(c)];
    if (ua !== ub || ub !== uc || ub === 'outside') { ++ambiguous; continue; }
    if (ub !== p.id) mismatches.push({ pixel: [x, y], cesium: p.id, server: ub, at: b });
    if (p.colour !== legend.get(p.id)) fail(`feature ${p.id}: colour property ${p.colour}, legend ${legend.get(p.id)}`);
    else ++matched;
    const rendered = chroma(rgbAt(x, y));
    let best = null, bestD = Infinity;
    for (const [rec, col] of legend) {
      const c2 = chroma(hex(col));
      const d = Math.hypot(...c2.map((v, i) => v - rendered[i]));
      if (d < bestD) { bestD = d; best = rec; }
    }
    if (best === p.id) ++colourOk;
    else if (process.env.CESIUM_DEBUG) console.log('colour', x, y, rgbAt(x, y), p.id, legend.get(p.id), best);
  }
}
if (matched < 50) fail(`only ${matched} of 50 pixels matched the server (${mismatches.length} mismatches, ${ambiguous} at contacts, ${tried} picked)`);
if (mismatches.length) fail(`scene.pick disagrees with the server: ${JSON.stringify(mismatches.slice(0, 5))}`);
const colourShare = colourOk / Math.max(1, matched + mismatches.length);
if (colourShare < 0.9) fail(`rendered colours: only ${(colourShare * 100).toFixed(0)} % nearest the picked unit's legend colour`);
if (foreign.length) fail(`the page requested other origins: ${foreign.slice(0, 5).join(', ')}`);
console.log(JSON.stringify({
  tiles: uris.length, phases: { ...phases, picksMs: Date.now() - t0 - loadMs - phases.cornersMs }, pixelsMatched: matched, mismatches: mismatches.length, atContacts: ambiguous, colourAgreement: +colourShare.toFixed(3),
  foreignRequests: foreign.length, firstLoadMs: loadMs, totalMs: Date.now() - t0, load: loadAverage(),
  cesium: require('cesium/package.json').version,
}));
await browser.close();
web.close();
server.stop();
if (!process.exitCode) console.log('cesium_3dtiles: ok');
