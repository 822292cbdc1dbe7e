// geoslice web client: requests to this page's origin, the busy indicator and the status line.
import { $, S } from './state.js?v=__GS_BUILD__';

let busyCount = 0;
export function busy(d) {
  busyCount = Math.max(0, busyCount + d);
  $('busy').hidden = busyCount === 0;
  document.body.setAttribute('aria-busy', busyCount > 0 ? 'true' : 'false');
}
class HttpError extends Error {
  constructor(status, message) { super(message); this.status = status; }
}
export async function request(url, opts = {}, as = 'json') {
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
export const api = (path) => `/v1/models/${encodeURIComponent(S.model.id)}${path}`;

export function setStatus(text, isError = false, action = null) {
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
