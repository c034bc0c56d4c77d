// gmotion studio in real Chromium (issue 16): `node studio.mjs path/to/gmotion`.
//
// Starts `gmotion studio --no-open --port 0` on a copy of grammars/toy.{gm,svg}, loads the
// page and checks: typing a rule changes the preview; a broken grammar shows a located
// diagnostic while the preview stays; clicking a shape highlights its timeline row; a
// frozen variation keeps its seed when the rest re-roll; save writes the file; an edit of
// the file on disk shows up in the page; no request leaves 127.0.0.1; and `animate -o
// preview.html` plays with the network off. Saves a screenshot to $STUDIO_SCREENSHOT when
// set (`STUDIO_SCREENSHOT=docs/studio.png` refreshes the README's picture), else beside its
// work files, so that a test run leaves the checkout as it was. Exits 1 on the first
// failed check.
import { spawn, spawnSync } from 'node:child_process';
import { copyFileSync, mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname } from 'node:path';
import { createInterface } from 'node:readline';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const root = join(here, '..', '..');
const gm = process.argv[2];
if (!gm) {
  console.error('usage: node studio.mjs path/to/gmotion');
  process.exit(2);
}

const dir = mkdtempSync(join(tmpdir(), 'gmotion-studio-'));
for (const f of ['toy.gm', 'toy.svg']) copyFileSync(join(root, 'grammars', f), join(dir, f));
const grammarFile = join(dir, 'toy.gm');

const child = spawn(gm, ['studio', '--no-open', '--port', '0', join(dir, 'toy.svg'), grammarFile], {
  stdio: ['ignore', 'pipe', 'inherit'],
});
const first = await new Promise((resolve, reject) => {
  createInterface({ input: child.stdout }).once('line', resolve);
  child.once('exit', (code) => reject(new Error(`gmotion studio exited (${code})`)));
});
const m = /^studio: (http:\/\/127\.0\.0\.1:(\d+)\/\?token=[0-9a-f]+)$/.exec(first);
if (!m) throw new Error(`unexpected first line: ${first}`);
const [, url, port] = m;
const origin = `http://127.0.0.1:${port}`;

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  // playwright gives every launch a fresh temporary profile (--user-data-dir).
});

let failed = false;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failed = true;
}

