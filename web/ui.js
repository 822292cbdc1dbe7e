// geoslice web client: views, tabs, the answer/legend/borehole sheet and copying text.
import { $, S, permalinkSoon } from './state.js?v=__GS_BUILD__';
import { planMap, sectionMap } from './map.js?v=__GS_BUILD__';
import { drawSectionOverlay, drawPlanOverlay } from './overlay.js?v=__GS_BUILD__';
import { render3d, drawHandles } from './view3d.js?v=__GS_BUILD__';

// A <dl> of label/value rows (answers, logs) and its row(label, value); empty values are left out.
export function defList() {
  const dl = document.createElement('dl');
  const row = (k, v) => {
    if (v == null || v === '') return;
    const dt = document.createElement('dt'), dd = document.createElement('dd');
    dt.textContent = k;
    dd.textContent = v;
    dl.append(dt, dd);
  };
  return { dl, row };
}

// ---- views, tabs, sheet ----------------------------------------------------------------
export function showView(v) {
  S.view = v;
  for (const name of ['plan', 'section', '3d']) {
    const on = name === v;
    $(`tab-${name}`).setAttribute('aria-selected', String(on));
    $(`tab-${name}`).tabIndex = on ? 0 : -1;
    $(`panel-${name}`).hidden = !on;
    $(`tools-${name}`).hidden = !on;
  }
  if (v === 'plan') { planMap.invalidateSize(); drawPlanOverlay(); }
  if (v === 'section') { sectionMap.invalidateSize(); drawSectionOverlay(); }
  if (v === '3d') { drawHandles(); render3d(false); }
  $('side').scrollTop = 0;  // a view's own controls first
  closeSheet();
  permalinkSoon();
}
export function showSheet(name) {
  for (const n of ['answer', 'legend', 'borehole']) {
    $(`st-${n}`).setAttribute('aria-selected', String(n === name));
    $(`st-${n}`).tabIndex = n === name ? 0 : -1;
    $(`sp-${n}`).hidden = n !== name;
  }
  revealSheet();
}
// Brings the answer sheet into sight: on a phone held upright it rises as a bottom sheet over
// the map, as map apps do (closed by its ✕, a view change or an error, which the status line
// then shows); elsewhere the side panel scrolls to it. An answer, a borehole or their errors
// are never left below the fold.
const PHONE_UPRIGHT = '(max-width: 699px) and (orientation: portrait)';
export function closeSheet() { document.body.classList.remove('sheet-up'); }
export function revealSheet() {
  if (window.matchMedia(PHONE_UPRIGHT).matches) { document.body.classList.add('sheet-up'); return; }
  const side = $('side'), sheet = $('sheet');
  const dy = sheet.getBoundingClientRect().top - side.getBoundingClientRect().top - 4;
  if (Math.abs(dy) > 8) side.scrollTop += dy;  // the sheet's top at the panel's top
}
export function tabKeys(container, names, show) {
  container.addEventListener('keydown', (e) => {
    const i = names.findIndex((n) => document.activeElement?.id?.endsWith(`-${n}`));
    if (i < 0 || !['ArrowLeft', 'ArrowRight'].includes(e.key)) return;
    const j = (i + (e.key === 'ArrowRight' ? 1 : names.length - 1)) % names.length;
    show(names[j]);
    container.querySelectorAll('[role=tab]')[j].focus();
  });
}

export async function copyText(text, button, done) {
  try { await navigator.clipboard.writeText(text); } catch (_) {
    const ta = document.createElement('textarea');
    ta.value = text;
    document.body.append(ta);
    ta.select();
    document.execCommand('copy');
    ta.remove();
  }
  const old = button.textContent;
  button.textContent = done;
  setTimeout(() => { button.textContent = old; }, 1500);
}
