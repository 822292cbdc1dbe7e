// geoslice web client: loading a model, its plan map and legend, and drawing a section's
// trace on the plan.
import * as V from './views.js?v=__GS_BUILD__';
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S, permalinkSoon, markPainted } from './state.js?v=__GS_BUILD__';
import { request, api, setStatus, failure, serverAway, whenServerBack } from './api.js?v=__GS_BUILD__';
import { RetryTiles, lngOf, latOf, uOf, vOf, usefulZoom, gridBounds, planMap } from './map.js?v=__GS_BUILD__';
import { drawPlanOverlay } from './overlay.js?v=__GS_BUILD__';
import { setSection } from './section.js?v=__GS_BUILD__';
import { clearAnswer, queryMap } from './query.js?v=__GS_BUILD__';
import { clearBorehole } from './borehole.js?v=__GS_BUILD__';
import { init3d } from './view3d.js?v=__GS_BUILD__';
import { loadHoles, drawHoles, collarNear, holeLog } from './holes.js?v=__GS_BUILD__';
import { loadSaved } from './saved.js?v=__GS_BUILD__';
import { loadContext, drawContext } from './context.js?v=__GS_BUILD__';
import { fillBlockColours } from './blocks.js?v=__GS_BUILD__';

// ---- model -----------------------------------------------------------------------------
export async function loadModel(id, restore = null) {
  S.modelT0 = performance.now();  // bench/web_bench.mjs: model switch -> its plan painted
  setCutReady(false);
  setStatus(t('loadingModel', id));
  let m;
  try {
    m = await request(`/v1/models/${encodeURIComponent(id)}`);
  } catch (e) {
    setStatus(t('failedModel', e.message), true);
    if (S.model) $('model').value = S.model.id;
    setCutReady(!!S.plan);  // the model on show stays usable
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
  // The old model's plan tiles go with it (else they stay drawn under the new plan).
  if (S.plan?.layer) planMap.removeLayer(S.plan.layer);
  if (gotoMarker) { gotoMarker.remove(); gotoMarker = null; }
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
  fillBlockColours();
  S.three = null;
  init3d(restore);
  // The model's holes, saved sections and context layer come beside its plan.
  const extras = [loadHoles(), loadSaved(), loadContext()];
  await loadPlan();  // clears the loading message once the plan is in
  await Promise.all(extras);
  drawPlanLine();
  return true;
}

// Cut, Undo and Clear act on the plan: off until one is shown.
function setCutReady(ready) {
  for (const id of ['undo', 'clear']) $(id).disabled = !ready;
  if (ready) updateDrawHint(); else $('cut').disabled = true;  // Cut also needs its points
}

export async function loadPlan() {
  const z = Number($('planZ').value);
  if (!$('planZ').checkValidity() || !Number.isFinite(z)) {
    setStatus(`${t('planElevation')}: ${$('planZ').min}..${$('planZ').max}`, true);
    return;
  }
  const gen = S.gen, ask = (S.planAsk = (S.planAsk || 0) + 1);
  let s;
  try {
    s = await request(api('/sections'), { method: 'POST', headers: { 'Content-Type': 'application/json' },
                                            body: JSON.stringify({ elevation: z }) });
  } catch (e) {
    if (gen !== S.gen || ask !== S.planAsk) return;
    setStatus(failure(t('planWhat'), e), true);
    if (serverAway(e)) whenServerBack('plan', () => { if (gen === S.gen && ask === S.planAsk) loadPlan(); });
    return;
  }
  // Another model, or a later elevation asked for meanwhile: this answer is stale.
  if (gen !== S.gen || ask !== S.planAsk) return;
  if (S.plan?.layer) planMap.removeLayer(S.plan.layer);
  const g = s.grid, maxNative = usefulZoom(g);
  const layer = new RetryTiles((z, x, y) => s.tiles.replace('{z}', z).replace('{x}', x).replace('{y}', y),
                               { minNativeZoom: 0, maxNativeZoom: maxNative, bounds: gridBounds(g), tileSize: 256 });
  S.plan = { z, sid: s.sid, grid: g, layer, maxNative, definition: s.definition };
  // The first plan tile on screen (bench/web_bench.mjs: the first usable view, a model switch).
  const t0 = S.modelT0 ?? performance.now();
  S.modelT0 = null;
  layer.once('tilepainted', () => markPainted('planTile', t0));
  planMap.setMaxZoom(maxNative);
  layer.addTo(planMap);
  setCutReady(true);
  if ($('status').dataset.loading) setStatus('');
  if (!S.planFitted) { planMap.fitBounds(gridBounds(g), { padding: [8, 8] }); S.planFitted = true; }
  drawContext();
  drawHoles();
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
export function drawPlanLine() {
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
export function modeAzimuth() {
  return S.mode === 'ns' ? 0 : S.mode === 'ew' ? 90 : Number($('azimuth').value) || 0;
}
export function setMode(mode) {
  S.mode = mode;
  for (const b of document.querySelectorAll('[data-mode]')) b.setAttribute('aria-pressed', String(b.dataset.mode === mode));
  $('azField').hidden = mode !== 'az';
  $('sliceField').hidden = mode !== 'slice';
  $('undo').hidden = $('clear').hidden = mode !== 'line';
  drawPlanLine();
}
export function updateDrawHint() {
  const h = $('drawHint');
  if (S.mode === 'line') {
    // The drawn line's grid length and each leg's grid bearing (CRS metres, grid north).
    let measure = '';
    if (S.points.length >= 2) {
      let total = 0;
      const legs = [];
      for (let i = 1; i < S.points.length; ++i) {
        total += V.legLength(S.points[i - 1], S.points[i]);
        legs.push(`${V.letter(i - 1)}→${V.letter(i)} ${String(Math.round(V.legBearing(S.points[i - 1], S.points[i])) % 360).padStart(3, '0')}°`);
      }
      measure = ` · ${t('lineLength', total.toLocaleString(undefined, { maximumFractionDigits: 1 }))} · ${legs.join(', ')}`;
    }
    h.textContent = `${t('hintLine')} (${t('points', S.points.length)}${measure})`;
  }
  else if (S.mode === 'slice') h.textContent = t('hintSlice');
  else if (S.mode === 'query') h.textContent = t('tapHint');
  else h.textContent = t('hintPoint') + (S.through ? ` (${t('through', V.fmt(S.through[0], 0), V.fmt(S.through[1], 0))})` : '');
  $('cut').disabled = !S.plan || (S.mode === 'line' && S.points.length < 2) ||
                      (['ns', 'ew', 'az'].includes(S.mode) && !S.through);
}
export function planClick(e) {
  if (!S.plan) return;
  // A tap on a drillhole's collar: a line or section point snaps to it (a line through two
  // holes is two taps); in Query mode it opens the hole's log.
  const hole = collarNear(e.latlng);
  const g = S.plan.grid, p = hole ? [hole.collar[0], hole.collar[1]] : [uOf(g, e.latlng.lng), vOf(g, e.latlng.lat)];
  if (S.mode === 'line') { S.points.push(p); drawPlanLine(); permalinkSoon(); }
  else if (['ns', 'ew', 'az'].includes(S.mode)) { S.through = p; drawPlanLine(); }
  else if (hole) holeLog(hole.id);
  else queryMap('plan', planMap, S.plan, e.latlng);
}

// ---- go to a coordinate ------------------------------------------------------------------
// "easting, northing" in the model's CRS (metres), or "lon, lat" (degrees, CGCS2000, for a
// Gauss-Kruger model: converted with the page's own Krüger series): the plan centres there
// and marks the point. A point outside the model's box is refused, naming the box.
let gotoMarker = null;
export function gotoCoordinate(text) {
  const m = /^\s*(-?\d+(?:\.\d*)?)\s*[,;\s]\s*(-?\d+(?:\.\d*)?)\s*$/.exec(text || '');
  if (!m || !S.plan) { setStatus(t('gotoBad'), true); return null; }
  let x = Number(m[1]), y = Number(m[2]);
  if (Math.abs(x) <= 180 && Math.abs(y) <= 90) {
    if (!S.gk) { setStatus(t('gotoNoGk'), true); return null; }
    [x, y] = V.lonLatToGk(S.gk, x, y);
  }
  const [min, max] = [S.model.bounds.min, S.model.bounds.max];
  if (!(x >= min[0] && x <= max[0] && y >= min[1] && y <= max[1])) {
    const r = (v) => Math.round(v).toLocaleString('en-GB').replace(/,/g, ' ');
    setStatus(t('gotoOutside', r(x), r(y), [r(min[0]), r(max[0]), r(min[1]), r(max[1])]), true);
    return null;
  }
  const g = S.plan.grid, ll = [latOf(g, y), lngOf(g, x)];
  planMap.setView(ll, Math.max(planMap.getZoom(), 2), { animate: false });
  if (gotoMarker) gotoMarker.remove();
  gotoMarker = L.circleMarker(ll, { radius: 7, color: '#0b62c4', weight: 3, interactive: false }).addTo(planMap);
  setStatus('');
  S.gotoPoint = [x, y];
  return [x, y];
}

// The device's position (when the user allows it), as a lon/lat go-to: WGS 84 from the
// browser taken as CGCS2000 (the two agree to about a metre, well within a phone's fix).
export function gotoMyPosition() {
  if (!navigator.geolocation) { setStatus(t('locateFailed', 'not available in this browser'), true); return; }
  navigator.geolocation.getCurrentPosition(
    (p) => gotoCoordinate(`${p.coords.longitude}, ${p.coords.latitude}`),
    (e) => setStatus(t('locateFailed', e.message || `error ${e.code}`), true),
    { enableHighAccuracy: true, timeout: 15000, maximumAge: 60000 });
}
