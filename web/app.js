// geoslice web client: plan map, sections as tiles, 3D view with a draggable plane,
// pixel queries, boreholes, export and permalinks. Plain ES modules, no build step; every
// request goes to this page's origin. This module wires the controls to the modules of one
// job each: state.js (S and the permalink), api.js (requests, status line), map.js (Leaflet
// maps, tiles, tile grid), overlay.js (axes, scale, grid), plan.js (model, plan map, legend),
// section.js, query.js, borehole.js, view3d.js, ui.js (views, tabs, sheet). Every import
// carries ?v=__GS_BUILD__ (the server replaces it with the build id), the same URL in every
// module, so a browser never mixes modules of two builds and each module loads once.
import * as V from './views.js?v=__GS_BUILD__';
import { t, setLanguage, initialLanguage, language } from './i18n.js?v=__GS_BUILD__';
import { $, S, permalink, permalinkSoon, readHash } from './state.js?v=__GS_BUILD__';
import { request, setStatus } from './api.js?v=__GS_BUILD__';
import { uOf, vOf, createMaps, planMap, sectionMap, onLongPress } from './map.js?v=__GS_BUILD__';
import { drawSectionOverlay, drawPlanOverlay } from './overlay.js?v=__GS_BUILD__';
import { loadModel, loadPlan, drawPlanLine, setMode, updateDrawHint, planClick, gotoCoordinate, gotoMyPosition } from './plan.js?v=__GS_BUILD__';
import { cut, measureClick, openSection, sectionLabel, setMeasuring, updateExports } from './section.js?v=__GS_BUILD__';
import { clearAnswer, queryMap, renderAnswer } from './query.js?v=__GS_BUILD__';
import { borehole } from './borehole.js?v=__GS_BUILD__';
import { render3d, setup3d, showAllUnits, isolateUnits, addPlane3d } from './view3d.js?v=__GS_BUILD__';
import { showView, showSheet, tabKeys, copyText, closeSheet } from './ui.js?v=__GS_BUILD__';
import { drawHoles, labelsFit, applyHoleParams, holeLog, sectionAlongHole, collarNear } from './holes.js?v=__GS_BUILD__';
import { openSaved, saveSection } from './saved.js?v=__GS_BUILD__';
import { drawContext } from './context.js?v=__GS_BUILD__';
import { setBlockColour } from './blocks.js?v=__GS_BUILD__';