const outside = [];
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 1000 }, deviceScaleFactor: 1 });
  page.on('request', (r) => {
    if (!r.url().startsWith(origin + '/') && !r.url().startsWith('data:') && !r.url().startsWith('blob:')) outside.push(r.url());
  });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => /version 1 /.test(document.getElementById('status').textContent));
  const frameReady = (v) => page.waitForFunction((v) => {
    const img = document.getElementById('preview-img');
    return img && img.complete && img.naturalWidth > 0 && img.src.includes('&v=' + v);
  }, v);
  // Pause at 2.8 s, where the circles are in their first slice.
  await page.click('#play');
  await page.$eval('#scrub', (el) => { el.value = String(Math.round(1000 * 2.8 / 6)); el.dispatchEvent(new Event('input')); });
  await page.waitForTimeout(300);
  await frameReady(1);
  const before = await page.locator('#stage').screenshot();

  // Type a rule: the circles turn red.
  const textarea = page.locator('#grammar');
  await textarea.click();
  await page.keyboard.press('Control+End');
  await page.keyboard.type('\nanimate(fill, local, 0, #ff0000) : [b, c] -> [red]\n');
  await page.waitForFunction(() => /version 2 /.test(document.getElementById('status').textContent));
  await frameReady(2);
  await page.waitForTimeout(200);
  const after = await page.locator('#stage').screenshot();
  check(!before.equals(after), 'typing a rule changes the preview');
  const good = await textarea.inputValue();

  // Break it: a located diagnostic, the preview stays at version 2.
  await page.keyboard.type('timesplit(0.5 : [all');
  await page.waitForSelector('#diagnostics .diagnostic');
  const diag = await page.textContent('#diagnostics');
  check(/line \d+, column \d+/.test(diag), `a broken grammar shows a located diagnostic (${diag.split('\n')[0]})`);
  await page.waitForTimeout(1200);
  const status = await page.textContent('#status');
  const still = await page.$eval('#preview-img', (img) => img.complete && img.naturalWidth > 0 && img.src.includes('&v=2'));
  check(/version 2 /.test(status) && still, 'the last good animation stays while the grammar is broken');
  await textarea.fill(good);
  await page.waitForSelector('#diagnostics .ok');

  // Put the caret on a number: a slider; dragging the number rewrites it.
  const pos = good.indexOf('translate(260');
  await textarea.evaluate((g, p) => { g.focus(); g.setSelectionRange(p + 10, p + 10); }, pos);
  await page.keyboard.press('ArrowRight');
  await page.waitForSelector('#slider-box', { state: 'visible' });
  const knob = await page.locator('#slider-value').boundingBox();
  await page.mouse.move(knob.x + 2, knob.y + 2);
  await page.mouse.down();
  await page.mouse.move(knob.x + 42, knob.y + 2, { steps: 4 });
  await page.mouse.up();
  const dragged = await textarea.inputValue();
  check(dragged.includes('translate(300'), `dragging a number rewrites it (${/translate\(\d+/.exec(dragged)})`);
  await textarea.fill(good);
  await page.waitForSelector('#diagnostics .ok');

  // Click the square (centroid 100, 160 in a 520 × 320 scene, at 0 s: hit-testing follows
  // the frame shown): its row is highlighted.
  await page.$eval('#scrub', (el) => { el.value = '0'; el.dispatchEvent(new Event('input')); });
  await page.waitForTimeout(300);
  const box = await page.locator('#overlay').boundingBox();
  await page.mouse.click(box.x + box.width * 100 / 520, box.y + box.height * 160 / 320);
  await page.waitForTimeout(300);
  const row = await page.$eval('#timeline .row.sel', (r) => r.querySelector('.name').textContent).catch(() => null);
  check(row === 's#0', `clicking a shape highlights its timeline row (${row})`);
  const listed = await page.$eval('#layer-rows .layer.sel', (r) => r.getAttribute('aria-label')).catch(() => null);
  check(listed === 's#0', `and its row in the layer tree (${listed})`);

  // Freeze the first variation, re-roll the others.
  await page.waitForSelector('#variations .cell');
  const seeds = () => page.$$eval('#variations .cell', (cs) => cs.map((c) => c.dataset.seed));
  const s0 = await seeds();
  await page.check('#variations .cell:first-child .freeze');
  await page.click('#var-roll');
  const s1 = await seeds();
  const frozen = await page.$eval('#variations .cell:first-child', (c) => c.classList.contains('frozen'));
  check(s1[0] === s0[0] && frozen && s1.slice(1).some((s, i) => s !== s0[i + 1]), 'a frozen variation keeps its seed while the rest re-roll');

  // Save writes the editor's text.
  await page.click('#save');
  await page.waitForFunction(() => /saved/.test(document.getElementById('status').textContent));
  check(readFileSync(grammarFile, 'utf8') === good, 'save writes the grammar file');

  // An edit on disk shows up.
  const edited = good.replace('duration 6s', 'duration 4s');
  writeFileSync(grammarFile, edited);
  await page.waitForFunction((t) => document.getElementById('grammar').value === t
    && / 4 s at /.test(document.getElementById('status').textContent), edited, { timeout: 10000 });
  check(true, 'an edit of the file on disk shows up in the page');

  // The other two players.
  for (const mode of ['lottie', 'smil']) {
    await page.selectOption('#mode', mode);
    await page.waitForSelector('#media svg', { timeout: 10000 });
    check(true, `the preview plays in ${mode === 'smil' ? 'SMIL' : 'lottie-web'}`);
  }
  await page.selectOption('#mode', 'render');
  await page.click('#play');
  await page.waitForTimeout(1500);
  await page.screenshot({ path: process.env.STUDIO_SCREENSHOT || join(dir, 'studio.png') });
  check(errors.length === 0, `no script errors ${errors.join('; ')}`);
  check(outside.length === 0, `no request leaves 127.0.0.1 ${outside.join(' ')}`);

  // `animate -o preview.html` plays with the network off: every request but the file's
  // own is refused.
  const html = join(dir, 'preview.html');
  const run = spawnSync(gm, ['animate', grammarFile, '-o', html], { stdio: 'inherit' });
  check(run.status === 0, 'gmotion animate -o preview.html');
  const offline = await browser.newPage();
  const asked = [];
  await offline.route('**/*', (r) => {
    if (r.request().url().startsWith('file://')) return r.continue();
    asked.push(r.request().url());
    return r.abort();
  });
  const perrors = [];
  offline.on('pageerror', (e) => perrors.push(String(e)));
  await offline.goto('file://' + html);
  await offline.waitForSelector('#lottie svg g', { timeout: 10000 });
  const smilPlays = await offline.$eval('#smil svg', (svg) => svg.getCurrentTime() >= 0 && svg.querySelectorAll('animate, animateTransform, animateMotion').length > 0);
  check(asked.length === 0 && perrors.length === 0 && smilPlays, `preview.html plays offline ${asked.join(' ')} ${perrors.join('; ')}`);
} catch (e) {
  console.log(`FAIL ${e.stack || e}`);
  failed = true;
} finally {
  await browser.close();
  child.kill();
}
process.exit(failed ? 1 : 0);
