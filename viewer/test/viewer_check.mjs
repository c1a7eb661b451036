// Load a geotex viewer page in Debian's headless Chromium and check it:
//   node test/viewer_check.mjs PAGE.html SCREENSHOT.png [EXPECTED_VIEWS] [--labels-on-mesh] [--size-ratio R]
// Fails (exit 1) on a console error or page error, a missing canvas, a blank picture, a view without
// its mesh, a decoded mesh whose box differs from the page's, or toggles that do not change the
// picture. --labels-on-mesh: every view with edge labels draws them on its mesh (red pixels only
// where the mesh is, and the page's own projections of the line points inside the mesh's pixels),
// before and after orbiting. --size-ratio R: the last view's mesh looks R times as tall as the
// first's (one shared scale). Exit 77 (skip) when Chromium or playwright-core is absent.
import { existsSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';

const SKIP = 77;
const flags = process.argv.slice(2);
const take = (name, arity) => {
  const i = flags.indexOf(name);
  return i < 0 ? null : flags.splice(i, 1 + arity).slice(1);
};
const labels_on_mesh = take('--labels-on-mesh', 0) !== null;
const size_ratio = (take('--size-ratio', 1) || [null])[0];
const [page_path, shot_path, expected_views = '1'] = flags;
if (!page_path || !shot_path) {
  console.error('usage: node test/viewer_check.mjs PAGE.html SCREENSHOT.png [EXPECTED_VIEWS]');
  process.exit(2);
}
const chromium_path = process.env.GEOTEX_CHROMIUM || '/usr/bin/chromium';
if (!existsSync(chromium_path)) {
  console.log(`SKIP: ${chromium_path} not found (install Debian's chromium: scripts/setup_viewer.sh)`);
  process.exit(SKIP);
}
let chromium;
try {
  ({ chromium } = await import('playwright-core'));
} catch {
  console.log('SKIP: playwright-core not installed (run npm ci in viewer/: scripts/setup_viewer.sh)');
  process.exit(SKIP);
}

const profile = mkdtempSync(join(tmpdir(), 'geotex-chromium-'));
const failures = [];
const fail = (msg) => { failures.push(msg); console.error(`FAIL: ${msg}`); };
let browser;
try {
  // A fresh profile folder per run (Playwright's way of passing --user-data-dir).
  browser = await chromium.launchPersistentContext(profile, {
    executablePath: chromium_path,
    viewport: { width: 1200, height: 700 },
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const page = browser.pages()[0] || (await browser.newPage());
  const messages = [];
  page.on('console', (m) => { if (m.type() === 'error') messages.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => messages.push(`page error: ${e.message}`));
  page.on('requestfailed', (r) => messages.push(`request failed: ${r.url()}`));
  // No network: any request for something other than a local file is refused (and so an error).
  const url = pathToFileURL(resolve(page_path)).href;
  await page.route('**/*', (route) => (route.request().url().startsWith('file:') ? route.continue() : route.abort()));
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.geotexViewer && window.geotexViewer.ready, null, { timeout: 30000 })
    .catch(() => fail('viewer did not report ready within 30 s'));

  const info = await page.evaluate(() => ({
    canvas: !!document.querySelector('canvas#gl'),
    views: document.querySelectorAll('.view').length,
    fields: window.geotexViewer ? window.geotexViewer.fields : [],
    error: document.getElementById('error').textContent,
  }));
  if (!info.canvas) fail('no canvas');
  if (info.views !== Number(expected_views)) fail(`${info.views} views, expected ${expected_views}`);
  if (info.error) fail(`page shows an error: ${info.error}`);

  // The decoded meshes have the boxes the page was written with (quantisation error only).
  const boxes = await page.evaluate(() => window.geotexViewer.boxes());
  boxes.forEach((b, k) => {
    const diag = Math.hypot(...b.expected.hi.map((h, j) => h - b.expected.lo[j]));
    for (let j = 0; j < 3; ++j)
      for (const [got, want] of [[b.lo[j], b.expected.lo[j]], [b.hi[j], b.expected.hi[j]]])
        if (!(Math.abs(got - want) <= 1e-4 * diag + 1e-6 * Math.abs(want)))
          fail(`view ${k + 1}: decoded box ${JSON.stringify([b.lo, b.hi])} differs from ${JSON.stringify(b.expected)}`);
  });

  // Statistics of the canvas, per view: fraction of non-background pixels and grey-level variance.
  const stats = () => page.evaluate(() => {
    const gl = document.getElementById('gl');
    const c = document.createElement('canvas');
    c.width = gl.width; c.height = gl.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(gl, 0, 0);
    const px = ctx.getImageData(0, 0, c.width, c.height).data;
    const views = [...document.querySelectorAll('.view')].map((v) => v.getBoundingClientRect());
    const top = gl.getBoundingClientRect(), s = c.width / top.width;
    let sum = 0, sum2 = 0, n = 0, hash = 0;
    const covered = views.map(() => 0), total = views.map(() => 0);
    for (let y = 0; y < c.height; ++y) for (let x = 0; x < c.width; ++x) {
      const i = 4 * (y * c.width + x);
      const g = (px[i] + px[i + 1] + px[i + 2]) / 3;
      sum += g; sum2 += g * g; ++n;
      hash = (hash * 31 + px[i] * 7 + px[i + 1] * 3 + px[i + 2]) >>> 0;
      const vx = x / s + top.left;
      const k = views.findIndex((r) => vx >= r.left && vx < r.right);
      if (k >= 0) { ++total[k]; if (px[i] < 250 || px[i + 1] < 250 || px[i + 2] < 250) ++covered[k]; }
    }
    const mean = sum / n;
    return { variance: sum2 / n - mean * mean, covered: covered.map((c, k) => c / Math.max(1, total[k])), hash };
  });
  // Labels lie on their meshes: with the labels hidden, the mesh's pixels (grown by 2 pixels for
  // anti-aliasing) must hold every red pixel of the picture with labels, and every line point as the
  // page projects it. Counted in the page (the pixels stay there).
  async function checkLabels(when) {
    const found = await page.evaluate(() => {
      const gl = document.getElementById('gl'), toggle = document.getElementById('edges');
      const top = gl.getBoundingClientRect(), s = gl.width / top.width, w = gl.width, h = gl.height;
      const grab = (on) => {
        toggle.checked = on;
        toggle.dispatchEvent(new Event('change'));
        const c = document.createElement('canvas');
        c.width = w; c.height = h;
        const ctx = c.getContext('2d');
        ctx.drawImage(gl, 0, 0);
        return ctx.getImageData(0, 0, w, h).data;
      };
      const bare = grab(false), lined = grab(true), grow = 2;
      const mask = new Uint8Array(w * h);
      for (let y = 0; y < h; ++y) for (let x = 0; x < w; ++x) {
        const i = 4 * (y * w + x);
        if (bare[i] < 250 || bare[i + 1] < 250 || bare[i + 2] < 250)
          for (let dy = -grow; dy <= grow; ++dy) for (let dx = -grow; dx <= grow; ++dx) {
            const X = x + dx, Y = y + dy;
            if (X >= 0 && Y >= 0 && X < w && Y < h) mask[Y * w + X] = 1;
          }
      }
      return [...document.querySelectorAll('.view')].map((v, k) => {
        const pts = window.geotexViewer.labelScreenPoints(k);
        const r = v.getBoundingClientRect();
        let red = 0, off = 0, outside = 0;
        for (let y = Math.max(0, Math.ceil((r.top - top.top) * s)); y < Math.min(h, (r.bottom - top.top) * s); ++y)
          for (let x = Math.max(0, Math.ceil((r.left - top.left) * s)); x < Math.min(w, (r.right - top.left) * s); ++x) {
            const i = 4 * (y * w + x);
            if (!(lined[i] > 150 && lined[i + 1] < 90 && lined[i + 2] < 90)) continue;  // label 1's red
            ++red;
            if (!mask[y * w + x]) ++off;
          }
        for (const [px, py] of pts) {
          const x = Math.floor((px - top.left) * s), y = Math.floor((py - top.top) * s);
          if (x < 0 || y < 0 || x >= w || y >= h || !mask[y * w + x]) ++outside;
        }
        return { points: pts.length, red, off, outside };
      });
    });
    found.forEach(({ points, red, off, outside }, k) => {
      if (points === 0) return;
      console.log(`${when}, view ${k + 1}: ${red} red pixels, ${off} off the mesh; ${points} line points, ${outside} off the mesh`);
      if (red < 20) fail(`${when}, view ${k + 1}: only ${red} red pixels (labels not drawn?)`);
      if (off > 0) fail(`${when}, view ${k + 1}: ${off} of ${red} red pixels lie off the mesh`);
      if (outside > 0) fail(`${when}, view ${k + 1}: ${outside} of ${points} projected line points lie off the mesh`);
    });
  }
  if (labels_on_mesh) await checkLabels('as opened');

  // One scale for all views: the last mesh's height on screen over the first's.
  if (size_ratio) {
    const heights = await page.evaluate(() => {
      const gl = document.getElementById('gl'), top = gl.getBoundingClientRect();
      const s = gl.width / top.width, w = gl.width, h = gl.height;
      const c = document.createElement('canvas');
      c.width = w; c.height = h;
      const ctx = c.getContext('2d');
      ctx.drawImage(gl, 0, 0);
      const px = ctx.getImageData(0, 0, w, h).data;
      return [...document.querySelectorAll('.view')].map((v) => {
        const r = v.getBoundingClientRect();
        let y0 = Infinity, y1 = -Infinity;
        for (let y = 0; y < h; ++y)
          for (let x = Math.max(0, Math.ceil((r.left - top.left) * s)); x < Math.min(w, (r.right - top.left) * s); ++x) {
            const i = 4 * (y * w + x);
            if (px[i] < 250 || px[i + 1] < 250 || px[i + 2] < 250) { y0 = Math.min(y0, y); y1 = Math.max(y1, y); }
          }
        return y1 - y0 + 1;
      });
    });
    const ratio = heights[heights.length - 1] / heights[0];
    console.log(`heights on screen ${heights.join(', ')} pixels: ratio ${ratio.toFixed(3)} (expected about ${size_ratio})`);
    if (!(Math.abs(ratio / Number(size_ratio) - 1) < 0.06)) fail(`size ratio ${ratio.toFixed(3)}, expected ${size_ratio}`);
  }

  const plain = await stats();
  console.log(`canvas: grey variance ${plain.variance.toFixed(1)}, covered per view ${plain.covered.map((c) => c.toFixed(3)).join(', ')}`);
  if (!(plain.variance > 50)) fail(`canvas looks blank (grey variance ${plain.variance.toFixed(2)})`);
  plain.covered.forEach((c, k) => { if (!(c > 0.02)) fail(`view ${k + 1} shows no mesh (${(100 * c).toFixed(2)}% covered)`); });

  // Toggles change the picture.
  await page.check('#wire');
  const wired = await stats();
  if (wired.hash === plain.hash) fail('wireframe toggle did not change the picture');
  await page.uncheck('#wire');
  await page.check('#flat');
  const flat = await stats();
  if (flat.hash === plain.hash) fail('flat-shading toggle did not change the picture');
  await page.uncheck('#flat');
  if (info.fields.length > 0) {
    // Switch between no field and a field (whichever the page did not start with).
    const start = await page.inputValue('#field');
    await page.selectOption('#field', start ? '' : info.fields[0]);
    const switched = await stats();
    if (switched.hash === plain.hash) fail('choosing another field did not change the picture');
    await page.selectOption('#field', info.fields[0]);
    if (!(await page.isVisible('#legend'))) fail('no legend with a field shown');
  }
  // Orbit by dragging: every view moves together (one shared camera).
  const before = await stats();
  await page.mouse.move(300, 400);
  await page.mouse.down();
  await page.mouse.move(420, 360, { steps: 5 });
  await page.mouse.up();
  const after = await stats();
  if (after.hash === before.hash) fail('dragging did not orbit the view');
  if (labels_on_mesh) await checkLabels('after orbiting');

  await page.screenshot({ path: shot_path });
  console.log(`screenshot: ${shot_path}`);
  for (const m of messages) fail(m);
} catch (e) {
  fail(`exception: ${e.message}`);
} finally {
  if (browser) await browser.close();
  rmSync(profile, { recursive: true, force: true });
}
if (failures.length) process.exit(1);
console.log('viewer check passed');
