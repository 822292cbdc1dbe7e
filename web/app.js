// geoslice web client: plan map, sections as tiles, 3D view with a draggable plane,
// pixel queries, boreholes, export and permalinks. Plain ES module, no build step; every
// request goes to this page's origin. State lives in S; every asynchronous answer carries
// the generation (S.gen) of the scene it was asked for and is dropped when that scene is
// gone, so the picture, the plane and the answer always belong to the same request.
import * as V from './views.js?v=__GS_BUILD__';
import { t, setLanguage, initialLanguage, language } from './i18n.js?v=__GS_BUILD__';

const $ = (id) => document.getElementById(id);
const S = {
  models: [], model: null, gk: null, gen: 0, view: 'plan', mode: 'line', points: [], through: null,
  plan: null, section: null, answer: null, queryId: 0, pdf: false,
  three: null, shown3d: null, shownProfile: null, bh: null,
};
const perf = { marks: [] };  // bench/web_bench.mjs reads these
window.geoslice = { S, perf };
const mark = (name, extra) => perf.marks.push({ name, t: performance.now(), ...extra });
// Marks taken at the next animation frame: the change is on screen.
const markPainted = (name, t0, extra) => requestAnimationFrame(() => mark(name, { ms: performance.now() - t0, ...extra }));

// ---- network ---------------------------------------------------------------------------
let busyCount = 0;
function busy(d) {
  busyCount = Math.max(0, busyCount + d);
  $('busy').hidden = busyCount === 0;
  document.body.setAttribute('aria-busy', busyCount > 0 ? 'true' : 'false');
}
class HttpError extends Error {
  constructor(status, message) { super(message); this.status = status; }
}
async function request(url, opts = {}, as = 'json') {
  busy(+1);
  try {
    let r;
    try { r = await fetch(url, opts); } catch (e) { throw new HttpError(0, e.message || 'network error'); }
    if (!r.ok) {
      let detail = '';
      try { const j = await r.json(); detail = j.detail || j.title || ''; } catch (_) { /* not JSON */ }
      throw new HttpError(r.status, `${r.status} ${detail || r.statusText || 'error'}`.trim());
    }
    return as === 'json' ? await r.json() : await r.blob();
  } finally { busy(-1); }
}
const api = (path) => `/v1/models/${encodeURIComponent(S.model.id)}${path}`;

function setStatus(text, isError = false, action = null) {
  const s = $('status');
  s.textContent = text || '';
  s.className = isError ? 'error' : '';
  if (action) {
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = action.label;
    b.onclick = action.run;
    s.append(b);
  }
}

// ---- tiles with retry ------------------------------------------------------------------
// Tiles are fetched (not <img src>) so that a 503 is seen and retried with back-off
// (Retry-After when given); tiles that stay failed are striped and counted in the status.
const RetryTiles = L.GridLayer.extend({
  initialize(urlOf, options) {
    this.urlOf = urlOf;
    this.retrying = new Set();
    this.failed = new Set();
    L.setOptions(this, options);
    this.on('tileunload', (e) => { if (e.tile.src.startsWith('blob:')) URL.revokeObjectURL(e.tile.src); });
  },
  createTile(c, done) {
    const img = document.createElement('img');
    img.alt = '';
    const key = `${c.z}/${c.x}/${c.y}`, url = this.urlOf(c.z, c.x, c.y), layer = this;
    let attempt = 0;
    const go = () => {
      busy(+1);
      fetch(url)
        .then((r) => {
          if (r.ok) return r.blob();
          throw { status: r.status, after: Number(r.headers.get('Retry-After')) || 0 };
        }, () => { throw { status: 0, after: 0 }; })
        .then((blob) => {
          img.onload = () => {
            layer.retrying.delete(key);
            layer.failed.delete(key);
            img.dataset.url = url;
            layer.fire('tilepainted', { key });
            done(null, img);
            tileStatus(layer);
          };
          img.src = URL.createObjectURL(blob);
        })
        .catch((e) => {
          const retryable = e.status === 0 || e.status === 503 || e.status === 504 || e.status === 429;
          if (retryable && attempt < 4 && layer._map) {
            const delay = Math.min(4000, Math.max(e.after * 1000, 300 * 2 ** attempt));
            ++attempt;
            layer.retrying.add(key);
            tileStatus(layer);
            setTimeout(go, delay);
          } else {
            layer.retrying.delete(key);
            layer.failed.add(key);
            img.className = 'tile-failed';
            done(new Error(`tile ${key}: ${e.status}`), img);
            tileStatus(layer);
          }
        })
        .finally(() => busy(-1));
    };
    go();
    return img;
  },
});
function tileStatus(layer) {
  if (layer !== S.section?.layer && layer !== S.plan?.layer) return;
  const failed = (S.section?.layer?.failed.size || 0) + (S.plan?.layer?.failed.size || 0);
  const retrying = (S.section?.layer?.retrying.size || 0) + (S.plan?.layer?.retrying.size || 0);
  if (failed) setStatus(t('tilesFailed', failed), true, { label: t('retry'), run: retryTiles });
  else if (retrying) setStatus(t('retrying', retrying));
  else if (/tile/.test($('status').textContent)) setStatus('');
}
function retryTiles() {
  for (const l of [S.section?.layer, S.plan?.layer]) if (l) { l.failed.clear(); l.redraw(); }
  setStatus('');
}

// ---- grids (api/view.hpp TileGrid) -------------------------------------------------------
const lngOf = (g, u) => ((u - g.origin.u) * 256) / g.size0;
const latOf = (g, v) => ((v - g.origin.v) * g.exaggeration * 256) / g.size0;
const uOf = (g, lng) => g.origin.u + (lng * g.size0) / 256;
const vOf = (g, lat) => g.origin.v + (lat * g.size0) / (256 * g.exaggeration);
function tileFrame(g, z, x, y) {
  const s = g.size0 / 2 ** z, sv = s / g.exaggeration;
  const u0 = g.origin.u + x * s, v1 = g.origin.v - y * sv;
  return `${u0},${u0 + s},${v1 - sv},${v1}`;
}
// Finest zoom that is still useful: about 0.25 m per pixel.
const usefulZoom = (g) => Math.max(0, Math.min(g.maxZoom, Math.ceil(Math.log2(g.size0 / 256 / 0.25))));
function gridBounds(g) {
  const e = g.extent;
  return L.latLngBounds([latOf(g, e.v0), lngOf(g, e.u0)], [latOf(g, e.v1), lngOf(g, e.u1)]);
}
// The pixel of the tile grid under a map point, at the zoom whose tiles are on screen.
function gridPixel(map, sec, latlng) {
  const z = Math.max(0, Math.min(sec.maxNative, Math.round(map.getZoom())));
  const X = latlng.lng * 2 ** z, Y = -latlng.lat * 2 ** z;
  const tx = Math.floor(X / 256), ty = Math.floor(Y / 256);
  const px = Math.floor(X - tx * 256), py = Math.floor(Y - ty * 256);
  const centre = L.latLng(-(ty * 256 + py + 0.5) / 2 ** z, (tx * 256 + px + 0.5) / 2 ** z);
  return { z, tx, ty, px, py, centre, frame: tileFrame(sec.grid, z, tx, ty) };
}

// ---- maps ------------------------------------------------------------------------------
function makeMap(id) {
  const map = L.map(id, { crs: L.CRS.Simple, zoomSnap: 0.25, zoomControl: false, attributionControl: false,
                          minZoom: -4, maxZoom: 8, tap: false, fadeAnimation: false });
  L.control.zoom({ position: 'bottomright', zoomInTitle: t('zoomIn'), zoomOutTitle: t('zoomOut') }).addTo(map);
  return map;
}
let planMap, sectionMap;

