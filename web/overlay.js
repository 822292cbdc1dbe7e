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
  if (!horizontal) svg.append(svgEl('text', { x: w - 8, y: 14, 'text-anchor': 'end', id: 'vxLabel' }, t('vxShown', g.exaggeration)));
  const vTop = g.extent.v1;
  for (const end of sec.ends) {
    const p = map.latLngToContainerPoint([latOf(g, vTop), lngOf(g, end.u)]);
    if (end.bend) svg.append(svgEl('line', { x1: p.x, x2: p.x, y1: 0, y2: h - 20, class: 'bend' }));
    const x = Math.max(70, Math.min(w - 16, p.x));
    svg.append(svgEl('text', { x, y: 36, 'text-anchor': 'middle', class: 'end' }, end.label));
  }
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
