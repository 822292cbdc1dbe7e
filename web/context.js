// geoslice web client: the plan's context layer (leases, workings, faults drawn by hand) from
// the model's <stem>.context.geojson, which the server serves in the model's CRS; named
// features are labelled where their labels fit.
import { $, S } from './state.js?v=__GS_BUILD__';
import { optional } from './api.js?v=__GS_BUILD__';
import { latOf, lngOf, planMap } from './map.js?v=__GS_BUILD__';

let layer = null;
export async function loadContext() {
  const model = S.model;
  S.context = null;
  drawContext();
  const j = await optional('/context.geojson', 'contextNotLoaded');
  if (S.model !== model) return;
  S.context = j;
  $('showContextField').hidden = !j;
  drawContext();
}

export function drawContext() {
  if (layer) { layer.remove(); layer = null; }
  if (!S.context || !S.plan || !$('showContext').checked) return;
  const g = S.plan.grid;
  layer = L.geoJSON(S.context, {
    coordsToLatLng: (c) => L.latLng(latOf(g, c[1]), lngOf(g, c[0])),
    style: (f) => ({ color: f.properties?.kind === 'lease' ? '#7b2fbe' : '#c2185b', weight: 2.5, dashArray: f.geometry.type.includes('Polygon') ? '8 5' : null,
                     fill: false, interactive: false }),
    pointToLayer: (f, ll) => L.circleMarker(ll, { radius: 5, color: '#c2185b', weight: 2, fillColor: '#fff', fillOpacity: 1, interactive: false }),
    interactive: false,
  }).addTo(planMap);
  // Labels: a point's beside it, a line's at its middle vertex, a polygon's at its first vertex
  // (inside the map when the outline is a lease around the model).
  for (const f of S.context.features) {
    const name = f.properties?.name;
    if (!name) continue;
    const c = f.geometry.coordinates, type = f.geometry.type;
    const p = type === 'Point' ? c : type === 'LineString' || type === 'MultiPoint' ? c[Math.floor(c.length / 2)]
      : type === 'Polygon' || type === 'MultiLineString' ? c[0][0] : c[0][0][0];
    L.marker([latOf(g, p[1]), lngOf(g, p[0])], { icon: L.divIcon({ className: 'ctx-label', html: '', iconSize: null }),
                                                keyboard: false, interactive: false })
      .addTo(layer).getElement().textContent = name;
  }
}
