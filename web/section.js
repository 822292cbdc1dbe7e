// geoslice web client: defining a section (line, plane, elevation), showing it as tiles
// and its export links.
import * as V from './views.js?v=__GS_BUILD__';
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S, mark, markPainted, permalinkSoon } from './state.js?v=__GS_BUILD__';
import { request, api, setStatus, hasApiKey, failure, serverAway, whenServerBack } from './api.js?v=__GS_BUILD__';
import { RetryTiles, tileFrame, usefulZoom, gridBounds, sectionMap, uOf, vOf, latOf, lngOf } from './map.js?v=__GS_BUILD__';
import { drawSectionOverlay } from './overlay.js?v=__GS_BUILD__';
import { drawPlanLine, modeAzimuth } from './plan.js?v=__GS_BUILD__';
import { clearAnswer } from './query.js?v=__GS_BUILD__';
import { showView } from './ui.js?v=__GS_BUILD__';
import { holeParams, holeLegend } from './holes.js?v=__GS_BUILD__';
import { blockParams } from './blocks.js?v=__GS_BUILD__';

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
export async function cut() {
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
  await openSection({ ...def, ...holeParams(), ...blockParams() });
}
// Defines the section on the server (plane, elevation) or checks it with a small image
// (polyline: tiles are section images with a frame). Only a section the server accepted
// replaces the one on show. `title`: the section's name (a saved section, "Line 12"), shown
// on screen and given to the print sheet.
export async function openSection(def, view = null, title = null) {
  const gen = S.gen;
  const t0 = performance.now();
  mark('cut', { def });
  let sec;
  try {
    sec = await defineSection(def);
  } catch (e) {
    if (gen !== S.gen) return false;
    setStatus(failure(t('cutWhat'), e), true);
    // The server was away, not the cut wrong: cut again as soon as it answers.
    if (serverAway(e)) whenServerBack('cut', () => { if (gen === S.gen) openSection(def, view, title); });
    return false;
  }
  if (gen !== S.gen) return false;
  sec.t0 = t0;
  sec.title = title || null;
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
    const q = `line=${def.line}&vx=${def.vx}${holeQuery(def)}`;
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
    return { kind: 'elevation', def, q: `elevation=${canon.get('elevation')}${holeQuery(def)}`, grid: g, sid: s.sid,
             ends: [], distance0: 0, url: (z, x, y) => s.tiles.replace('{z}', z).replace('{x}', x).replace('{y}', y) };
  }
  const nums = canon.get('plane').split(',').map(Number);
  const plane = { n: nums.slice(0, 3), d: nums[3] };
  const { u } = V.planeBasis(plane.n);
  const ends = [{ u: g.extent.u0, label: V.compass(-u[0], -u[1]) }, { u: g.extent.u1, label: V.compass(u[0], u[1]) }];
  return { kind: 'plane', def, q: `plane=${canon.get('plane')}&vx=${canon.get('vx')}${holeQuery(def)}`, plane, grid: g, sid: s.sid,
           ends, distance0: g.extent.u0, url: (z, x, y) => s.tiles.replace('{z}', z).replace('{x}', x).replace('{y}', y) };
}
// The drillhole and block-colouring parameters of a definition as a query suffix (the
// server's default hole window when none is given).
function holeQuery(def) {
  return (def.holes != null ? `&holes=${def.holes}` : '') + (def.holecolour ? `&holecolour=${encodeURIComponent(def.holecolour)}` : '') +
         (def.colour ? `&colour=${encodeURIComponent(def.colour)}` : '');
}
export function setSection(sec, view = null) {
  ++S.gen;
  if (S.section?.layer) sectionMap.removeLayer(S.section.layer);
  S.section = sec;
  clearMeasure();
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
  holeLegend(sec);
  drawSectionOverlay();
  drawPlanLine();
  permalinkSoon();
}
export function sectionLabel(sec) {
  let s;
  if (sec.kind === 'line') s = sec.pts.map((_, i) => V.letter(i)).join('-');
  else if (sec.kind === 'elevation') s = `${t('elevation')} ${sec.def.elevation} m`;
  else s = `${sec.ends[0].label}-${sec.ends[1].label}, vx ${sec.grid.exaggeration}`;
  return sec.title ? `${sec.title} (${s})` : s;
}
export function updateExports() {
  const sec = S.section;
  for (const id of ['expPng', 'expSvg', 'expGeojson', 'expDxf', 'expPdf']) {
    const a = $(id);
    if (!sec) { a.removeAttribute('href'); a.setAttribute('aria-disabled', 'true'); continue; }
    a.removeAttribute('aria-disabled');
    const ext = { expPng: 'png', expSvg: 'svg', expGeojson: 'geojson', expDxf: 'dxf', expPdf: 'pdf' }[id];
    // A PDF is a print sheet: its paper sizes it (A3 landscape by default), so no size. The
    // PNG is the same sheet as an image (axes, scale, legend, title block) where the server
    // makes sheets; DXF is the section as drawn (plane metres) for CAD.
    // A named section's sheet carries its name in the title.
    const title = sec.title ? `&title=${encodeURIComponent(sec.title)}` : '';
    const extra = { geojson: '&space=world', pdf: title, dxf: '', png: S.pdf ? `&decorate=1&dpi=150${title}` : '&size=2048x1024',
                    svg: '&size=2048x1024' }[ext];
    a.href = api(`/section.${ext}?${sec.q}${extra}`);
    a.download = `${S.model.id}-section.${ext}`;
    // A link cannot send the API key: with one, the file is fetched and saved from here.
    a.onclick = hasApiKey() ? (e) => { e.preventDefault(); downloadWithKey(a.href, a.download); } : null;
  }
  $('expPdf').hidden = !S.pdf;
}
async function downloadWithKey(url, name) {
  try {
    const blob = await request(url, {}, 'blob');
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = name;
    a.click();
    setTimeout(() => URL.revokeObjectURL(a.href), 10000);
  } catch (e) {
    setStatus(e.message, true);
  }
}

