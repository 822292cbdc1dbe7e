// Browser tests of the geoslice web client against the real server (CTest label web).
//   node tests/web/web_test.mjs BUILD/cli/geoslice OUT_DIR [filter]
// Debian's chromium through playwright-core. Every request of every page is recorded: any
// request to another origin fails the run. Screenshots of each state go to OUT_DIR.
// Error paths that the real server cannot be made to produce on demand (a 502 from a
// proxy, a refused connection, a 503 on a tile) are injected at the browser's network
// layer with page.route; everything else talks to the real server.
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { startServer, launch, axeSource, PHONE, PHONE_SMALL, PHONE_LANDSCAPE, DESKTOP } from './lib.mjs';

const [binary, outDir, filter] = process.argv.slice(2);
if (!binary || !outDir) {
  console.error('usage: node web_test.mjs GEOSLICE_BINARY OUT_DIR [filter]');
  process.exit(2);
}
fs.mkdirSync(outDir, { recursive: true });

const server = await startServer(binary);
const origin = server.url;
const browser = await launch();
const foreign = [];
const failures = [];
let passed = 0;

function check(cond, what) {
  if (!cond) throw new Error(what);
}

async function newPage(device, opts = {}) {
  const ctx = await browser.newContext({ ...device, ...opts });
  // Zero requests to any other origin: recorded here, and refused so that nothing waits.
  await ctx.route((url) => !url.href.startsWith(origin), (route) => {
    foreign.push(route.request().url());
    return route.abort('blockedbyclient');
  });
  const page = await ctx.newPage();
  page.errors = [];
  page.on('pageerror', (e) => page.errors.push(e.message));
  page.on('request', (r) => {
    const u = r.url();
    if (!u.startsWith(origin) && !u.startsWith('data:') && !u.startsWith('blob:')) foreign.push(u);
  });
  return page;
}
async function open(page, hash = '') {
  await page.goto(`${origin}/${hash}`);
  await page.waitForSelector('body[data-ready="1"]', { timeout: 20000 });
  await settle(page);
}
// Waits until no request of the page is in flight (the loading indicator is off).
async function settle(page, ms = 15000) {
  await page.waitForFunction(() => document.getElementById('busy').hidden, null, { timeout: ms });
  await page.waitForTimeout(50);
}
// A cut the real server refuses (a line of 257 vertices; it takes at most 256), asked for from the plan.
async function cutRefused(page) {
  await page.evaluate(() => {
    const b = window.geoslice.S.model.bounds, pts = [];
    for (let i = 0; i < 257; ++i) pts.push([b.min[0] + (i / 256) * (b.max[0] - b.min[0]), 0.5 * (b.min[1] + b.max[1])]);
    window.geoslice.setPoints(pts);
  });
  await page.locator('#tab-plan').click();
  await page.locator('#cut').click();
}
// A one-finger touch drag through CDP from `from`, `steps` moves of `step` px, `pause` ms
// apart; then waits for the 3D view's full frame.
async function touchDrag(page, cdp, from, step, steps, pause) {
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ x: from[0], y: from[1] }] });
  for (let i = 1; i <= steps; ++i) {
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: [{ x: from[0] + step[0] * i, y: from[1] + step[1] * i }] });
    await page.waitForTimeout(pause);
  }
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
  await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small, null, { timeout: 30000 });
  await settle(page);
}
const shot = (page, name) => page.screenshot({ path: path.join(outDir, `${name}.png`) });
const state = (page, fn) => page.evaluate(fn);

// A tap on a map: a phone's bottom sheet from the answer before is put away first, as a user
// swipes it down to tap what it covers.
async function tap(page, x, y) {
  if (await page.evaluate(() => document.body.classList.contains('sheet-up'))) await page.locator('#sheetClose').click();
  const touch = page.context()._options?.hasTouch;
  if (touch) await page.touchscreen.tap(x, y);
  else await page.mouse.click(x, y);
}
async function longPress(page, x, y) {
  const touch = page.context()._options?.hasTouch;
  if (touch) {
    const cdp = await page.context().newCDPSession(page);
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ x, y }] });
    await page.waitForTimeout(900);
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
  } else {
    await page.mouse.move(x, y);
    await page.mouse.down();
    await page.waitForTimeout(900);
    await page.mouse.up();
  }
}
async function box(page, selector) {
  const b = await page.locator(selector).first().boundingBox();
  check(b, `${selector} has no box`);
  return b;
}
// A point of the plan map in world coordinates -> page pixels.
async function planPoint(page, x, y) {
  return page.evaluate(([x, y]) => {
    const { planMap } = window.geoslice.maps();
    const g = window.geoslice.S.plan.grid;
    const ll = [((y - g.origin.v) * 256) / g.size0, ((x - g.origin.u) * 256) / g.size0];
    const p = planMap.latLngToContainerPoint(ll);
    const r = planMap.getContainer().getBoundingClientRect();
    return [r.left + p.x, r.top + p.y];
  }, [x, y]);
}
async function bounds(page) {
  return page.evaluate(() => window.geoslice.S.model.bounds);
}

// Every visible control: not covered (elementFromPoint at its centre is the control) and,
// on touch layouts, at least 44 x 44 CSS pixels.
async function controlsUncovered(page, touch) {
  return page.evaluate((touch) => {
    const sel = 'button, select, input, a[href], [role=tab], .leaflet-control a';
    const bad = [];
    for (const el of document.querySelectorAll(sel)) {
      if (!el.checkVisibility?.() || el.closest('[hidden]')) continue;
      el.scrollIntoView({ block: 'nearest', inline: 'nearest' });
      const r = el.getBoundingClientRect();
      if (r.width === 0 || r.height === 0) continue;
      const name = `${el.tagName.toLowerCase()}#${el.id || ''}.${el.className || ''}[${(el.textContent || el.getAttribute('aria-label') || '').trim().slice(0, 20)}]`;
      const cx = r.left + r.width / 2, cy = r.top + r.height / 2;
      if (cx < 0 || cy < 0 || cx > innerWidth || cy > innerHeight) { bad.push(`${name} off screen`); continue; }
      const hit = document.elementFromPoint(cx, cy);
      const label = el.closest('label');
      if (!(hit === el || el.contains(hit) || (label && label.contains(hit)))) bad.push(`${name} covered by ${hit?.tagName}#${hit?.id}.${hit?.className}`);
      if (touch && (r.width < 43.5 || r.height < 43.5)) bad.push(`${name} is ${r.width.toFixed(0)}x${r.height.toFixed(0)}`);
    }
    return bad;
  }, touch);
}
async function axe(page) {
  await page.addScriptTag({ content: axeSource });
  const r = await page.evaluate(async () => {
    const res = await window.axe.run(document, { resultTypes: ['violations'] });
    return res.violations.map((v) => ({ id: v.id, impact: v.impact, nodes: v.nodes.length, target: v.nodes[0]?.target }));
  });
  return r;
}
async function cutLine(page, fractions) {
  const b = await bounds(page);
  await page.locator('[data-mode="line"]').click();
  await page.locator('#clear').click();
  for (const [fx, fy] of fractions) {
    const [x, y] = await planPoint(page, b.min[0] + fx * (b.max[0] - b.min[0]), b.min[1] + fy * (b.max[1] - b.min[1]));
    await tap(page, x, y);
  }
  await page.locator('#cut').click();
  await page.waitForFunction(() => window.geoslice.S.section && window.geoslice.perf.marks.some((m) => m.name === 'firstTile'), null, { timeout: 20000 });
  await settle(page);
}
// The colour of the section image under page pixel (x, y): the 5x5 neighbourhood of the
// tile pixel there, and whether it is uniform (away from anti-aliased edges).
async function pixelUnder(page, x, y) {
  return page.evaluate(([x, y]) => {
    // Tiles take no pointer events: the loaded tile of the zoom on show under (x, y).
    const sec = window.geoslice.S.section;
    const z = Math.max(0, Math.min(sec.maxNative, Math.round(window.geoslice.maps().sectionMap.getZoom())));
    const img = Object.values(sec.layer._tiles).map((t) => t.coords.z === z && t.el).find((e) => {
      if (!e || !e.complete || !e.naturalWidth) return false;
      const r = e.getBoundingClientRect();
      return r.left <= x && x < r.right && r.top <= y && y < r.bottom;
    });
    if (!img) return null;
    const r = img.getBoundingClientRect();
    const ix = Math.floor(((x - r.left) / r.width) * img.naturalWidth), iy = Math.floor(((y - r.top) / r.height) * img.naturalHeight);
    const c = document.createElement('canvas');
    c.width = img.naturalWidth; c.height = img.naturalHeight;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const d = g.getImageData(Math.max(0, ix - 2), Math.max(0, iy - 2), 5, 5).data;
    let uniform = true;
    for (let i = 4; i < d.length; i += 4) for (let k = 0; k < 4; ++k) if (d[i + k] !== d[k]) uniform = false;
    const p = g.getImageData(ix, iy, 1, 1).data;
    return { rgba: [...p], uniform };
  }, [x, y]);
}
const hex = (h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16));

