// geoslice web client: pixel queries and the answer sheet.
import * as V from './views.js?v=__GS_BUILD__';
import { t, fieldName, fieldValue } from './i18n.js?v=__GS_BUILD__';
import { $, S, markPainted } from './state.js?v=__GS_BUILD__';
import { request, api } from './api.js?v=__GS_BUILD__';
import { gridPixel } from './map.js?v=__GS_BUILD__';
import { showSheet, revealSheet, defList } from './ui.js?v=__GS_BUILD__';
import { holeLog } from './holes.js?v=__GS_BUILD__';

// ---- queries ---------------------------------------------------------------------------
let marker = null;
export function clearAnswer(message = null) {
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
export async function runQuery(url, where, show) {
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
  revealSheet();
  markPainted('answer', t0, { record: j.record?.id ?? null });
}
export function queryMap(where, map, sec, latlng) {
  const p = gridPixel(map, sec, latlng);
  const q = where === 'plan' ? `elevation=${S.plan.z}` : sec.q;
  const url = api(`/query?${q}&frame=${p.frame}&size=256x256&px=${p.px}&py=${p.py}`);
  runQuery(url, where, () => {
    marker = L.marker(p.centre, { icon: L.divIcon({ className: 'qmark', iconSize: [16, 16] }), keyboard: false,
                                  interactive: false }).addTo(map);
  });
}
// A drawn drillhole under the tap: the hole, the depth along it, and its logged intervals
// there, beside the model's unit at that pixel (above), with a button to its strip log.
function holeAnswer(h, record) {
  const div = document.createElement('div');
  div.className = 'hole-answer';
  const h3 = document.createElement('h3');
  h3.textContent = t('holeTitle', h.id);
  div.append(h3);
  const { dl, row } = defList();
  row(t('holeDepth'), `${V.fmt(h.depth, 1)} ${t('metres')}`);
  row(t('holeOffset'), `${V.fmt(Math.abs(h.offset), 1)} ${t('metres')} ${t(h.side === 'front' ? 'inFront' : 'behind')}`);
  for (const iv of h.intervals || []) {
    const cols = Object.entries(iv.columns).filter(([, v]) => v !== '' && v != null).map(([k, v]) => `${k} ${v}`).join(' · ');
    row(`${V.fmt(iv.from, 1)}–${V.fmt(iv.to, 1)} ${t('metres')}`, cols);
  }
  row(t('modelHere'), record ? record.name || `#${record.id}` : t('noGeology'));
  div.append(dl);
  const b = document.createElement('button');
  b.type = 'button';
  b.className = 'holeLogBtn';
  b.textContent = t('stripLog');
  b.onclick = () => holeLog(h.id);
  div.append(b);
  return div;
}
export function renderAnswer(j, where) {
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
  const { dl, row } = defList();
  if (j.hit && r)
    for (const [k, v] of Object.entries(r)) row(fieldName(k), typeof v === 'object' ? JSON.stringify(v) : String(fieldValue(v)));
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
  row(t('source'), fieldValue(j.source));
  box.append(dl);
  if (j.drillhole) box.append(holeAnswer(j.drillhole, r));
  $('copyAnswer').hidden = false;
}
