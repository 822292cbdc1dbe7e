// geoslice web client: the model's drillholes. On the plan: collars, traces and ids (a tap on
// a collar in Query mode opens its log; in Line mode the point snaps to the collar, so a line
// through two holes is two taps). On sections: the server draws the holes within a window
// (holes=W) coloured by an interval column (holecolour=), with their legend here. A hole's
// strip log puts the logged units beside the model's along the same hole, with the share of
// the logged length where they agree; a section along the hole is one button away.
import * as V from './views.js?v=__GS_BUILD__';
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S } from './state.js?v=__GS_BUILD__';
import { request, api, optional } from './api.js?v=__GS_BUILD__';
import { latOf, lngOf, planMap, sectionMap } from './map.js?v=__GS_BUILD__';
import { svgEl } from './overlay.js?v=__GS_BUILD__';
import { showSheet, revealSheet, defList } from './ui.js?v=__GS_BUILD__';
import { openSection } from './section.js?v=__GS_BUILD__';
import { blockParams } from './blocks.js?v=__GS_BUILD__';

// ---- the holes of a model ------------------------------------------------------------------
let layer = null;
export async function loadHoles() {
  const model = S.model;
  S.holes = null;
  drawHoles();
  fillHoleColumns();
  const j = await optional('/drillholes', 'holesNotLoaded');
  if (S.model !== model) return;
  S.holes = j;
  $('holeTools').hidden = $('showHolesField').hidden = !j;
  drawHoles();
  fillHoleColumns();
}

export function drawHoles() {
  if (layer) { layer.remove(); layer = null; }
  if (!S.holes || !S.plan || !$('showHoles').checked) return;
  const g = S.plan.grid, ll = (p) => [latOf(g, p[1]), lngOf(g, p[0])];
  layer = L.layerGroup().addTo(planMap);
  for (const h of S.holes.holes) {
    if (h.trace.length > 1) L.polyline(h.trace.map(ll), { color: '#1b1b1b', weight: 1.5, interactive: false }).addTo(layer);
    L.circleMarker(ll(h.collar), { radius: 4, color: '#000', weight: 2, fillColor: '#fff', fillOpacity: 1,
                                   interactive: false }).addTo(layer);
    L.marker(ll(h.collar), { icon: L.divIcon({ className: 'hole-id', html: '', iconSize: null }), keyboard: false,
                             interactive: false }).addTo(layer).getElement().textContent = h.id;
  }
  labelsFit();
}
// Hole ids only where they do not run into each other: shown when the nearest two collars
// are at least 44 px apart at this zoom.
export function labelsFit() {
  if (!S.holes || !S.plan) return;
  const pts = S.holes.holes.map((h) => planMap.latLngToContainerPoint([latOf(S.plan.grid, h.collar[1]), lngOf(S.plan.grid, h.collar[0])]));
  let closest = Infinity;
  for (let i = 0; i < pts.length; ++i)
    for (let k = i + 1; k < pts.length; ++k) closest = Math.min(closest, pts[i].distanceTo(pts[k]));
  planMap.getContainer().classList.toggle('hole-ids', closest >= 44);
}

// The hole whose collar is within `px` pixels of a tap on the plan, nearest first; null if none.
export function collarNear(latlng, px = 14) {
  if (!S.holes || !S.plan || !$('showHoles').checked) return null;
  const at = planMap.latLngToContainerPoint(latlng);
  let best = null, bestD = px;
  for (const h of S.holes.holes) {
    const p = planMap.latLngToContainerPoint([latOf(S.plan.grid, h.collar[1]), lngOf(S.plan.grid, h.collar[0])]);
    const d = p.distanceTo(at);
    if (d <= bestD) { best = h; bestD = d; }
  }
  return best;
}
export const holeById = (id) => S.holes?.holes.find((h) => h.id === id) || null;

