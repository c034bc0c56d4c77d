// The studio's code editor and layer tree (issue 43, item 4), in real Chromium, driven by
// role and name: `node studio_code.mjs path/to/gmotion`.
//
// Checks: line numbers for every line of a long grammar, each level with its line of
// text, and the highlighted layer drawn where the textarea draws its text (the two
// compared pixel by pixel); highlighting classes on sample tokens; an injected error
// marked on its line (gutter and squiggle) with its help shown on hover and at the caret;
// clicking a diagnostic puts the caret on its place; three independent errors give three
// marks, on the lines `gmotion check` names; the layer tree of a grouped SVG (its group
// ids nested, a data-name shown with its id beside it), collapsed and expanded by mouse and keys, a group selected in the
// preview, the timeline and the rule form; 8000 shapes in the tree, every one reachable
// with a few dozen rows in the page. Prints (does not check) how long a 4 MiB paste takes
// to draw. With $STUDIO_SHOTS set to a folder, saves the screenshots docs/studio.md shows.
// Exits 1 on the first failed check.
import { spawnSync } from 'node:child_process';
import { mkdtempSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { launchChromium, startStudio } from './studio_harness.mjs';

const gm = process.argv[2];
if (!gm) {
  console.error('usage: node studio_code.mjs path/to/gmotion');
  process.exit(2);
}
const shots = process.env.STUDIO_SHOTS || null;
const dir = mkdtempSync(join(tmpdir(), 'gmotion-studio-code-'));
writeFileSync(join(dir, 'face.svg'), `<svg xmlns="http://www.w3.org/2000/svg" width="400" height="200">
  <rect id="sky" x="0" y="0" width="400" height="120" fill="#d0ebff"/>
  <g id="face">
    <g id="eyes"><circle id="eye_l" cx="160" cy="60" r="12" fill="#222"/><circle id="eye_r" cx="240" cy="60" r="12" fill="#222"/></g>
    <rect id="mouth" x="160" y="100" width="80" height="12" fill="#c92a2a"/>
  </g>
  <g id="ground" data-name="the ground"><rect id="grass" x="0" y="150" width="400" height="20" fill="#2b8a3e"/><rect id="soil" x="0" y="170" width="400" height="30" fill="#795548"/></g>
</svg>`);
// A long grammar: 120 lines of comment before the rules, so the box scrolls.
const header = 'scene face.svg\nduration 2s  # two seconds\n'
  + Array.from({ length: 120 }, (_, i) => `# note ${i + 1}: the rules come after the notes`).join('\n') + '\n';
const rules = 'timesplit(0.5, 0.5) : [all, all] -> [a, inv_a]\n'
  + 'animate(fill, local, 0, #ff0000, ease=ease-out) : [a, eyes] -> [red]  // the eyes go red\n'
  + 'animate(affine, local, 0.1 * id, rotate(90) scale(1.2), ease=cubic(0.3, 0, 0.2, 1)) : [a, (mouth, sky)] -> [spin]\n';
const good = header + rules;
writeFileSync(join(dir, 'face.gm'), good);
const GROUPS = 8, PER = 1000;
writeFileSync(join(dir, 'many.svg'), '<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="800">'
  + Array.from({ length: GROUPS }, (_, g) => `<g id="row${g}">`
    + Array.from({ length: PER }, (_, i) => `<rect x="${i}" y="${g * 100}" width="1" height="10"/>`).join('') + '</g>').join('')
  + '</svg>');
writeFileSync(join(dir, 'many.gm'), 'duration 1s\n');

const children = [];
const studio = (scene, grammar) => startStudio(gm, scene, grammar, children);

let failed = false;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failed = true;
}

