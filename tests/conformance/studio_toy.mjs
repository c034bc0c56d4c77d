// The paper's toy grammar recreated in the studio with the mouse and the rule form alone
// (issue 43's acceptance): `node studio_toy.mjs path/to/gmotion`.
//
// From an empty grammar on grammars/toy.svg, every line of grammars/toy.gm is made by
// clicking (the timeline's slices, the preview's shapes, the form's menus) and filling the
// form's fields: the duration, the split into a slice and its inverted twin, the eased move,
// the second split, the scale and the staggered rotate-and-scale. The saved grammar must
// pass `gmotion check`, and its frames at five times must be the very pixels of
// grammars/toy.gm's (both drawn by `gmotion animate … --time T`). Then a spatial rule
// written with the form cuts the background into two pieces. Exits 1 on the first failed
// check.
import { spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { launchChromium, startStudio } from './studio_harness.mjs';

const here = dirname(fileURLToPath(import.meta.url));
const root = join(here, '..', '..');
const gm = process.argv[2];
if (!gm) {
  console.error('usage: node studio_toy.mjs path/to/gmotion');
  process.exit(2);
}
const dir = mkdtempSync(join(tmpdir(), 'gmotion-studio-toy-'));
const scene = join(root, 'grammars', 'toy.svg');
const grammarFile = join(dir, 'mine.gm');

let failed = false;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failed = true;
}

const children = [];
const url = await startStudio(gm, scene, grammarFile, children);

