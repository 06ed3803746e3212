// The fit report in a real browser: Debian's Chromium, headless, driven by
// playwright-core (pinned in scripts/web), opens index.html from disk and
// checks that
//   - the page logs no console error and no request fails;
//   - every image loaded;
//   - every 3D view drew the model (non-background pixels in a screenshot of
//     its canvas), and hiding the body changes the picture;
//   - every figure on the page equals the one in the stage's report, to the
//     digits shown; figures shown as "not checked" are absent from the reports;
//   - the timings equal those of the stages' timing.json.
//   node scripts/tests/report_browser_test.mjs FIT_DIR   (the report is FIT_DIR/report)
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { pathToFileURL } from 'node:url';

const web = path.join(path.dirname(new URL(import.meta.url).pathname), '..', 'web', 'node_modules');
const chromiumPath = '/usr/bin/chromium';
for (const [what, where] of [['playwright-core', path.join(web, 'playwright-core')], ['Chromium', chromiumPath]]) {
  if (!fs.existsSync(where)) {
    console.error(`${what} is not installed (${where}): run \`make deps\``);
    process.exit(1);
  }
}
const { chromium } = await import(pathToFileURL(path.join(web, 'playwright-core', 'index.mjs')).href);

const fitDir = path.resolve(process.argv[2]);
const index = path.join(fitDir, 'report', 'index.html');
let failures = 0, passes = 0;
function check(ok, what) {
  if (ok) passes++;
  else {
    failures++;
    console.error('FAIL: ' + what);
  }
}

const jsonCache = new Map();
function reportValue(file, pointer) {
  if (!jsonCache.has(file)) jsonCache.set(file, JSON.parse(fs.readFileSync(path.join(fitDir, file), 'utf8')));
  let v = jsonCache.get(file);
  if (pointer === '') return v;
  for (const raw of pointer.split('/').slice(1)) {
    const key = raw.replace(/~1/g, '/').replace(/~0/g, '~');
    if (v === null || typeof v !== 'object' || !(key in v)) return undefined;
    v = v[key];
  }
  return v;
}

// The page's number, scaled back to the report's unit, and the largest
// difference its rounding allows.
function pageNumber(text, format) {
  const scale = {percent2: 100, mm2: 1000}[format] || 1;
  const m = text.replace('\u00d7', '').match(/-?\d+(\.(\d+))?/);
  if (!m) return null;
  const digits = m[2] ? m[2].length : 0;
  return {value: parseFloat(m[0]) / scale, tolerance: (0.5 * Math.pow(10, -digits) + 1e-9) / scale};
}

function compareFigure(f) {
  const where = `${f.src}#${f.ptr} (${f.format})`;
  // An empty pointer: the stage wrote nothing of the kind anywhere.
  const v = f.ptr === '' ? undefined : reportValue(f.src, f.ptr);
  if (f.absent) {
    check(f.text === 'not checked' && (v === undefined || v === null),
          `${where}: shown as not checked but the report has ${String(JSON.stringify(v)).slice(0, 200)}`);
    return;
  }
  if (v === undefined) return check(false, `${where}: on the page as "${f.text}" but not in the report`);
  if (f.format === 'text') return check(f.text === String(v), `${where}: page "${f.text}", report ${JSON.stringify(v)}`);
  if (f.format === 'yesno') return check(f.text === (v ? 'yes' : 'no'), `${where}: page "${f.text}", report ${v}`);
  if (f.format === 'integer') return check(f.text === String(v), `${where}: page "${f.text}", report ${v}`);
  const n = pageNumber(f.text, f.format);
  check(n !== null && typeof v === 'number' && Math.abs(n.value - v) <= n.tolerance,
        `${where}: page "${f.text}", report ${v}`);
}

