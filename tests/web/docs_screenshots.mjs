// The README's screenshots: docs/web-phone.png and docs/web-desktop.png, from the demo.
//   node tests/web/docs_screenshots.mjs build/cli/geoslice docs
import path from 'node:path';
import { startServer, launch, PHONE, DESKTOP } from './lib.mjs';

const [binary, out] = process.argv.slice(2);
const server = await startServer(binary, { demo: true });
const browser = await launch();
const idle = (page) => page.waitForFunction(() => document.getElementById('busy').hidden, null, { timeout: 30000 });

async function session(device, scale) {
  const ctx = await browser.newContext({ ...device, deviceScaleFactor: scale });
  const page = await ctx.newPage();
  await page.goto(`${server.url}/`);
  await page.waitForSelector('body[data-ready="1"]');
  const b = await page.evaluate(() => window.geoslice.S.model.bounds);
  const X = (f) => b.min[0] + f * (b.max[0] - b.min[0]), Y = (f) => b.min[1] + f * (b.max[1] - b.min[1]);
  await page.evaluate((pts) => { window.geoslice.setPoints(pts); }, [[X(0.08), Y(0.3)], [X(0.45), Y(0.55)], [X(0.92), Y(0.5)]]);
  await page.evaluate(() => window.geoslice.cut());
  await page.waitForFunction(() => window.geoslice.S.section);
  await idle(page);
  return page;
}
// Phone: the A-B-C section with an answer at the orebody's host.
{
  const page = await session(PHONE, 2);
  const m = await page.locator('#sectionMap').boundingBox();
  await page.touchscreen.tap(m.x + m.width * 0.45, m.y + m.height * 0.55);
  await page.waitForFunction(() => window.geoslice.S.answer);
  await idle(page);
  await page.screenshot({ path: path.join(out, 'web-phone.png') });
  await page.context().close();
}
// Desktop: the 3D view with its plane and profile, an answer from the profile.
{
  const page = await session(DESKTOP, 1);
  await page.locator('#tab-3d').click();
  await page.locator('#plAz').fill('60');
  await page.locator('#plOffset').fill('300');
  await page.waitForFunction(() => window.geoslice.S.shown3d && !window.geoslice.S.shown3d.small && window.geoslice.S.shown3d.params.includes('size'));
  await page.waitForTimeout(500);
  await idle(page);
  const p = await page.locator('#profileImg').boundingBox();
  await page.mouse.click(p.x + p.width * 0.3, p.y + p.height * 0.5);
  await page.waitForFunction(() => window.geoslice.S.answer);
  await idle(page);
  await page.screenshot({ path: path.join(out, 'web-desktop.png') });
  await page.context().close();
}
await browser.close();
server.stop();