const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 1000 }, deviceScaleFactor: 1 });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  const status = () => page.textContent('#status');
  let version = 1;
  // Each insertion is one edit: wait until the studio has built it, and fail loudly on a
  // grammar it refuses (the form must write only what it accepts).
  const built = async (what) => {
    version += 1;
    // Built (the version moves) or refused (its diagnostics shown): either ends the wait.
    await page.waitForFunction((v) => new RegExp('version ' + v + ' ').test(document.getElementById('status').textContent)
      || document.querySelector('#diagnostics .diagnostic'), version);
    const diag = (await page.textContent('#diagnostics')).trim();
    check(/no problems/.test(diag), `${what} builds (${diag.split('\n')[0]})`);
  };
  await page.waitForFunction(() => /version 1 /.test(document.getElementById('status').textContent));
  await page.getByRole('button', { name: 'play' }).click(); // pause: the timeline holds still

  const form = page.locator('#rule-form');
  const kind = form.getByRole('combobox', { name: 'rule', exact: true });
  const insert = form.getByRole('button', { name: 'Insert rule' });
  const field = (name) => form.getByLabel(name, { exact: true });
  // A slice of a shape's row on the timeline, by its label.
  const slice = (row, label) => page.locator('#timeline .row', { hasText: row }).locator('.slice', { hasText: new RegExp('^' + label + '$') }).first();

  // duration 6s
  await kind.selectOption('directive');
  await form.getByRole('combobox', { name: 'directive', exact: true }).selectOption('duration');
  await field('directive value').fill('6s');
  await insert.click();
  await built('the duration');

  // timesplit(0.5, 0.5) : [all, (s, c)] -> [a, inv_a]
  await kind.selectOption('timesplit');
  await field('slice').fill('all');
  await field('shapes').fill('(s, c)');
  await field('fractions').fill('0.5, 0.5');
  await field('output tags').fill('a, inv_a');
  await insert.click();
  await built('the split into a slice and its inverted twin');

  // animate(affine, world, 0, translate(260, 0), ease=ease-in-out) : [a, s] -> [tran]:
  // the slice from the square's hatched twin, the shape by clicking the square at rest.
  await slice('s#0', 'inv_a').click();
  check(await field('slice').inputValue() === 'a', 'the square\'s inverted slice names its twin');
  await page.getByRole('slider', { name: 'time', exact: true }).fill('0');
  await page.waitForTimeout(300);
  const stage = await page.locator('#overlay').boundingBox();
  await page.mouse.click(stage.x + stage.width * 100 / 520, stage.y + stage.height * 160 / 320);
  await page.waitForTimeout(300);
  check(await field('shapes').inputValue() === 's', 'a click on the square names it in the form');
  await kind.selectOption('animate');
  await form.getByRole('combobox', { name: 'what', exact: true }).selectOption('affine');
  await form.getByRole('combobox', { name: 'space', exact: true }).selectOption('world');
  await field('delay').fill('0');
  await field('value').fill('translate(260, 0)');
  await form.getByRole('combobox', { name: 'rule easing', exact: true }).selectOption('ease-in-out');
  await field('output tag').fill('tran');
  await insert.click();
  await built('the eased move');

  // timesplit(0.4, 0.6) : [a, c] -> [b, d]: the slice from a circle's row.
  await slice('c#1', 'a').click();
  check(await field('slice').inputValue() === 'a', 'a circle\'s slice names its tag');
  await kind.selectOption('timesplit');
  await field('shapes').fill('c');
  await field('fractions').fill('0.4, 0.6');
  await field('output tags').fill('b, d');
  await insert.click();
  await built('the second split');

  // animate(affine, local, 0, scale(0.5)) : [b, c] -> [scale]
  await slice('c#1', 'b').click();
  check(await field('slice').inputValue() === 'b', 'the new slice b is on the timeline and names itself');
  await kind.selectOption('animate');
  await field('shapes').fill('c');
  await form.getByRole('combobox', { name: 'space', exact: true }).selectOption('local');
  await field('delay').fill('0');
  await field('value').fill('scale(0.5)');
  await form.getByRole('combobox', { name: 'rule easing', exact: true }).selectOption('');
  await field('output tag').fill('scale');
  await insert.click();
  await built('the scale');

  // animate(affine, local, 0.15 * id, rotate(90) scale(1.6)) : [d, c] -> [rot_scale]
  await slice('c#1', 'd').click();
  check(await field('slice').inputValue() === 'd', 'slice d names itself');
  await field('delay').fill('0.15 * id');
  await field('value').fill('rotate(90) scale(1.6)');
  await field('output tag').fill('rot_scale');
  await insert.click();
  await built('the staggered rotate-and-scale');

  await page.getByRole('button', { name: 'Save' }).click();
  await page.waitForFunction(() => /saved/.test(document.getElementById('status').textContent));
  const written = readFileSync(grammarFile, 'utf8');
  console.log(written.trimEnd().split('\n').map((l) => '     | ' + l).join('\n'));
  const checked = spawnSync(gm, ['check', scene, grammarFile], { encoding: 'utf8' });
  check(checked.status === 0 && !/error/.test(checked.stderr), `gmotion check accepts it ${checked.stderr.trim()}`);

  // The frames: the recreated grammar against the paper's, pixel for pixel.
  for (const t of [0.4, 1.7, 2.6, 3.9, 5.3]) {
    const ours = join(dir, `mine-${t}.png`);
    const theirs = join(dir, `toy-${t}.png`);
    const a = spawnSync(gm, ['animate', scene, grammarFile, '-o', ours, '--time', String(t)], { encoding: 'utf8' });
    const b = spawnSync(gm, ['animate', join(root, 'grammars', 'toy.gm'), '-o', theirs, '--time', String(t)], { encoding: 'utf8' });
    const same = a.status === 0 && b.status === 0 && readFileSync(ours).equals(readFileSync(theirs));
    check(same, `the frame at ${t} s is grammars/toy.gm's ${a.stderr.trim()} ${b.stderr.trim()}`);
  }
  // A spatial rule with the form: the background outlined into an inside and a ring, each
  // operator's example arguments filled in when it is chosen.
  const shapesBefore = await page.evaluate(() => S.shapes.length);
  await kind.selectOption('spatial');
  check(await field('slice').isDisabled(), 'a spatial rule has no slice to fill');
  await form.getByRole('combobox', { name: 'operator', exact: true }).selectOption('outline');
  check(await field('arguments').inputValue() === '25' && await field("pieces' tags").inputValue() === 'inside, ring',
    'choosing an operator fills in its example arguments and output tags');
  await field('shapes').fill('background');
  await field('arguments').fill('10');
  await insert.click();
  await built('the spatial rule');
  const shapesAfter = await page.evaluate(() => S.shapes.length);
  const text = await page.getByRole('textbox', { name: 'grammar' }).inputValue();
  check(/^outline\(10\) : background -> \[inside, ring\]$/m.test(text) && +shapesAfter === +shapesBefore + 1,
    `the form wrote the spatial rule and the background became two pieces (${shapesBefore} → ${shapesAfter} shapes)`);
  check(errors.length === 0, `no script errors ${errors.join('; ')}`);
} finally {
  await browser.close();
  children.forEach((c) => c.kill());
}
process.exit(failed ? 1 : 0);