// ---- start -----------------------------------------------------------------------------
async function main() {
  const h = readHash();
  setLanguage(initialLanguage(h.lang));
  createMaps();
  const planSwallow = onLongPress(planMap, (ll) => { if (S.plan) borehole(uOf(S.plan.grid, ll.lng), vOf(S.plan.grid, ll.lat)); });
  const secSwallow = onLongPress(sectionMap, (ll) => {
    const sec = S.section;
    if (!sec) return;
    const u = uOf(sec.grid, ll.lng), v = vOf(sec.grid, ll.lat);
    if (sec.kind === 'line') { const p = V.pointAt(sec.pts, u); borehole(p[0], p[1]); return; }
    const { u: U, v: Vb } = V.planeBasis(sec.plane?.n || [0, 0, -1]);
    const n = sec.plane?.n || [0, 0, -1], d = sec.plane?.d ?? sec.def.elevation;
    const w = V.add(V.add(V.mul(n, -d), V.mul(U, u)), V.mul(Vb, v));
    borehole(w[0], w[1]);
  });
  planMap.on('click', (e) => { if (!planSwallow()) planClick(e); });
  sectionMap.on('click', (e) => {
    if (secSwallow() || !S.section) return;
    if (S.measure?.on) measureClick(e.latlng); else queryMap('section', sectionMap, S.section, e.latlng);
  });
  $('measure').onclick = () => setMeasuring(!S.measure?.on);
  $('gotoBtn').onclick = () => gotoCoordinate($('goto').value);
  $('locate').onclick = () => gotoMyPosition();
  $('goto').addEventListener('keydown', (e) => { if (e.key === 'Enter') { e.preventDefault(); gotoCoordinate($('goto').value); } });
  // Keyboard: arrows pan (Leaflet), +/- zoom, Enter acts at the centre of the map as a tap would.
  for (const [map, act] of [[planMap, (ll) => planClick({ latlng: ll })],
                            [sectionMap, (ll) => S.section && queryMap('section', sectionMap, S.section, ll)]]) {
    map.getContainer().addEventListener('keydown', (e) => {
      if (e.key === 'Enter' && e.target === map.getContainer()) { e.preventDefault(); act(map.getCenter()); }
    });
  }
  planMap.getContainer().setAttribute('aria-label', 'plan map');
  sectionMap.getContainer().setAttribute('aria-label', 'section map');
  planMap.on('move zoom resize', drawPlanOverlay);
  planMap.on('zoomend', labelsFit);
  $('showHoles').onchange = () => drawHoles();
  $('showContext').onchange = () => drawContext();
  $('showAll3d').onclick = () => showAllUnits();
  $('sheetClose').onclick = () => closeSheet();
  $('addPlane3d').onclick = () => addPlane3d();
  $('blockColour').onchange = () => { setBlockColour($('blockColour').value); applyHoleParams(); render3d(false); };
  $('blockColour3d').onchange = () => { setBlockColour($('blockColour3d').value); render3d(false); };
  $('cut3d').onchange = () => render3d(false);
  $('holeWindow').onchange = () => applyHoleParams();
  $('holeColour').onchange = () => applyHoleParams();
  $('savedSel').onchange = () => { if ($('savedSel').value) openSaved($('savedSel').value); };
  $('saveSection').onclick = () => saveSection($('saveName').value);
  $('saveName').addEventListener('keydown', (e) => { if (e.key === 'Enter') { e.preventDefault(); saveSection($('saveName').value); } });
  sectionMap.on('move zoom resize', drawSectionOverlay);
  sectionMap.on('moveend', permalinkSoon);
  for (const b of document.querySelectorAll('[data-mode]')) b.onclick = () => setMode(b.dataset.mode);
  $('undo').onclick = () => { S.points.pop(); drawPlanLine(); };
  $('clear').onclick = () => { S.points = []; drawPlanLine(); };
  $('cut').onclick = () => cut();
  $('planZ').addEventListener('change', () => loadPlan());
  $('azimuth').addEventListener('input', () => drawPlanLine());
  $('model').addEventListener('change', () => loadModel($('model').value));
  $('lang').onclick = () => {
    setLanguage(language() === 'zh' ? 'en' : 'zh', true);
    updateDrawHint();
    if (S.answer) renderAnswer(S.answer.json, S.answer.where); else clearAnswer();
    drawPlanOverlay(); drawSectionOverlay();
    if (S.section) $('sectionTitle').textContent = `${t('sectionOf')}: ${sectionLabel(S.section)}`;
    permalinkSoon();
  };
  $('link').onclick = () => copyText(permalink(), $('link'), t('linkCopied'));
  $('copyAnswer').onclick = () => {
    const text = [...$('answer').querySelectorAll('h2, dt, dd')].map((e) => (e.tagName === 'DT' ? `${e.textContent}: ` : `${e.textContent}\n`)).join('');
    copyText(text, $('copyAnswer'), t('copied'));
  };
  for (const v of ['plan', 'section', '3d']) $(`tab-${v}`).onclick = () => showView(v);
  for (const n of ['answer', 'legend', 'borehole']) $(`st-${n}`).onclick = () => showSheet(n);
  tabKeys(document.querySelector('#tabs .tablist'), ['plan', 'section', '3d'], showView);
  tabKeys(document.querySelector('.sheettabs'), ['answer', 'legend', 'borehole'], showSheet);
  setup3d();
  setMode('line');

  // Until a model's plan is in, say what is loading and offer nothing that needs it (on a
  // slow network the first answers take seconds).
  // (index.html starts in this state, so that it shows before any script has run.)
  $('model').disabled = true;
  $('model').replaceChildren(new Option(t('loading'), ''));
  setStatus(t('loadingModels'));
  let list;
  try {
    list = await request('/v1/models');
  } catch (e) {
    setStatus(t('failedModel', e.message), true);
    return;
  }
  $('model').replaceChildren();
  $('model').disabled = false;
  request('/openapi.json').then((o) => {
    const f = o.paths?.['/v1/models/{id}/section.{format}']?.get?.parameters?.find((p) => p.name === 'format');
    S.pdf = !!f?.schema?.enum?.includes('pdf');
    updateExports();
  }).catch(() => {});
  S.models = list.models;
  for (const m of list.models) { const o = new Option(m.id, m.id); o.title = m.name || m.id; $('model').add(o); }
  if (!list.models.length) { setStatus(t('noModels'), true); return; }
  const first = list.models.find((m) => m.id === h.m) ? h.m : list.models[0].id;
  $('model').value = first;
  if (!(await loadModel(first, h))) return;
  if (h.vx) $('vx').value = h.vx;
  if (h.hw != null && $('holeWindow')) $('holeWindow').value = h.hw;
  if (h.hc && [...$('holeColour').options].some((o) => o.value === h.hc)) $('holeColour').value = h.hc;
  if (h.sec) {
    const i = h.sec.indexOf(':'), kind = h.sec.slice(0, i), val = h.sec.slice(i + 1);
    const def = kind === 'elevation' ? { elevation: Number(val) } : { [kind]: val, vx: Number(h.vx) || 2 };
    if (h.hw != null) def.holes = Number(h.hw);
    if (h.hc) def.holecolour = h.hc;
    if (kind === 'line') {
      const n = val.split(',').map(Number);
      S.points = [];
      for (let k = 0; k + 1 < n.length; k += 2) S.points.push([n[k], n[k + 1]]);
      drawPlanLine();
    }
    await openSection(def, h.sv, h.st);
  }
  showView(h.v && ['plan', 'section', '3d'].includes(h.v) ? h.v : S.section ? 'section' : 'plan');
  document.body.dataset.ready = '1';
}

// Test and benchmark hooks (tests/web, bench/web_bench.mjs): read-only views of the state
// plus the same entry points the controls use.
Object.assign(window.geoslice, {
  V,
  setPoints: (pts) => { S.points = pts.map((p) => [p[0], p[1]]); drawPlanLine(); },
  cut: () => cut(),
  openSection,
  maps: () => ({ planMap, sectionMap }),
  render3d,
  permalink,
  holeLog,
  sectionAlongHole,
  isolateUnits,
  addPlane3d,
  collarNear,
  openSaved,
  saveSection,
});
main();
