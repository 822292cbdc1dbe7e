// In-browser timings of the web client against a real server on this host, phone size
// (390x844, touch, scale 3), Debian's chromium. Prints JSON.
//   node bench/web_bench.mjs build/cli/geoslice [--runs 15]
// Needs tests/web/node_modules (cd tests/web && npm ci).
//   cut_first_tile_ms: Cut pressed -> POST /sections -> first tile fetched, decoded, painted
//                      (a new plane each run, so nothing is cached)
//   tap_answer_ms:     tap on the section -> query answered and shown
//   drag_frame_ms:     plane handle moved -> the small 3D frame and its profile shown
//   release_frame_ms:  handle released -> full-size 3D frame and profile shown
//   first_view_ms:     navigation -> the first plan tile painted (a fresh page each run, the
//                      browser's cache kept as a returning user's)
//   skeleton_ms:       navigation -> first contentful paint (the "Loading…" skeleton) with
//                      every API request held 2 s, as on a slow network
//   model_switch_ms:   another model picked -> its first plan tile painted (two generated mines)
import { startServer, launch, PHONE, loadAverage } from '../tests/web/lib.mjs';

const binary = process.argv[2];
const runs = Number(process.argv[process.argv.indexOf('--runs') + 1]) || 15;
if (!binary) { console.error('usage: node bench/web_bench.mjs GEOSLICE_BINARY [--runs N]'); process.exit(2); }

const stats = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  const q = (p) => s[Math.min(s.length - 1, Math.floor(p * s.length))];
  return { n: s.length, median: +q(0.5).toFixed(1), p90: +q(0.9).toFixed(1), min: +s[0].toFixed(1), max: +s[s.length - 1].toFixed(1) };
};
const loadBefore = loadAverage();
const server = await startServer(binary, { demo: true });
const browser = await launch();
const ctx = await browser.newContext(PHONE);
const page = await ctx.newPage();
await page.goto(`${server.url}/`);
await page.waitForSelector('body[data-ready="1"]', { timeout: 30000 });
const marks = (name, from) => page.evaluate(([n, f]) => window.geoslice.perf.marks.slice(f).filter((m) => m.name === n).map((m) => m.ms), [name, from]);
const count = () => page.evaluate(() => window.geoslice.perf.marks.length);
const idle = () => page.waitForFunction(() => document.getElementById('busy').hidden, null, { timeout: 30000 });

// Cut -> first tile.
const cut = [];
const b = await page.evaluate(() => window.geoslice.S.model.bounds);
for (let i = 0; i < runs; ++i) {
  const y = b.min[1] + (b.max[1] - b.min[1]) * (0.1 + (0.8 * i) / runs) + Math.random();
  const from = await count();
  await page.evaluate((y) => window.geoslice.openSection({ plane: `0,1,0,${-y}`, vx: 2 }), y);
  await page.waitForFunction((f) => window.geoslice.perf.marks.slice(f).some((m) => m.name === 'firstTile'), from, { timeout: 30000 });
  cut.push(...(await marks('firstTile', from)));
  await idle();
}
// Tap -> answer.
const tap = [];
const m = await page.locator('#sectionMap').boundingBox();
for (let i = 0; i < runs * 2; ++i) {
  const from = await count();
  await page.touchscreen.tap(m.x + m.width * (0.2 + 0.6 * ((i * 0.618) % 1)), m.y + m.height * (0.25 + 0.5 * ((i * 0.377) % 1)));
  await page.waitForFunction((f) => window.geoslice.perf.marks.slice(f).some((x) => x.name === 'answer'), from, { timeout: 10000 });
  tap.push(...(await marks('answer', from)));
}
// Plane drag in 3D.
await page.locator('#tab-3d').click();
await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small, null, { timeout: 30000 });
await idle();
const drag = [], release = [];
const cdp = await ctx.newCDPSession(page);
for (let r = 0; r < 3; ++r) {
  const h = await page.locator('#moveHandle').boundingBox();
  const cx = h.x + h.width / 2, cy = h.y + h.height / 2, dir = r % 2 ? -1 : 1;
  const from = await count();
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ x: cx, y: cy }] });
  for (let i = 1; i <= runs; ++i) {
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove', touchPoints: [{ x: cx + dir * 3 * i, y: cy + dir * 1.5 * i }] });
    await page.waitForTimeout(40);
  }
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
  await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small, null, { timeout: 30000 });
  await idle();
  const frames = await page.evaluate((f) => window.geoslice.perf.marks.slice(f).filter((x) => x.name === 'frame3d'), from);
  drag.push(...frames.filter((x) => x.small).map((x) => x.ms));
  release.push(...frames.filter((x) => !x.small).map((x) => x.ms));
}
const view = await page.locator('#view3d').boundingBox();
await ctx.close();

