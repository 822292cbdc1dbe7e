// geoslice web client: saved sections. A model's exploration lines (its <stem>.sections.json)
// and the sections saved through the server are listed by name; picking one opens it titled
// so on screen and in the print sheet. The section on show can be saved by name when the
// server keeps saved sections (serve --sections-dir).
import { t } from './i18n.js?v=__GS_BUILD__';
import { $, S } from './state.js?v=__GS_BUILD__';
import { request, api, setStatus } from './api.js?v=__GS_BUILD__';
import { drawPlanLine } from './plan.js?v=__GS_BUILD__';
import { openSection, sectionLabel, updateExports } from './section.js?v=__GS_BUILD__';
import { holeParams } from './holes.js?v=__GS_BUILD__';
import { blockParams } from './blocks.js?v=__GS_BUILD__';

export async function loadSaved(select = null) {
  const model = S.model;
  let j = null;
  try {
    j = await request(api('/saved-sections'));
  } catch (_) { /* an older server, or none: the picker stays hidden */ }
  if (S.model !== model) return;
  S.saved = j;
  for (const w of j?.warnings || []) setStatus(w, true);
  const sel = $('savedSel');
  sel.replaceChildren(new Option(t('savedPick'), ''));
  for (const s of j?.sections || []) {
    const o = new Option(s.source === 'saved' ? `${s.name} ★` : s.name, s.id);
    o.title = s.query;
    sel.add(o);
  }
  $('savedField').hidden = !(j?.sections?.length);
  $('saveRow').hidden = !j?.saving;
  if (select) sel.value = select;
}

// A saved section's query (line=..&vx=.. | plane=..&vx=.. | elevation=..) as a definition.
export function defOf(query) {
  const p = new URLSearchParams(query);
  if (p.has('line')) return { line: p.get('line'), vx: Number(p.get('vx') || 1) };
  if (p.has('plane')) return { plane: p.get('plane'), vx: Number(p.get('vx') || 1) };
  return { elevation: Number(p.get('elevation')) };
}

export async function openSaved(id) {
  const s = S.saved?.sections.find((x) => x.id === id);
  if (!s) return false;
  const def = defOf(s.query);
  if (def.line) {
    // The line on the plan too, as if drawn there.
    const n = def.line.split(',').map(Number);
    S.points = [];
    for (let k = 0; k + 1 < n.length; k += 2) S.points.push([n[k], n[k + 1]]);
    drawPlanLine();
  }
  return openSection({ ...def, ...holeParams(), ...blockParams() }, null, s.name);
}

// Saves the section on show under `name`; the list is loaded again with it selected.
export async function saveSection(name) {
  const sec = S.section;
  name = (name || '').trim();
  if (!sec || !name) { setStatus(t('saveNeedsName'), true); return null; }
  const body = { name };
  if (sec.kind === 'line') Object.assign(body, { line: sec.def.line, vx: sec.def.vx });
  else if (sec.kind === 'plane') Object.assign(body, { plane: sec.def.plane, vx: sec.def.vx });
  else body.elevation = sec.def.elevation;
  let s;
  try {
    s = await request(api('/saved-sections'), { method: 'POST', headers: { 'Content-Type': 'application/json' },
                                                body: JSON.stringify(body) });
  } catch (e) {
    setStatus(t('saveFailed', e.message), true);
    return null;
  }
  sec.title = s.name;
  $('sectionTitle').textContent = `${t('sectionOf')}: ${sectionLabel(sec)}`;
  updateExports();
  setStatus(t('savedAs', s.name));
  await loadSaved(s.id);
  return s;
}
