// The page `gmotion animate … -o preview.html` writes, in real Chromium (issue 43, item 8):
// `node preview.mjs path/to/gmotion`.
//
// Checks that the timeline lists every shape (250 squares: past the 200 rows the page
// used to stop at), drawing only the rows in view, the last square reachable by scrolling;
// that the Lottie side of a `loop false` grammar stops on its last frame while a looping
// one goes on; and that the page raises no script error. Exits 1 on the first failed check.
import { spawnSync } from 'node:child_process';
import { mkdtempSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { chromium } from 'playwright-core';

const gm = process.argv[2];
if (!gm) {
  console.error('usage: node preview.mjs path/to/gmotion');
  process.exit(2);
}
const dir = mkdtempSync(join(tmpdir(), 'gmotion-preview-'));
const SQUARES = 250;
let squares = '';
for (let i = 0; i < SQUARES; i += 1) {
  squares += `<rect data-tag="sq" x="${(i % 25) * 16}" y="${Math.floor(i / 25) * 16}" width="12" height="12" fill="#1d71b8"/>`;
}
writeFileSync(join(dir, 'grid.svg'), `<svg xmlns="http://www.w3.org/2000/svg" width="400" height="160">${squares}</svg>`);
const grammar = (loop) => `scene grid.svg\nduration 1s\nfps 30\nloop ${loop}\n`
  + 'timesplit(0.5, 0.5) : [all, sq] -> [turn, inv_turn]\n'
  + 'animate(affine, local, 0.002 * id, rotate(90)) : [turn, sq] -> [turned]\n';
writeFileSync(join(dir, 'once.gm'), grammar('false'));
writeFileSync(join(dir, 'loop.gm'), grammar('true'));

let failed = false;
const check = (ok, what) => {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failed = true;
};

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu'],
});
try {
  for (const name of ['once', 'loop']) {
    const html = join(dir, `${name}.html`);
    const run = spawnSync(gm, ['-q', 'animate', join(dir, `${name}.gm`), '-o', html], { stdio: 'inherit' });
    check(run.status === 0, `gmotion animate ${name}.gm -o ${name}.html`);
    const page = await browser.newPage({ viewport: { width: 1100, height: 900 } });
    const errors = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    await page.goto('file://' + html);
    await page.waitForSelector('#lottie svg g', { timeout: 10000 });
    if (name === 'once') {
      const count = await page.textContent('#timeline-count');
      check(count === `(${SQUARES} shapes)`, `the timeline counts every shape: ${count}`);
      const rows = await page.getByRole('listitem').count();
      check(rows > 0 && rows < 100, `only the rows in view are built (${rows})`);
      await page.$eval('#timeline', (v) => { v.scrollTop = v.scrollHeight; });
      await page.waitForTimeout(200);
      const last = page.getByRole('listitem').filter({ hasText: `sq#${SQUARES - 1}` });
      check(await last.count() === 1, `the last shape's row (sq#${SQUARES - 1}) is reached by scrolling`);
      const slices = await last.locator('.slice').allTextContents();
      check(slices.includes('turned') && slices.includes('inv_turned'), `its slices are drawn: ${slices.join(', ')}`);
    }
    // One second of animation, then 1.5 s more: a looping player is somewhere in its second
    // pass, one that plays once has stopped on its last frame.
    await page.waitForTimeout(2500);
    const state = await page.evaluate(() => ({ paused: anim.isPaused, frame: anim.currentFrame, total: anim.totalFrames }));
    if (name === 'once') {
      check(state.paused && state.frame >= state.total - 1, `loop false: lottie-web stopped on its last frame (${JSON.stringify(state)})`);
    } else {
      check(!state.paused, `loop true: lottie-web still plays (${JSON.stringify(state)})`);
    }
    check(errors.length === 0, `no script errors ${errors.join('; ')}`);
    await page.close();
  }
} catch (e) {
  console.log(`FAIL ${e.stack || e}`);
  failed = true;
} finally {
  await browser.close();
}
process.exit(failed ? 1 : 0);
