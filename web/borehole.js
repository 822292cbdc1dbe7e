// geoslice web client: virtual boreholes and their log.
import * as V from './views.js?v=__GS_BUILD__';
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S } from './state.js?v=__GS_BUILD__';
import { request, api } from './api.js?v=__GS_BUILD__';
import { svgEl } from './overlay.js?v=__GS_BUILD__';
import { showSheet, revealSheet, defList } from './ui.js?v=__GS_BUILD__';

// ---- boreholes -------------------------------------------------------------------------
export function clearBorehole(message = null) {
  S.bh = null;
  const box = $('bh');
  box.replaceChildren();
  const p = document.createElement('p');
  p.className = message ? 'err' : 'hint';
  p.textContent = message || t('bhHint');
  box.append(p);
}
export async function borehole(x, y) {
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
  revealSheet();
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
  const { dl, row } = defList();
  if (j.collar) row(t('collar'), `${V.fmt(j.collar[0])}, ${V.fmt(j.collar[1])}, ${V.fmt(j.collar[2])}`);
  for (const i of iv)
    row(`${V.fmt(i.from_collar_m, 1)}–${V.fmt(i.to_collar_m, 1)} m`,
        [i.attributes?.name || i.body, i.attributes?.lithology, i.attributes?.age].filter(Boolean).join(' · '));
  row(t('faults'), cr.length ? cr.map((c) => `${c.surface} @ ${V.fmt(c.depth_collar_m, 1)} m`).join('; ') : t('none'));
  box.append(dl);
}