const userDataDir = fs.mkdtempSync(path.join(os.tmpdir(), 'gp-report-chromium-'));
const context = await chromium.launchPersistentContext(userDataDir, {
  executablePath: chromiumPath,
  headless: true,
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
         '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  viewport: {width: 1280, height: 900},
});
try {
  const page = await context.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push('console error: ' + m.text()); });
  page.on('pageerror', (e) => errors.push('page error: ' + e.message));
  page.on('requestfailed', (r) => errors.push('request failed: ' + r.url()));
  page.on('request', (r) => { if (!r.url().startsWith('file:') && !r.url().startsWith('data:')) errors.push('network request: ' + r.url()); });
  await page.goto(pathToFileURL(index).href, {waitUntil: 'load'});
  const viewers = await page.locator('.viewer').count();
  await page.waitForFunction((n) => document.querySelectorAll('.viewer[data-rendered="1"]').length === n, viewers,
                             {timeout: 120000});

  // Images.
  const images = await page.$$eval('img', (all) => all.map((i) => ({src: i.getAttribute('src'), ok: i.complete && i.naturalWidth > 0})));
  check(images.length >= 2 * viewers + 3, `expected at least ${2 * viewers + 3} images, found ${images.length}`);
  for (const i of images) check(i.ok, `image did not load: ${i.src}`);

  // 3D views: count the pixels of a screenshot of each canvas that are not
  // the white background, with the body shown and hidden.
  const keyPoses = reportValue('fit/report.json', '/key_poses').length;
  check(viewers === keyPoses, `expected one 3D view per key pose (${keyPoses}), found ${viewers}`);
  async function inkOf(canvas) {
    await canvas.scrollIntoViewIfNeeded();
    const png = await canvas.screenshot();
    return page.evaluate(async (b64) => {
      const img = new Image();
      img.src = 'data:image/png;base64,' + b64;
      await img.decode();
      const c = document.createElement('canvas');
      c.width = img.width;
      c.height = img.height;
      const g = c.getContext('2d');
      g.drawImage(img, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data;
      let ink = 0;
      for (let i = 0; i < d.length; i += 4) if (d[i] < 245 || d[i + 1] < 245 || d[i + 2] < 245) ink++;
      return ink / (c.width * c.height);
    }, png.toString('base64'));
  }
  for (let k = 0; k < viewers; ++k) {
    const viewer = page.locator('.viewer').nth(k);
    const canvas = viewer.locator('canvas');
    const withBody = await inkOf(canvas);
    check(withBody > 0.05, `3D view ${k + 1}: only ${(100 * withBody).toFixed(2)} % of the canvas is drawn`);
    await viewer.locator('.show-body').uncheck();
    const without = await inkOf(canvas);
    check(without > 0.01 && without < withBody, `3D view ${k + 1}: hiding the body should leave the garment ` +
          `(${(100 * without).toFixed(2)} % drawn, with the body ${(100 * withBody).toFixed(2)} %)`);
    await viewer.locator('.show-body').check();
  }

  // Figures against the reports.
  const figures = await page.$$eval('.figure', (all) => all.map((e) => ({
    src: e.dataset.src, ptr: e.dataset.ptr, format: e.dataset.format, text: e.textContent,
    absent: e.classList.contains('absent')})));
  check(figures.length > 12 * keyPoses, `expected the key poses' figures, found ${figures.length} figures`);
  for (const f of figures) compareFigure(f);
  // Every stage of the fixture now writes every figure the page shows (the
  // sewn fit was the last one missing), so no figure needs to read "not
  // checked"; one that does is compared above (absent from the reports).
  const before = await page.locator('#before-after img').count();
  check(before === keyPoses, `expected ${keyPoses} before/after pictures (NO_ADAPT=1), found ${before}`);

  // No cell shows a raw field dump (a report's field names and values, as the
  // crossings cell once did: "deepest_body_vertex_id: -1"), only plain words and figures.
  const cells = await page.$$eval('td', (all) => all.map((e) => e.textContent));
  check(cells.length > 20, `expected the tables' cells, found ${cells.length}`);
  for (const c of cells)
    check(!/[a-z]+(_[a-z0-9]+)+\s*:/.test(c) && !/[{}\[\]"]/.test(c), `a cell shows a raw field dump: "${c}"`);
  // The page opens with the verdict, then the pictures of the poses and the
  // pattern; the tables come after.
  const order = await page.$$eval('section', (all) => all.map((e) => e.id));
  const at = (id) => order.indexOf(id);
  check(at('checks') === 0 && at('renders') === 1 && at('pattern') === 2 && at('key-poses') > at('pattern'),
        `sections in the order verdict, poses, pattern, tables; found ${order.join(', ')}`);
  const downloads = await page.$$eval('ul.downloads a', (all) => all.map((a) => a.getAttribute('href')));
  for (const f of ['files/pattern.dxf', 'files/pattern-a4.pdf', 'files/pattern-letter.pdf'])
    check(downloads.includes(f), `the page links ${f}`);
  for (const f of downloads) check(fs.existsSync(path.join(fitDir, 'report', f)), `linked file exists: ${f}`);

  // Timings (filled in from timing.js).
  const timings = await page.$$eval('.timing', (all) => all.map((e) => ({src: e.dataset.src, ptr: e.dataset.ptr, text: e.textContent})));
  check(timings.length >= 5, `expected the stages' timings, found ${timings.length}`);
  for (const t of timings) {
    const v = reportValue(t.src, t.ptr);
    check(typeof v === 'number' && Math.abs(parseFloat(t.text) - v) <= 0.005 + 1e-9, `${t.src}#${t.ptr}: page "${t.text}", file ${v}`);
  }

  for (const e of errors) check(false, e);
  await page.screenshot({path: path.join(fitDir, 'report-browser-test.png')});
} finally {
  await context.close();
  fs.rmSync(userDataDir, {recursive: true, force: true});
}
console.log(`${passes} passed, ${failures} failed`);
process.exit(failures ? 1 : 0);