// Long-press (600 ms, < 10 px of movement, one pointer) on a map: fn(latlng). The click
// that ends a long-press is swallowed.
function onLongPress(map, fn) {
  const el = map.getContainer();
  let timer = null, start = null, pointers = 0, swallow = false;
  const cancel = () => { clearTimeout(timer); timer = null; };
  el.addEventListener('pointerdown', (e) => {
    ++pointers;
    swallow = false;
    if (pointers > 1 || e.target.closest('.leaflet-control')) return cancel();
    start = [e.clientX, e.clientY];
    timer = setTimeout(() => {
      timer = null;
      swallow = true;
      const r = el.getBoundingClientRect();
      fn(map.containerPointToLatLng([start[0] - r.left, start[1] - r.top]));
    }, 600);
  });
  el.addEventListener('pointermove', (e) => {
    if (timer && Math.hypot(e.clientX - start[0], e.clientY - start[1]) > 10) cancel();
  });
  const up = () => { pointers = Math.max(0, pointers - 1); cancel(); };
  el.addEventListener('pointerup', up);
  el.addEventListener('pointercancel', up);
  el.addEventListener('contextmenu', (e) => e.preventDefault());
  return () => { const s = swallow; swallow = false; return s; };
}

// ---- overlays: axes, scale bar, ends, grid ----------------------------------------------
const svgNS = 'http://www.w3.org/2000/svg';
function svgEl(tag, attrs, text) {
  const e = document.createElementNS(svgNS, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text != null) e.textContent = text;
  return e;
}
function scaleBar(svg, map, g, w, h) {
  const mPerPx = g.size0 / 256 / 2 ** map.getZoom();
  const m = V.niceStep(mPerPx * 80), px = m / mPerPx;
  const x0 = 72, y0 = h - 48;
  svg.append(svgEl('rect', { x: x0 - 4, y: y0 - 16, width: px + 8, height: 24, class: 'axisbg' }));
  svg.append(svgEl('path', { d: `M${x0},${y0 - 4}v6h${px}v-6`, stroke: '#000', 'stroke-width': 2, fill: 'none' }));
  svg.append(svgEl('text', { x: x0 + px / 2, y: y0 - 6, 'text-anchor': 'middle', id: 'scaleText' },
                   `${m >= 1000 ? m / 1000 + ' km' : m + ' ' + t('metres')}`));
}
function axes(svg, map, g, w, h, leftLabel, bottomLabel, bottomValue) {
  const aw = Math.max(44, 14 + 7.5 * String(Math.round(Math.abs(g.origin.v))).length);
  svg.append(svgEl('rect', { x: 0, y: 0, width: aw, height: h, class: 'axisbg' }));
  svg.append(svgEl('rect', { x: 0, y: h - 20, width: w, height: 20, class: 'axisbg' }));
  const mPerPx = g.size0 / 256 / 2 ** map.getZoom();
  const stepV = V.niceStep((mPerPx / g.exaggeration) * 40), stepU = V.niceStep(mPerPx * 90);
  const top = map.containerPointToLatLng([0, 0]), bottom = map.containerPointToLatLng([0, h]);
  const vTop = vOf(g, top.lat), vBottom = vOf(g, bottom.lat);
  for (let v = Math.ceil(vBottom / stepV) * stepV; v <= vTop; v += stepV) {
    const y = map.latLngToContainerPoint([latOf(g, v), 0]).y;
    if (y < 12 || y > h - 24) continue;
    svg.append(svgEl('line', { x1: aw - 6, x2: aw, y1: y, y2: y, stroke: '#000' }));
    svg.append(svgEl('text', { x: aw - 7, y: y + 4, 'text-anchor': 'end' }, Math.round(v)));
  }
  const left = map.containerPointToLatLng([0, 0]), right = map.containerPointToLatLng([w, 0]);
  const uL = uOf(g, left.lng), uR = uOf(g, right.lng);
  for (let u = Math.ceil(bottomValue(uL) / stepU) * stepU; bottomValue(uL) <= u && u <= bottomValue(uR); u += stepU) {
    const x = map.latLngToContainerPoint([0, lngOf(g, u - bottomValue(uL) + uL)]).x;
    if (x < aw + 30 || x > w - 30) continue;
    svg.append(svgEl('line', { x1: x, x2: x, y1: h - 20, y2: h - 14, stroke: '#000' }));
    svg.append(svgEl('text', { x, y: h - 5, 'text-anchor': 'middle' }, Math.round(u)));
  }
  svg.append(svgEl('text', { x: aw + 4, y: 14, class: 'axis-label' }, leftLabel));
  svg.append(svgEl('text', { x: aw + 4, y: h - 24, class: 'axis-label' }, bottomLabel));
}
function drawSectionOverlay() {
  const svg = $('sectionOverlay');
  svg.replaceChildren();
  const sec = S.section;
  if (!sec || S.view !== 'section' || !sectionMap._loaded) return;
  const map = sectionMap, g = sec.grid, { x: w, y: h } = map.getSize();
  const horizontal = sec.kind === 'elevation';
  axes(svg, map, g, w, h, horizontal ? t('northAxis') : t('elevAxis'), horizontal ? t('eastAxis') : t('distAxis'),
       horizontal ? (u) => u : (u) => u - sec.distance0);
  scaleBar(svg, map, g, w, h);
  if (!horizontal) svg.append(svgEl('text', { x: w - 8, y: 14, 'text-anchor': 'end', id: 'vxLabel' }, t('vxShown', g.exaggeration)));
  const vTop = g.extent.v1;
  for (const end of sec.ends) {
    const p = map.latLngToContainerPoint([latOf(g, vTop), lngOf(g, end.u)]);
    if (end.bend) svg.append(svgEl('line', { x1: p.x, x2: p.x, y1: 0, y2: h - 20, class: 'bend' }));
    const x = Math.max(70, Math.min(w - 16, p.x));
    svg.append(svgEl('text', { x, y: 36, 'text-anchor': 'middle', class: 'end' }, end.label));
  }
}
function drawPlanOverlay() {
  const svg = $('planOverlay');
  svg.replaceChildren();
  if (!S.plan || S.view !== 'plan' || !planMap._loaded) return;
  const map = planMap, g = S.plan.grid, { x: w, y: h } = map.getSize();
  axes(svg, map, g, w, h, t('northAxis'), t('eastAxis'), (u) => u);
  scaleBar(svg, map, g, w, h);
  // Grid lines in the model's CRS.
  const mPerPx = g.size0 / 256 / 2 ** map.getZoom();
  const step = V.niceStep(mPerPx * 90);
  const tl = map.containerPointToLatLng([0, 0]), br = map.containerPointToLatLng([w, h]);
  const x0 = uOf(g, tl.lng), x1 = uOf(g, br.lng), y1 = vOf(g, tl.lat), y0 = vOf(g, br.lat);
  for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) {
    const px = map.latLngToContainerPoint([0, lngOf(g, x)]).x;
    if (px > 52) svg.append(svgEl('line', { x1: px, x2: px, y1: 0, y2: h - 20, class: 'grid' }));
  }
  for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) {
    const py = map.latLngToContainerPoint([latOf(g, y), 0]).y;
    if (py < h - 20) svg.append(svgEl('line', { x1: 52, x2: w, y1: py, y2: py, class: 'grid' }));
  }
  // Lon/lat graticule (CGCS2000) when the model is in a Gauss-Kruger CRS.
  if (S.gk) {
    const ll0 = V.gkToLonLat(S.gk, x0, y0), ll1 = V.gkToLonLat(S.gk, x1, y1);
    const d = V.niceStep(Math.max(ll1[0] - ll0[0], ll1[1] - ll0[1]) / 4);
    const toPx = (lon, lat) => {
      const [x, y] = V.lonLatToGk(S.gk, lon, lat);
      return map.latLngToContainerPoint([latOf(g, y), lngOf(g, x)]);
    };
    for (let lon = Math.ceil(ll0[0] / d) * d; lon <= ll1[0]; lon += d) {
      const a = toPx(lon, ll0[1] - d), b = toPx(lon, ll1[1] + d);
      svg.append(svgEl('line', { x1: a.x, y1: a.y, x2: b.x, y2: b.y, class: 'grat' }));
      const lp = toPx(lon, ll1[1]);
      svg.append(svgEl('text', { x: lp.x + 3, y: h - 26, fill: '#0b62c4' }, `${lon.toFixed(3)}°E`));
    }
    for (let lat = Math.ceil(ll0[1] / d) * d; lat <= ll1[1]; lat += d) {
      const a = toPx(ll0[0] - d, lat), b = toPx(ll1[0] + d, lat);
      svg.append(svgEl('line', { x1: a.x, y1: a.y, x2: b.x, y2: b.y, class: 'grat' }));
      svg.append(svgEl('text', { x: w - 4, y: toPx(ll1[0], lat).y - 3, 'text-anchor': 'end' }, `${lat.toFixed(3)}°N`));
    }
  }
  svg.append(svgEl('text', { x: w - 12, y: 36, 'text-anchor': 'end', class: 'end' }, '↑N'));
}