const tests = {
  async offline_and_layout_phone() {
    for (const [name, dev] of [['phone-390', PHONE], ['phone-360', PHONE_SMALL], ['phone-landscape', PHONE_LANDSCAPE], ['desktop', DESKTOP]]) {
      const page = await newPage(dev, { locale: 'en-GB' });
      await open(page);
      const touch = !!dev.hasTouch;
      await shot(page, `${name}-plan`);
      let bad = await controlsUncovered(page, touch);
      check(bad.length === 0, `${name} plan: ${bad.join('; ')}`);
      await cutLine(page, [[0.15, 0.3], [0.5, 0.6], [0.85, 0.4]]);
      await shot(page, `${name}-section`);
      bad = await controlsUncovered(page, touch);
      check(bad.length === 0, `${name} section: ${bad.join('; ')}`);
      await page.locator('#tab-3d').click();
      await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small, null, { timeout: 30000 });
      await settle(page);
      await shot(page, `${name}-3d`);
      bad = await controlsUncovered(page, touch);
      check(bad.length === 0, `${name} 3d: ${bad.join('; ')}`);
      check(page.errors.length === 0, `page errors: ${page.errors.join('; ')}`);
      await page.context().close();
    }
  },

  // Labels over labels (issue 27 item 6): "Easting (m)" under "105.020°E", the scale bar over
  // "Distance (m)", the zoom buttons over 30.600°N, end A pinned beside B once scrolled away,
  // and a translucent band over the model's western part. On a desktop and a phone, on the
  // plan at three zooms and on a section before and after end A scrolls away: no label's box
  // meets another's or a map control's, no overlay rectangle covers 5 % of the map, and an
  // end out of view is named at the edge it lies beyond.
  async overlay_labels_never_overlap() {
    const clashes = (page, svgId, mapId) => page.evaluate(([svgId, mapId]) => {
      const svg = document.getElementById(svgId), host = svg.getBoundingClientRect();
      const boxes = [];
      for (const el of svg.querySelectorAll(':scope > text, :scope > g')) {
        const b = el.getBBox();
        if (b.width && b.height) boxes.push({ what: el.textContent.trim(), x: b.x, y: b.y, w: b.width, h: b.height });
      }
      for (const c of document.querySelectorAll(`#${mapId} .leaflet-control`)) {
        const r = c.getBoundingClientRect();
        if (r.width && r.height) boxes.push({ what: `control ${c.className.split(' ').pop()}`, x: r.left - host.left, y: r.top - host.top, w: r.width, h: r.height });
      }
      const bad = [];
      for (let i = 0; i < boxes.length; ++i)
        for (let j = i + 1; j < boxes.length; ++j) {
          const a = boxes[i], b = boxes[j];
          if (a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h) bad.push(`'${a.what}' meets '${b.what}'`);
        }
      const bands = [...svg.querySelectorAll('rect')].filter((r) => { const b = r.getBBox(); return b.width * b.height > 0.05 * host.width * host.height; });
      return { bad, bands: bands.length, labels: boxes.length, ends: [...svg.querySelectorAll('text[data-end]')].map((e) => e.textContent) };
    }, [svgId, mapId]);
    for (const [name, dev] of [['desktop', DESKTOP], ['phone', PHONE]]) {
      const page = await newPage(dev, { locale: 'en-GB' });
      await open(page);
      for (const dz of [0, 1, 2]) {
        if (dz) {
          await page.evaluate(() => { const m = window.geoslice.maps().planMap; m.setZoom(m.getZoom() + 1, { animate: false }); });
          await settle(page);
        }
        const r = await clashes(page, 'planOverlay', 'planMap');
        check(r.labels > 5, `${name} plan +${dz}: only ${r.labels} labels`);
        check(r.bad.length === 0, `${name} plan +${dz}: ${r.bad.join('; ')}`);
        check(r.bands === 0, `${name} plan +${dz}: ${r.bands} overlay rectangles cover over 5 % of the map`);
      }
      await open(page);  // the plan as it starts, so that the cut's taps land on the model
      await cutLine(page, [[0.15, 0.5], [0.85, 0.5]]);
      let r = await clashes(page, 'sectionOverlay', 'sectionMap');
      check(r.bad.length === 0, `${name} section: ${r.bad.join('; ')}`);
      check(r.bands === 0, `${name} section: ${r.bands} overlay rectangles cover over 5 % of the map`);
      check(r.ends.includes('A') && r.ends.includes('B'), `${name} section: ends ${r.ends}`);
      // Zoom in on end B so that A scrolls away to the left.
      await page.evaluate(() => {
        const { sectionMap } = window.geoslice.maps();
        sectionMap.setZoom(sectionMap.getZoom() + 2, { animate: false });
        sectionMap.panBy([sectionMap.getSize().x * 1.5, 0], { animate: false });
      });
      await settle(page);
      r = await clashes(page, 'sectionOverlay', 'sectionMap');
      await shot(page, `${name}-section-end-away`);
      check(r.bad.length === 0, `${name} section, A away: ${r.bad.join('; ')}`);
      check(!r.ends.includes('A'), `${name} section, A away: still labelled in place (${r.ends})`);
      check(r.ends.some((e) => e.includes('A') && /[‹›]/.test(e)) || r.ends.length < 2, `${name} section, A away: ${r.ends}`);
      check(page.errors.length === 0, `page errors: ${page.errors.join('; ')}`);
      await page.context().close();
    }
  },

  async accessibility_axe() {
    const page = await newPage(PHONE);
    await open(page);
    const all = [];
    all.push(...(await axe(page)).map((v) => ({ ...v, view: 'plan' })));
    await cutLine(page, [[0.2, 0.5], [0.8, 0.5]]);
    const [cx, cy] = await page.evaluate(() => { const r = document.getElementById('sectionMap').getBoundingClientRect(); return [r.left + r.width / 2, r.top + r.height / 2]; });
    await tap(page, cx, cy);
    await settle(page);
    all.push(...(await axe(page)).map((v) => ({ ...v, view: 'section+answer' })));
    await page.locator('#tab-3d').click();
    await page.waitForFunction(() => window.geoslice.S.shown3d, null, { timeout: 30000 });
    await settle(page);
    all.push(...(await axe(page)).map((v) => ({ ...v, view: '3d' })));
    await page.locator('#st-legend').click();
    all.push(...(await axe(page)).map((v) => ({ ...v, view: 'legend' })));
    fs.writeFileSync(path.join(outDir, 'axe.json'), JSON.stringify(all, null, 1));
    const severe = all.filter((v) => v.impact === 'critical' || v.impact === 'serious');
    console.log(`axe-core: ${all.length} violations in 4 states, ${severe.length} critical/serious` +
                (all.length ? ` (${[...new Set(all.map((v) => `${v.id}:${v.impact}`))].join(', ')})` : ''));
    check(severe.length === 0, `axe critical/serious: ${JSON.stringify(severe)}`);
    await page.context().close();
  },

  // On phones nothing a user waits for lands below the fold: Cut before any scrolling, the
  // answer of a tap, an error in the status line, and the 3D plane's fields.
  async results_in_view_on_phones() {
    const inView = (page, sel) => page.evaluate((sel) => {
      const el = document.querySelector(sel);
      if (!el || !el.checkVisibility?.()) return `${sel} not shown`;
      const r = el.getBoundingClientRect();
      return r.top >= 0 && r.left >= 0 && r.top + Math.min(r.height, 40) <= innerHeight && r.right <= innerWidth + 1 ? '' :
        `${sel} at ${r.left | 0},${r.top | 0} ${r.width | 0}x${r.height | 0} outside ${innerWidth}x${innerHeight}`;
    }, sel);
    for (const [name, dev] of [['390x844', PHONE], ['360x740', PHONE_SMALL], ['844x390', PHONE_LANDSCAPE]]) {
      const page = await newPage(dev, { locale: 'en-GB' });
      await open(page);
      let bad = await inView(page, '#cut');
      check(!bad, `${name}: Cut in sight: ${bad}`);
      await cutLine(page, [[0.15, 0.3], [0.85, 0.6]]);
      const m = await box(page, '#sectionMap');
      await tap(page, m.x + m.width * 0.5, m.y + m.height * 0.6);
      await page.waitForFunction(() => window.geoslice.S.answer, null, { timeout: 10000 });
      bad = await inView(page, '#answer h2');
      check(!bad, `${name}: the answer in sight: ${bad}`);
      bad = await inView(page, '#answer dl');  // its details too, not only the heading
      check(!bad, `${name}: the answer's details in sight: ${bad}`);
      await shot(page, `results-${name}-answer`);
      if (dev.viewport.height > dev.viewport.width) {
        // Upright: a bottom sheet over the map (it covers part of the map), put away by its ✕.
        const over = await page.evaluate(() => {
          const s = document.getElementById('sheet').getBoundingClientRect(), m = document.getElementById('stage').getBoundingClientRect();
          return { up: document.body.classList.contains('sheet-up'), top: s.top, mapBottom: m.bottom, bottom: s.bottom };
        });
        check(over.up && over.top < over.mapBottom && over.bottom <= dev.viewport.height + 1, `${name}: the answer is a bottom sheet over the map: ${JSON.stringify(over)}`);
        await page.locator('#sheetClose').click();
        check(!(await page.evaluate(() => document.body.classList.contains('sheet-up'))), `${name}: the sheet goes down`);
      }
      // A cut the server refuses: the reason in sight.
      await cutRefused(page);
      await page.waitForFunction(() => /rejected/.test(document.getElementById('status').textContent), null, { timeout: 10000 });
      bad = await inView(page, '#status');
      check(!bad, `${name}: the error in sight: ${bad}`);
      await page.locator('#tab-3d').click();
      bad = await inView(page, '#plAz');
      check(!bad, `${name}: the 3D plane's fields in sight: ${bad}`);
      await page.context().close();
    }
  },

  // On a slow network (2 s per API request) the page says what it is loading at once and
  // offers no Cut until there is a plan to cut; then the message goes and Cut is offered.
  async slow_network_says_it_is_loading() {
    const page = await newPage(PHONE, { locale: 'en-GB' });
    await page.route('**/v1/**', async (r) => { await new Promise((res) => setTimeout(res, 2000)); await r.continue(); });
    const t0 = Date.now();
    await page.goto(`${origin}/`, { waitUntil: 'commit' });
    await page.waitForFunction(() => /Loading/.test(document.getElementById('status')?.textContent || ''), null, { timeout: 3000, polling: 20 });
    const early = Date.now() - t0;
    check(await page.locator('#cut').isDisabled(), 'Cut is off while nothing is loaded');
    check(await page.locator('#model').isDisabled(), 'the model list is off while it loads');
    await shot(page, 'slow-network-loading');
    await page.waitForSelector('body[data-ready="1"]', { timeout: 30000 });
    check(!(await page.locator('#clear').isDisabled()), 'the line tools are offered once the plan is in');
    await page.locator('[data-mode="slice"]').click();
    check(!(await page.locator('#cut').isDisabled()), 'Cut is offered once the plan is in (a slice needs no points)');
    check(!/Loading/.test(await page.locator('#status').textContent()), 'the loading message goes');
    console.log(`slow network: a loading message ${early} ms after navigation, ready after ${Date.now() - t0} ms`);
    await page.context().close();
  },

  async line_cut_query_colours_borehole() {
    const page = await newPage(PHONE);
    await open(page);
    await cutLine(page, [[0.1, 0.2], [0.45, 0.7], [0.9, 0.5]]);
    const sec = await state(page, () => ({ kind: window.geoslice.S.section.kind, ends: window.geoslice.S.section.ends.map((e) => e.label) }));
    check(sec.kind === 'line' && sec.ends.join('') === 'ABC', `section ${JSON.stringify(sec)}`);
    const overlay = await page.locator('#sectionOverlay').textContent();
    for (const s of ['A', 'B', 'C', 'vx 2', 'Elevation (m)', 'Distance (m)']) check(overlay.includes(s), `overlay lacks '${s}': ${overlay}`);
    check(await page.locator('#sectionOverlay .bend').count() === 1, 'one bend (B) marked');
    // Taps: the answer names the legend colour under the pointer.
    const m = await box(page, '#sectionMap');
    let agree = 0, tried = 0;
    const legend = await state(page, () => Object.fromEntries(window.geoslice.S.model.legend.map((r) => [r.id, r.colour])));
    for (let i = 0; i < 24 && agree < 8; ++i) {
      const x = m.x + m.width * (0.15 + 0.7 * ((i * 0.618) % 1)), y = m.y + m.height * (0.2 + 0.6 * ((i * 0.377) % 1));
      const px = await pixelUnder(page, x, y);
      if (!px || !px.uniform) continue;
      await tap(page, x, y);
      await page.waitForFunction(() => window.geoslice.S.answer, null, { timeout: 10000 });
      const ans = await state(page, () => window.geoslice.S.answer.json);
      ++tried;
      if (px.rgba[3] === 0) { check(!ans.hit, `transparent pixel answered ${ans.record?.name}`); continue; }
      check(ans.hit, `coloured pixel ${px.rgba} answered no geology`);
      const c = hex(legend[ans.record.id]);
      // PNG tiles carry the record colour exactly inside a body: 0 tolerance would do;
      // 2 allows for the colour management of the canvas read-back.
      check(c.every((v, k) => Math.abs(v - px.rgba[k]) <= 2), `tap (${x | 0},${y | 0}): pixel ${px.rgba} vs legend ${legend[ans.record.id]} of ${ans.record.name}`);
      ++agree;
      if (agree === 1) {
        check(await page.locator('#sectionMap .qmark').count() === 1, 'marker at the queried point');
        const text = await page.locator('#answer').textContent();
        for (const s of ['Easting', 'Northing', 'Longitude', 'Latitude', 'Elevation', 'Distance along section', 'Lithology']) check(text.includes(s), `answer lacks ${s}`);
        check(await page.locator('#answer').getAttribute('aria-live') === 'polite', 'answer is announced');
        check(await page.locator('#legend li.hit').count() === 1, 'legend entry highlighted');
        check(await page.locator('#legendMini li.hit').count() === 1, 'on-screen legend entry highlighted');
        // The page's own Gauss-Kruger inverse (it draws the lon/lat graticule) against the
        // server's GeographicLib answer. Tolerance 1e-7 degrees (about 1 cm): far below a
        // pixel of the plan; the n^4 Krüger series is good to well under a millimetre.
        const d = await page.evaluate((w) => {
          const gk = window.geoslice.V.gaussKruger(w.crs);
          const [lon, lat] = window.geoslice.V.gkToLonLat(gk, w.x, w.y);
          const [x, y] = window.geoslice.V.lonLatToGk(gk, w.geodetic.lon, w.geodetic.lat);
          return [Math.abs(lon - w.geodetic.lon), Math.abs(lat - w.geodetic.lat), Math.hypot(x - w.x, y - w.y)];
        }, ans.world);
        console.log(`graticule Gauss-Kruger vs GeographicLib: |dlon| ${d[0].toExponential(1)} deg, |dlat| ${d[1].toExponential(1)} deg, round trip ${d[2].toExponential(1)} m`);
        check(d[0] < 1e-7 && d[1] < 1e-7 && d[2] < 0.01, `graticule projection vs GeographicLib: ${d}`);
        await shot(page, 'phone-answer');
      }
    }
    console.log(`colour check: ${agree} taps named the colour under them (of ${tried} answered)`);
    check(agree >= 5, `only ${agree} taps checked`);
    // Keyboard: Enter on the focused section map asks about its centre.
    await page.locator('#sectionMap').focus();
    await page.keyboard.press('Enter');
    await page.waitForFunction(() => window.geoslice.S.answer && document.querySelector('#sectionMap .qmark'), null, { timeout: 10000 });
    // Long-press on the section: a virtual borehole as a strip log.
    await longPress(page, m.x + m.width * 0.5, m.y + m.height * 0.5);
    await page.waitForFunction(() => document.querySelector('#bhLog'), null, { timeout: 10000 });
    const bh = await state(page, () => window.geoslice.S.bh);
    check(bh.intervals.length > 0, 'borehole has intervals');
    check(await page.locator('#bhLog rect').count() === bh.intervals.length, 'one strip per interval');
    check((await page.locator('#bh').textContent()).includes('Faults crossed'), 'faults listed');
    await shot(page, 'phone-borehole');
    // Long-press on the plan.
    await page.locator('#tab-plan').click();
    const b = await bounds(page);
    const [x, y] = await planPoint(page, 0.5 * (b.min[0] + b.max[0]), 0.5 * (b.min[1] + b.max[1]));
    const before = bh;
    await longPress(page, x, y);
    await page.waitForFunction((o) => window.geoslice.S.bh && window.geoslice.S.bh.origin[0] !== o, before.origin[0], { timeout: 10000 });
    const bh2 = await state(page, () => window.geoslice.S.bh);
    check(Math.abs(bh2.origin[0] - 0.5 * (b.min[0] + b.max[0])) < 30, `plan borehole at ${bh2.origin}`);
    await page.context().close();
  },

  async orientations_and_slice() {
    const page = await newPage(DESKTOP);
    await open(page);
    const b = await bounds(page);
    const mid = await planPoint(page, 0.5 * (b.min[0] + b.max[0]), 0.5 * (b.min[1] + b.max[1]));
    for (const [mode, left, right] of [['ew', 'W', 'E'], ['ns', 'S', 'N']]) {
      await page.locator('#tab-plan').click();
      await page.locator(`[data-mode="${mode}"]`).click();
      await tap(page, mid[0], mid[1]);
      await page.locator('#cut').click();
      await page.waitForFunction((l) => window.geoslice.S.section?.ends?.[0]?.label === l, left, { timeout: 15000 });
      const ends = await state(page, () => window.geoslice.S.section.ends.map((e) => e.label));
      check(ends.join('') === left + right, `${mode}: ends ${ends}`);
      await settle(page);
      await shot(page, `desktop-section-${mode}`);
    }
    await page.locator('#tab-plan').click();
    await page.locator('[data-mode="az"]').click();
    await page.locator('#azimuth').fill('30');
    await tap(page, mid[0], mid[1]);
    await page.locator('#cut').click();
    await page.waitForFunction(() => window.geoslice.S.section?.ends?.[1]?.label === 'NE', null, { timeout: 15000 });
    await page.locator('#tab-plan').click();
    await page.locator('[data-mode="slice"]').click();
    await page.locator('#sliceZ').fill('300');
    await page.locator('#cut').click();
    await page.waitForFunction(() => window.geoslice.S.section?.kind === 'elevation', null, { timeout: 15000 });
    await settle(page);
    await shot(page, 'desktop-slice');
    // Export links point at the same section.
    const href = await page.locator('#expSvg').getAttribute('href');
    check(/section\.svg\?elevation=300/.test(href), `svg export ${href}`);
    const svg = await page.evaluate((u) => fetch(u).then((r) => r.text()), href);
    check(svg.startsWith('<?xml') || svg.startsWith('<svg'), 'SVG export is SVG');
    const gj = await page.evaluate((u) => fetch(u).then((r) => r.json()), await page.locator('#expGeojson').getAttribute('href'));
    check(gj.type === 'FeatureCollection' && gj.features.length > 0, 'GeoJSON export');
    // PNG export is the print sheet as an image (axes, legend, title: decorate=1), not the bare
    // picture; DXF is the section for CAD.
    const pngHref = await page.locator('#expPng').getAttribute('href');
    check(/decorate=1/.test(pngHref), `PNG export is the decorated sheet: ${pngHref}`);
    const png = await page.evaluate((u) => fetch(u).then(async (r) => {
      const b = new DataView(await r.arrayBuffer());
      return [r.status, r.headers.get('content-type'), b.getUint32(16), b.getUint32(20)];
    }), pngHref);
    check(png[0] === 200 && png[1] === 'image/png' && png[2] > 2000 && png[2] > png[3], `PNG export: ${png}`);
    const dxf = await page.evaluate((u) => fetch(u).then(async (r) => [r.status, (await r.text()).includes('AC1015')]),
                                    await page.locator('#expDxf').getAttribute('href'));
    check(dxf[0] === 200 && dxf[1], `DXF export: ${dxf}`);
    // The server offers section.pdf (a print sheet): the PDF link is shown and answers a PDF.
    check(!(await page.locator('#expPdf').isHidden()), 'PDF export shown');
    const pdf = await page.evaluate((u) => fetch(u).then(async (r) => [r.status, r.headers.get('content-type'),
      new TextDecoder().decode((await r.arrayBuffer()).slice(0, 5))]), await page.locator('#expPdf').getAttribute('href'));
    check(pdf[0] === 200 && pdf[1] === 'application/pdf' && pdf[2] === '%PDF-', `PDF export ${pdf}`);
    await page.context().close();
  },

  async three_d_plane_drag() {
    const page = await newPage(PHONE);
    await open(page);
    await page.locator('#tab-3d').click();
    await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small, null, { timeout: 30000 });
    await settle(page);
    const sizes = [];
    page.on('request', (r) => { const m = /view=perspective.*size=(\d+)x(\d+)/.exec(r.url()); if (m) sizes.push(+m[1]); });
    const off0 = Number(await page.locator('#plOffset').inputValue());
    const h = await box(page, '#moveHandle');
    const cx = h.x + h.width / 2, cy = h.y + h.height / 2;
    // Drag with touch (CDP), 8 steps.
    const cdp = await page.context().newCDPSession(page);
    await touchDrag(page, cdp, [cx, cy], [8, 4], 8, 60);
    const off1 = Number(await page.locator('#plOffset').inputValue());
    check(off1 !== off0, `dragging the move handle moved the plane (${off0} -> ${off1})`);
    // Pinch (two touch points moving apart) zooms the camera in.
    const dist0 = await state(page, () => window.geoslice.S.three.dist);
    const vb = await box(page, '#view3d');
    const [px, py] = [vb.x + vb.width * 0.5, vb.y + vb.height * 0.85];
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ x: px - 20, y: py, id: 1 }, { x: px + 20, y: py, id: 2 }] });
    for (let i = 1; i <= 5; ++i) {
      await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: [{ x: px - 20 - 12 * i, y: py, id: 1 }, { x: px + 20 + 12 * i, y: py, id: 2 }] });
      await page.waitForTimeout(50);
    }
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
    const dist1 = await state(page, () => window.geoslice.S.three.dist);
    check(dist1 < dist0 * 0.8, `pinch zoomed in: ${dist0} -> ${dist1}`);
    await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small, null, { timeout: 30000 });
    await settle(page);
    const vw = (await box(page, '#view3d')).width;
    check(sizes.some((w) => w <= Math.ceil(vw / 3) + 1), `small frames while dragging: ${sizes}`);
    check(sizes.length && sizes[sizes.length - 1] >= vw, `full frame on release: ${sizes}`);
    const shown = await state(page, () => window.geoslice.S.shown3d.params);
    const plane = await state(page, () => `plane=${window.geoslice.S.shown3d.profile.split('plane=')[1].split('&')[0]}`);
    check(shown.includes(plane), 'the 3D image and the profile show the same plane');
    await shot(page, 'phone-3d-dragged');
    // A long thumb drag can never take the plane off the model: the offset stops at the
    // model's extent along the normal, the last frame is drawn, no error, the handles stay.
    {
      const hm = await box(page, '#moveHandle');
      await touchDrag(page, cdp, [hm.x + hm.width / 2, hm.y + hm.height / 2], [25, 12], 30, 30);
      const after = await page.evaluate(() => {
        const S = window.geoslice.S, { min, max } = S.model.bounds;
        const off = Number(document.getElementById('plOffset').value);
        const az = (Number(document.getElementById('plAz').value) * Math.PI) / 180, dip = (Number(document.getElementById('plDip').value) * Math.PI) / 180;
        const n = [-Math.cos(az) * Math.sin(dip), Math.sin(az) * Math.sin(dip), Math.cos(dip)];
        const support = 0.5 * (Math.abs(n[0]) * (max[0] - min[0]) + Math.abs(n[1]) * (max[1] - min[1]) + Math.abs(n[2]) * (max[2] - min[2]));
        return { off, support, status: document.getElementById('status').textContent, error: document.getElementById('status').className === 'error',
                 shownOff: S.shown3d.profile };
      });
      check(Math.abs(after.off) < after.support, `the plane stays in the model: offset ${after.off}, extent ${after.support.toFixed(0)}`);
      check(Math.abs(after.off) > 0.9 * after.support, `a long drag reaches the model's edge: ${after.off} of ${after.support.toFixed(0)}`);
      check(!after.error, `no error after the long drag: ${after.status}`);
      check(!(await page.locator('#rotateHandle').isHidden()), 'the rotate handle stays');
      await shot(page, 'phone-3d-dragged-to-edge');
    }
    // Rotate with the keyboard.
    await page.locator('#rotateHandle').focus();
    await page.keyboard.press('ArrowRight');
    await page.waitForFunction(() => Number(document.getElementById('plAz').value) === 95, null, { timeout: 5000 });
    // Tap the 3D view and the profile: both answer.
    const v = await box(page, '#view3d');
    await tap(page, v.x + v.width * 0.5, v.y + v.height * 0.6);
    await page.waitForFunction(() => window.geoslice.S.answer?.where === '3d', null, { timeout: 10000 });
    const p = await box(page, '#profileImg');
    await tap(page, p.x + p.width * 0.5, p.y + p.height * 0.6);
    await page.waitForFunction(() => window.geoslice.S.answer?.where === 'profile', null, { timeout: 10000 });
    await shot(page, 'phone-3d-answer');
    await page.context().close();
  },

  async errors_never_lie() {
    const page = await newPage(PHONE);
    await open(page);
    await cutLine(page, [[0.2, 0.4], [0.8, 0.6]]);
    const before = await state(page, () => ({ def: window.geoslice.S.section.def, gen: window.geoslice.S.gen }));
    // A cut the real server rejects (257 vertices; at most 256): nothing changes.
    await cutRefused(page);
    await page.waitForFunction(() => /Cut rejected/.test(document.getElementById('status').textContent), null, { timeout: 10000 });
    let after = await state(page, () => ({ def: window.geoslice.S.section.def, gen: window.geoslice.S.gen }));
    check(JSON.stringify(after) === JSON.stringify(before), 'a rejected cut changed the section');
    check(/more than 512 values/.test(await page.locator('#status').textContent()), 'the server\'s reason is shown');
    await shot(page, 'error-cut-rejected');
    // Client-side range check (vx outside 0.1..100): refused before any request.
    await page.evaluate(() => window.geoslice.setPoints([[window.geoslice.S.model.bounds.min[0] + 100, window.geoslice.S.model.bounds.min[1] + 100], [window.geoslice.S.model.bounds.max[0] - 100, window.geoslice.S.model.bounds.max[1] - 100]]));
    await page.locator('#vx').fill('500');
    await page.locator('#cut').click();
    check(/0\.1\.\.100/.test(await page.locator('#status').textContent()), 'vx range named');
    after = await state(page, () => ({ def: window.geoslice.S.section.def, gen: window.geoslice.S.gen }));
    check(JSON.stringify(after) === JSON.stringify(before), 'an invalid vx changed the section');
    await page.locator('#vx').fill('2');
    // A server that is away (every request to it fails: the connection refused) is not a
    // rejection: the page says it cannot reach the server, and cuts again by itself when
    // the server answers; nothing stays striped or in error.
    await page.route('**/*', (r) => (r.request().url().startsWith(page.url().split('/#')[0].split('?')[0].replace(/\/$/, '')) && !/\/web\//.test(r.request().url()) ? r.abort('connectionrefused') : r.continue()));
    await page.evaluate(() => window.geoslice.setPoints([[window.geoslice.S.model.bounds.min[0] + 300, window.geoslice.S.model.bounds.min[1] + 300], [window.geoslice.S.model.bounds.max[0] - 300, window.geoslice.S.model.bounds.max[1] - 200]]));
    await page.locator('#cut').click();
    await page.waitForFunction(() => /cannot reach the server/.test(document.getElementById('status').textContent), null, { timeout: 10000 });
    check(!/rejected/.test(await page.locator('#status').textContent()), `a server away is not a rejection: ${await page.locator('#status').textContent()}`);
    await shot(page, 'error-server-away');
    await page.unroute('**/*');
    await page.waitForFunction((d) => JSON.stringify(window.geoslice.S.section.def) !== d, JSON.stringify(before.def), { timeout: 20000 });
    await page.waitForFunction(() => document.getElementById('status').className !== 'error' && document.querySelectorAll('img.tile-failed').length === 0, null, { timeout: 20000 });
    check(!/cannot reach/.test(await page.locator('#status').textContent()), 'the error went when the server came back');
    // Input ranges come from the model's bounds.
    const b = await bounds(page);
    check(Number(await page.locator('#sliceZ').getAttribute('min')) === Math.floor(b.min[2]), 'slice min from bounds');
    check(Number(await page.locator('#sliceZ').getAttribute('max')) === Math.ceil(b.max[2]), 'slice max from bounds');

    // Failed queries clear the old answer (502 from a proxy, connection refused).
    await page.locator('#tab-section').click();
    const m = await box(page, '#sectionMap');
    await tap(page, m.x + m.width / 2, m.y + m.height / 2);
    await page.waitForFunction(() => window.geoslice.S.answer, null, { timeout: 10000 });
    for (const [kind, fail] of [['502', (r) => r.fulfill({ status: 502, contentType: 'text/plain', body: 'bad gateway' })],
                                ['refused', (r) => r.abort('connectionrefused')]]) {
      await page.route('**/query?**', fail);
      await tap(page, m.x + m.width * 0.4, m.y + m.height * 0.55);
      await page.waitForFunction(() => /Query failed/.test(document.getElementById('answer').textContent), null, { timeout: 10000 });
      check(await state(page, () => window.geoslice.S.answer) === null, `${kind}: the old answer stays`);
      check(await page.locator('#sectionMap .qmark').count() === 0, `${kind}: the old marker stays`);
      await shot(page, `error-query-${kind}`);
      await page.unroute('**/query?**');
    }

    // Tiles: 503 twice then served -> retried and painted; always 503 -> a visible message.
    let n503 = 0;
    await page.route('**/section.png?line=**frame=**', (r) => (n503++ < 2 ? r.fulfill({ status: 503, headers: { 'Retry-After': '0' }, body: '' }) : r.continue()));
    await page.locator('#tab-plan').click();
    await cutLine(page, [[0.3, 0.3], [0.7, 0.7]]);
    check(n503 >= 2, 'tiles were refused');
    check(await page.locator('#sectionMap img.tile-failed').count() === 0, 'refused tiles were retried and painted');
    await page.unroute('**/section.png?line=**frame=**');
    await page.route('**/section.png?line=**frame=**', (r) => r.fulfill({ status: 503, body: '' }));
    await page.locator('#tab-plan').click();
    await page.locator('[data-mode="line"]').click();
    await page.locator('#clear').click();
    const [x1, y1] = await planPoint(page, b.min[0] + 0.25 * (b.max[0] - b.min[0]), b.min[1] + 0.5 * (b.max[1] - b.min[1]));
    const [x2, y2] = await planPoint(page, b.min[0] + 0.6 * (b.max[0] - b.min[0]), b.min[1] + 0.45 * (b.max[1] - b.min[1]));
    await tap(page, x1, y1);
    await tap(page, x2, y2);
    await page.locator('#cut').click();
    await page.waitForFunction(() => /retrying/.test(document.getElementById('status').textContent), null, { timeout: 10000 });
    await page.waitForFunction(() => /could not be loaded/.test(document.getElementById('status').textContent), null, { timeout: 30000 });
    check(await page.locator('#status button').isVisible(), 'a retry button');
    await shot(page, 'error-tiles-503');
    await page.unroute('**/section.png?line=**frame=**');
    await page.locator('#status button').click();
    await page.waitForFunction(() => document.querySelectorAll('#sectionMap img.tile-failed').length === 0 && !/could not/.test(document.getElementById('status').textContent), null, { timeout: 20000 });

    // A model switch resets the view: no section, no answer, a new plan, queries to the new model.
    await tap(page, m.x + m.width / 2, m.y + m.height / 2);
    await page.waitForFunction(() => window.geoslice.S.answer, null, { timeout: 10000 });
    const planBefore = await state(page, () => window.geoslice.S.plan.sid);
    await page.locator('#model').selectOption('mine-b');
    await page.waitForFunction((s) => window.geoslice.S.plan && window.geoslice.S.plan.sid !== s, planBefore, { timeout: 15000 });
    const s2 = await state(page, () => ({ section: window.geoslice.S.section, answer: window.geoslice.S.answer, model: window.geoslice.S.model.id, points: window.geoslice.S.points.length }));
    check(s2.section === null && s2.answer === null && s2.model === 'mine-b' && s2.points === 0, `after switch: ${JSON.stringify(s2)}`);
    // Exactly one plan layer: the old model's tiles are gone, also after quick switching.
    const planLayers = () => page.evaluate(() => document.querySelectorAll('#planMap .leaflet-tile-pane > .leaflet-layer').length);
    check(await planLayers() === 1, `one plan layer after a switch, not ${await planLayers()}`);
    for (const id of ['mine-a', 'mine-b', 'mine-a', 'mine-b']) await page.locator('#model').selectOption(id);
    await page.waitForFunction(() => window.geoslice.S.plan && window.geoslice.S.model.id === 'mine-b', null, { timeout: 15000 });
    await page.waitForTimeout(1500);  // any stale answer of the quick switches has arrived by now
    check(await planLayers() === 1, `one plan layer after quick switches, not ${await planLayers()}`);
    await page.locator('#tab-section').click();
    check(await page.locator('#noSection').isVisible(), 'the section view says there is none');
    await shot(page, 'model-switched');
    const nb = await bounds(page);
    check(nb.min[0] !== b.min[0], 'the new model has other bounds');
    check(Number(await page.locator('#sliceZ').getAttribute('max')) === Math.ceil(nb.max[2]), 'ranges follow the new model');
    await page.context().close();
  },

  async permalink_and_language() {
    const page = await newPage(DESKTOP, { locale: 'zh-CN' });
    await open(page);
    check((await page.locator('#tab-plan').textContent()) === '平面', 'Chinese from Accept-Language');
    check(await page.evaluate(() => document.documentElement.lang) === 'zh-CN', 'html lang zh-CN');
    await cutLine(page, [[0.2, 0.3], [0.8, 0.7]]);
    await shot(page, 'desktop-zh-section');
    // An answer in Chinese: every label is Chinese (a model's own attribute names aside, none
    // here), and the record's kind and era are translated.
    const sm = await box(page, '#sectionMap');
    await tap(page, sm.x + sm.width * 0.5, sm.y + sm.height * 0.6);
    await page.waitForFunction(() => window.geoslice.S.answer?.json.hit, null, { timeout: 10000 });
    const zh = await page.evaluate(() => ({
      labels: [...document.querySelectorAll('#answer dt')].map((e) => e.textContent),
      values: Object.fromEntries([...document.querySelectorAll('#answer dt')].map((e) => [e.textContent, e.nextElementSibling.textContent])),
    }));
    const english = zh.labels.filter((l) => !/[\u4e00-\u9fff]/.test(l));
    check(english.length === 0, `English labels left in Chinese mode: ${english.join(', ')}`);
    check(/[\u4e00-\u9fff]/.test(zh.values['类型'] || ''), `kind translated: ${zh.values['类型']}`);
    await shot(page, 'desktop-zh-answer');
    await page.locator('#lang').click();
    check((await page.locator('#tab-plan').textContent()) === 'Plan', 'switched to English');
    await page.waitForTimeout(300);
    const link = await state(page, () => window.geoslice.permalink());
    const def = await state(page, () => window.geoslice.S.section.def);
    const page2 = await newPage(DESKTOP);
    await page2.goto(link);
    await page2.waitForSelector('body[data-ready="1"]', { timeout: 20000 });
    await settle(page2);
    const def2 = await state(page2, () => window.geoslice.S.section?.def);
    check(JSON.stringify(def2) === JSON.stringify(def), `permalink restores the section: ${JSON.stringify(def2)} vs ${JSON.stringify(def)}`);
    check(await state(page2, () => window.geoslice.S.view) === 'section', 'permalink restores the view');
    check((await page2.locator('#tab-plan').textContent()) === 'Plan', 'permalink keeps the language');
    await page.context().close();
    await page2.context().close();
  },

  // API keys: the page opened with #key=KEY keeps the key in localStorage, drops it from the
  // address (and so from permalinks), and every request (JSON, images, tiles) carries it; a
  // page without a key says how to give one.
  async api_key_from_the_address() {
    const key = 'webClientKey-0123456789abcdef';
    const keyed = await startServer(binary, { keys: `viewer ${key} mine-a\n` });
    const ctx = await browser.newContext(DESKTOP);
    try {
      await ctx.route((url) => !url.href.startsWith(keyed.url), (route) => route.abort('blockedbyclient'));
      const sent = [];
      const page = await ctx.newPage();
      page.on('request', (r) => { if (r.url().includes('/v1/')) sent.push([r.url(), r.headers().authorization || '']); });
      await page.goto(`${keyed.url}/#key=${key}&lang=en`);
      await page.waitForSelector('body[data-ready="1"]', { timeout: 20000 });
      await page.waitForFunction(() => document.getElementById('busy').hidden, null, { timeout: 15000 });
      check(!page.url().includes(key), `the key left the address: ${page.url()}`);
      check(page.url().includes('lang=en'), `the rest of the address stays: ${page.url()}`);
      check(await page.evaluate(() => localStorage.getItem('geoslice.apiKey')) === key, 'the key is kept');
      const models = await page.evaluate(() => window.geoslice.S.models.map((m) => m.id));
      check(JSON.stringify(models) === '["mine-a"]', `the key's models only: ${models}`);
      check(!(await page.evaluate(() => window.geoslice.permalink())).includes(key), 'no key in the permalink');
      await cutLine(page, [[0.2, 0.5], [0.8, 0.5]]);
      check(sent.some(([u]) => u.includes('/tiles/')), 'tiles were fetched');
      const bare = sent.filter(([, a]) => a !== `Bearer ${key}`);
      check(sent.length > 3 && bare.length === 0, `every request carries the key: ${JSON.stringify(bare)}`);
      const page2 = await (await browser.newContext(DESKTOP)).newPage();
      await page2.goto(`${keyed.url}/#lang=en`);
      await page2.waitForFunction(() => /API key/.test(document.getElementById('status').textContent), null, { timeout: 20000 });
      await page2.context().close();
    } finally {
      await ctx.close();
      keyed.stop();
    }
  },

  // Drillholes and saved sections on a phone, against the demo (32 holes, five exploration
  // lines and a fence) with a sections directory: holes on the plan, a line opened by name and
  // titled so on screen and in the PDF, a tap on a drawn hole answered with the hole beside the
  // model, its strip log agreeing with the server's check, a section along the hole, a line
  // snapped through two collars, a section saved by name that a new page lists again, and the
  // hole and save controls in Chinese.
  async drillholes_and_saved_sections() {
    const store = fs.mkdtempSync(path.join(outDir, 'sections-'));
    const demo = await startServer(binary, { demo: true, extraArgs: ['--sections-dir', store] });
    const ctx = await browser.newContext({ ...PHONE, locale: 'en-GB' });
    try {
      await ctx.route((url) => !url.href.startsWith(demo.url), (route) => { foreign.push(route.request().url()); return route.abort('blockedbyclient'); });
      const page = await ctx.newPage();
      page.errors = [];
      page.on('pageerror', (e) => page.errors.push(e.message));
      const ready = async () => {
        await page.waitForSelector('body[data-ready="1"]', { timeout: 20000 });
        await page.waitForFunction(() => document.getElementById('busy').hidden, null, { timeout: 15000 });
        await page.waitForTimeout(50);
      };
      await page.goto(`${demo.url}/#lang=en`);
      await ready();
      const server = await (await fetch(`${demo.url}/v1/models/demo/drillholes`)).json();
      const drawn = await page.evaluate(() => ({ holes: window.geoslice.S.holes?.holes.length,
                                                 ids: document.querySelectorAll('#planMap .hole-id').length }));
      check(server.holes.length === 32 && drawn.holes === 32 && drawn.ids === 32, `holes on the plan: ${JSON.stringify(drawn)}`);
      // The demo's context layer (lease, decline, shaft) on the plan, labelled.
      const ctxDrawn = await page.evaluate(() => ({ n: window.geoslice.S.context?.features.length,
                                                    labels: [...document.querySelectorAll('#planMap .ctx-label')].map((e) => e.textContent) }));
      check(ctxDrawn.n === 3 && ctxDrawn.labels.length === 3 && ctxDrawn.labels.includes('1号竖井 No. 1 shaft'),
            `context layer: ${JSON.stringify(ctxDrawn)}`);
      await shot(page, 'phone-holes-plan');

      // The exploration lines, by name, as the server lists them.
      const listed = await (await fetch(`${demo.url}/v1/models/demo/saved-sections`)).json();
      const options = await page.evaluate(() => [...document.querySelectorAll('#savedSel option')].map((o) => o.textContent).slice(1));
      check(JSON.stringify(options) === JSON.stringify(listed.sections.map((s) => s.name)), `saved sections: ${options}`);
      const line0 = listed.sections.find((s) => s.name === 'Line 0');
      await page.selectOption('#savedSel', line0.id);
      await page.waitForFunction(() => window.geoslice.S.section?.title === 'Line 0', null, { timeout: 15000 });
      await ready();
      const title = await page.locator('#sectionTitle').textContent();
      check(/Line 0/.test(title), `on screen: ${title}`);
      const pdfHref = await page.locator('#expPdf').getAttribute('href');
      check(pdfHref.includes('title=Line%200'), `PDF link: ${pdfHref}`);
      const pdf = Buffer.from(await (await fetch(`${demo.url}${pdfHref}`)).arrayBuffer());
      fs.writeFileSync(path.join(outDir, 'line0.pdf'), pdf);
      const text = execFileSync('pdftotext', [path.join(outDir, 'line0.pdf'), '-']).toString();
      check(/Line 0: Geological section/.test(text), `the PDF's title: ${text.slice(0, 200)}`);

      // The east-west fence: a tap on a drawn hole answers the hole beside the model's unit.
      const fence = listed.sections.find((s) => /fence/.test(s.name));
      await page.locator('#tab-plan').click();
      await page.selectOption('#savedSel', fence.id);
      await page.waitForFunction((n) => window.geoslice.S.section?.title === n, fence.name, { timeout: 15000 });
      await ready();
      const gj = await (await fetch(`${demo.url}/v1/models/demo/section.geojson?${fence.query}&space=plane`)).json();
      const hole = gj.features.find((f) => f.properties.kind === 'drillhole' && f.properties.side === 'behind' &&
                                          f.properties.to - f.properties.from > 60);
      check(hole, 'a drawn hole on the fence');
      const [a, b] = hole.geometry.coordinates;
      const at = await page.evaluate(([u, v]) => {
        const { sectionMap } = window.geoslice.maps(), g = window.geoslice.S.section.grid;
        const p = sectionMap.latLngToContainerPoint([((v - g.origin.v) * g.exaggeration * 256) / g.size0, ((u - g.origin.u) * 256) / g.size0]);
        const r = sectionMap.getContainer().getBoundingClientRect();
        return [r.left + p.x, r.top + p.y];
      }, [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2]);
      await tap(page, at[0], at[1]);
      await page.waitForSelector('.hole-answer', { timeout: 15000 });
      const answer = await page.locator('.hole-answer').textContent();
      check(answer.includes(`Drillhole ${hole.properties.hole}`) && /Model here/.test(answer), `hole answer: ${answer}`);
      await shot(page, 'phone-hole-answer');
      // Its strip log: the model agrees over the share the server's check finds for that hole.
      await page.locator('.hole-answer .holeLogBtn').click();
      await page.waitForSelector('#holeLog', { timeout: 15000 });
      const log = await page.evaluate(() => window.geoslice.S.holeLog);
      const checkDoc = await (await fetch(`${demo.url}/v1/models/demo/drillholes/check`)).json();
      const h = checkDoc.holes.find((x) => x.hole === hole.properties.hole);
      check(log.id === hole.properties.hole && Math.abs(log.share - h.agreed_m / h.logged_m) < 1e-9,
            `strip log share ${log.share} vs the check's ${h.agreed_m / h.logged_m}`);
      await shot(page, 'phone-strip-log');
      // A section along the hole contains its collar.
      await page.locator('#sectionAlongHole').click();
      await page.waitForFunction((id) => window.geoslice.S.section?.title?.includes(id), hole.properties.hole, { timeout: 15000 });
      await ready();
      const along = await page.evaluate((id) => {
        const s = window.geoslice.S, c = s.holes.holes.find((x) => x.id === id).collar, p = s.section.plane;
        return p.n[0] * c[0] + p.n[1] * c[1] + p.n[2] * c[2] + p.d;
      }, hole.properties.hole);
      check(Math.abs(along) < 0.01, `the collar is ${along} m off the section along its hole`);

      // A line snapped through two collars: taps 6 px off each collar give the collars exactly.
      await page.evaluate(() => document.getElementById('tab-plan').click());
      await page.locator('[data-mode="line"]').click();
      await page.locator('#clear').click();
      const rect = await box(page, '#planMap');
      const two = [];
      for (const c of server.holes) {
        const p = await planPoint(page, c.collar[0], c.collar[1]);
        if (p[0] > rect.x + 30 && p[0] < rect.x + rect.width - 30 && p[1] > rect.y + 30 && p[1] < rect.y + rect.height - 30 &&
            two.every((o) => Math.hypot(o.p[0] - p[0], o.p[1] - p[1]) > 40)) two.push({ collar: c.collar, p });
        if (two.length === 2) break;
      }
      check(two.length === 2, 'two collars in sight on the plan');
      for (const { p } of two) await tap(page, p[0] + 6, p[1] - 4);
      const pts = await page.evaluate(() => window.geoslice.S.points);
      check(pts.length === 2 && pts.every((p, i) => p[0] === two[i].collar[0] && p[1] === two[i].collar[1]),
            `snapped points ${JSON.stringify(pts)} vs collars ${JSON.stringify(two.map((c) => c.collar))}`);
      await page.locator('#cut').click();
      await page.waitForFunction(() => window.geoslice.S.section?.kind === 'line', null, { timeout: 15000 });
      await ready();
      // Saved by name, listed again by a new page.
      await page.locator('#saveName').fill('Through two holes');
      await page.locator('#saveSection').click();
      await page.waitForFunction(() => [...document.querySelectorAll('#savedSel option')].some((o) => o.textContent === 'Through two holes ★'), null, { timeout: 15000 });
      check(fs.readdirSync(path.join(store, 'demo')).length === 1, 'one file in the sections directory');
      const page2 = await ctx.newPage();
      page2.on('pageerror', (e) => page.errors.push(e.message));
      await page2.goto(`${demo.url}/#lang=zh`);
      await page2.waitForSelector('body[data-ready="1"]', { timeout: 20000 });
      await page2.waitForFunction(() => document.getElementById('busy').hidden, null, { timeout: 15000 });
      const names = await page2.evaluate(() => [...document.querySelectorAll('#savedSel option')].map((o) => o.textContent));
      check(names.includes('Through two holes ★'), `listed again: ${names}`);
      // The new controls in Chinese.
      const labels = await page2.evaluate(() => ['#showHolesField span', '#showContextField span', '#holeTools span', '#saveRow span', '#saveSection', '#savedField span']
        .flatMap((q) => [...document.querySelectorAll(q)].map((e) => e.textContent.trim())));
      const english = labels.filter((l) => !/[\u4e00-\u9fff]/.test(l));
      check(english.length === 0, `English left in Chinese: ${english}`);
      await page2.close();
      check(page.errors.length === 0, `page errors: ${page.errors.join('; ')}`);
    } finally {
      await ctx.close();
      demo.stop();
    }
  },

  // Units hidden in 3D: unticking a unit asks the server for the picture without it
  // (hide=), and the server's pixel answers over the whole image never name it, while the
  // same view with everything shown did.
  async hide_units_in_3d() {
    const page = await newPage(DESKTOP, { locale: 'en-GB' });
    await open(page);
    await page.locator('#tab-3d').click();
    await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small, null, { timeout: 30000 });
    await settle(page);
    const before = await page.evaluate(() => window.geoslice.S.shown3d);
    const grid = [];
    for (let y = 0; y < 16; ++y) for (let x = 0; x < 16; ++x) grid.push([Math.floor((x + 0.5) * before.w / 16), Math.floor((y + 0.5) * before.h / 16)]);
    const answers = async (params) => {
      const view = Object.fromEntries(new URLSearchParams(params));
      const r = await fetch(`${origin}/v1/models/mine-a/query`, { method: 'POST', headers: { 'Content-Type': 'application/json' },
                                                                  body: JSON.stringify({ view, pixels: grid }) });
      const text = await r.text();
      check(r.status === 200, `batch query: ${r.status} ${text}`);
      return JSON.parse(text).results.map((a) => a.record?.id ?? 0);
    };
    const shown = await answers(before.params);
    const counts = new Map();
    for (const id of shown) if (id) counts.set(id, (counts.get(id) || 0) + 1);
    const target = [...counts].sort((a, b) => b[1] - a[1])[0][0];
    await page.locator(`#units3d input[data-record="${target}"]`).uncheck();
    await page.waitForFunction((id) => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small &&
                                       window.geoslice.S.shown3d.params.includes(`hide=${id}`), target, { timeout: 30000 });
    await settle(page);
    const after = await page.evaluate(() => window.geoslice.S.shown3d.params);
    const hidden = await answers(after);
    check(!hidden.includes(target), `record ${target} still answered with hide=${target}`);
    check(hidden.filter((id, i) => id !== shown[i]).length >= counts.get(target), 'hiding changed the answers where the unit was');
    check((await page.evaluate(() => window.geoslice.permalink())).includes(`h3=${target}`), 'the permalink keeps the hidden unit');
    await shot(page, 'desktop-3d-hidden');
    await page.locator('#showAll3d').click();
    await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.params.includes('hide='), null, { timeout: 30000 });
    await settle(page);
    // A second plane: the current one kept, then turned to strike 0; the view is cut by both
    // (cut=union: the kept side of each stays), and the server's answers follow both planes.
    const onePlane = await answers((await page.evaluate(() => window.geoslice.S.shown3d.params)));
    await page.locator('#addPlane3d').click();
    await page.locator('#plAz').fill('0');
    await page.locator('#plAz').dispatchEvent('input');
    await page.waitForFunction(() => (window.geoslice.S.shown3d?.params.match(/plane=/g) || []).length === 2 &&
                                     !window.geoslice.S.shown3d.small, null, { timeout: 30000 });
    await settle(page);
    const two = await page.evaluate(() => window.geoslice.S.shown3d.params);
    check(two.includes('cut=union'), `two planes: ${two}`);
    const planes = [...new URLSearchParams(two).getAll('plane')];
    const twoParams = new URLSearchParams(two);
    twoParams.delete('plane');
    twoParams.set('planes', planes.join(';'));
    const twoAnswers = await answers(twoParams.toString());
    check(twoAnswers.some((id, i) => id !== onePlane[i]), 'the second plane changed what the view shows');
    const listed = await page.locator('#planes3d li').count();
    check(listed === 1, `${listed} kept planes listed`);
    await shot(page, 'desktop-3d-two-planes');
    check(page.errors.length === 0, `page errors: ${page.errors.join('; ')}`);
    await page.context().close();
  },

  // The 3D profile's axes say what the image shows: at each elevation tick's row and each
  // distance tick's column the server's pixel query finds that elevation (world z) and that
  // distance from the left edge (plane u), within one pixel's metres.
  async profile_axes_are_true() {
    const page = await newPage(DESKTOP, { locale: 'en-GB' });
    await open(page);
    await page.locator('#tab-3d').click();
    await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small &&
                                     document.querySelectorAll('#profileOverlay .tick-v').length >= 2, null, { timeout: 30000 });
    await settle(page);
    const t = await page.evaluate(() => {
      const w = window.geoslice.S.shown3d, r = document.getElementById('profileBox').getBoundingClientRect();
      const ticks = (cls, attr, axis) => [...document.querySelectorAll(`#profileOverlay .${cls}`)].map((e) => ({
        value: Number(e.dataset[attr]), at: Number(e.getAttribute(axis)) }));
      return { profile: w.profile, pw: w.pw, ph: w.ph, frame: w.frame, width: r.width, height: r.height,
               v: ticks('tick-v', 'v', 'y'), u: ticks('tick-u', 'u', 'x') };
    });
    check(t.v.length >= 2 && t.u.length >= 2, `ticks: ${JSON.stringify(t)}`);
    const metresPerPixel = (t.frame[1] - t.frame[0]) / t.pw;
    const ask = async (px, py) => (await (await fetch(`${origin}/v1/models/mine-a/query?${t.profile}&px=${px}&py=${py}`)).json());
    for (const { value, at } of t.v) {
      const py = Math.floor(((at - 4) / t.height) * t.ph);  // the label's baseline sits 4 px below the tick
      const a = await ask(Math.floor(t.pw / 2), py);
      check(Number.isFinite(a.world?.z) && Math.abs(a.world.z - value) <= 1.5 * metresPerPixel,
            `elevation tick ${value}: the server's row ${py} is at z ${a.world?.z} (${metresPerPixel.toFixed(2)} m a pixel)`);
    }
    for (const { value, at } of t.u) {
      const px = Math.floor((at / t.width) * t.pw);
      const a = await ask(px, Math.floor(t.ph / 2));
      const along = a.section.u - t.frame[0];
      check(Math.abs(along - value) <= 1.5 * metresPerPixel, `distance tick ${value}: column ${px} is ${along} m from the left edge`);
    }
    await shot(page, 'desktop-3d-profile-axes');
    await page.context().close();
  },

  // A block model's property colours the section and the 3D view: the pick reaches the
  // section's definition, tiles and the 3D request (colour=), the ramp's legend is shown, and
  // the server's answer at a coloured pixel of the section names the block cell and its grade.
  async block_model_colouring() {
    let csv = 'x,y,z,dx,dy,dz,grade [g/t Au]\n';
    for (let k = 0; k < 6; ++k) for (let j = 0; j < 8; ++j) for (let i = 0; i < 12; ++i)
      csv += `${35497250 + 500 * i},${3384850 + 500 * j},${-450 + 500 * k},500,500,500,${i + 0.5}\n`;
    const blocky = await startServer(binary, {
      models: [{ name: 'blocky', triangles: 30000, seed: 7 }],
      files: { 'blocky.blocks.json': JSON.stringify({ source: 'blocky_cells.csv', clip: ['Shaximiao Formation (graben)'] }),
               'blocky_cells.csv': csv },
    });
    const ctx = await browser.newContext({ ...DESKTOP, locale: 'en-GB' });
    try {
      await ctx.route((url) => !url.href.startsWith(blocky.url), (route) => { foreign.push(route.request().url()); return route.abort('blockedbyclient'); });
      const page = await ctx.newPage();
      page.errors = [];
      page.on('pageerror', (e) => page.errors.push(e.message));
      await page.goto(`${blocky.url}/#lang=en`);
      await page.waitForSelector('body[data-ready="1"]', { timeout: 20000 });
      const b = await page.evaluate(() => window.geoslice.S.model.bounds);
      const y = (b.min[1] + b.max[1]) / 2;
      await page.evaluate((y) => window.geoslice.openSection({ plane: `0,1,0,${-y}`, vx: 1 }), y);
      await page.waitForFunction(() => window.geoslice.S.section, null, { timeout: 15000 });
      check(!(await page.locator('#blockTools').isHidden()), 'the block colouring control is shown');
      const options = await page.evaluate(() => [...document.querySelectorAll('#blockColour option')].map((o) => o.value));
      check(options.includes('grade'), `properties offered: ${options}`);
      await page.selectOption('#blockColour', 'grade');
      await page.waitForFunction(() => window.geoslice.S.section?.def.colour === 'grade', null, { timeout: 15000 });
      await page.waitForFunction(() => document.getElementById('busy').hidden, null, { timeout: 15000 });
      const q = await page.evaluate(() => window.geoslice.S.section.q);
      check(q.includes('colour=grade'), `section query: ${q}`);
      await page.waitForFunction(() => { const i = document.getElementById('blockLegend'); return !i.hidden && i.complete && i.naturalWidth > 0; }, null, { timeout: 15000 });
      // A pixel of the graben's top stratum in the middle of the section: a block cell with its grade.
      const x = (b.min[0] + b.max[0]) / 2;
      let found = null;
      for (let z = b.max[2] - 100; z > b.min[2] && !found; z -= 100) {
        const frame = `${x - 5},${x + 5},${z - 5},${z + 5}`;
        const r = await (await fetch(`${blocky.url}/v1/models/blocky/query?${q}&frame=${frame}&size=10x10&px=5&py=5`)).json();
        if (r.block?.cell) found = r;
      }
      check(found, 'a coloured block cell under the section');
      const gradeValue = found.block.values?.grade ?? found.block.properties?.grade ?? found.block.grade;
      check(gradeValue != null, `the answer names the grade: ${JSON.stringify(found.block)}`);
      await page.locator('#tab-3d').click();
      await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small, null, { timeout: 30000 });
      check((await page.evaluate(() => window.geoslice.S.shown3d.params)).includes('colour=grade'), '3D asks for the colouring');
      await shot(page, 'desktop-blocks-3d');
      check(page.errors.length === 0, `page errors: ${page.errors.join('; ')}`);
    } finally {
      await ctx.close();
      blocky.stop();
    }
  },

  async assets_cached_and_typed() {
    const r = await fetch(`${origin}/`);
    check(r.headers.get('cache-control') === 'no-cache' && r.headers.get('etag'), 'index: no-cache + ETag');
    const html = await r.text();
    const v = /app\.js\?v=([0-9a-f]+)/.exec(html)?.[1];
    check(v, 'asset URLs carry the build id');
    for (const [p, type] of [['app.js', 'text/javascript'], ['app.css', 'text/css'], ['leaflet/leaflet.js', 'text/javascript'],
                             ['leaflet/leaflet.css', 'text/css'], ['leaflet/images/layers.png', 'image/png']]) {
      const a = await fetch(`${origin}/web/${p}?v=${v}`);
      check(a.status === 200 && a.headers.get('content-type').startsWith(type), `${p}: ${a.status} ${a.headers.get('content-type')}`);
      check(/max-age=\d+/.test(a.headers.get('cache-control')), `${p} cache-control`);
      const again = await fetch(`${origin}/web/${p}`, { headers: { 'If-None-Match': a.headers.get('etag') } });
      check(again.status === 304, `${p}: If-None-Match gives 304`);
    }
    // Every module the client imports (followed from app.js) is served, and every import
    // names it with this build's id, so a browser never mixes modules of two builds.
    const seen = new Set(), todo = ['app.js'];
    while (todo.length) {
      const p = todo.pop();
      if (seen.has(p)) continue;
      seen.add(p);
      const a = await fetch(`${origin}/web/${p}?v=${v}`);
      check(a.status === 200 && a.headers.get('content-type').startsWith('text/javascript'), `${p}: ${a.status}`);
      const text = await a.text();
      for (const m of text.matchAll(/^import\s[^'"]*['"]([^'"]+)['"]/gm)) {
        const [file, query] = m[1].replace(/^\.\//, '').split('?');
        check(query === `v=${v}`, `${p} imports ${m[1]} with the build id ${v}`);
        todo.push(file);
      }
    }
    check(seen.size >= 12, `app.js and its modules: ${[...seen].join(' ')}`);
    check((await fetch(`${origin}/web/nothing.js`)).status === 404, 'unknown asset 404');
  },

  // Measuring (issue: distance and bearing on the plan; true distance and apparent dip on a
  // section whatever vx). The plan's line A-B of legs (+300 m east, +400 m north) is 500 m at
  // bearing 037° (closed form). On a vertical section, taps at section points 800 m apart
  // along and 400 m apart up the section measure hypot(800, 400) = 894.4 m and an apparent dip
  // of atan(400 / 800) = 26.57°, the same at vx 1 and vx 2 (within the taps' pixel rounding).
  async measuring_in_true_metres() {
    const page = await newPage(DESKTOP, { locale: 'en-GB' });
    await open(page);
    const b = await bounds(page);
    const x0 = b.min[0] + 0.2 * (b.max[0] - b.min[0]), y0 = b.min[1] + 0.5 * (b.max[1] - b.min[1]);
    const hint = await page.evaluate(([x, y]) => {
      window.geoslice.setPoints([[x, y], [x + 300, y + 400]]);
      return document.getElementById('drawHint').textContent;
    }, [x0, y0]);
    check(hint.includes('500 m') && hint.includes('A→B 037°'), `plan hint: ${hint}`);
    const results = [];
    for (const vx of [1, 2]) {
      await page.evaluate(([x, y, x1, vx]) => window.geoslice.openSection({ line: `${x},${y},${x1},${y}`, vx }),
                          [x0, y0, b.max[0] - 0.2 * (b.max[0] - b.min[0]), vx]);
      await page.waitForFunction((vx) => window.geoslice.S.section?.def?.vx === vx, vx, { timeout: 20000 });
      await settle(page);
      if (await page.locator('#measure').getAttribute('aria-pressed') !== 'true') await page.locator('#measure').click();
      // Section points around the map's centre, placed through the tile grid's own rule
      // (api/view.hpp TileGrid: lng = (u - u0) 256 / size0, lat = (v - v0) vx 256 / size0).
      const taps = await page.evaluate(() => {
        const map = window.geoslice.maps().sectionMap, g = window.geoslice.S.section.grid, c = map.getCenter();
        const u = g.origin.u + (c.lng * g.size0) / 256, v = g.origin.v + (c.lat * g.size0) / (256 * g.exaggeration);
        const box = map.getContainer().getBoundingClientRect();
        return [[u - 400, v - 200], [u + 400, v + 200]].map(([pu, pv]) => {
          const p = map.latLngToContainerPoint([((pv - g.origin.v) * g.exaggeration * 256) / g.size0, ((pu - g.origin.u) * 256) / g.size0]);
          return [box.left + p.x, box.top + p.y];
        });
      });
      for (const [x, y] of taps) await page.mouse.click(x, y);
      const r = await page.evaluate(() => ({ m: window.geoslice.S.measure.result, text: document.getElementById('measureOut').textContent,
                                              answer: window.geoslice.S.answer }));
      check(r.m, `vx ${vx}: no measurement (${r.text})`);
      check(!r.answer, `vx ${vx}: a measuring tap also queried`);
      check(Math.abs(r.m.length - 894.43) < 894.43 * 0.015, `vx ${vx}: length ${r.m.length} m, want 894.4`);
      check(Math.abs(r.m.dip - 26.565) < 1.0, `vx ${vx}: apparent dip ${r.m.dip}°, want 26.57`);
      check(r.text.includes('apparent dip') && r.text.includes('(true)'), `vx ${vx}: ${r.text}`);
      results.push(r.m);
      // The units along the line (apparent thickness): the stretches cover the whole line
      // (the section's regions partition the model), and the server's own pixel query at each
      // stretch's middle names the same record.
      await page.waitForFunction(() => window.geoslice.S.measure.result?.units, null, { timeout: 15000 });
      const along = await page.evaluate(() => ({ units: window.geoslice.S.measure.result.units, pts: window.geoslice.S.measure.pts,
        line: window.geoslice.S.section.def.line, text: document.getElementById('measureOut').textContent }));
      const sum = along.units.reduce((acc, u) => acc + u.length, 0);
      check(along.units.length >= 2, `vx ${vx}: ${along.units.length} units along the line`);
      check(Math.abs(sum - r.m.length) < 1e-6 * r.m.length, `vx ${vx}: stretches sum to ${sum} m of ${r.m.length}`);
      check(along.text.includes('apparent thickness along it'), along.text);
      if (vx === 1) {
        const [a, bb] = along.pts;
        for (const u of along.units) {
          const tm = 0.5 * (u.from + u.to), mu = a[0] + tm * (bb[0] - a[0]), mv = a[1] + tm * (bb[1] - a[1]);
          const view = `line=${along.line}&frame=${mu - 1},${mu + 1},${mv - 1},${mv + 1}&size=101x101&px=50&py=50`;
          const answer = await (await fetch(`${origin}/v1/models/mine-a/query?${view}`)).json();
          check(answer.record?.id === u.record || answer.record === u.record,
                `stretch ${u.name} (${u.length.toFixed(1)} m): the query at its middle says ${JSON.stringify(answer.record)?.slice(0, 80)}`);
        }
      }
      await shot(page, `measure-vx${vx}`);
    }
    check(Math.abs(results[0].length - results[1].length) < 15, `vx 1 and 2 differ: ${results.map((m) => m.length)}`);
    check(page.errors.length === 0, `page errors: ${page.errors.join('; ')}`);
    await page.context().close();
  },

  // Go to a coordinate: easting/northing in the model's CRS, or CGCS2000 lon/lat (mine-a is
  // EPSG:4523, Gauss-Kruger zone 35); the plan centres on it. The lon/lat of a point comes
  // from PROJ's cs2cs when it is installed (an independent conversion), else from the page's
  // own inverse series; outside the model and bad text are refused, naming the problem.
  async go_to_a_coordinate() {
    const page = await newPage(DESKTOP, { locale: 'en-GB' });
    await open(page);
    const b = await bounds(page);
    const x = b.min[0] + 0.37 * (b.max[0] - b.min[0]), y = b.min[1] + 0.61 * (b.max[1] - b.min[1]);
    // The map's centre in metres, and a pixel's size there (Leaflet centres to whole pixels).
    const centre = () => page.evaluate(() => {
      const g = window.geoslice.S.plan.grid, map = window.geoslice.maps().planMap, c = map.getCenter();
      const px = g.size0 / 256 / 2 ** map.getZoom();
      return [g.origin.u + (c.lng * g.size0) / 256, g.origin.v + (c.lat * g.size0) / (256 * g.exaggeration), px];
    });
    const goto = async (text) => {
      await page.locator('#goto').fill(text);
      await page.locator('#gotoBtn').click();
      await page.waitForTimeout(100);
    };
    await goto(`${x.toFixed(2)}, ${y.toFixed(2)}`);
    let c = await centre();
    check(Math.hypot(c[0] - x, c[1] - y) < c[2], `easting/northing: centre ${c} for ${x}, ${y}`);
    let lonlat;
    try {
      const out = execFileSync('cs2cs', ['-f', '%.10f', 'EPSG:4523', 'EPSG:4490'], { input: `${y} ${x}\n` }).toString().trim().split(/\s+/);
      lonlat = [Number(out[1]), Number(out[0])];  // EPSG:4490 is lat, lon
    } catch (_) {
      lonlat = await page.evaluate(([x, y]) => window.geoslice.V.gkToLonLat(window.geoslice.V.gaussKruger('EPSG:4523'), x, y), [x, y]);
    }
    await page.evaluate(() => window.geoslice.maps().planMap.panBy([200, 120], { animate: false }));
    await goto(`${lonlat[0].toFixed(9)}, ${lonlat[1].toFixed(9)}`);
    c = await centre();
    check(Math.hypot(c[0] - x, c[1] - y) < c[2], `lon/lat ${lonlat}: centre ${c} for ${x}, ${y}`);
    // The point itself, converted by the page: within 1 cm of cs2cs's.
    const p = await page.evaluate(() => window.geoslice.S.gotoPoint);
    check(Math.hypot(p[0] - x, p[1] - y) < 0.01, `lon/lat ${lonlat} -> ${p}, want ${x}, ${y}`);
    await goto(`${(b.max[0] + 5000).toFixed(0)}, ${y.toFixed(0)}`);
    let status = await page.locator('#status').textContent();
    check(/outside the model/.test(status), `outside: ${status}`);
    c = await centre();
    check(Math.hypot(c[0] - x, c[1] - y) < c[2], 'a refused point does not move the plan');
    await goto('north of the pit');
    status = await page.locator('#status').textContent();
    check(/two numbers/.test(status), `bad text: ${status}`);
    check(page.errors.length === 0, `page errors: ${page.errors.join('; ')}`);
    await page.context().close();
    // My position: allowed, the device at the same lon/lat -> the same point; refused -> said.
    const here = await newPage(DESKTOP, { locale: 'en-GB', geolocation: { longitude: lonlat[0], latitude: lonlat[1] },
                                          permissions: ['geolocation'] });
    await open(here);
    await here.locator('#locate').click();
    await here.waitForFunction(() => window.geoslice.S.gotoPoint, null, { timeout: 10000 });
    const q = await here.evaluate(() => window.geoslice.S.gotoPoint);
    check(Math.hypot(q[0] - x, q[1] - y) < 0.01, `my position ${lonlat} -> ${q}, want ${x}, ${y}`);
    await here.context().close();
    const denied = await newPage(DESKTOP, { locale: 'en-GB' });
    await open(denied);
    await denied.locator('#locate').click();
    await denied.waitForFunction(() => /My position/.test(document.getElementById('status').textContent), null, { timeout: 20000 });
    await denied.context().close();
  },

  // A model baked again on the server while a page shows it (last: it changes mine-b). The
  // server swaps the version in (it watches its models directory); the page's pinned URLs
  // then answer 404 model_version, and the page reloads itself at the new version with the
  // same view (its permalink) instead of showing failed tiles.
  async model_baked_again_reloads_the_view() {
    const page = await newPage(DESKTOP, { locale: 'en-GB' });
    await open(page, '#m=mine-b');
    const v1 = await state(page, () => window.geoslice.S.model.version);
    check(await state(page, () => window.geoslice.S.model.id) === 'mine-b', 'mine-b on show');
    const tmp = path.join(server.dir, 'mine-b.tmp.glb.part');
    execFileSync(binary, ['generate', '--triangles', '30000', '--seed', '8', '--crs', 'EPSG:4523', '--at', '105.3,30.9', '--out', tmp]);
    fs.renameSync(tmp, path.join(server.dir, 'mine-b.glb'));
    let v2 = v1;
    for (let i = 0; i < 300 && v2 === v1; ++i) {
      await new Promise((r) => setTimeout(r, 100));
      v2 = (await (await fetch(`${origin}/v1/models/mine-b`)).json()).version;
    }
    check(v2 !== v1, 'the server did not load the model baked again within 30 s');
    // The next request of the page (a query of the plan's centre) meets the new version.
    await page.locator('[data-mode="query"]').click();
    const box = await page.locator('#planMap').boundingBox();
    const reloaded = page.waitForEvent('load', { timeout: 20000 });
    await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
    await reloaded;
    await page.waitForSelector('body[data-ready="1"]', { timeout: 20000 });
    await settle(page);
    const after = await state(page, () => ({ id: window.geoslice.S.model.id, version: window.geoslice.S.model.version,
      failed: document.querySelectorAll('#planMap .tile-failed').length }));
    check(after.id === 'mine-b' && after.version === v2, `after the reload: ${JSON.stringify(after)} (want version ${v2})`);
    check(after.failed === 0, `${after.failed} failed plan tiles after the reload`);
    check(page.errors.length === 0, `page errors: ${page.errors.join('; ')}`);
    await page.context().close();
  },
};

// GEOSLICE_WEB_ONLY=name,name runs only those tests (while working on one).
const only = (process.env.GEOSLICE_WEB_ONLY || '').split(',').filter(Boolean);
for (const [name, fn] of Object.entries(tests)) {
  if (only.length && !only.includes(name)) continue;
  if (filter && !name.includes(filter)) continue;
  const t0 = Date.now();
  try {
    await fn();
    ++passed;
    console.log(`ok   ${name} (${Date.now() - t0} ms)`);
  } catch (e) {
    failures.push(name);
    console.log(`FAIL ${name}: ${e.message}`);
  }
}
await browser.close();
server.stop();
if (foreign.length) {
  console.log(`FAIL requests to other origins: ${[...new Set(foreign)].join(', ')}`);
  failures.push('foreign requests');
} else console.log('ok   zero requests to other origins');
console.log(`${passed} passed, ${failures.length} failed; screenshots in ${outDir}`);
process.exit(failures.length ? 1 : 0);
