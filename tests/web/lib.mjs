// Shared by tests/web/web_test.mjs and bench/web_bench.mjs: start a real geoslice server,
// launch Debian's chromium through playwright-core (never a downloaded browser).
import { spawn, execFileSync } from 'node:child_process';
import fs from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
function need(name) {
  try { return require.resolve(name); } catch (_) {
    console.error(`${name} is missing: run 'npm ci' in tests/web (scripts/test.sh does)`);
    process.exit(1);
  }
}
export const { chromium } = require(need('playwright-core'));
export const axeSource = fs.readFileSync(need('axe-core/axe.min.js'), 'utf8');

export const CHROMIUM = process.env.GEOSLICE_CHROMIUM || '/usr/bin/chromium';
export const CHROMIUM_ARGS = ['--headless=new', '--no-sandbox', '--disable-gpu', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];

export const PHONE = { viewport: { width: 390, height: 844 }, deviceScaleFactor: 3, isMobile: true, hasTouch: true };
export const PHONE_SMALL = { viewport: { width: 360, height: 740 }, deviceScaleFactor: 3, isMobile: true, hasTouch: true };
export const PHONE_LANDSCAPE = { viewport: { width: 844, height: 390 }, deviceScaleFactor: 3, isMobile: true, hasTouch: true };
export const DESKTOP = { viewport: { width: 1280, height: 800 }, deviceScaleFactor: 1 };

async function freePort() {
  return new Promise((resolve, reject) => {
    const s = net.createServer();
    s.listen(0, '127.0.0.1', () => { const p = s.address().port; s.close(() => resolve(p)); });
    s.on('error', reject);
  });
}

// Two small generated models (different seeds and places) in a temporary directory, so
// that switching models can be tested; or the built-in demo when `demo` is set; or `models`:
// [{ name, triangles, seed }] generated in EPSG:4523; `extraArgs` go to `serve`. `keys`: text of an API keys file
// (api/access_keys.hpp) the server is started with.
// `files`: more files (name -> text) written beside the generated models (sidecars).
export async function startServer(binary, { demo = false, log = null, keys = null, models = null, extraArgs = [], files = {} } = {}) {
  const args = ['serve', '--host', '127.0.0.1', '--workers', '2', '--log-level', 'warn', ...extraArgs];
  let dir = null;
  if (demo) args.push('--demo-triangles', '200000');
  else {
    dir = fs.mkdtempSync(path.join(os.tmpdir(), 'geoslice-web-'));
    const list = models || [{ name: 'mine-a', triangles: 60000, seed: 1 },
      { name: 'mine-b', triangles: 30000, seed: 7, at: '105.3,30.9' }];
    for (const m of list) {
      execFileSync(binary, ['generate', '--triangles', String(m.triangles), '--seed', String(m.seed), '--crs', 'EPSG:4523',
        ...(m.at ? ['--at', m.at] : []), '--out', path.join(dir, `${m.name}.glb`)]);
    }
    for (const [name, text] of Object.entries(files)) fs.writeFileSync(path.join(dir, name), text);
    args.push('--models', dir);
  }
  if (keys) {
    dir = dir || fs.mkdtempSync(path.join(os.tmpdir(), 'geoslice-web-'));
    fs.writeFileSync(path.join(dir, 'keys'), keys);
    args.push('--keys', path.join(dir, 'keys'));
  }
  const port = await freePort();
  args.push('--port', String(port));
  const proc = spawn(binary, args, { stdio: ['ignore', log ? 'pipe' : 'ignore', 'pipe'] });
  let stderr = '';
  proc.stderr.on('data', (d) => { stderr += d; });
  const url = `http://127.0.0.1:${port}`;
  for (let i = 0; i < 300; ++i) {
    try {
      const r = await fetch(`${url}/readyz`);
      if (r.status === 200) break;
    } catch (_) { /* not up yet */ }
    if (proc.exitCode != null) throw new Error(`server exited: ${stderr}`);
    await new Promise((r) => setTimeout(r, 100));
  }
  return {
    url, proc, dir,
    stop() { proc.kill('SIGTERM'); if (dir) fs.rmSync(dir, { recursive: true, force: true }); },
  };
}

// `webgl`: WebGL through SwiftShader (software), for CesiumJS.
export async function launch({ webgl = false } = {}) {
  if (!fs.existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} is missing: apt-get install chromium (scripts/install-deps.sh)`);
  const args = webgl ? [...CHROMIUM_ARGS, '--use-angle=swiftshader', '--enable-unsafe-swiftshader'] : CHROMIUM_ARGS;
  return chromium.launch({ executablePath: CHROMIUM, args });
}

export const loadAverage = () => os.loadavg().map((x) => +x.toFixed(2));
