// geoslice web client: the Leaflet maps (plan and section), tiles fetched with retry, the
// tile grid (api/view.hpp TileGrid) and long-press.
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S } from './state.js?v=__GS_BUILD__';
import { busy, checkModelVersion, setStatus, withKey, whenServerBack } from './api.js?v=__GS_BUILD__';

// ---- tiles with retry ------------------------------------------------------------------
// Tiles are fetched (not <img src>) so that a 503 is seen and retried with back-off
// (Retry-After when given); tiles that stay failed are striped and counted in the status.
export const RetryTiles = L.GridLayer.extend({
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
      fetch(url, { headers: withKey() })
        .then((r) => {
          if (r.ok) return r.blob();
          checkModelVersion(r);
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
            // A server that was away: the striped tiles are fetched again once it is back.
            if (retryable) whenServerBack('tiles', retryTiles);
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
  for (const l of [S.section?.layer, S.plan?.layer]) if (l?.failed.size) { l.failed.clear(); l.redraw(); }
  if (/tile/.test($('status').textContent)) setStatus('');
}

// ---- grids (api/view.hpp TileGrid) -------------------------------------------------------
export const lngOf = (g, u) => ((u - g.origin.u) * 256) / g.size0;
export const latOf = (g, v) => ((v - g.origin.v) * g.exaggeration * 256) / g.size0;
export const uOf = (g, lng) => g.origin.u + (lng * g.size0) / 256;
export const vOf = (g, lat) => g.origin.v + (lat * g.size0) / (256 * g.exaggeration);
export function tileFrame(g, z, x, y) {
  const s = g.size0 / 2 ** z, sv = s / g.exaggeration;
  const u0 = g.origin.u + x * s, v1 = g.origin.v - y * sv;
  return `${u0},${u0 + s},${v1 - sv},${v1}`;
}
// Finest zoom that is still useful: about 0.25 m per pixel.
export const usefulZoom = (g) => Math.max(0, Math.min(g.maxZoom, Math.ceil(Math.log2(g.size0 / 256 / 0.25))));
export function gridBounds(g) {
  const e = g.extent;
  return L.latLngBounds([latOf(g, e.v0), lngOf(g, e.u0)], [latOf(g, e.v1), lngOf(g, e.u1)]);
}
// The pixel of the tile grid under a map point, at the zoom whose tiles are on screen.
export function gridPixel(map, sec, latlng) {
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
// The two maps, made once by createMaps() when the page starts (main() in app.js).
export let planMap, sectionMap;
export function createMaps() {
  planMap = makeMap('planMap');
  sectionMap = makeMap('sectionMap');
}

// Long-press (600 ms, < 10 px of movement, one pointer) on a map: fn(latlng). The click
// that ends a long-press is swallowed.
export function onLongPress(map, fn) {
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