// ---- model -----------------------------------------------------------------------------
async function loadModel(id, restore = null) {
  let m;
  try {
    m = await request(`/v1/models/${encodeURIComponent(id)}`);
  } catch (e) {
    setStatus(t('failedModel', e.message), true);
    if (S.model) $('model').value = S.model.id;
    return false;
  }
  // A new model: everything that belonged to the old one goes.
  ++S.gen;
  S.model = m;
  S.gk = V.gaussKruger(m.crs?.id);
  S.points = [];
  S.through = null;
  clearAnswer();
  clearBorehole();
  setSection(null);
  S.plan = null;
  const [min, max] = [m.bounds.min, m.bounds.max];
  for (const f of ['planZ', 'sliceZ']) {
    $(f).min = Math.floor(min[2]);
    $(f).max = Math.ceil(max[2]);
  }
  const zMid = Math.round(min[2] + 0.5 * (max[2] - min[2]));
  $('planZ').value = restore?.pz ?? zMid;
  $('sliceZ').value = restore?.sz ?? zMid;
  const half = 0.5 * Math.hypot(max[0] - min[0], max[1] - min[1]);
  $('plOffset').min = -Math.ceil(half);
  $('plOffset').max = Math.ceil(half);
  renderLegend();
  S.three = null;
  init3d(restore);
  setStatus('');
  await loadPlan();
  drawPlanLine();
  return true;
}

async function loadPlan() {
  const z = Number($('planZ').value);
  if (!$('planZ').checkValidity() || !Number.isFinite(z)) {
    setStatus(`${t('planElevation')}: ${$('planZ').min}..${$('planZ').max}`, true);
    return;
  }
  const gen = S.gen;
  let s;
  try {
    s = await request(api('/sections'), { method: 'POST', headers: { 'Content-Type': 'application/json' },
                                            body: JSON.stringify({ elevation: z }) });
  } catch (e) {
    setStatus(t('failedCut', e.message), true);
    return;
  }
  if (gen !== S.gen) return;
  if (S.plan?.layer) planMap.removeLayer(S.plan.layer);
  const g = s.grid, maxNative = usefulZoom(g);
  const layer = new RetryTiles((z, x, y) => s.tiles.replace('{z}', z).replace('{x}', x).replace('{y}', y),
                               { minNativeZoom: 0, maxNativeZoom: maxNative, bounds: gridBounds(g), tileSize: 256 });
  S.plan = { z, sid: s.sid, grid: g, layer, maxNative, definition: s.definition };
  planMap.setMaxZoom(maxNative);
  layer.addTo(planMap);
  if (!S.planFitted) { planMap.fitBounds(gridBounds(g), { padding: [8, 8] }); S.planFitted = true; }
  drawPlanOverlay();
  permalinkSoon();
}

function renderLegend() {
  // The section view's compact legend: colour, name, lithology and age of each unit.
  const mini = $('legendMini');
  mini.replaceChildren();
  for (const r of S.model.legend || []) {
    const li = document.createElement('li');
    li.dataset.record = r.id;
    li.innerHTML = '<span class="sw"></span><span></span>';
    li.firstChild.style.background = r.colour;
    li.lastChild.textContent = [r.name, r.lithology, r.age].filter(Boolean).join(' · ');
    mini.append(li);
  }
  const ul = $('legend');
  ul.replaceChildren();
  for (const r of S.model.legend || []) {
    const li = document.createElement('li');
    li.dataset.record = r.id;
    li.innerHTML = `<span class="sw"></span><strong></strong><span class="sub"></span>`;
    li.querySelector('.sw').style.background = r.colour;
    li.querySelector('strong').textContent = r.name;
    li.querySelector('.sub').textContent = [r.lithology, r.age, r.kind].filter(Boolean).join(' · ');
    li.title = r.colour;
    ul.append(li);
  }
}

// ---- drawing on the plan -----------------------------------------------------------------
let planLine = null;
function drawPlanLine() {
  if (planLine) planLine.remove();
  planLine = L.layerGroup().addTo(planMap);
  if (!S.plan) return;
  const g = S.plan.grid, ll = (p) => [latOf(g, p[1]), lngOf(g, p[0])];
  const [bmin, bmax] = [S.model.bounds.min, S.model.bounds.max];
  L.rectangle([ll(bmin), ll(bmax)], { color: '#333', weight: 1.5, fill: false, dashArray: '2 4', interactive: false }).addTo(planLine);
  const pts = S.mode === 'line' ? S.points : [];
  if (pts.length) L.polyline(pts.map(ll), { color: '#e00', weight: 3 }).addTo(planLine);
  pts.forEach((p, i) => L.marker(ll(p), { icon: L.divIcon({ className: 'pt-label', html: V.letter(i), iconSize: null }),
                                          keyboard: false, interactive: false }).addTo(planLine));
  if (S.through && ['ns', 'ew', 'az'].includes(S.mode)) {
    const az = modeAzimuth(), [min, max] = [S.model.bounds.min, S.model.bounds.max];
    const plane = V.planeFrom(az, 90, [S.through[0], S.through[1], 0]);
    const poly = V.planeBoxPolygon(plane, min, max);
    if (poly.length) L.polyline(poly.map((p) => ll(p)), { color: '#e00', weight: 3, dashArray: '8 6' }).addTo(planLine);
    L.circleMarker(ll(S.through), { radius: 6, color: '#e00' }).addTo(planLine);
  }
  // The section on show, as a trace.
  const sec = S.section;
  if (sec?.kind === 'line') L.polyline(sec.pts.map(ll), { color: '#0b62c4', weight: 2 }).addTo(planLine);
  if (sec?.kind === 'plane') {
    const poly = V.planeBoxPolygon(sec.plane, S.model.bounds.min, S.model.bounds.max);
    if (poly.length) L.polyline(poly.map(ll), { color: '#0b62c4', weight: 2 }).addTo(planLine);
  }
  updateDrawHint();
}
function modeAzimuth() {
  return S.mode === 'ns' ? 0 : S.mode === 'ew' ? 90 : Number($('azimuth').value) || 0;
}
function setMode(mode) {
  S.mode = mode;
  for (const b of document.querySelectorAll('[data-mode]')) b.setAttribute('aria-pressed', String(b.dataset.mode === mode));
  $('azField').hidden = mode !== 'az';
  $('sliceField').hidden = mode !== 'slice';
  $('undo').hidden = $('clear').hidden = mode !== 'line';
  drawPlanLine();
}
function updateDrawHint() {
  const h = $('drawHint');
  if (S.mode === 'line') h.textContent = `${t('hintLine')} (${t('points', S.points.length)})`;
  else if (S.mode === 'slice') h.textContent = t('hintSlice');
  else if (S.mode === 'query') h.textContent = t('tapHint');
  else h.textContent = t('hintPoint') + (S.through ? ` (${t('through', V.fmt(S.through[0], 0), V.fmt(S.through[1], 0))})` : '');
  $('cut').disabled = (S.mode === 'line' && S.points.length < 2) || (['ns', 'ew', 'az'].includes(S.mode) && !S.through);
}
function planClick(e) {
  if (!S.plan) return;
  const g = S.plan.grid, p = [uOf(g, e.latlng.lng), vOf(g, e.latlng.lat)];
  if (S.mode === 'line') { S.points.push(p); drawPlanLine(); permalinkSoon(); }
  else if (['ns', 'ew', 'az'].includes(S.mode)) { S.through = p; drawPlanLine(); }
  else queryMap('plan', planMap, S.plan, e.latlng);
}

