// geoslice web client: the 3D view with a draggable plane and its profile.
import * as V from './views.js?v=__GS_BUILD__';
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S, markPainted, permalinkSoon } from './state.js?v=__GS_BUILD__';
import { request, api, setStatus } from './api.js?v=__GS_BUILD__';
import { svgEl } from './overlay.js?v=__GS_BUILD__';
import { clearAnswer, runQuery } from './query.js?v=__GS_BUILD__';
import { blockQuery } from './blocks.js?v=__GS_BUILD__';

// ---- 3D view ---------------------------------------------------------------------------
export function init3d(restore) {
  const [min, max] = [S.model.bounds.min, S.model.bounds.max];
  const centre = V.mul(V.add(min, max), 0.5);
  const radius = 0.5 * Math.hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]);
  const p3 = restore?.p3 || [90, 90, 0], cam = restore?.cam || [135, 35, (radius / Math.tan((20 * Math.PI) / 180)) * 1.05];
  S.three = { centre, radius, az: cam[0], el: cam[1], dist: cam[2], fov: 40 };
  $('plAz').value = p3[0];
  $('plDip').value = p3[1];
  setOffset(Number(p3[2]));
  S.shown3d = S.shownProfile = null;
  $('img3d').removeAttribute('src');
  $('profileImg').removeAttribute('src');
  S.hidden3d = new Set(restore?.h3 || []);
  unitList3d();
  S.planes3d = [];
  planeList3d();
}

// ---- more planes -------------------------------------------------------------------------
// The plane being dragged plus up to five kept ones (the server cuts a view by up to six):
// Add plane keeps the current one where it is; their removed sides combine by the cut mode
// (cut=union: what is on the kept side of every plane stays; intersection: what is on the
// removed side of every plane goes). The profile below is the current plane's.
export function addPlane3d() {
  if (S.planes3d.length >= 5) { setStatus(t('maxPlanes'), true); return false; }
  S.planes3d.push({ az: Number($('plAz').value) || 0, dip: Number($('plDip').value) || 0,
                    off: Number($('plOffset').value) || 0, plane: currentPlane() });
  planeList3d();
  render3d(false);
  return true;
}
function planeList3d() {
  const ul = $('planes3d');
  ul.replaceChildren();
  $('cut3dField').hidden = !S.planes3d.length;
  S.planes3d.forEach((p, i) => {
    const li = document.createElement('li');
    const b = document.createElement('button');
    b.type = 'button';
    b.textContent = '✕';
    b.setAttribute('aria-label', t('removePlane', i + 2));
    b.onclick = () => { S.planes3d.splice(i, 1); planeList3d(); render3d(false); };
    li.append(document.createTextNode(t('planeN', i + 2, p.az, p.dip, p.off)), b);
    ul.append(li);
  });
}
const planesParam = () => S.planes3d?.length
  ? S.planes3d.map((p) => `&plane=${V.planeText(p.plane)}`).join('') + `&cut=${$('cut3d').value}` : '';
