// geoslice web client: colouring by a block-model property. A model with a block model
// (its <stem>.blocks.json) offers its properties; the one chosen colours the clipping bodies
// of sections, tiles and the 3D view by class (the server's colour=), with the ramp's legend.
import { $, S } from './state.js?v=__GS_BUILD__';
import { api } from './api.js?v=__GS_BUILD__';

const SELECTS = ['blockColour', 'blockColour3d'];
export function fillBlockColours() {
  const props = S.model?.blocks?.properties || [];
  S.blockColour = '';
  for (const id of SELECTS) {
    const sel = $(id);
    sel.replaceChildren(new Option('—', ''));
    for (const p of props) sel.add(new Option(p.unit ? `${p.name} (${p.unit})` : p.name, p.name));
    sel.value = '';
  }
  for (const id of ['blockTools', 'blockTools3d']) $(id).hidden = !props.length;
  showBlockLegend();
}
// The chosen property, from either select (the other follows).
export function setBlockColour(name) {
  S.blockColour = name || '';
  for (const id of SELECTS) $(id).value = S.blockColour;
  showBlockLegend();
}
export const blockParams = () => (S.blockColour ? { colour: S.blockColour } : {});
export const blockQuery = () => (S.blockColour ? `&colour=${encodeURIComponent(S.blockColour)}` : '');
function showBlockLegend() {
  const img = $('blockLegend');
  img.hidden = !S.blockColour;
  if (S.blockColour) img.src = api(`/legend.png?colour=${encodeURIComponent(S.blockColour)}`);
  else img.removeAttribute('src');
}