// ---- sections --------------------------------------------------------------------------
function checkInputs(ids) {
  for (const id of ids) {
    const el = $(id);
    if (!el.checkValidity() || el.value === '') {
      const label = el.closest('label')?.querySelector('span')?.textContent || id;
      setStatus(t('failedCut', `${label}: ${el.value} (${el.min}..${el.max})`), true);
      return false;
    }
  }
  return true;
}
async function cut() {
  if (!S.model) return;
  const vx = Number($('vx').value);
  let def;
  if (S.mode === 'line') {
    if (!checkInputs(['vx'])) return;
    def = { line: S.points.map((p) => `${+p[0].toFixed(3)},${+p[1].toFixed(3)}`).join(','), vx };
  } else if (S.mode === 'slice') {
    if (!checkInputs(['sliceZ'])) return;
    def = { elevation: Number($('sliceZ').value) };
  } else {
    if (!checkInputs(S.mode === 'az' ? ['vx', 'azimuth'] : ['vx'])) return;
    if (!S.through) return;
    const zc = 0.5 * (S.model.bounds.min[2] + S.model.bounds.max[2]);
    def = { plane: V.planeText(V.planeFrom(modeAzimuth(), 90, [S.through[0], S.through[1], zc])), vx };
  }
  await openSection(def);
}
// Defines the section on the server (plane, elevation) or checks it with a small image
// (polyline: tiles are section images with a frame). Only a section the server accepted
// replaces the one on show.
async function openSection(def, view = null) {
  const gen = S.gen;
  const t0 = performance.now();
  mark('cut', { def });
  let sec;
  try {
    sec = await defineSection(def);
  } catch (e) {
    if (gen === S.gen) setStatus(t('failedCut', e.message), true);
    return false;
  }
  if (gen !== S.gen) return false;
  sec.t0 = t0;
  setStatus('');
  setSection(sec, view);
  return true;
}
async function defineSection(def) {
  const model = S.model;
  if (def.line) {
    const pts = [];
    const nums = def.line.split(',').map(Number);
    for (let i = 0; i + 1 < nums.length; i += 2) pts.push([nums[i], nums[i + 1]]);
    const q = `line=${def.line}&vx=${def.vx}`;
    await request(api(`/section.png?${q}&size=64x32`), {}, 'blob');  // the server's verdict on the line
    const ch = V.chainages(pts), len = ch[ch.length - 1];
    const [z0, z1] = [model.bounds.min[2], model.bounds.max[2]];
    const size0 = 2 ** Math.ceil(Math.log2(Math.max(len, (z1 - z0) * def.vx, 1e-3)));
    const grid = { origin: { u: 0, v: z1 }, size0, exaggeration: def.vx, maxZoom: 24,
                   extent: { u0: 0, u1: len, v0: z0, v1: z1 } };
    const ends = pts.map((p, i) => ({ u: ch[i], label: V.letter(i), bend: i > 0 && i < pts.length - 1 }));
    return { kind: 'line', def, q, pts, grid, ends, distance0: 0,
             url: (z, x, y) => api(`/section.png?${q}&frame=${tileFrame(grid, z, x, y)}&size=256x256`) };
  }
  const s = await request(api('/sections'), { method: 'POST', headers: { 'Content-Type': 'application/json' },
                                               body: JSON.stringify(def) });
  const canon = new URLSearchParams(s.definition);
  const g = s.grid;
  if (def.elevation != null) {
    return { kind: 'elevation', def, q: `elevation=${canon.get('elevation')}`, grid: g, sid: s.sid,
             ends: [], distance0: 0, url: (z, x, y) => s.tiles.replace('{z}', z).replace('{x}', x).replace('{y}', y) };
  }
  const nums = canon.get('plane').split(',').map(Number);
  const plane = { n: nums.slice(0, 3), d: nums[3] };
  const { u } = V.planeBasis(plane.n);
  const ends = [{ u: g.extent.u0, label: V.compass(-u[0], -u[1]) }, { u: g.extent.u1, label: V.compass(u[0], u[1]) }];
  return { kind: 'plane', def, q: `plane=${canon.get('plane')}&vx=${canon.get('vx')}`, plane, grid: g, sid: s.sid,
           ends, distance0: g.extent.u0, url: (z, x, y) => s.tiles.replace('{z}', z).replace('{x}', x).replace('{y}', y) };
}
function setSection(sec, view = null) {
  ++S.gen;
  if (S.section?.layer) sectionMap.removeLayer(S.section.layer);
  S.section = sec;
  clearAnswer();
  $('noSection').hidden = !!sec;
  $('tools-section').dataset.has = sec ? '1' : '';
  if (!sec) { drawSectionOverlay(); updateExports(); return; }
  sec.maxNative = usefulZoom(sec.grid);
  sec.layer = new RetryTiles(sec.url, { minNativeZoom: 0, maxNativeZoom: sec.maxNative,
                                        bounds: gridBounds(sec.grid), tileSize: 256 });
  let first = true;
  sec.layer.on('tilepainted', () => {
    if (first) { first = false; markPainted('firstTile', sec.t0); }
  });
  showView('section');
  sectionMap.setMaxZoom(sec.maxNative);
  if (view) sectionMap.setView([view[0], view[1]], view[2], { animate: false });
  else sectionMap.fitBounds(gridBounds(sec.grid), { padding: [24, 24], animate: false });
  sec.layer.addTo(sectionMap);
  $('sectionTitle').textContent = `${t('sectionOf')}: ${sectionLabel(sec)}`;
  updateExports();
  drawSectionOverlay();
  drawPlanLine();
  permalinkSoon();
}
function sectionLabel(sec) {
  if (sec.kind === 'line') return sec.pts.map((_, i) => V.letter(i)).join('-');
  if (sec.kind === 'elevation') return `${t('elevation')} ${sec.def.elevation} m`;
  return `${sec.ends[0].label}-${sec.ends[1].label}, vx ${sec.grid.exaggeration}`;
}
function updateExports() {
  const sec = S.section;
  for (const id of ['expPng', 'expSvg', 'expGeojson', 'expPdf']) {
    const a = $(id);
    if (!sec) { a.removeAttribute('href'); a.setAttribute('aria-disabled', 'true'); continue; }
    a.removeAttribute('aria-disabled');
    const ext = { expPng: 'png', expSvg: 'svg', expGeojson: 'geojson', expPdf: 'pdf' }[id];
    // A PDF is a print sheet: its paper sizes it (A3 landscape by default), so no size.
    const extra = ext === 'geojson' ? '&space=world' : ext === 'pdf' ? '' : '&size=2048x1024';
    a.href = api(`/section.${ext}?${sec.q}${extra}`);
    a.download = `${S.model.id}-section.${ext}`;
  }
  $('expPdf').hidden = !S.pdf;
}