const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 1000 }, deviceScaleFactor: 1 });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(await studio(join(dir, 'face.svg'), join(dir, 'face.gm')));
  await page.waitForFunction(() => /version 1 /.test(document.getElementById('status').textContent));
  await page.getByRole('button', { name: 'play' }).click();   // pause
  await page.waitForSelector('#diagnostics .ok');
  const editor = page.getByRole('textbox', { name: 'grammar' });
  const lines = good.split('\n').length;

  // Line numbers: each beside its line of text, down to the last.
  const rows = () => page.evaluate(() => {
    const hl = [...document.querySelectorAll('#highlight .hl')].map((e) => [e.getBoundingClientRect().top, e.textContent]);
    const ln = [...document.querySelectorAll('#gutter .ln')].map((e) => [e.getBoundingClientRect().top, +e.textContent]);
    const text = document.getElementById('grammar').value.split('\n');
    return { hl, ln, text };
  });
  const aligned = ({ hl, ln, text }) => ln.length > 10 && ln.length === hl.length
    && ln.every(([y, n], k) => Math.abs(y - hl[k][0]) < 0.5 && hl[k][1].trimEnd() === text[n - 1].trimEnd());
  const atTop = await rows();
  await editor.evaluate((g) => { g.scrollTop = g.scrollHeight; });
  await page.waitForTimeout(150);
  const atEnd = await rows();
  check(aligned(atTop) && aligned(atEnd) && atTop.ln[0][1] === 1 && atEnd.ln[atEnd.ln.length - 1][1] === lines,
    `line numbers 1 to ${lines}, each level with its line of text (${atTop.ln.length} drawn of ${lines})`);

  // The highlighted layer is where the textarea draws its text: the textarea's own text
  // (made visible, the layer hidden) covers the same pixels as the layer's.
  const ink = async () => {
    const shot = await page.locator('#code').screenshot();
    return page.evaluate(async (b64) => {
      const img = new Image();
      img.src = 'data:image/png;base64,' + b64;
      await img.decode();
      const c = document.createElement('canvas');
      c.width = img.width; c.height = img.height;
      const x = c.getContext('2d');
      x.drawImage(img, 0, 0);
      const d = x.getImageData(0, 0, c.width - 20, c.height - 20).data;   // not the scrollbars
      const out = [];
      for (let i = 0; i < d.length; i += 4) out.push(d[i] + d[i + 1] + d[i + 2] < 600 ? 1 : 0);
      return out;
    }, shot.toString('base64'));
  };
  // Both drawn in black, without underlines, so only where the glyphs fall differs.
  await editor.evaluate((g) => { g.scrollTop = 0; g.scrollLeft = 0; g.blur(); });
  const plain = await page.addStyleTag({ content: '#highlight, #highlight span { color: #000 !important; text-decoration: none !important; background: none !important; }' });
  await page.waitForTimeout(150);
  const layer = await ink();
  const own = await page.addStyleTag({ content: '#grammar { color: #000 !important; } #highlight { visibility: hidden; }' });
  await page.waitForTimeout(100);
  const mine = await ink();
  let both = 0, either = 0;
  for (let i = 0; i < layer.length; i++) { both += layer[i] & mine[i]; either += layer[i] | mine[i]; }
  check(either > 1000 && both / either > 0.95, `the highlighted text lies on the textarea's own (${(100 * both / either).toFixed(1)} % of inked pixels shared)`);
  await plain.evaluate((e) => e.remove());
  await own.evaluate((e) => e.remove());

  // Highlighting: the lexer's classes on sample tokens.
  await editor.evaluate((g) => { g.scrollTop = g.scrollHeight; });
  await page.waitForTimeout(150);
  const classes = await page.evaluate(() => {
    const out = {};
    for (const s of document.querySelectorAll('#highlight span')) if (!(s.textContent in out)) out[s.textContent] = s.className;
    return out;
  });
  const want = { timesplit: 't-kw', '0.5': 't-num', eyes: 't-tag', '->': 't-op', '#ff0000': 't-col', ease: 't-param', '// the eyes go red': 't-com', rotate: 't-fn' };
  const wrong = Object.entries(want).filter(([k, v]) => classes[k] !== v);
  if (shots) await page.locator('#editor').screenshot({ path: join(shots, 'studio-code.png') });
  await editor.evaluate((g) => { g.scrollTop = 0; });
  await page.waitForTimeout(150);
  const top = await page.evaluate(() => Object.fromEntries([...document.querySelectorAll('#highlight .hl:first-child span, #highlight .hl:nth-child(2) span')].map((s) => [s.textContent, s.className])));
  if (top.scene !== 't-dir') wrong.push(['scene', top.scene]);
  if (top['face.svg'] !== 't-path') wrong.push(['face.svg', top['face.svg']]);
  if (top['# two seconds'] !== 't-com') wrong.push(['# two seconds', top['# two seconds']]);
  check(wrong.length === 0, `tokens highlighted by class: rule head, number, tag, arrow, colour, named argument, comments, function, directive, path ${JSON.stringify(wrong)}`);

  // One injected error: marked on its line, its help on hover and at the caret.
  const typo = good.replace('animate(fill', 'animate(fil');
  const typoLine = typo.split('\n').findIndex((l) => l.includes('animate(fil,')) + 1;
  await editor.fill(typo);
  await page.waitForSelector('#diagnostics .diagnostic');
  await editor.evaluate((g) => { g.scrollTop = g.scrollHeight; });
  await page.waitForTimeout(200);
  const marked = await page.$$eval('#gutter .ln.mark', (ls) => ls.map((l) => +l.dataset.line));
  const squiggle = page.locator('#highlight .squiggle').first();
  const under = await squiggle.textContent().catch(() => '');
  const sq = await squiggle.boundingBox();
  await page.mouse.move(sq.x + sq.width / 2, sq.y + sq.height / 2);
  await page.waitForSelector('#diag-tip:not([hidden])');
  const tip = await page.textContent('#diag-tip');
  check(marked.length === 1 && marked[0] === typoLine && under === 'fil' && /help: /.test(tip),
    `an error is marked on line ${marked} (under \`${under}\`) and hovering it shows its help (${tip.split('\n').find((l) => /help/.test(l))})`);

  // Clicking the diagnostic in the list puts the caret on its place.
  await editor.evaluate((g) => { g.scrollTop = 0; g.setSelectionRange(0, 0); });
  await page.locator('#diagnostics .diagnostic').first().click();
  const caret = await editor.evaluate((g) => [document.activeElement === g, g.selectionStart, g.getAttribute('aria-describedby')]);
  check(caret[0] && caret[1] === typo.indexOf('fil,') && caret[2] === 'diag-tip',
    `clicking the diagnostic puts the caret at offset ${caret[1]} (the error's ${typo.indexOf('fil,')}), its message describing the box`);

  // Three independent errors: three marks, on the lines `gmotion check` names.
  const broken = good.replace('animate(fill', 'animate(fil').replace('timesplit(0.5, 0.5)', 'timesplit(0.5, 0.6)')
    + 'animate(afine, world, 0, translate(1, 0)) : [a, sky] -> [n]\n';
  await editor.fill(broken);
  await page.waitForFunction(() => document.querySelectorAll('#diagnostics .diagnostic').length === 3, null, { timeout: 10000 }).catch(() => {});
  await editor.evaluate((g) => { g.scrollTop = g.scrollHeight; });
  await page.waitForTimeout(200);
  const three = await page.$$eval('#gutter .ln.mark', (ls) => ls.map((l) => +l.dataset.line));
  const squiggles = await page.$$eval('#highlight .squiggle', (ss) => new Set(ss.map((s) => s.dataset.k)).size);
  writeFileSync(join(dir, 'broken.gm'), broken);
  const cli = spawnSync(gm, ['check', join(dir, 'broken.gm')], { encoding: 'utf8' });
  const cliLines = [...cli.stderr.matchAll(/broken\.gm:(\d+):\d+: error: /g)].map((m) => +m[1]);
  check(three.length === 3 && squiggles === 3 && JSON.stringify([...three].sort((a, b) => a - b)) === JSON.stringify([...cliLines].sort((a, b) => a - b)),
    `three independent errors, three marks on lines ${three} (gmotion check: ${cliLines})`);
  await page.mouse.move(0, 0);
  await editor.evaluate((g) => { g.focus(); });
  await page.locator('#diagnostics .diagnostic').nth(2).click();
  await page.waitForTimeout(100);
  if (shots) await page.locator('section', { has: page.locator('#editor') }).screenshot({ path: join(shots, 'studio-diagnostics.png') });
  await editor.fill(good);
  await page.waitForSelector('#diagnostics .ok');
  const cleared = await page.$$eval('#gutter .ln.mark, #highlight .squiggle', (x) => x.length);
  check(cleared === 0, 'the marks go when the errors are fixed');

  // The layer tree: the SVG's groups by their ids, nested.
  const tree = page.getByRole('tree', { name: 'layers' });
  const item = (name) => tree.getByRole('treeitem', { name, exact: true });
  await item('face').waitFor();
  const levels = await Promise.all(['face', 'eyes', 'the ground'].map((n) => item(n).getAttribute('aria-level')));
  const beside = await item('the ground').locator('.dim').textContent();
  const count = () => tree.getByRole('treeitem').count();
  check(levels.join() === '1,2,1' && /^ground · 2 shapes$/.test(beside), `the tree shows the groups face > eyes and "the ground" (its data-name; its id beside it: ${beside}) (levels ${levels})`);
  const open = await count();
  await item('face').locator('.twisty').click();
  const closed = await count();
  const faceClosed = await item('face').getAttribute('aria-expanded');
  await item('face').press('ArrowRight');
  const reopened = await count();
  await item('eyes').click();
  await item('eyes').press('ArrowLeft');
  const eyesClosed = [await count(), await item('eyes').getAttribute('aria-expanded')];
  await item('eyes').press('ArrowRight');
  check(closed === open - 4 && faceClosed === 'false' && reopened === open && eyesClosed[0] === open - 2 && eyesClosed[1] === 'false',
    `collapsing and expanding: ${open} rows, ${closed} with face closed, ${reopened} reopened (→), ${eyesClosed[0]} with eyes closed (←)`);

  // Selecting a group selects its shapes everywhere; the form gets its name.
  await item('eyes').click();
  await page.waitForTimeout(200);
  const sel = await page.evaluate(() => ({
    rows: [...document.querySelectorAll('#timeline .row.sel .name')].map((n) => n.textContent),
    boxes: document.querySelectorAll('#overlay .box.sel.group').length,
    form: document.getElementById('rule-shape').value,
    leaves: [...document.querySelectorAll('#layer-rows .layer.sel')].map((e) => e.getAttribute('aria-label')),
  }));
  check(sel.rows.length === 2 && sel.boxes === 2 && sel.form === 'eyes' && sel.leaves.length === 3,
    `selecting eyes selects its 2 shapes: timeline [${sel.rows}], ${sel.boxes} boxes, form "${sel.form}", tree [${sel.leaves}]`);
  if (shots) await page.locator('#layers').screenshot({ path: join(shots, 'studio-layers.png') });
  // A shape picked on the canvas leaves the group and is shown in the tree.
  const stage = await page.locator('#overlay').boundingBox();
  await page.mouse.click(stage.x + stage.width * 200 / 400, stage.y + stage.height * 106 / 200);
  await page.waitForTimeout(300);
  const after = await page.evaluate(() => [selected, [...document.querySelectorAll('#layer-rows .layer.sel')].map((e) => +e.dataset.i)]);
  check(after[0] >= 0 && after[1].length === 1 && after[1][0] === after[0] && await page.$$eval('#overlay .box.sel.group', (b) => b.length) === 0,
    `a shape clicked in the preview leaves the group and is the one selected in the tree (#${after[1]})`);
  // A press where nothing is drawn leaves a chosen group too.
  await item('eyes').click();
  const chosenBoxes = await page.$$eval('#overlay .box.sel.group', (b) => b.length);
  await page.mouse.click(stage.x + stage.width * 20 / 400, stage.y + stage.height * 135 / 200);
  await page.waitForTimeout(300);
  const left = await page.evaluate(() => [document.querySelectorAll('#overlay .box.sel.group').length, document.querySelectorAll('#layer-rows .layer.sel').length]);
  check(chosenBoxes === 2 && left[0] === 0 && left[1] === 0, `a press on nothing in the preview leaves the group (${chosenBoxes} boxes, then ${left[0]})`);

  // A 4 MiB paste: the editor draws the lines in view only (measured, not checked).
  const big = await page.evaluate(async () => {
    const g = document.getElementById('grammar');
    const line = 'animate(affine, local, 0.25 * id, translate(10, 0) * rotate(45)) : [a, r] -> [moved]  # note\n';
    const text = line.repeat(Math.floor((4 * 1024 * 1024 - 4096) / line.length));
    const frame = () => new Promise((r) => requestAnimationFrame(() => r()));
    // What a bare textarea of the same size takes to lay the text out, for comparison.
    const bare = document.createElement('textarea');
    bare.wrap = 'off';
    bare.style.cssText = 'position:absolute;left:0;top:0;width:600px;height:340px;font:12px/16px ui-monospace,monospace';
    document.body.appendChild(bare);
    const b0 = performance.now();
    bare.value = text;
    await frame(); await frame();
    const alone = performance.now() - b0;
    bare.remove();
    await frame();
    const t0 = performance.now();
    g.value = text;
    g.dispatchEvent(new Event('input'));
    await frame(); await frame();
    const paste = performance.now() - t0;
    const scrolls = [];
    // The editor's own work for a scroll: the textarea scrolled and laid out first.
    for (let k = 1; k <= 20; k++) {
      g.scrollTop = g.scrollHeight * k / 20;
      void g.scrollHeight;
      const s0 = performance.now();
      paintEditor();
      scrolls.push(performance.now() - s0);
    }
    scrolls.sort((a, b) => a - b);
    return { bytes: text.length, lines: text.split('\n').length, alone, paste, median: scrolls[10], worst: scrolls[19], drawn: document.querySelectorAll('#highlight .hl').length };
  });
  console.log(`measure: a ${(big.bytes / 1048576).toFixed(2)} MiB paste (${big.lines} lines) drawn in ${big.paste.toFixed(1)} ms (a bare textarea: ${big.alone.toFixed(1)} ms); after a scroll the ${big.drawn} lines in view are drawn in ${big.median.toFixed(2)} ms median, ${big.worst.toFixed(2)} ms worst of 20`);
  check(big.drawn < 80, `a 4 MiB paste keeps ${big.drawn} lines in the page`);
  await editor.fill(good);
  await page.waitForSelector('#diagnostics .ok', { timeout: 20000 });

  // 8000 shapes: every one reachable in the tree, a few dozen rows in the page.
  const many = await browser.newPage({ viewport: { width: 1280, height: 1000 }, deviceScaleFactor: 1 });
  many.on('pageerror', (e) => errors.push(String(e)));
  await many.goto(await studio(join(dir, 'many.svg'), join(dir, 'many.gm')));
  await many.waitForFunction((n) => document.getElementById('layer-count').textContent.includes(n + ' shapes'), GROUPS * PER, { timeout: 60000 });
  const inPage = await many.$$eval('#layer-rows .layer', (rs) => rs.length);
  await many.$eval('#layers', (l) => { l.scrollTop = l.scrollHeight; });
  await many.waitForTimeout(200);
  const last = await many.$$eval('#layer-rows .layer', (rs) => rs.map((r) => [r.getAttribute('aria-label'), r.dataset.i]));
  const lastShape = last.map(([, i]) => +i).filter((i) => i >= 0).sort((a, b) => a - b).pop();
  await many.$eval('#layers', (l) => { l.scrollTop = 0; });
  await many.waitForTimeout(100);
  await many.getByRole('treeitem', { name: 'row0', exact: true }).click();
  const groupRows = await many.evaluate(() => chosen && chosen.shapes.size);
  check(lastShape === GROUPS * PER - 1 && inPage < 80 && groupRows === PER,
    `${GROUPS * PER} shapes in ${GROUPS} groups: the last (#${lastShape}) reached by scrolling, ${inPage} rows in the page, a group selecting its ${groupRows}`);
  check(errors.length === 0, `no script errors ${errors.join('; ')}`);
} catch (e) {
  console.log(`FAIL ${e.stack || e}`);
  failed = true;
} finally {
  await browser.close();
  for (const c of children) c.kill();
}
process.exit(failed ? 1 : 0);