// The window and colouring of holes on sections: view parameters for the section on show.
export function holeParams() {
  if (!S.holes) return {};
  const w = Number($('holeWindow').value);
  const p = { holes: Number.isFinite(w) && w >= 0 ? w : 50 };
  if ($('holeColour').value) p.holecolour = $('holeColour').value;
  return p;
}
function fillHoleColumns() {
  const sel = $('holeColour'), keep = sel.value;
  sel.replaceChildren(new Option(t('holeColourNone'), ''));
  for (const c of S.holes?.columns || []) {
    const o = new Option(`${c.column}${c.unit ? ` (${c.unit})` : ''}`, `${c.table}.${c.column}`);
    sel.add(o);
  }
  if ([...sel.options].some((o) => o.value === keep)) sel.value = keep;
}

// The hole or block colouring controls changed: the section on show again, same view, with
// the new window and colours.
export function applyHoleParams() {
  const sec = S.section;
  if (!sec) return;
  const def = { ...sec.def };
  delete def.holes;
  delete def.holecolour;
  delete def.colour;
  const c = sectionMap.getCenter();
  openSection({ ...def, ...holeParams(), ...blockParams() }, [c.lat, c.lng, sectionMap.getZoom()], sec.title);
}

// The legend of the hole colours on the section on show (GeoJSON's holeLegend).
export async function holeLegend(sec) {
  const ul = $('holeLegend');
  ul.replaceChildren();
  ul.hidden = true;
  if (!sec || !sec.def.holecolour) return;
  const gen = S.gen;
  let gj;
  try { gj = await request(api(`/section.geojson?${sec.q}&space=plane`)); } catch (_) { return; }
  if (gen !== S.gen || !gj.holeLegend) return;
  const cap = document.createElement('li');
  cap.className = 'cap';
  cap.textContent = `${t('holesBy')} ${gj.holeLegend.column}${gj.holeLegend.unit ? ` (${gj.holeLegend.unit})` : ''}`;
  ul.append(cap);
  for (const e of gj.holeLegend.entries) {
    const li = document.createElement('li');
    li.innerHTML = '<span class="sw line"></span><span></span>';
    li.firstChild.style.background = e.colour;
    li.lastChild.textContent = e.label;
    ul.append(li);
  }
  ul.hidden = false;
}