// ---- queries ---------------------------------------------------------------------------
let marker = null;
function clearAnswer(message = null) {
  ++S.queryId;
  S.answer = null;
  if (marker) { marker.remove(); marker = null; }
  $('qmark3d').setAttribute('hidden', '');
  for (const d of document.querySelectorAll('.qdot')) d.remove();
  for (const li of document.querySelectorAll('#legend li.hit, #legendMini li.hit')) li.classList.remove('hit');
  const box = $('answer');
  box.replaceChildren();
  const p = document.createElement('p');
  p.className = message ? 'err' : 'hint';
  p.textContent = message || t('tapHint');
  box.append(p);
  $('copyAnswer').hidden = true;
}
async function runQuery(url, where, show) {
  clearAnswer();
  const id = S.queryId, gen = S.gen;
  const t0 = performance.now();
  $('answer').firstChild.textContent = t('loading');
  showSheet('answer');
  let j;
  try {
    j = await request(url);
  } catch (e) {
    if (id === S.queryId && gen === S.gen) clearAnswer(t('failedQuery', e.message));
    return;
  }
  if (id !== S.queryId || gen !== S.gen) return;  // a newer question or another picture
  show?.();
  renderAnswer(j, where);
  markPainted('answer', t0, { record: j.record?.id ?? null });
}
function queryMap(where, map, sec, latlng) {
  const p = gridPixel(map, sec, latlng);
  const q = where === 'plan' ? `elevation=${S.plan.z}` : sec.q;
  const url = api(`/query?${q}&frame=${p.frame}&size=256x256&px=${p.px}&py=${p.py}`);
  runQuery(url, where, () => {
    marker = L.marker(p.centre, { icon: L.divIcon({ className: 'qmark', iconSize: [16, 16] }), keyboard: false,
                                  interactive: false }).addTo(map);
  });
}
function renderAnswer(j, where) {
  S.answer = { json: j, where };
  const box = $('answer');
  box.replaceChildren();
  const h = document.createElement('h2');
  const r = j.record;
  if (j.hit && r) {
    const sw = document.createElement('span');
    sw.className = 'sw';
    sw.style.background = r.colour || '#ccc';
    h.append(sw, document.createTextNode(r.name || `#${r.id}`));
    for (const li of document.querySelectorAll(`#legend li[data-record="${r.id}"], #legendMini li[data-record="${r.id}"]`)) li.classList.add('hit');
  } else h.textContent = t('noGeology');
  box.append(h);
  const dl = document.createElement('dl');
  const row = (k, v) => {
    if (v == null || v === '') return;
    const dt = document.createElement('dt'), dd = document.createElement('dd');
    dt.textContent = k;
    dd.textContent = v;
    dl.append(dt, dd);
  };
  if (j.hit && r) for (const [k, v] of Object.entries(r)) row(k, typeof v === 'object' ? JSON.stringify(v) : String(v));
  row(t('body'), j.body);
  const w = j.world || {};
  if (Number.isFinite(w.x)) row(t('world'), `${V.fmt(w.x)}, ${V.fmt(w.y)}, ${V.fmt(w.z)}`);
  row(t('crs'), w.crs);
  if (w.projected) {
    row(t('easting'), V.fmt(w.projected.easting));
    row(t('northing'), V.fmt(w.projected.northing));
    row(t('zone'), w.projected.zone);
  }
  if (w.geodetic) {
    row(t('lon'), `${w.geodetic.lon.toFixed(7)}°`);
    row(t('lat'), `${w.geodetic.lat.toFixed(7)}°`);
  }
  if (Number.isFinite(w.z)) row(t('elevation'), `${V.fmt(w.z)} m`);
  const along = j.section?.distanceAlong ?? j.distanceAlong;
  if (where === 'section' && S.section && S.section.kind !== 'elevation' && j.section) {
    row(t('distance'), `${V.fmt(S.section.kind === 'line' ? j.section.distanceAlong : j.section.u - S.section.distance0)} m`);
  } else if (where === '3d' && Number.isFinite(along)) row(t('distanceEye'), `${V.fmt(along)} m`);
  else if (where === 'profile' && Number.isFinite(along)) row(t('distance'), `${V.fmt(along)} m`);
  row(t('source'), j.source);
  box.append(dl);
  $('copyAnswer').hidden = false;
}

// ---- boreholes -------------------------------------------------------------------------
function clearBorehole(message = null) {
  S.bh = null;
  const box = $('bh');
  box.replaceChildren();
  const p = document.createElement('p');
  p.className = message ? 'err' : 'hint';
  p.textContent = message || t('bhHint');
  box.append(p);
}
async function borehole(x, y) {
  const gen = S.gen;
  clearBorehole(null);
  $('bh').firstChild.textContent = t('loading');
  showSheet('borehole');
  let j;
  try {
    j = await request(api(`/borehole?x=${x.toFixed(3)}&y=${y.toFixed(3)}`));
  } catch (e) {
    if (gen === S.gen) clearBorehole(t('failedBorehole', e.message));
    return;
  }
  if (gen !== S.gen) return;
  S.bh = j;
  renderBorehole(j, x, y);
}
function renderBorehole(j, x, y) {
  const box = $('bh');
  box.replaceChildren();
  const h = document.createElement('h2');
  h.textContent = t('bhAt', V.fmt(x, 1), V.fmt(y, 1));
  box.append(h);
  const iv = j.intervals || [], cr = j.crossings || [];
  const total = Math.max(1, ...iv.map((i) => i.to_collar_m), ...cr.map((c) => c.depth_collar_m));
  const H = 420, top = 16, W = 360, k = (H - top - 10) / total;
  const svg = svgEl('svg', { id: 'bhLog', viewBox: `0 0 ${W} ${H}`, role: 'img', 'aria-label': t('borehole') });
  const step = V.niceStep(total / 8);
  for (let d = 0; d <= total + 1e-9; d += step) {
    const y = top + d * k;
    svg.append(svgEl('line', { x1: 52, x2: 58, y1: y, y2: y, stroke: '#000' }));
    svg.append(svgEl('text', { x: 50, y: y + 4, 'text-anchor': 'end' }, Math.round(d)));
  }
  svg.append(svgEl('text', { x: 2, y: 10 }, t('depth')));
  for (const i of iv) {
    const y0 = top + i.from_collar_m * k, y1 = top + i.to_collar_m * k;
    svg.append(svgEl('rect', { x: 60, y: y0, width: 50, height: Math.max(1, y1 - y0),
                              fill: i.attributes?.colour || '#ccc', stroke: '#0006' }));
    if (y1 - y0 >= 12) svg.append(svgEl('text', { x: 116, y: (y0 + y1) / 2 + 4 }, i.attributes?.name || i.body));
  }
  for (const c of cr) {
    const y = top + c.depth_collar_m * k;
    svg.append(svgEl('line', { x1: 54, x2: 116, y1: y, y2: y, stroke: '#d00', 'stroke-width': 3 }));
    svg.append(svgEl('text', { x: 300, y: y - 3, 'text-anchor': 'middle', fill: '#d00' }, c.surface));
  }
  box.append(svg);
  const dl = document.createElement('dl');
  const row = (k2, v) => {
    const dt = document.createElement('dt'), dd = document.createElement('dd');
    dt.textContent = k2;
    dd.textContent = v;
    dl.append(dt, dd);
  };
  if (j.collar) row(t('collar'), `${V.fmt(j.collar[0])}, ${V.fmt(j.collar[1])}, ${V.fmt(j.collar[2])}`);
  for (const i of iv)
    row(`${V.fmt(i.from_collar_m, 1)}–${V.fmt(i.to_collar_m, 1)} m`,
        [i.attributes?.name || i.body, i.attributes?.lithology, i.attributes?.age].filter(Boolean).join(' · '));
  row(t('faults'), cr.length ? cr.map((c) => `${c.surface} @ ${V.fmt(c.depth_collar_m, 1)} m`).join('; ') : t('none'));
  box.append(dl);
}
function sectionWorldXY(sec, u) {
  if (sec.kind === 'line') return V.pointAt(sec.pts, u);
  return null;
}

