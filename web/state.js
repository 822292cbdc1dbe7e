// geoslice web client: the shared state and the permalink. State lives in S; every
// asynchronous answer carries the generation (S.gen) of the scene it was asked for and is
// dropped when that scene is gone, so the picture, the plane and the answer always belong
// to the same request.
import { language } from './i18n.js?v=__GS_BUILD__';
import { sectionMap } from './map.js?v=__GS_BUILD__';

export const $ = (id) => document.getElementById(id);
export const S = {
  models: [], model: null, gk: null, gen: 0, view: 'plan', mode: 'line', points: [], through: null,
  plan: null, section: null, answer: null, queryId: 0, pdf: false,
  three: null, shown3d: null, shownProfile: null, bh: null,
};
const perf = { marks: [] };  // bench/web_bench.mjs reads these
window.geoslice = { S, perf };
export const mark = (name, extra) => perf.marks.push({ name, t: performance.now(), ...extra });
// Marks taken at the next animation frame: the change is on screen.
export const markPainted = (name, t0, extra) => requestAnimationFrame(() => mark(name, { ms: performance.now() - t0, ...extra }));

// ---- permalink -------------------------------------------------------------------------
export function permalink() {
  if (!S.model) return '';
  const p = new URLSearchParams();
  p.set('m', S.model.id);
  p.set('v', S.view);
  p.set('lang', language());
  p.set('pz', $('planZ').value);
  const sec = S.section;
  if (sec) {
    p.set('sec', sec.kind === 'line' ? `line:${sec.def.line}` : sec.kind === 'plane' ? `plane:${sec.def.plane}` : `elevation:${sec.def.elevation}`);
    if (sec.def.vx) p.set('vx', sec.def.vx);
    if (sec.def.holes != null) p.set('hw', sec.def.holes);
    if (sec.def.holecolour) p.set('hc', sec.def.holecolour);
    if (sec.title) p.set('st', sec.title);
    const c = sectionMap.getCenter();
    p.set('sv', `${c.lat.toFixed(4)},${c.lng.toFixed(4)},${sectionMap.getZoom()}`);
  }
  if (S.three) {
    p.set('p3', [$('plAz').value, $('plDip').value, $('plOffset').value].join(','));
    p.set('cam', [S.three.az, S.three.el, S.three.dist].map((x) => +x.toFixed(2)).join(','));
    if (S.hidden3d?.size) p.set('h3', [...S.hidden3d].join(','));
  }
  return `${location.origin}${location.pathname}#${p}`;
}
export function permalinkSoon() {
  clearTimeout(S.linkTimer);
  S.linkTimer = setTimeout(() => { if (S.model) history.replaceState(null, '', permalink()); }, 200);
}
export function readHash() {
  const p = new URLSearchParams(location.hash.slice(1));
  const nums = (k) => (p.get(k) ? p.get(k).split(',').map(Number) : null);
  return { m: p.get('m'), v: p.get('v'), lang: p.get('lang'), pz: p.get('pz'), sec: p.get('sec'), vx: p.get('vx'),
           hw: p.get('hw'), hc: p.get('hc'), st: p.get('st'),
           sv: nums('sv'), p3: nums('p3'), cam: nums('cam'), h3: nums('h3') };
}
