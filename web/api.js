// geoslice web client: requests to this page's origin, the API key they carry, the busy
// indicator and the status line.
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S, permalink } from './state.js?v=__GS_BUILD__';

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
      try {
        const j = await r.json();
        detail = j.detail || j.title || '';
        if (j.code === 'model_version') modelVersionChanged();
      } catch (_) { /* not JSON */ }
      const message = `${r.status} ${detail || r.statusText || 'error'}`.trim();
      throw new HttpError(r.status, r.status === 401 ? t('needKey', message) : message);
    }
    return as === 'json' ? await r.json() : await r.blob();
  } finally { busy(-1); }
}
// Every model URL is pinned to the model's content version (version=, from /v1/models): caches may
// keep its answer for ever, and a re-baked model makes new URLs instead of stale pictures.
export const api = (path) => {
  const url = `/v1/models/${encodeURIComponent(S.model.id)}${path}`;
  return S.model.version ? `${url}${url.includes('?') ? '&' : '?'}version=${encodeURIComponent(S.model.version)}` : url;
};

// A model's optional resource (its drillholes, its context layer): the JSON, or null when the
// model has none (404); a sidecar that did not load (409) is said with `what` and is null too.
export async function optional(path, what) {
  const model = S.model;
  try {
    return await request(api(path));
  } catch (e) {
    if (S.model === model && e.status === 409) setStatus(t(what, e.message), true);
    return null;
  }
}

// A pinned URL answered 404 model_version: the model was baked again on the server (a new
// version, new URLs). The page reloads with its permalink (kept in the address), so the same
// view comes back at the new version; once per page.
let reloading = false;
export function modelVersionChanged() {
  if (reloading) return;
  reloading = true;
  setStatus(t('modelChanged'));
  if (S.model) history.replaceState(null, '', permalink());
  setTimeout(() => location.reload(), 600);
}
// For answers read without request() (tiles): a 404 whose problem says model_version.
export function checkModelVersion(r) {
  if (r.status !== 404) return;
  r.clone().json().then((j) => { if (j.code === 'model_version') modelVersionChanged(); }, () => {});
}

// Whether a failed request's cause is the server being away (no answer, 502-504: retried
// when it is back) rather than the request itself (4xx: a verdict, not retried).
export const serverAway = (e) => !e || e.status === 0 || e.status === 502 || e.status === 503 || e.status === 504;
// The message for a failed action: "rejected" only for a verdict on the request; a server
// that did not answer is said so, with "retrying".
export function failure(what, e) {
  if (e && e.status === 0) return t('unreachable', what);
  if (serverAway(e)) return t('serverAway', what, e.message);
  return t('rejected', what, e.message);
}
// Runs `run` once the server answers /healthz again (polled every 2 s while it does not);
// the callbacks registered for one outage run together, the latest per key.
const whenBack = new Map();
let polling = false;
export function whenServerBack(key, run) {
  whenBack.set(key, run);
  if (polling) return;
  polling = true;
  const poll = async () => {
    let ok = false;
    try { ok = (await fetch('/healthz', { cache: 'no-store' })).ok; } catch (_) { ok = false; }
    if (!ok) { setTimeout(poll, 2000); return; }
    polling = false;
    const runs = [...whenBack.values()];
    whenBack.clear();
    for (const r of runs) r();
  };
  setTimeout(poll, 1000);
}

export function setStatus(text, isError = false, action = null) {
  const s = $('status');
  // A new error does not take away the Retry of the one before it.
  const kept = isError && !action ? s.querySelector('button') : null;
  s.textContent = text || '';
  // A loading message is marked, so that what follows the load clears it and nothing else.
  if (text && !isError && /…$/.test(text)) s.dataset.loading = '1'; else delete s.dataset.loading;
  if (kept) s.append(' ', kept);
  s.className = isError ? 'error' : '';
  // An error is read in the status line: a phone's bottom sheet gives way to it (ui.js).
  if (isError) document.body.classList.remove('sheet-up');
  if (action) {
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = action.label;
    b.onclick = action.run;
    s.append(b);
  }
}