// ---- 3D view ---------------------------------------------------------------------------
function init3d(restore) {
  const [min, max] = [S.model.bounds.min, S.model.bounds.max];
  const centre = V.mul(V.add(min, max), 0.5);
  const radius = 0.5 * Math.hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]);
  const p3 = restore?.p3 || [90, 90, 0], cam = restore?.cam || [135, 35, (radius / Math.tan((20 * Math.PI) / 180)) * 1.05];
  S.three = { centre, radius, az: cam[0], el: cam[1], dist: cam[2], fov: 40 };
  $('plAz').value = p3[0];
  $('plDip').value = p3[1];
  $('plOffset').value = p3[2];
  S.shown3d = S.shownProfile = null;
  $('img3d').removeAttribute('src');
  $('profileImg').removeAttribute('src');
}
function currentPlane() {
  const th = S.three;
  const az = Number($('plAz').value) || 0, dip = Math.min(90, Math.max(0, Number($('plDip').value) || 0));
  const off = Number($('plOffset').value) || 0;
  const base = V.planeFrom(az, dip, th.centre);
  return { n: base.n, d: base.d - off };
}
function camera() {
  const th = S.three;
  return V.orbitCamera(th.centre, th.az, th.el, th.dist, th.fov);
}
const vec = (a) => a.map((x) => +x.toFixed(3)).join(',');
function view3dParams(w, h) {
  const cam = camera();
  return `plane=${V.planeText(currentPlane())}&view=perspective&eye=${vec(cam.eye)}&target=${vec(cam.target)}` +
         `&up=0,0,1&fov=${cam.fov}&size=${w}x${h}&bg=%23eef1f4`;
}
let want3d = null, inflight3d = false;
// Asks for the 3D image (small while dragging, full when released) and the profile of
// the same plane; at most one request of each in flight, the latest wish wins.
function render3d(small) {
  if (!S.model || S.view !== '3d') return;
  const box = $('view3d').getBoundingClientRect(), pbox = $('profileBox').getBoundingClientRect();
  const dpr = Math.min(2, window.devicePixelRatio || 1);
  const sc = small ? 1 / 3 : dpr;
  const w = Math.max(32, Math.min(1280, Math.round(box.width * sc))), h = Math.max(32, Math.min(1280, Math.round(box.height * sc)));
  const pw = Math.max(32, Math.min(1280, Math.round(pbox.width * sc))), ph = Math.max(32, Math.min(1280, Math.round(pbox.height * sc)));
  want3d = { gen: S.gen, small, params: view3dParams(w, h), w, h, plane: currentPlane(), cam: camera(),
             profile: `plane=${V.planeText(currentPlane())}&size=${pw}x${ph}`, pw, ph, t0: performance.now() };
  drawHandles();
  pump3d();
  permalinkSoon();
}
async function pump3d() {
  if (inflight3d || !want3d) return;
  const w = want3d;
  want3d = null;
  inflight3d = true;
  try {
    const [img, prof] = await Promise.allSettled([
      request(api(`/section.${w.small ? 'jpg' : 'png'}?${w.params}`), {}, 'blob'),
      request(api(`/section.png?${w.profile}`), {}, 'blob'),
    ]);
    if (w.gen === S.gen) {
      if (img.status === 'fulfilled' && prof.status === 'fulfilled') {
        await Promise.all([showBlob($('img3d'), img.value), showBlob($('profileImg'), prof.value)]);
        S.shown3d = w;
        clearAnswerIf(['3d', 'profile']);
        drawProfileOverlay();
        markPainted('frame3d', w.t0, { small: w.small });
        if (/3D/.test($('status').textContent) || $('status').dataset.src === '3d') setStatus('');
      } else {
        const e = img.status === 'rejected' ? img.reason : prof.reason;
        setStatus(t('failed3d', e.message), true);
        $('status').dataset.src = '3d';
      }
    }
  } finally {
    inflight3d = false;
    if (want3d) pump3d();
  }
}
function clearAnswerIf(wheres) {
  if (S.answer && wheres.includes(S.answer.where)) clearAnswer();
}
function showBlob(img, blob) {
  return new Promise((resolve) => {
    const old = img.src;
    img.onload = img.onerror = () => { if (old.startsWith('blob:')) URL.revokeObjectURL(old); resolve(); };
    img.src = URL.createObjectURL(blob);
  });
}
function drawHandles() {
  const el = $('view3d'), r = el.getBoundingClientRect();
  const cam = camera(), plane = currentPlane();
  const poly = V.planeBoxPolygon(plane, S.model.bounds.min, S.model.bounds.max);
  const pts = poly.map((p) => V.project(cam, r.width, r.height, p)).filter(Boolean);
  $('planePoly').setAttribute('points', pts.map((p) => p.join(',')).join(' '));
  const mh = $('moveHandle'), rh = $('rotateHandle');
  if (!poly.length) { mh.style.left = `${r.width / 2}px`; mh.style.top = `${r.height / 2}px`; rh.hidden = true; return; }
  rh.hidden = false;
  const c = V.mul(poly.reduce(V.add, [0, 0, 0]), 1 / poly.length);
  const { u } = V.planeBasis(plane.n);
  const clampXY = (p) => [Math.max(26, Math.min(r.width - 26, p[0])), Math.max(26, Math.min(r.height - 26, p[1]))];
  const pc = clampXY(V.project(cam, r.width, r.height, c) || [r.width / 2, r.height / 2]);
  const pr = clampXY(V.project(cam, r.width, r.height, V.add(c, V.mul(u, S.three.radius * 0.45))) || [pc[0] + 60, pc[1]]);
  if (Math.hypot(pr[0] - pc[0], pr[1] - pc[1]) < 56) pr[0] = pc[0] + (pc[0] < r.width - 90 ? 60 : -60);
  S.handles = { pc, pr, c };
  mh.style.left = `${pc[0]}px`; mh.style.top = `${pc[1]}px`;
  rh.style.left = `${pr[0]}px`; rh.style.top = `${pr[1]}px`;
}
function drawProfileOverlay() {
  const svg = $('profileOverlay');
  svg.replaceChildren();
  const { u } = V.planeBasis(currentPlane().n);
  const r = $('profileBox').getBoundingClientRect();
  svg.append(svgEl('text', { x: 6, y: 18, class: 'end' }, V.compass(-u[0], -u[1])));
  svg.append(svgEl('text', { x: r.width - 6, y: 18, 'text-anchor': 'end', class: 'end' }, V.compass(u[0], u[1])));
}
function setup3d() {
  const el = $('view3d');
  const pointers = new Map();
  let drag = null, pinch0 = null, tap = null;
  el.addEventListener('pointerdown', (e) => {
    if (e.target.closest('.handle')) return;
    el.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, [e.clientX, e.clientY]);
    if (pointers.size === 1) { drag = [e.clientX, e.clientY]; tap = { x: e.clientX, y: e.clientY, t: performance.now() }; }
    if (pointers.size === 2) { const [a, b] = [...pointers.values()]; pinch0 = { d: Math.hypot(a[0] - b[0], a[1] - b[1]), dist: S.three.dist }; tap = null; }
  });
  el.addEventListener('pointermove', (e) => {
    if (!pointers.has(e.pointerId)) return;
    pointers.set(e.pointerId, [e.clientX, e.clientY]);
    if (pointers.size === 2 && pinch0) {
      const [a, b] = [...pointers.values()];
      const d = Math.hypot(a[0] - b[0], a[1] - b[1]);
      S.three.dist = Math.max(S.three.radius * 0.3, Math.min(S.three.radius * 20, pinch0.dist * (pinch0.d / Math.max(1, d))));
      render3d(true);
    } else if (drag) {
      const dx = e.clientX - drag[0], dy = e.clientY - drag[1];
      if (tap && Math.hypot(e.clientX - tap.x, e.clientY - tap.y) > 6) tap = null;
      if (tap) return;
      drag = [e.clientX, e.clientY];
      S.three.az = (S.three.az - dx * 0.4 + 360) % 360;
      S.three.el = Math.max(5, Math.min(89, S.three.el + dy * 0.3));
      render3d(true);
    }
  });
  const end = (e) => {
    if (!pointers.has(e.pointerId)) return;
    pointers.delete(e.pointerId);
    if (pointers.size === 0) {
      if (tap && performance.now() - tap.t < 700) query3d(e);
      else render3d(false);
      drag = pinch0 = tap = null;
    }
  };
  el.addEventListener('pointerup', end);
  el.addEventListener('pointercancel', end);
  el.addEventListener('wheel', (e) => {
    e.preventDefault();
    S.three.dist = Math.max(S.three.radius * 0.3, Math.min(S.three.radius * 20, S.three.dist * (e.deltaY > 0 ? 1.1 : 1 / 1.1)));
    render3d(true);
    clearTimeout(S.wheelTimer);
    S.wheelTimer = setTimeout(() => render3d(false), 250);
  }, { passive: false });
  el.addEventListener('keydown', (e) => {
    const k = { ArrowLeft: [-5, 0], ArrowRight: [5, 0], ArrowUp: [0, 5], ArrowDown: [0, -5] }[e.key];
    if (!k || e.target !== el) return;
    e.preventDefault();
    S.three.az = (S.three.az + k[0] + 360) % 360;
    S.three.el = Math.max(5, Math.min(89, S.three.el + k[1]));
    render3dSoon();
  });
  handleDrag($('moveHandle'), (dx, dy) => {
    const cam = camera(), r = el.getBoundingClientRect(), h = S.handles;
    const plane = currentPlane(), L0 = S.three.radius * 0.1;
    const a = V.project(cam, r.width, r.height, h.c), b = V.project(cam, r.width, r.height, V.add(h.c, V.mul(plane.n, L0)));
    if (!a || !b) return;
    const sv = [b[0] - a[0], b[1] - a[1]], len = Math.hypot(sv[0], sv[1]);
    if (len < 2) return;
    const metres = ((dx * sv[0] + dy * sv[1]) / len) * (L0 / len);
    setOffset(Number($('plOffset').value) + metres);
  }, (key) => {
    const d = { ArrowRight: 50, ArrowUp: 50, ArrowLeft: -50, ArrowDown: -50 }[key];
    if (d) setOffset(Number($('plOffset').value) + d);
    return !!d;
  });
  handleDrag($('rotateHandle'), (dx, dy, e) => {
    const r = el.getBoundingClientRect(), pc = S.handles.pc;
    const p1 = [e.clientX - r.left, e.clientY - r.top], p0 = [p1[0] - dx, p1[1] - dy];
    const a0 = Math.atan2(p0[1] - pc[1], p0[0] - pc[0]), a1 = Math.atan2(p1[1] - pc[1], p1[0] - pc[0]);
    let da = ((a1 - a0) * 180) / Math.PI;
    if (da > 180) da -= 360;
    if (da < -180) da += 360;
    setAz(Number($('plAz').value) + da);
  }, (key) => {
    const d = { ArrowRight: 5, ArrowUp: 5, ArrowLeft: -5, ArrowDown: -5 }[key];
    if (d) setAz(Number($('plAz').value) + d);
    return !!d;
  });
  for (const id of ['plAz', 'plDip', 'plOffset']) $(id).addEventListener('input', () => render3dSoon());
  $('resetCam').onclick = () => { init3d({ p3: [Number($('plAz').value), Number($('plDip').value), Number($('plOffset').value)] }); render3d(false); };
  $('profileImg').addEventListener('click', (e) => queryProfile(e));
  new ResizeObserver(() => { if (S.view === '3d') render3dSoon(); }).observe($('view3d'));
}
function setOffset(v) {
  const el = $('plOffset');
  el.value = Math.round(Math.max(Number(el.min), Math.min(Number(el.max), v)));
}
function setAz(v) { $('plAz').value = Math.round(((v % 360) + 360) % 360); }
function render3dSoon() {
  clearTimeout(S.r3timer);
  drawHandles();
  S.r3timer = setTimeout(() => render3d(false), 120);
}
// Drag a handle: small frames while moving, the full image on release; keys for keyboards.
function handleDrag(btn, onMove, onKey) {
  let last = null;
  btn.addEventListener('pointerdown', (e) => { e.stopPropagation(); btn.setPointerCapture(e.pointerId); last = [e.clientX, e.clientY]; });
  btn.addEventListener('pointermove', (e) => {
    if (!last) return;
    const dx = e.clientX - last[0], dy = e.clientY - last[1];
    last = [e.clientX, e.clientY];
    onMove(dx, dy, e);
    render3d(true);
  });
  const end = () => { if (last) { last = null; render3d(false); } };
  btn.addEventListener('pointerup', end);
  btn.addEventListener('pointercancel', end);
  btn.addEventListener('keydown', (e) => { if (onKey(e.key)) { e.preventDefault(); render3dSoon(); } });
}
function query3d(e) {
  const w = S.shown3d;
  if (!w) return;
  const r = $('img3d').getBoundingClientRect();
  const px = Math.floor(((e.clientX - r.left) / r.width) * w.w), py = Math.floor(((e.clientY - r.top) / r.height) * w.h);
  runQuery(api(`/query?${w.params}&px=${px}&py=${py}`), '3d', () => {
    const m = $('qmark3d');
    m.setAttribute('cx', e.clientX - r.left);
    m.setAttribute('cy', e.clientY - r.top);
    m.removeAttribute('hidden');
  });
}
function queryProfile(e) {
  const w = S.shown3d;
  if (!w) return;
  const r = $('profileImg').getBoundingClientRect();
  const px = Math.floor(((e.clientX - r.left) / r.width) * w.pw), py = Math.floor(((e.clientY - r.top) / r.height) * w.ph);
  runQuery(api(`/query?${w.profile}&px=${px}&py=${py}`), 'profile', () => {
    const dot = svgEl('circle', { cx: e.clientX - r.left, cy: e.clientY - r.top, r: 7, class: 'qdot' });
    $('profileOverlay').append(dot);
  });
}

