// The studio started from an After Effects animation (issue 45, item 5):
// `node studio_learn.mjs path/to/gmotion`.
//
// `gmotion studio --learn material_wave_loading.json wave.gm` learns the grammar and its
// still scene, then opens them: the page's grammar is the file's, it builds with no
// problem, the five dots are rows of the timeline, and each dot's jump starts later than
// the one before (the stagger the animation holds, found as offsets). With $STUDIO_SHOTS
// set to a folder, saves the timeline docs/learn.md shows. Exits 1 on the first failed
// check.
import { readFileSync, mkdtempSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { launchChromium, startStudioWith } from './studio_harness.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const root = join(here, '..', '..');
const gm = process.argv[2];
if (!gm) {
  console.error('usage: node studio_learn.mjs path/to/gmotion');
  process.exit(2);
}
const shots = process.env.STUDIO_SHOTS || null;
const dir = mkdtempSync(join(tmpdir(), 'gmotion-studio-learn-'));
const animation = join(root, 'cli', 'tests', 'data', 'learn', 'material_wave_loading.json');
const grammarFile = join(dir, 'wave.gm');

let failed = false;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failed = true;
}

const children = [];
const url = await startStudioWith(gm, ['--learn', animation, grammarFile], children);
const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1100, height: 760 }, deviceScaleFactor: 1 });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => /version 1 /.test(document.getElementById('status').textContent));
  await page.getByRole('button', { name: 'play' }).click(); // pause: the picture holds still
  const learned = readFileSync(grammarFile, 'utf8');
  const shown = await page.getByRole('textbox', { name: 'grammar' }).inputValue();
  check(shown === learned && /timesplit/.test(learned), 'the page shows the learned grammar, as written to the file');
  const diag = (await page.textContent('#diagnostics')).trim();
  check(/no problems/.test(diag), `the learned grammar builds (${diag.split('\n')[0]})`);
  // Each dot's first change: its start, in seconds, from the timeline's sliders (named
  // `change start K of TAG#ID`), dots in the order of their rows.
  const starts = await page.evaluate(() => {
    const first = new Map();
    for (const s of document.querySelectorAll('#rows [role=slider]')) {
      const m = /^change start \d+ of (.+#\d+)$/.exec(s.getAttribute('aria-label') || '');
      if (m && !first.has(m[1])) first.set(m[1], +s.getAttribute('aria-valuenow'));
    }
    return [...first.values()];
  });
  check(starts.length === 5, `five dots have a change to start (${starts.length})`);
  const gaps = starts.slice(1).map((s, k) => s - starts[k]);
  check(gaps.every((g) => g > 0.1 && g < 0.25), `each dot jumps later than the one before (starts ${starts.map((s) => s.toFixed(3)).join(', ')} s)`);
  // Seek to a time where the stagger shows: the first dots up, the last ones still down.
  await page.getByRole('slider', { name: 'time', exact: true }).fill('340');   // in thousandths of the length
  await page.waitForTimeout(500);
  if (shots) await page.screenshot({ path: join(shots, 'learn-stagger.png') });
  check(errors.length === 0, `no script errors ${errors.join('; ')}`);
} finally {
  await browser.close();
  for (const c of children) c.kill();
}
process.exit(failed ? 1 : 0);
