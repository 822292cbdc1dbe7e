// geoslice web client: the SVG overlays on the maps (axes, scale bar, section ends, grid,
// graticule).
import * as V from './views.js?v=__GS_BUILD__';
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S } from './state.js?v=__GS_BUILD__';
import { lngOf, latOf, uOf, vOf, planMap, sectionMap } from './map.js?v=__GS_BUILD__';

// ---- overlays: axes, scale bar, ends, grid ----------------------------------------------
const svgNS = 'http://www.w3.org/2000/svg';
export function svgEl(tag, attrs, text) {
  const e = document.createElementNS(svgNS, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text != null) e.textContent = text;
  return e;
}
// Labels by priority (attribute data-p, 0 first): the scale bar and section ends, then axis
// titles, then tick values, then graticule values. declutter() keeps a label only where it
// meets no label kept before it and no map control (zoom buttons, attribution), so nothing is
// ever drawn over anything else; what it drops is the least important.
function declutter(svg, map) {
  const host = svg.getBoundingClientRect();
  const kept = [];
  for (const c of map.getContainer().querySelectorAll('.leaflet-control')) {
    const r = c.getBoundingClientRect();
    if (r.width && r.height) kept.push({ x: r.left - host.left, y: r.top - host.top, width: r.width, height: r.height });
  }
  const meets = (a, b) => a.x < b.x + b.width + 2 && b.x < a.x + a.width + 2 && a.y < b.y + b.height + 2 && b.y < a.y + a.height + 2;
  const items = [...svg.querySelectorAll(':scope > [data-p]')].sort((a, b) => a.dataset.p - b.dataset.p);
  for (const el of items) {
    const b = el.getBBox();
    if (kept.some((k) => meets(k, b))) el.remove();
    else kept.push({ x: b.x, y: b.y, width: b.width, height: b.height });
  }
}
function scaleBar(svg, map, g, w, h) {
  const mPerPx = g.size0 / 256 / 2 ** map.getZoom();
  const m = V.niceStep(mPerPx * 80), px = m / mPerPx;
  const x0 = 72, y0 = h - 48;
  const bar = svgEl('g', { id: 'scaleBar', 'data-p': 0 });
  bar.append(svgEl('rect', { x: x0 - 4, y: y0 - 16, width: px + 8, height: 24, class: 'axisbg' }));
  bar.append(svgEl('path', { d: `M${x0},${y0 - 4}v6h${px}v-6`, stroke: '#000', 'stroke-width': 2, fill: 'none' }));
  bar.append(svgEl('text', { x: x0 + px / 2, y: y0 - 6, 'text-anchor': 'middle', id: 'scaleText' },
                   `${m >= 1000 ? m / 1000 + ' km' : m + ' ' + t('metres')}`));
  svg.append(bar);
}
// Ticks and values along the left and bottom edges, without a band behind them (the white
// halo of every label keeps it legible and leaves the model's colours as they are).
function axes(svg, map, g, w, h, leftLabel, bottomLabel, bottomValue) {
  const aw = Math.max(44, 14 + 7.5 * String(Math.round(Math.abs(g.origin.v))).length);
  const mPerPx = g.size0 / 256 / 2 ** map.getZoom();
  const stepV = V.niceStep((mPerPx / g.exaggeration) * 40), stepU = V.niceStep(mPerPx * 90);
  const top = map.containerPointToLatLng([0, 0]), bottom = map.containerPointToLatLng([0, h]);
  const vTop = vOf(g, top.lat), vBottom = vOf(g, bottom.lat);
  for (let v = Math.ceil(vBottom / stepV) * stepV; v <= vTop; v += stepV) {
    const y = map.latLngToContainerPoint([latOf(g, v), 0]).y;
    if (y < 12 || y > h - 24) continue;
    svg.append(svgEl('line', { x1: aw - 6, x2: aw, y1: y, y2: y, stroke: '#000' }));
    svg.append(svgEl('text', { x: aw - 7, y: y + 4, 'text-anchor': 'end', 'data-p': 2 }, Math.round(v)));
  }
  const left = map.containerPointToLatLng([0, 0]), right = map.containerPointToLatLng([w, 0]);
  const uL = uOf(g, left.lng), uR = uOf(g, right.lng);
  for (let u = Math.ceil(bottomValue(uL) / stepU) * stepU; bottomValue(uL) <= u && u <= bottomValue(uR); u += stepU) {
    const x = map.latLngToContainerPoint([0, lngOf(g, u - bottomValue(uL) + uL)]).x;
    if (x < aw + 30 || x > w - 30) continue;
    svg.append(svgEl('line', { x1: x, x2: x, y1: h - 20, y2: h - 14, stroke: '#000' }));
    svg.append(svgEl('text', { x, y: h - 5, 'text-anchor': 'middle', 'data-p': 2 }, Math.round(u)));
  }
  svg.append(svgEl('text', { x: aw + 4, y: 14, class: 'axis-label', 'data-p': 1 }, leftLabel));
  svg.append(svgEl('text', { x: aw + 4, y: h - 24, class: 'axis-label', 'data-p': 1 }, bottomLabel));
}
export function drawSectionOverlay() {
  const svg = $('sectionOverlay');
  svg.replaceChildren();
  const sec = S.section;
  if (!sec || S.view !== 'section' || !sectionMap._loaded) return;
  const map = sectionMap, g = sec.grid, { x: w, y: h } = map.getSize();
  const horizontal = sec.kind === 'elevation';
  axes(svg, map, g, w, h, horizontal ? t('northAxis') : t('elevAxis'), horizontal ? t('eastAxis') : t('distAxis'),
       horizontal ? (u) => u : (u) => u - sec.distance0);
  scaleBar(svg, map, g, w, h);
  if (!horizontal) svg.append(svgEl('text', { x: w - 8, y: 14, 'text-anchor': 'end', id: 'vxLabel', 'data-p': 1 }, t('vxShown', g.exaggeration)));
  const vTop = g.extent.v1;
  // An end in view is labelled above it; one scrolled away is named at the edge it lies
  // beyond, with an arrow, after those in view (so it never hides one that is there).
  for (const end of sec.ends) {
    const p = map.latLngToContainerPoint([latOf(g, vTop), lngOf(g, end.u)]);
    if (end.bend) svg.append(svgEl('line', { x1: p.x, x2: p.x, y1: 0, y2: h - 20, class: 'bend' }));
    const inView = p.x >= 0 && p.x <= w;
    const x = Math.max(70, Math.min(w - 16, p.x));
    const text = inView ? end.label : p.x < 0 ? `‹ ${end.label}` : `${end.label} ›`;
    svg.append(svgEl('text', { x, y: 36, 'text-anchor': inView ? 'middle' : p.x < 0 ? 'start' : 'end', class: 'end',
                              'data-end': end.label, 'data-p': inView ? 0 : 0.5 }, text));
  }
  declutter(svg, map);
}
export function drawPlanOverlay() {
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
      svg.append(svgEl('text', { x: lp.x + 3, y: h - 26, fill: '#0b62c4', 'data-p': 3 }, `${lon.toFixed(3)}°E`));
    }
    for (let lat = Math.ceil(ll0[1] / d) * d; lat <= ll1[1]; lat += d) {
      const a = toPx(ll0[0] - d, lat), b = toPx(ll1[0] + d, lat);
      svg.append(svgEl('line', { x1: a.x, y1: a.y, x2: b.x, y2: b.y, class: 'grat' }));
      svg.append(svgEl('text', { x: w - 4, y: toPx(ll1[0], lat).y - 3, 'text-anchor': 'end', 'data-p': 3 }, `${lat.toFixed(3)}°N`));
    }
  }
  svg.append(svgEl('text', { x: w - 12, y: 36, 'text-anchor': 'end', class: 'end', 'data-p': 1 }, '↑N'));
  declutter(svg, map);
}