// ---- views, tabs, sheet ----------------------------------------------------------------
function showView(v) {
  S.view = v;
  for (const name of ['plan', 'section', '3d']) {
    const on = name === v;
    $(`tab-${name}`).setAttribute('aria-selected', String(on));
    $(`tab-${name}`).tabIndex = on ? 0 : -1;
    $(`panel-${name}`).hidden = !on;
    $(`tools-${name}`).hidden = !on;
  }
  if (v === 'plan') { planMap.invalidateSize(); drawPlanOverlay(); }
  if (v === 'section') { sectionMap.invalidateSize(); drawSectionOverlay(); }
  if (v === '3d') { drawHandles(); render3d(false); }
  permalinkSoon();
}
function showSheet(name) {
  for (const n of ['answer', 'legend', 'borehole']) {
    $(`st-${n}`).setAttribute('aria-selected', String(n === name));
    $(`st-${n}`).tabIndex = n === name ? 0 : -1;
    $(`sp-${n}`).hidden = n !== name;
  }
}
function tabKeys(container, names, show) {
  container.addEventListener('keydown', (e) => {
    const i = names.findIndex((n) => document.activeElement?.id?.endsWith(`-${n}`));
    if (i < 0 || !['ArrowLeft', 'ArrowRight'].includes(e.key)) return;
    const j = (i + (e.key === 'ArrowRight' ? 1 : names.length - 1)) % names.length;
    show(names[j]);
    container.querySelectorAll('[role=tab]')[j].focus();
  });
}