// The units of the 3D view, each with a box to show or hide it (the server's hide=: the
// picture of the model without them, answered alike by taps).
function unitList3d() {
  const ul = $('units3d');
  ul.replaceChildren();
  const seen = new Set();
  for (const r of S.model.legend || []) {
    if (seen.has(r.id)) continue;
    seen.add(r.id);
    const li = document.createElement('li');
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.checked = !S.hidden3d.has(r.id);
    box.dataset.record = r.id;
    box.onchange = () => {
      if (box.checked) S.hidden3d.delete(r.id); else S.hidden3d.add(r.id);
      render3d(false);
    };
    const sw = document.createElement('span');
    sw.className = 'sw';
    sw.style.background = r.colour;
    label.append(box, sw, document.createTextNode(r.name || `#${r.id}`));
    li.append(label);
    ul.append(li);
  }
}
export function showAllUnits() {
  S.hidden3d = new Set();
  for (const b of $('units3d').querySelectorAll('input')) b.checked = true;
  render3d(false);
}
export function isolateUnits(ids) {
  S.hidden3d = new Set((S.model.legend || []).map((r) => r.id).filter((id) => !ids.includes(id)));
  for (const b of $('units3d').querySelectorAll('input')) b.checked = !S.hidden3d.has(Number(b.dataset.record));
  render3d(false);
}
const hideParam = () => (S.hidden3d?.size ? `&hide=${[...S.hidden3d].sort((a, b) => a - b).join(',')}` : '');
function currentPlane() {
  const th = S.three;
  const az = Number($('plAz').value) || 0, dip = Math.min(90, Math.max(0, Number($('plDip').value) || 0));
  const off = Number($('plOffset').value) || 0;
  const base = V.planeFrom(az, dip, th.centre);
  return { n: base.n, d: base.d - off };
}
function camera() {
  const th = S.three;
  return V.orbitCamera(th.centre, th.az, th.el, th.dist, th.fov);
}
const vec = (a) => a.map((x) => +x.toFixed(3)).join(',');
function view3dParams(w, h) {
  const cam = camera();
  return `plane=${V.planeText(currentPlane())}${planesParam()}&view=perspective&eye=${vec(cam.eye)}&target=${vec(cam.target)}` +
         `&up=0,0,1&fov=${cam.fov}&size=${w}x${h}&bg=%23eef1f4${hideParam()}${blockQuery()}`;
}
let want3d = null, inflight3d = false;
// Asks for the 3D image (small while dragging, full when released) and the profile of
// the same plane; at most one request of each in flight, the latest wish wins.
export function render3d(small) {
  if (!S.model || S.view !== '3d') return;
  const box = $('view3d').getBoundingClientRect(), pbox = $('profileBox').getBoundingClientRect();
  const dpr = Math.min(2, window.devicePixelRatio || 1);
  const sc = small ? 1 / 3 : dpr;
  const w = Math.max(32, Math.min(1280, Math.round(box.width * sc))), h = Math.max(32, Math.min(1280, Math.round(box.height * sc)));
  const pw = Math.max(32, Math.min(1280, Math.round(pbox.width * sc))), ph = Math.max(32, Math.min(1280, Math.round(pbox.height * sc)));
  want3d = { gen: S.gen, small, params: view3dParams(w, h), w, h, plane: currentPlane(), cam: camera(),
             pw, ph, t0: performance.now() };
  want3d.frame = profileFrame(want3d.plane, pw, ph);
  want3d.profile = `plane=${V.planeText(want3d.plane)}&size=${pw}x${ph}&frame=${want3d.frame.map((x) => +x.toFixed(3)).join(',')}${blockQuery()}`;
  drawHandles();
  pump3d();
  permalinkSoon();
}
async function pump3d() {
  if (inflight3d || !want3d) return;
  const w = want3d;
  want3d = null;
  inflight3d = true;
  try {
    const [img, prof] = await Promise.allSettled([
      request(api(`/section.${w.small ? 'jpg' : 'png'}?${w.params}`), {}, 'blob'),
      request(api(`/section.png?${w.profile}`), {}, 'blob'),
    ]);
    if (w.gen === S.gen) {
      if (img.status === 'fulfilled' && prof.status === 'fulfilled') {
        await Promise.all([showBlob($('img3d'), img.value), showBlob($('profileImg'), prof.value)]);
        S.shown3d = w;
        clearAnswerIf(['3d', 'profile']);
        drawProfileOverlay();
        markPainted('frame3d', w.t0, { small: w.small });
        if (/3D/.test($('status').textContent) || $('status').dataset.src === '3d') setStatus('');
      } else {
        const e = img.status === 'rejected' ? img.reason : prof.reason;
        setStatus(t('failed3d', e.message), true);
        $('status').dataset.src = '3d';
      }
    }
  } finally {
    inflight3d = false;
    if (want3d) pump3d();
  }
}
function clearAnswerIf(wheres) {
  if (S.answer && wheres.includes(S.answer.where)) clearAnswer();
}
function showBlob(img, blob) {
  return new Promise((resolve) => {
    const old = img.src;
    img.onload = img.onerror = () => { if (old.startsWith('blob:')) URL.revokeObjectURL(old); resolve(); };
    img.src = URL.createObjectURL(blob);
  });
}
export function drawHandles() {
  const el = $('view3d'), r = el.getBoundingClientRect();
  const cam = camera(), plane = currentPlane();
  const poly = V.planeBoxPolygon(plane, S.model.bounds.min, S.model.bounds.max);
  const pts = poly.map((p) => V.project(cam, r.width, r.height, p)).filter(Boolean);
  $('planePoly').setAttribute('points', pts.map((p) => p.join(',')).join(' '));
  const mh = $('moveHandle'), rh = $('rotateHandle');
  if (!poly.length) { mh.style.left = `${r.width / 2}px`; mh.style.top = `${r.height / 2}px`; rh.hidden = true; return; }
  rh.hidden = false;
  const c = V.mul(poly.reduce(V.add, [0, 0, 0]), 1 / poly.length);
  const { u } = V.planeBasis(plane.n);
  const clampXY = (p) => [Math.max(26, Math.min(r.width - 26, p[0])), Math.max(26, Math.min(r.height - 26, p[1]))];
  const pc = clampXY(V.project(cam, r.width, r.height, c) || [r.width / 2, r.height / 2]);
  const pr = clampXY(V.project(cam, r.width, r.height, V.add(c, V.mul(u, S.three.radius * 0.45))) || [pc[0] + 60, pc[1]]);
  if (Math.hypot(pr[0] - pc[0], pr[1] - pc[1]) < 56) pr[0] = pc[0] + (pc[0] < r.width - 90 ? 60 : -60);
  S.handles = { pc, pr, c };
  mh.style.left = `${pc[0]}px`; mh.style.top = `${pc[1]}px`;
  rh.style.left = `${pr[0]}px`; rh.style.top = `${pr[1]}px`;
}
// The profile's frame in plane metres [u0, u1, v0, v1] (u along the plane, v up it: the
// elevation on a vertical plane), fitted to its pixels: the model box's corners projected,
// 3 % margin, the same metres per pixel both ways (vx 1). Asked for explicitly, so that the
// overlay's axes and scale say exactly what the image shows.
function profileFrame(plane, pw, ph) {
  const { u, v } = V.planeBasis(plane.n);
  const [min, max] = [S.model.bounds.min, S.model.bounds.max];
  let u0 = Infinity, u1 = -Infinity, v0 = Infinity, v1 = -Infinity;
  for (const x of [min[0], max[0]]) for (const y of [min[1], max[1]]) for (const z of [min[2], max[2]]) {
    const a = V.dot([x, y, z], u), b = V.dot([x, y, z], v);
    u0 = Math.min(u0, a); u1 = Math.max(u1, a); v0 = Math.min(v0, b); v1 = Math.max(v1, b);
  }
  const per = 1.03 * Math.max((u1 - u0) / pw, (v1 - v0) / ph), cu = (u0 + u1) / 2, cv = (v0 + v1) / 2;
  return [cu - (per * pw) / 2, cu + (per * pw) / 2, cv - (per * ph) / 2, cv + (per * ph) / 2];
}
// Ends, axes (distance along from the left edge, elevation or distance up the plane), a
// scale bar and the vx of the profile below the 3D view.
function drawProfileOverlay() {
  const svg = $('profileOverlay');
  svg.replaceChildren();
  const w = S.shown3d;
  const { u } = V.planeBasis(currentPlane().n);
  const r = $('profileBox').getBoundingClientRect();
  svg.append(svgEl('text', { x: 6, y: 18, class: 'end' }, V.compass(-u[0], -u[1])));
  svg.append(svgEl('text', { x: r.width - 6, y: 18, 'text-anchor': 'end', class: 'end' }, V.compass(u[0], u[1])));
  if (!w?.frame || r.width < 80 || r.height < 60) return;
  const [u0, u1, v0, v1] = w.frame;
  const X = (uu) => ((uu - u0) / (u1 - u0)) * r.width, Y = (vv) => ((v1 - vv) / (v1 - v0)) * r.height;
  const vertical = Math.abs(w.plane.n[2]) < 1e-9;
  // Up the plane: elevations on a vertical plane; ticks every nice step, inside the left edge.
  const sv = V.niceStep((v1 - v0) / Math.max(2, Math.floor(r.height / 45)));
  for (let vv = Math.ceil(v0 / sv) * sv; vv <= v1; vv += sv) {
    const y = Y(vv);
    if (y < 50 || y > r.height - 30) continue;
    svg.append(svgEl('line', { x1: 0, x2: 6, y1: y, y2: y, stroke: '#000' }));
    svg.append(svgEl('text', { x: 9, y: y + 4, class: 'tick-v', 'data-v': vv }, Math.round(vv)));
  }
  svg.append(svgEl('text', { x: 9, y: 38 }, vertical ? t('elevAxis') : t('upPlaneAxis')));
  // Along: metres from the left edge.
  const su = V.niceStep((u1 - u0) / Math.max(2, Math.floor(r.width / 90)));
  for (let d = su; d < u1 - u0; d += su) {
    const x = X(u0 + d);
    if (x > r.width - 40) continue;
    svg.append(svgEl('line', { x1: x, x2: x, y1: r.height, y2: r.height - 6, stroke: '#000' }));
    svg.append(svgEl('text', { x, y: r.height - 9, 'text-anchor': 'middle', class: 'tick-u', 'data-u': d }, Math.round(d)));
  }
  // A scale bar of a round length near a fifth of the width, and the vx (1: true scale).
  const len = V.niceStep((u1 - u0) / 5), px = X(u0 + len) - X(u0);
  const bx = r.width - px - 12, by = 30;
  svg.append(svgEl('line', { x1: bx, x2: bx + px, y1: by, y2: by, stroke: '#000', 'stroke-width': 3, class: 'scalebar', 'data-m': len }));
  svg.append(svgEl('text', { x: bx + px / 2, y: by + 14, 'text-anchor': 'middle' }, `${len} ${t('metres')} · ${t('vxShown', 1)}`));
}
export function setup3d() {
  const el = $('view3d');
  const pointers = new Map();
  let drag = null, pinch0 = null, tap = null;
  el.addEventListener('pointerdown', (e) => {
    if (e.target.closest('.handle')) return;
    el.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, [e.clientX, e.clientY]);
    if (pointers.size === 1) { drag = [e.clientX, e.clientY]; tap = { x: e.clientX, y: e.clientY, t: performance.now() }; }
    if (pointers.size === 2) { const [a, b] = [...pointers.values()]; pinch0 = { d: Math.hypot(a[0] - b[0], a[1] - b[1]), dist: S.three.dist }; tap = null; }
  });
  el.addEventListener('pointermove', (e) => {
    if (!pointers.has(e.pointerId)) return;
    pointers.set(e.pointerId, [e.clientX, e.clientY]);
    if (pointers.size === 2 && pinch0) {
      const [a, b] = [...pointers.values()];
      const d = Math.hypot(a[0] - b[0], a[1] - b[1]);
      S.three.dist = Math.max(S.three.radius * 0.3, Math.min(S.three.radius * 20, pinch0.dist * (pinch0.d / Math.max(1, d))));
      render3d(true);
    } else if (drag) {
      const dx = e.clientX - drag[0], dy = e.clientY - drag[1];
      if (tap && Math.hypot(e.clientX - tap.x, e.clientY - tap.y) > 6) tap = null;
      if (tap) return;
      drag = [e.clientX, e.clientY];
      S.three.az = (S.three.az - dx * 0.4 + 360) % 360;
      S.three.el = Math.max(5, Math.min(89, S.three.el + dy * 0.3));
      render3d(true);
    }
  });
  const end = (e) => {
    if (!pointers.has(e.pointerId)) return;
    pointers.delete(e.pointerId);
    if (pointers.size === 0) {
      if (tap && performance.now() - tap.t < 700) query3d(e);
      else render3d(false);
      drag = pinch0 = tap = null;
    }
  };
  el.addEventListener('pointerup', end);
  el.addEventListener('pointercancel', end);
  el.addEventListener('wheel', (e) => {
    e.preventDefault();
    S.three.dist = Math.max(S.three.radius * 0.3, Math.min(S.three.radius * 20, S.three.dist * (e.deltaY > 0 ? 1.1 : 1 / 1.1)));
    render3d(true);
    clearTimeout(S.wheelTimer);
    S.wheelTimer = setTimeout(() => render3d(false), 250);
  }, { passive: false });
  el.addEventListener('keydown', (e) => {
    const k = { ArrowLeft: [-5, 0], ArrowRight: [5, 0], ArrowUp: [0, 5], ArrowDown: [0, -5] }[e.key];
    if (!k || e.target !== el) return;
    e.preventDefault();
    S.three.az = (S.three.az + k[0] + 360) % 360;
    S.three.el = Math.max(5, Math.min(89, S.three.el + k[1]));
    render3dSoon();
  });
  handleDrag($('moveHandle'), (dx, dy) => {
    const cam = camera(), r = el.getBoundingClientRect(), h = S.handles;
    const plane = currentPlane(), L0 = S.three.radius * 0.1;
    const a = V.project(cam, r.width, r.height, h.c), b = V.project(cam, r.width, r.height, V.add(h.c, V.mul(plane.n, L0)));
    if (!a || !b) return;
    const sv = [b[0] - a[0], b[1] - a[1]], len = Math.hypot(sv[0], sv[1]);
    if (len < 2) return;
    const metres = ((dx * sv[0] + dy * sv[1]) / len) * (L0 / len);
    setOffset(Number($('plOffset').value) + metres);
  }, (key) => {
    const d = { ArrowRight: 50, ArrowUp: 50, ArrowLeft: -50, ArrowDown: -50 }[key];
    if (d) setOffset(Number($('plOffset').value) + d);
    return !!d;
  });
  handleDrag($('rotateHandle'), (dx, dy, e) => {
    const r = el.getBoundingClientRect(), pc = S.handles.pc;
    const p1 = [e.clientX - r.left, e.clientY - r.top], p0 = [p1[0] - dx, p1[1] - dy];
    const a0 = Math.atan2(p0[1] - pc[1], p0[0] - pc[0]), a1 = Math.atan2(p1[1] - pc[1], p1[0] - pc[0]);
    let da = ((a1 - a0) * 180) / Math.PI;
    if (da > 180) da -= 360;
    if (da < -180) da += 360;
    setAz(Number($('plAz').value) + da);
  }, (key) => {
    const d = { ArrowRight: 5, ArrowUp: 5, ArrowLeft: -5, ArrowDown: -5 }[key];
    if (d) setAz(Number($('plAz').value) + d);
    return !!d;
  });
  // A turned or tilted plane may reach less far: the offset is clamped again. A typed offset
  // is clamped when the field is left (clamping while typing would eat a leading '-').
  for (const id of ['plAz', 'plDip'])
    $(id).addEventListener('input', () => { setOffset(Number($('plOffset').value)); render3dSoon(); });
  $('plOffset').addEventListener('input', () => render3dSoon());
  $('plOffset').addEventListener('change', () => { setOffset(Number($('plOffset').value)); render3dSoon(); });
  $('resetCam').onclick = () => { init3d({ p3: [Number($('plAz').value), Number($('plDip').value), Number($('plOffset').value)] }); render3d(false); };
  $('profileImg').addEventListener('click', (e) => queryProfile(e));
  new ResizeObserver(() => { if (S.view === '3d') render3dSoon(); }).observe($('view3d'));
}
// How far the plane may move from the model's centre along its normal and still cut the
// model: the bounding box's support distance in that direction, less 1% so that a sliver
// stays in view. A drag or a typed offset past it stops there (the server would answer 400).
export function offsetLimit() {
  const { min, max } = S.model.bounds;
  const az = Number($('plAz').value) || 0, dip = Math.min(90, Math.max(0, Number($('plDip').value) || 0));
  const n = V.planeFrom(az, dip, S.three.centre).n;
  const h = 0.5 * (Math.abs(n[0]) * (max[0] - min[0]) + Math.abs(n[1]) * (max[1] - min[1]) + Math.abs(n[2]) * (max[2] - min[2]));
  return Math.floor(0.99 * h);
}
function setOffset(v) {
  const el = $('plOffset'), lim = offsetLimit();
  el.min = -lim;
  el.max = lim;
  el.value = Math.round(Math.max(-lim, Math.min(lim, Number.isFinite(v) ? v : 0)));
}
function setAz(v) {
  $('plAz').value = Math.round(((v % 360) + 360) % 360);
  setOffset(Number($('plOffset').value));  // a turned plane may reach less far
}
function render3dSoon() {
  clearTimeout(S.r3timer);
  drawHandles();
  S.r3timer = setTimeout(() => render3d(false), 120);
}
// Drag a handle: small frames while moving, the full image on release; keys for keyboards.
function handleDrag(btn, onMove, onKey) {
  let last = null;
  btn.addEventListener('pointerdown', (e) => { e.stopPropagation(); btn.setPointerCapture(e.pointerId); last = [e.clientX, e.clientY]; });
  btn.addEventListener('pointermove', (e) => {
    if (!last) return;
    const dx = e.clientX - last[0], dy = e.clientY - last[1];
    last = [e.clientX, e.clientY];
    onMove(dx, dy, e);
    render3d(true);
  });
  const end = () => { if (last) { last = null; render3d(false); } };
  btn.addEventListener('pointerup', end);
  btn.addEventListener('pointercancel', end);
  btn.addEventListener('keydown', (e) => { if (onKey(e.key)) { e.preventDefault(); render3dSoon(); } });
}
function query3d(e) {
  const w = S.shown3d;
  if (!w) return;
  const r = $('img3d').getBoundingClientRect();
  const px = Math.floor(((e.clientX - r.left) / r.width) * w.w), py = Math.floor(((e.clientY - r.top) / r.height) * w.h);
  runQuery(api(`/query?${w.params}&px=${px}&py=${py}`), '3d', () => {
    const m = $('qmark3d');
    m.setAttribute('cx', e.clientX - r.left);
    m.setAttribute('cy', e.clientY - r.top);
    m.removeAttribute('hidden');
  });
}
function queryProfile(e) {
  const w = S.shown3d;
  if (!w) return;
  const r = $('profileImg').getBoundingClientRect();
  const px = Math.floor(((e.clientX - r.left) / r.width) * w.pw), py = Math.floor(((e.clientY - r.top) / r.height) * w.ph);
  runQuery(api(`/query?${w.profile}&px=${px}&py=${py}`), 'profile', () => {
    const dot = svgEl('circle', { cx: e.clientX - r.left, cy: e.clientY - r.top, r: 7, class: 'qdot' });
    $('profileOverlay').append(dot);
  });
}