// First usable view, fresh pages.
const firstView = [];
const ctx2 = await browser.newContext(PHONE);
for (let i = 0; i < Math.max(5, Math.round(runs / 2)); ++i) {
  const p = await ctx2.newPage();
  await p.goto(`${server.url}/`);
  await p.waitForFunction(() => window.geoslice?.perf.marks.some((x) => x.name === 'planTile'), null, { timeout: 30000 });
  firstView.push(await p.evaluate(() => window.geoslice.perf.marks.find((x) => x.name === 'planTile').t));
  await p.close();
}
// The skeleton on a network of 2 s per API request.
const skeleton = [];
for (let i = 0; i < 3; ++i) {
  const p = await ctx2.newPage();
  await p.route((u) => u.pathname.startsWith('/v1/'), async (route) => { await new Promise((r) => setTimeout(r, 2000)); await route.continue(); });
  await p.goto(`${server.url}/`);
  await p.waitForFunction(() => performance.getEntriesByName('first-contentful-paint').length > 0, null, { timeout: 10000 });
  const fcp = await p.evaluate(() => ({ fcp: performance.getEntriesByName('first-contentful-paint')[0].startTime,
                                        text: document.getElementById('status').textContent }));
  if (!/Loading|加载/.test(fcp.text)) throw new Error(`no loading message at first paint: ${fcp.text}`);
  skeleton.push(fcp.fcp);
  await p.close();
}
await ctx2.close();
server.stop();
// Model switch, on a server of two generated mines.
const two = await startServer(binary);
const ctx3 = await browser.newContext(PHONE);
const p3 = await ctx3.newPage();
await p3.goto(`${two.url}/`);
await p3.waitForSelector('body[data-ready="1"]', { timeout: 30000 });
const ids = await p3.evaluate(() => window.geoslice.S.models.map((x) => x.id));
const switchMs = [];
for (let i = 0; i < Math.max(6, runs); ++i) {
  const from = await p3.evaluate(() => window.geoslice.perf.marks.length);
  await p3.selectOption('#model', ids[(i + 1) % ids.length]);
  await p3.waitForFunction((f) => window.geoslice.perf.marks.slice(f).some((x) => x.name === 'planTile'), from, { timeout: 30000 });
  switchMs.push(...(await p3.evaluate((f) => window.geoslice.perf.marks.slice(f).filter((x) => x.name === 'planTile').map((x) => x.ms), from)));
  await p3.waitForFunction(() => document.getElementById('busy').hidden, null, { timeout: 30000 });
}
await browser.close();
two.stop();
console.log(JSON.stringify({
  bench: 'web_bench', device: 'phone 390x844 touch dpr 3', chromium: '/usr/bin/chromium', model: 'demo (200k triangles)',
  view3d_css_px: [Math.round(view.width), Math.round(view.height)], small_frame_scale: 1 / 3,
  cut_first_tile_ms: stats(cut), tap_answer_ms: stats(tap), drag_frame_ms: stats(drag), release_frame_ms: stats(release),
  first_view_ms: stats(firstView), skeleton_ms: stats(skeleton), model_switch_ms: stats(switchMs),
  goals_ms: { cut_first_tile: 150, tap_answer_p90: 50, drag_frame_p90: 100, first_view: 1000, skeleton: 300, model_switch: 500 },
  load_average_before: loadBefore, load_average_after: loadAverage(),
}, null, 1));