// ---- permalink -------------------------------------------------------------------------
function permalink() {
  if (!S.model) return '';
  const p = new URLSearchParams();
  p.set('m', S.model.id);
  p.set('v', S.view);
  p.set('lang', language());
  p.set('pz', $('planZ').value);
  const sec = S.section;
  if (sec) {
    p.set('sec', sec.kind === 'line' ? `line:${sec.def.line}` : sec.kind === 'plane' ? `plane:${sec.def.plane}` : `elevation:${sec.def.elevation}`);
    if (sec.def.vx) p.set('vx', sec.def.vx);
    const c = sectionMap.getCenter();
    p.set('sv', `${c.lat.toFixed(4)},${c.lng.toFixed(4)},${sectionMap.getZoom()}`);
  }
  if (S.three) {
    p.set('p3', [$('plAz').value, $('plDip').value, $('plOffset').value].join(','));
    p.set('cam', [S.three.az, S.three.el, S.three.dist].map((x) => +x.toFixed(2)).join(','));
  }
  return `${location.origin}${location.pathname}#${p}`;
}
function permalinkSoon() {
  clearTimeout(S.linkTimer);
  S.linkTimer = setTimeout(() => { if (S.model) history.replaceState(null, '', permalink()); }, 200);
}
function readHash() {
  const p = new URLSearchParams(location.hash.slice(1));
  const nums = (k) => (p.get(k) ? p.get(k).split(',').map(Number) : null);
  return { m: p.get('m'), v: p.get('v'), lang: p.get('lang'), pz: p.get('pz'), sec: p.get('sec'), vx: p.get('vx'),
           sv: nums('sv'), p3: nums('p3'), cam: nums('cam') };
}

async function copyText(text, button, done) {
  try { await navigator.clipboard.writeText(text); } catch (_) {
    const ta = document.createElement('textarea');
    ta.value = text;
    document.body.append(ta);
    ta.select();
    document.execCommand('copy');
    ta.remove();
  }
  const old = button.textContent;
  button.textContent = done;
  setTimeout(() => { button.textContent = old; }, 1500);
}

// ---- start -----------------------------------------------------------------------------
async function main() {
  const h = readHash();
  setLanguage(initialLanguage(h.lang));
  planMap = makeMap('planMap');
  sectionMap = makeMap('sectionMap');
  const planSwallow = onLongPress(planMap, (ll) => { if (S.plan) borehole(uOf(S.plan.grid, ll.lng), vOf(S.plan.grid, ll.lat)); });
  const secSwallow = onLongPress(sectionMap, (ll) => {
    const sec = S.section;
    if (!sec) return;
    const u = uOf(sec.grid, ll.lng), v = vOf(sec.grid, ll.lat);
    if (sec.kind === 'line') { const p = V.pointAt(sec.pts, u); borehole(p[0], p[1]); return; }
    const { u: U, v: Vb } = V.planeBasis(sec.plane?.n || [0, 0, -1]);
    const n = sec.plane?.n || [0, 0, -1], d = sec.plane?.d ?? sec.def.elevation;
    const w = V.add(V.add(V.mul(n, -d), V.mul(U, u)), V.mul(Vb, v));
    borehole(w[0], w[1]);
  });
  planMap.on('click', (e) => { if (!planSwallow()) planClick(e); });
  sectionMap.on('click', (e) => { if (!secSwallow() && S.section) queryMap('section', sectionMap, S.section, e.latlng); });
  // Keyboard: arrows pan (Leaflet), +/- zoom, Enter acts at the centre of the map as a tap would.
  for (const [map, act] of [[planMap, (ll) => planClick({ latlng: ll })],
                            [sectionMap, (ll) => S.section && queryMap('section', sectionMap, S.section, ll)]]) {
    map.getContainer().addEventListener('keydown', (e) => {
      if (e.key === 'Enter' && e.target === map.getContainer()) { e.preventDefault(); act(map.getCenter()); }
    });
  }
  planMap.getContainer().setAttribute('aria-label', 'plan map');
  sectionMap.getContainer().setAttribute('aria-label', 'section map');
  planMap.on('move zoom resize', drawPlanOverlay);
  sectionMap.on('move zoom resize', drawSectionOverlay);
  sectionMap.on('moveend', permalinkSoon);
  for (const b of document.querySelectorAll('[data-mode]')) b.onclick = () => setMode(b.dataset.mode);
  $('undo').onclick = () => { S.points.pop(); drawPlanLine(); };
  $('clear').onclick = () => { S.points = []; drawPlanLine(); };
  $('cut').onclick = () => cut();
  $('planZ').addEventListener('change', () => loadPlan());
  $('azimuth').addEventListener('input', () => drawPlanLine());
  $('model').addEventListener('change', () => loadModel($('model').value));
  $('lang').onclick = () => {
    setLanguage(language() === 'zh' ? 'en' : 'zh', true);
    updateDrawHint();
    if (S.answer) renderAnswer(S.answer.json, S.answer.where); else clearAnswer();
    drawPlanOverlay(); drawSectionOverlay();
    if (S.section) $('sectionTitle').textContent = `${t('sectionOf')}: ${sectionLabel(S.section)}`;
    permalinkSoon();
  };
  $('link').onclick = () => copyText(permalink(), $('link'), t('linkCopied'));
  $('copyAnswer').onclick = () => {
    const text = [...$('answer').querySelectorAll('h2, dt, dd')].map((e) => (e.tagName === 'DT' ? `${e.textContent}: ` : `${e.textContent}\n`)).join('');
    copyText(text, $('copyAnswer'), t('copied'));
  };
  for (const v of ['plan', 'section', '3d']) $(`tab-${v}`).onclick = () => showView(v);
  for (const n of ['answer', 'legend', 'borehole']) $(`st-${n}`).onclick = () => showSheet(n);
  tabKeys(document.querySelector('#tabs .tablist'), ['plan', 'section', '3d'], showView);
  tabKeys(document.querySelector('.sheettabs'), ['answer', 'legend', 'borehole'], showSheet);
  setup3d();
  setMode('line');

  let list;
  try {
    list = await request('/v1/models');
  } catch (e) {
    setStatus(t('failedModel', e.message), true);
    return;
  }
  request('/openapi.json').then((o) => {
    const f = o.paths?.['/v1/models/{id}/section.{format}']?.get?.parameters?.find((p) => p.name === 'format');
    S.pdf = !!f?.schema?.enum?.includes('pdf');
    updateExports();
  }).catch(() => {});
  S.models = list.models;
  for (const m of list.models) { const o = new Option(m.id, m.id); o.title = m.name || m.id; $('model').add(o); }
  if (!list.models.length) { setStatus(t('noModels'), true); return; }
  const first = list.models.find((m) => m.id === h.m) ? h.m : list.models[0].id;
  $('model').value = first;
  if (!(await loadModel(first, h))) return;
  if (h.vx) $('vx').value = h.vx;
  if (h.sec) {
    const i = h.sec.indexOf(':'), kind = h.sec.slice(0, i), val = h.sec.slice(i + 1);
    const def = kind === 'elevation' ? { elevation: Number(val) } : { [kind]: val, vx: Number(h.vx) || 2 };
    if (kind === 'line') {
      const n = val.split(',').map(Number);
      S.points = [];
      for (let k = 0; k + 1 < n.length; k += 2) S.points.push([n[k], n[k + 1]]);
      drawPlanLine();
    }
    await openSection(def, h.sv);
  }
  showView(h.v && ['plan', 'section', '3d'].includes(h.v) ? h.v : S.section ? 'section' : 'plan');
  document.body.dataset.ready = '1';
}

// Test and benchmark hooks (tests/web, bench/web_bench.mjs): read-only views of the state
// plus the same entry points the controls use.
Object.assign(window.geoslice, {
  V,
  setPoints: (pts) => { S.points = pts.map((p) => [p[0], p[1]]); drawPlanLine(); },
  cut: () => cut(),
  openSection,
  maps: () => ({ planMap, sectionMap }),
  render3d,
  permalink,
});
main();
