// geoslice web client: requests to this page's origin, the API key they carry, the busy
// indicator and the status line.
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S } from './state.js?v=__GS_BUILD__';

// API keys (geoslice serve --keys): a key given once as #key=KEY in the page's address is
// kept in this browser's localStorage and taken out of the address at once, so that it is
// in no permalink, bookmark or history entry; #key= (empty) forgets it. Every request to the
// server then sends it as Authorization: Bearer KEY.
const KEY_STORE = 'geoslice.apiKey';
(function takeKeyFromAddress() {
  const p = new URLSearchParams(location.hash.slice(1));
  if (!p.has('key')) return;
  try {
    if (p.get('key')) localStorage.setItem(KEY_STORE, p.get('key')); else localStorage.removeItem(KEY_STORE);
  } catch (_) { /* storage disabled: the key is not kept */ }
  p.delete('key');
  const rest = p.toString();
  history.replaceState(null, '', `${location.pathname}${location.search}${rest ? `#${rest}` : ''}`);
})();
function apiKey() {
  try { return localStorage.getItem(KEY_STORE) || ''; } catch (_) { return ''; }
}
export const hasApiKey = () => apiKey() !== '';
// `headers` with the API key added (when there is one).
export function withKey(headers = {}) {
  const k = apiKey();
  return k ? { ...headers, Authorization: `Bearer ${k}` } : headers;
}

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
    try { r = await fetch(url, { ...opts, headers: withKey(opts.headers) }); } catch (e) { throw new HttpError(0, e.message || 'network error'); }
    if (!r.ok) {
      let detail = '';
      try { const j = await r.json(); detail = j.detail || j.title || ''; } catch (_) { /* not JSON */ }
      const message = `${r.status} ${detail || r.statusText || 'error'}`.trim();
      throw new HttpError(r.status, r.status === 401 ? t('needKey', message) : message);
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