// ---- measuring on a section ------------------------------------------------------------
// With Measure on, two taps on the section give the true distance between them (section
// metres: u along it, v up it, the exaggeration taken out) and, on a vertical section (a
// polyline, or a plane with a horizontal normal), the apparent dip of the line they draw.
let measureLayer = null;
export function clearMeasure() {
  S.measure = { on: S.measure?.on || false, pts: [], result: null };
  if (measureLayer) { measureLayer.remove(); measureLayer = null; }
  $('measureOut').hidden = !S.measure.on;
  $('measureOut').textContent = S.measure.on ? t('measureHint') : '';
}
export function setMeasuring(on) {
  S.measure = { on, pts: [], result: null };
  $('measure').setAttribute('aria-pressed', String(on));
  clearMeasure();
}
export async function measureClick(latlng) {
  const sec = S.section;
  if (!sec) return;
  if (S.measure.pts.length >= 2) clearMeasure();
  const p = [uOf(sec.grid, latlng.lng), vOf(sec.grid, latlng.lat)];
  S.measure.pts.push(p);
  if (!measureLayer) measureLayer = L.layerGroup().addTo(sectionMap);
  L.circleMarker(latlng, { radius: 5, color: '#e00', interactive: false }).addTo(measureLayer);
  if (S.measure.pts.length < 2) return;
  const [a, b] = S.measure.pts;
  L.polyline([[latOf(sec.grid, a[1]), lngOf(sec.grid, a[0])], [latOf(sec.grid, b[1]), lngOf(sec.grid, b[0])]],
             { color: '#e00', weight: 2, dashArray: '6 4', interactive: false }).addTo(measureLayer);
  const vertical = sec.kind === 'line' || (sec.kind === 'plane' && Math.abs(sec.plane?.n?.[2] ?? 1) < 1e-9);
  const m = V.sectionMeasure(a, b, vertical);
  S.measure.result = m;
  $('measureOut').hidden = false;
  const said = t('measured', m.length.toLocaleString(undefined, { maximumFractionDigits: 1 }),
                 m.dip == null ? null : m.dip.toFixed(1));
  $('measureOut').textContent = said;
  // The units the line crosses, and its length in each: the exact section's polygons in the
  // same [u, v] metres (section.geojson, space=plane), fetched once per section.
  const gen = S.gen;
  try {
    if (!sec.regions) {
      const gj = await request(api(`/section.geojson?${sec.q}&space=plane`));
      sec.regions = gj.features.filter((f) => f.geometry?.type === 'MultiPolygon' || f.geometry?.type === 'Polygon')
        .map((f) => ({ record: f.properties.record, name: f.properties.attributes?.name || f.properties.name,
                       rings: f.geometry.type === 'Polygon' ? f.geometry.coordinates : f.geometry.coordinates.flat() }));
    }
    if (gen !== S.gen || S.measure.result !== m) return;
    const stretches = V.lengthsAlong(a, b, sec.regions);
    m.units = stretches;
    const byUnit = new Map();
    for (const s of stretches) byUnit.set(s.name, (byUnit.get(s.name) || 0) + s.length);
    if (byUnit.size)
      $('measureOut').textContent = `${said} · ${t('alongLine')}: ${[...byUnit].map(([n, l]) => `${n} ${l.toFixed(1)} m`).join(', ')}`;
  } catch (_) { /* the distance and dip stay; the units are left out */ }
}