// ---- a hole's strip log ---------------------------------------------------------------------
// The logged units (the code column's intervals, coloured as the model colours that unit) and
// the model's units traced along the same hole, side by side down one depth axis.
const PALETTE = ['#8dd3c7', '#ffffb3', '#bebada', '#fb8072', '#80b1d3', '#fdb462', '#b3de69', '#fccde5'];
function unitColour(name) {
  const r = (S.model.legend || []).find((l) => l.name === name);
  if (r) return r.colour;
  let h = 0;
  for (const c of String(name)) h = (h * 31 + c.codePointAt(0)) >>> 0;
  return PALETTE[h % PALETTE.length];
}
// The share of the logged length (intervals whose code names a unit) where the model has
// that unit too.
export function agreement(logged, model) {
  let total = 0, agreed = 0;
  for (const l of logged) {
    if (!l.unit) continue;
    total += l.to_m - l.from_m;
    for (const m of model)
      if (m.unit === l.unit) agreed += Math.max(0, Math.min(l.to_m, m.to_m) - Math.max(l.from_m, m.from_m));
  }
  return total > 0 ? agreed / total : null;
}
export async function holeLog(id) {
  const model = S.model;
  const box = $('bh');
  box.replaceChildren(Object.assign(document.createElement('p'), { className: 'hint', textContent: t('loading') }));
  showSheet('borehole');
  let j;
  try {
    j = await request(api(`/drillholes/${encodeURIComponent(id)}/log`));
  } catch (e) {
    if (S.model === model) box.replaceChildren(Object.assign(document.createElement('p'), { className: 'err', textContent: t('failedBorehole', e.message) }));
    return null;
  }
  if (S.model !== model) return null;
  const table = j.tables.find((tb) => tb.code_column) || null;
  const logged = table ? table.intervals : [];
  const modelled = j.model.intervals;
  const share = agreement(logged, modelled);
  S.holeLog = { id, share, logged: logged.length, modelled: modelled.length };
  box.replaceChildren();
  const h = document.createElement('h2');
  h.textContent = t('holeTitle', j.hole);
  box.append(h);
  const total = Math.max(1, j.total_depth_m || 0, ...logged.map((i) => i.to_m), ...modelled.map((i) => i.to_m));
  const H = 440, top = 30, W = 360, k = (H - top - 10) / total;
  const svg = svgEl('svg', { id: 'holeLog', viewBox: `0 0 ${W} ${H}`, role: 'img', 'aria-label': t('holeTitle', j.hole) });
  svg.append(svgEl('text', { x: 2, y: 10 }, t('depth')));
  svg.append(svgEl('text', { x: 85, y: 24, 'text-anchor': 'middle' }, t('logged')));
  svg.append(svgEl('text', { x: 165, y: 24, 'text-anchor': 'middle' }, t('modelUnits')));
  const step = V.niceStep(total / 8);
  for (let d = 0; d <= total + 1e-9; d += step) {
    const y = top + d * k;
    svg.append(svgEl('line', { x1: 52, x2: 58, y1: y, y2: y, stroke: '#000' }));
    svg.append(svgEl('text', { x: 50, y: y + 4, 'text-anchor': 'end' }, Math.round(d)));
  }
  const column = (rows, x, label, colour) => {
    for (const r of rows) {
      const y0 = top + r.from_m * k, y1 = top + r.to_m * k;
      const rect = svgEl('rect', { x, y: y0, width: 50, height: Math.max(1, y1 - y0), fill: colour(r), stroke: '#0006' });
      rect.dataset.unit = r.unit ?? '';
      svg.append(rect);
      if (y1 - y0 >= 12 && x > 100) svg.append(svgEl('text', { x: x + 56, y: (y0 + y1) / 2 + 4 }, label(r)));
    }
  };
  const code = table ? table.columns.findIndex((c) => c.name === table.code_column) : -1;
  column(logged, 60, (r) => r.values[code], (r) => (r.unit ? unitColour(r.unit) : '#ddd'));
  column(modelled, 140, (r) => r.unit, (r) => r.colour || unitColour(r.unit));
  for (const c of j.model.crossings) {
    const y = top + c.depth_m * k;
    svg.append(svgEl('line', { x1: 136, x2: 194, y1: y, y2: y, stroke: '#d00', 'stroke-width': 3 }));
  }
  box.append(svg);
  const { dl, row } = defList();
  row(t('collar'), `${V.fmt(j.collar[0])}, ${V.fmt(j.collar[1])}, ${V.fmt(j.collar[2])}`);
  row(t('holeDepth'), `${V.fmt(total, 1)} ${t('metres')}`);
  row(t('agrees'), share == null ? t('noCodes') : `${(100 * share).toFixed(1)} %`);
  for (const r of logged)
    row(`${V.fmt(r.from_m, 1)}–${V.fmt(r.to_m, 1)} ${t('metres')}`, [r.values[code], r.unit && r.unit !== r.values[code] ? r.unit : null].filter(Boolean).join(' · '));
  box.append(dl);
  const b = document.createElement('button');
  b.type = 'button';
  b.id = 'sectionAlongHole';
  b.textContent = t('sectionAlong');
  b.onclick = () => sectionAlongHole(id);
  box.append(b);
  revealSheet();
  return S.holeLog;
}

// A vertical section through the hole's collar along its azimuth (for a vertical hole, along
// the azimuth field), so the hole lies in it.
export async function sectionAlongHole(id) {
  const h = holeById(id);
  if (!h) return false;
  const az = Math.abs(h.dip) > 89.9 ? Number($('azimuth').value) || 90 : h.azimuth;
  const plane = V.planeFrom(az, 90, h.collar);
  return openSection({ plane: V.planeText(plane), vx: Number($('vx').value) || 1, ...holeParams() }, null,
                     t('alongHole', h.id));
}
