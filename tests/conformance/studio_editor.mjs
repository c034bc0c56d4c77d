// The studio as an editor (issue 43), in real Chromium, driven by role and name:
// `node studio_editor.mjs path/to/gmotion`.
//
// Checks: `studio SCENE NEW.gm` creates the empty grammar; the timeline (a ruler that
// seeks, Space and the arrows, a boundary dragged to retime, every row of 1000 reachable, the
// canvas drawing the bars under their slices and the playhead at the time); rules written with the form
// alone (an inverted slice names its twin, a selected shape its unique alias) leave a
// grammar `gmotion check` accepts; a click hits the shape where the frame shown draws it;
// every independent error is listed with its help; an outside edit under unsaved edits is
// a conflict (Save refuses, both texts kept, keep mine / take theirs); every variation
// cell is drawn on twenty reloads; handles on the canvas (a drag rewriting the square's
// translate so the frame shown follows, a rotate and a scale handle), the colour picker
// and the easing curve editor, each undone and redone, and a rule proposed for a shape no
// rule moves; an 800 × 800 scene leaves the timeline in view. With
// $STUDIO_SHOTS set to a folder, saves the screenshots docs/studio.md shows. Exits 1 on
// the first failed check.
import { spawnSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { launchChromium, startStudio } from './studio_harness.mjs';

// In the page: for the timeline row named `name`, whether the canvas shows each of its
// forward slices' colour in the middle of the slice's element, and whether the playhead's
// red is at the time shown (on the ruler, clear of the bars).
function timelinePixels(name) {
  const cv = document.getElementById('tl-canvas'), g = cv.getContext('2d');
  const r = cv.getBoundingClientRect(), k = cv.width / r.width;
  const at = (x, y) => [...g.getImageData(Math.floor((x - r.left) * k), Math.floor((y - r.top) * k), 1, 1).data];
  const rgb = (css) => {
    const probe = document.createElement('span');
    probe.style.color = css;
    document.body.appendChild(probe);
    const c = getComputedStyle(probe).color.match(/\d+/g).map(Number);
    probe.remove();
    return c;
  };
  const near = (a, b) => a.slice(0, 3).every((v, i) => Math.abs(v - b[i]) <= 3);
  const row = [...document.querySelectorAll('#rows .row')].find((x) => x.querySelector('.name').textContent === name);
  // Three points across each bar, two of which must be its tag's colour: the playhead
  // (2 px wide, moving while the page plays) can cover one of them, never two.
  const bars = [...row.querySelectorAll('.slice:not(.inv)')].map((el) => {
    const b = el.getBoundingClientRect();
    const want = rgb(colour(el.textContent));
    const got = [0.25, 0.5, 0.75].map((f) => at(b.left + b.width * f, b.top + b.height - 3));
    return { tag: el.textContent, ok: got.filter((c) => near(c, want)).length >= 2, got: got.map((c) => c.slice(0, 3).join(',')).join(' ') };
  });
  const ruler = document.getElementById('ruler').getBoundingClientRect();
  const x = ruler.left + ruler.width * t / S.duration;
  return { bars, playhead: near(at(x, ruler.top + 3), [0xe0, 0x31, 0x31]), readout: document.getElementById('readout').textContent };
}

const here = dirname(fileURLToPath(import.meta.url));
const root = join(here, '..', '..');
const gm = process.argv[2];
if (!gm) {
  console.error('usage: node studio_editor.mjs path/to/gmotion');
  process.exit(2);
}
const shots = process.env.STUDIO_SHOTS || null;
const dir = mkdtempSync(join(tmpdir(), 'gmotion-studio-editor-'));
// The toy scene, its first circle named `sun` (its tag `c` is shared by four circles).
writeFileSync(join(dir, 'toy.svg'), readFileSync(join(root, 'grammars', 'toy.svg'), 'utf8')
  .replace('<circle data-tag="c" cx="220"', '<circle data-tag="c" id="sun" cx="220"'));
writeFileSync(join(dir, 'toy.gm'), readFileSync(join(root, 'grammars', 'toy.gm'), 'utf8'));
writeFileSync(join(dir, 'many.svg'), '<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="100">'
  + Array.from({ length: 1000 }, (_, i) => `<rect data-tag="r" x="${i}" y="${(i * 7) % 90}" width="1" height="10"/>`).join('') + '</svg>');
writeFileSync(join(dir, 'many.gm'), 'duration 2s\ntimesplit(0.5, 0.5) : [all, r] -> [a, inv_a]\nanimate(opacity, local, 0.001 * id, 0) : [a, r] -> [fade]\n');
writeFileSync(join(dir, 'big.svg'), '<svg xmlns="http://www.w3.org/2000/svg" width="800" height="800">'
  + '<rect data-tag="r" x="100" y="100" width="600" height="600" fill="#17bebb"/></svg>');

const children = [];
const studio = (scene, grammar) => startStudio(gm, scene, grammar, children);

let failed = false;
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failed = true;
}
const checkFile = (file) => spawnSync(gm, ['check', file], { encoding: 'utf8' });

const browser = await launchChromium();
try {
  const grammarFile = join(dir, 'new.gm');
  const url = await studio(join(dir, 'toy.svg'), grammarFile);
  check(existsSync(grammarFile) && readFileSync(grammarFile, 'utf8') === '', 'studio SCENE NEW.gm creates the empty grammar');
  const page = await browser.newPage({ viewport: { width: 1280, height: 1000 }, deviceScaleFactor: 1 });
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(url);
  await page.waitForFunction(() => /version 1 /.test(document.getElementById('status').textContent));
  const version = (v) => page.waitForFunction((v) => new RegExp('version ' + v + ' ').test(document.getElementById('status').textContent), v);
  await page.getByRole('button', { name: 'play' }).click();   // pause

  // A split of every timeline into a slice and its inverted twin, with the form.
  const form = page.locator('#rule-form');
  await form.getByLabel('fractions', { exact: true }).fill('0.5, 0.5');
  await form.getByLabel('output tags', { exact: true }).fill('a, inv_a');
  await form.getByRole('button', { name: 'Insert rule' }).click();
  await version(2);
  // Click the square's inverted slice: the form names its twin.
  await page.locator('#timeline .row', { hasText: 's#0' }).locator('.slice.inv').click();
  const slice = await form.getByLabel('slice', { exact: true }).inputValue();
  check(slice === 'a', `an inverted slice names its twin in the form (${slice})`);
  await form.getByRole('combobox', { name: 'rule', exact: true }).selectOption('animate');
  await form.getByLabel('shapes', { exact: true }).fill('s');
  await form.getByLabel('value', { exact: true }).fill('translate(260, 0)');
  await form.getByLabel('output tag', { exact: true }).fill('tran');
  await form.getByRole('button', { name: 'Insert rule' }).click();
  await version(3);
  const diag = await page.textContent('#diagnostics');
  check(/no problems/.test(diag), `the rules the form wrote build (${diag.trim().split('\n')[0]})`);

  // Select the first circle in the preview: the form names `sun`, not the shared `c`.
  const stage = await page.locator('#overlay').boundingBox();
  const at = (x, y) => [stage.x + stage.width * x / 520, stage.y + stage.height * y / 320];
  await page.getByRole('slider', { name: 'time', exact: true }).fill('0');
  await page.waitForTimeout(300);
  await page.mouse.click(...at(220, 160));
  await page.waitForTimeout(300);
  const shape = await form.getByLabel('shapes', { exact: true }).inputValue();
  check(shape === 'sun', `a selected shape is named by its unique alias (${shape})`);

  // Hit-testing the frame shown: halfway through (the empty grammar's 5 s) the square is
  // 260 to the right (320–400 × 120–200; its corner at 395, 195 lies outside the circle
  // at 360, 160).
  await page.getByRole('slider', { name: 'time', exact: true }).fill('500');
  await page.waitForTimeout(300);
  await page.mouse.click(...at(395, 195));
  await page.waitForTimeout(300);
  const moved = await page.$eval('#timeline .row.sel .name', (n) => n.textContent).catch(() => null);
  await page.mouse.click(...at(135, 195));
  await page.waitForTimeout(300);
  const rest = await page.$eval('#timeline .row.sel .name', (n) => n.textContent).catch(() => null);
  check(moved === 's#0' && rest !== 's#0', `a click hits the square where the frame shows it (${moved}; at its rest place ${rest})`);
  if (shots) await page.screenshot({ path: join(shots, 'studio-editor.png') });

  // Save, and `gmotion check` accepts what the form wrote.
  await page.getByRole('button', { name: 'Save' }).click();
  await page.waitForFunction(() => /saved/.test(document.getElementById('status').textContent));
  const checked = checkFile(grammarFile);
  check(checked.status === 0, `gmotion check accepts the grammar the form wrote ${checked.stderr}`);
  const good = readFileSync(grammarFile, 'utf8');

  // Every independent error with its help, as `gmotion check` gives them.
  const broken = good + 'animate(opacity, local, 0, 2) : [a, s] -> [m]\nanimate(afine, world, 0, translate(1, 0)) : [a, s] -> [n]\ntimesplit(0.5, 0.6) : [all, s] -> [p, q]\n';
  const editor = page.getByRole('textbox', { name: 'grammar' });
  await editor.fill(broken);
  await page.waitForFunction(() => document.querySelectorAll('#diagnostics .diagnostic').length > 0);
  const shown = await page.$$eval('#diagnostics .diagnostic', (ds) => ds.map((d) => d.textContent));
  writeFileSync(join(dir, 'broken.gm'), broken.replace('scene toy.svg', ''));
  const cli = checkFile(join(dir, 'broken.gm'));
  const cliCount = (cli.stderr.match(/: error: /g) || []).length;
  check(shown.length === 3 && cliCount === 3 && shown.some((d) => /help: did you mean `affine`/.test(d)) && shown.every((d) => /^line \d+, column \d+/.test(d)),
    `every error is shown with its place and help (${shown.length} in the page, ${cliCount} from check)`);
  await editor.fill(good);
  await page.waitForSelector('#diagnostics .ok');

  // An outside edit while the page has unsaved edits: a conflict, both texts kept.
  const mine = good.replace('translate(260, 0)', 'translate(200, 0)');
  await editor.fill(mine);
  await page.waitForTimeout(600);
  const theirs = good.replace('0.5, 0.5', '0.4, 0.6');
  writeFileSync(grammarFile, theirs);
  const alert = page.getByRole('alert', { name: 'conflict with the file on disk' });
  await alert.waitFor({ state: 'visible', timeout: 10000 });
  const kept = await editor.inputValue();
  const onDisk = await page.getByRole('textbox', { name: 'text on disk' }).inputValue();
  check(kept === mine && onDisk === theirs, 'a conflict keeps my text and shows theirs');
  await page.getByRole('button', { name: 'Save' }).click();
  await page.waitForFunction(() => /not saved/.test(document.getElementById('status').textContent));
  check(readFileSync(grammarFile, 'utf8') === theirs, 'Save refuses to overwrite the file changed on disk');
  if (shots) await page.screenshot({ path: join(shots, 'studio-conflict.png') });
  await alert.getByRole('button', { name: 'Take theirs' }).click();
  await alert.waitFor({ state: 'hidden' });
  check(await editor.inputValue() === theirs, 'take theirs puts the file\'s text in the editor');
  await editor.fill(mine);
  await page.waitForTimeout(600);
  writeFileSync(grammarFile, good);
  await alert.waitFor({ state: 'visible', timeout: 10000 });
  await alert.getByRole('button', { name: 'Keep mine' }).click();
  await alert.waitFor({ state: 'hidden' });
  await page.getByRole('button', { name: 'Save' }).click();
  await page.waitForFunction(() => /saved \//.test(document.getElementById('status').textContent));
  check(readFileSync(grammarFile, 'utf8') === mine, 'keep mine, then Save writes my text');
  // Merge: my change and the file's on different lines both kept, no markers written.
  const mineToo = mine.replace('translate(200, 0)', 'translate(220, 0)');
  await editor.fill(mineToo);
  await page.waitForTimeout(600);
  writeFileSync(grammarFile, '# tuned elsewhere\n' + mine);
  await alert.waitFor({ state: 'visible', timeout: 10000 });
  await alert.getByRole('button', { name: 'Merge' }).click();
  await alert.waitFor({ state: 'hidden' });
  const merged = await editor.inputValue();
  check(merged === '# tuned elsewhere\n' + mineToo && !/<<<<<<<|>>>>>>>/.test(readFileSync(grammarFile, 'utf8')),
    'merge keeps my change and the file\'s, and writes no conflict markers');
  await page.getByRole('button', { name: 'Save' }).click();
  await page.waitForFunction(() => /saved \//.test(document.getElementById('status').textContent));

  // A dropped connection: an edit made while the studio does not answer stays in the page
  // and reaches the server once it answers; a paste past 4 MiB is refused, said, and kept.
  const pageServerText = async () => (await page.request.get(url.replace('/?', '/api/grammar?'))).text();
  const pageServerHas = async (text) => {
    for (let i = 0; i < 50 && await pageServerText() !== text; i++) await page.waitForTimeout(100);
    return await pageServerText() === text;
  };
  const statusSays = (re) => page.waitForFunction((re) => new RegExp(re).test(document.getElementById('status').textContent), re.source, { timeout: 8000 })
    .then(() => true, () => false);
  const online = await editor.inputValue();
  await page.route('**/api/**', (route) => route.abort());
  const offline = online + '# written while the studio did not answer\n';
  await editor.fill(offline);
  const said = await statusSays(/not answering/);
  await page.waitForTimeout(1500);
  const keptOffline = await editor.inputValue() === offline;
  await page.unroute('**/api/**');
  check(said && keptOffline && await pageServerHas(offline),
    `an edit made while the studio did not answer is said, kept and sent once it answers (said ${said}, kept ${keptOffline})`);
  const huge = offline + '#' + 'x'.repeat(4 << 20) + '\n';
  await editor.fill(huge);
  const refused = await statusSays(/not applied: .*4 MiB/);
  await page.waitForTimeout(1500);
  check(refused && (await editor.inputValue()).length === huge.length && await pageServerText() === offline,
    `a paste past 4 MiB is refused with a message and stays in the page (said ${refused})`);
  await editor.fill(offline);
  check(await pageServerHas(offline), 'the text made small again is taken');

  // Variations: every cell drawn, twenty loads in a row.
  let blank = 0;
  for (let i = 0; i < 20; i++) {
    await page.goto(url);
    const drawn = await page.waitForFunction(() => {
      const cells = document.querySelectorAll('#variations .cell');
      return cells.length > 0 && [...cells].every((c) => c.dataset.drawn);
    }, null, { timeout: 8000 }).then(() => true, () => false);
    if (!drawn) blank++;
  }
  check(blank === 0, `every variation cell is drawn on twenty reloads (${blank} loads with a blank cell)`);

  // Variations that play (Fig. 8): while the main clock runs every cell moves through the
  // frames with it, and paused each settles on the frame shown.
  await page.waitForFunction(() => /version \d+ /.test(document.getElementById('status').textContent));
  const play = page.getByRole('button', { name: 'play' });
  if (await play.textContent() === '▶') await play.click();
  const seen = new Map();
  for (let i = 0; i < 40; i++) {
    await page.waitForTimeout(50);
    for (const [seed, frame] of await page.$$eval('#variations .cell', (cs) => cs.map((c) => [c.dataset.seed, c.dataset.frame])))
      (seen.get(seed) || seen.set(seed, new Set()).get(seed)).add(frame);
  }
  const fewest = Math.min(...[...seen.values()].map((f) => f.size));
  // At the toy's size a thumbnail is drawn in milliseconds: a cell that shows fewer than
  // 12 frames in 2 s is stepping (as the cells once did, four times a second), not playing.
  check(seen.size >= 6 && fewest >= 12, `every variation plays with the clock (${seen.size} cells, the slowest showed ${fewest} frames in 2 s)`);
  await play.click();
  const settled = await page.waitForFunction(() => {
    const frame = String(Math.round(t * S.fps));
    const cells = [...document.querySelectorAll('#variations .cell')];
    return cells.every((c) => c.dataset.frame === frame) && frame;
  }, null, { timeout: 5000 }).then((h) => h.jsonValue(), () => null);
  check(settled !== null, `paused, every variation shows the frame the preview shows (frame ${settled})`);

  // The timeline on the toy grammar: the ruler seeks, Space plays, arrows step.
  const toy = await browser.newPage({ viewport: { width: 1280, height: 1000 }, deviceScaleFactor: 1 });
  toy.on('pageerror', (e) => errors.push(String(e)));
  const toyFile = join(dir, 'toy.gm');
  await toy.goto(await studio(join(dir, 'toy.svg'), toyFile));
  await toy.waitForFunction(() => /version 1 /.test(document.getElementById('status').textContent));
  const ruler = toy.getByRole('slider', { name: 'timeline ruler' });
  const rb = await ruler.boundingBox();
  await toy.mouse.click(rb.x + rb.width * 0.5, rb.y + rb.height / 2);
  const readout = () => toy.textContent('#readout');
  const seeked = await readout();
  check(/^3\.0\d\d \//.test(seeked) && await toy.getByRole('button', { name: 'play' }).textContent() === '▶',
    `a click on the ruler pauses and seeks (${seeked})`);
  await toy.mouse.move(rb.x + rb.width * 0.2, rb.y + rb.height / 2);
  await toy.mouse.down();
  await toy.mouse.move(rb.x + rb.width * 0.25, rb.y + rb.height / 2, { steps: 3 });
  await toy.mouse.up();
  check(/^1\.50\d \//.test(await readout()), `dragging on the ruler scrubs (${await readout()})`);
  await toy.keyboard.press('ArrowRight');
  await toy.keyboard.press('ArrowRight');
  const stepped = await readout();
  check(/frame 47$/.test(stepped), `→ steps a frame at a time (${stepped})`);
  await toy.keyboard.press('Home');
  check(/^0\.000 /.test(await readout()), 'Home goes to the start');
  await toy.keyboard.press(' ');
  await toy.waitForTimeout(400);
  const playing = await readout();
  await toy.keyboard.press(' ');
  const paused = await readout();
  await toy.waitForTimeout(300);
  check(!/^0\.000 /.test(playing) && paused === await readout(), `Space plays and pauses (${playing} → ${paused})`);

  // The timeline is drawn on a canvas: each slice's bar in its tag's colour under the
  // slice's element, the playhead where the time is.
  const drawn = await toy.evaluate(timelinePixels, 's#0');
  check(drawn.bars.length >= 1 && drawn.bars.every((b) => b.ok), `the canvas draws s#0's bars under their slices in their tags' colours (${JSON.stringify(drawn.bars)})`);
  check(drawn.playhead, `the canvas draws the playhead at the time shown (${drawn.readout})`);

  // Zoom: twice in by the buttons, the tracks 4× as wide about the middle (the boundary
  // at 3 s of 6 stays put), a click on the zoomed ruler seeking the time under it,
  // Ctrl+wheel keeping the time under the mouse, fit going back.
  const edgeX = async () => {
    const b = await toy.getByRole('slider', { name: 'boundary 0 of s#0' }).boundingBox();
    return b.x + b.width / 2;
  };
  const fitX = await edgeX();
  await toy.getByRole('button', { name: 'zoom in' }).click();
  await toy.getByRole('button', { name: 'zoom in' }).click();
  const rbz = await ruler.boundingBox();
  check(Math.abs(rbz.width / rb.width - 4) < 0.02, `zoom in twice draws the tracks 4× as wide (${(rbz.width / rb.width).toFixed(3)}×)`);
  const zoomedX = await edgeX();
  if (shots) await toy.locator('#timeline').screenshot({ path: join(shots, 'studio-zoom.png') });
  check(Math.abs(zoomedX - fitX) < 1.5, `zooming about the middle keeps the time there in place (boundary at ${fitX.toFixed(1)} → ${zoomedX.toFixed(1)} px)`);
  await toy.mouse.click(zoomedX + 100, rb.y + rb.height / 2);
  const wanted = 3 + 100 / rbz.width * 6;
  const got = parseFloat(await readout());
  check(Math.abs(got - wanted) < 0.01, `a click on the zoomed ruler seeks the time under it (${got} s, ${wanted.toFixed(3)} s wanted)`);
  const rowsTop = (await toy.locator('#rows').boundingBox()).y;
  await toy.mouse.move(zoomedX, rowsTop + 5);
  await toy.keyboard.down('Control');
  await toy.mouse.wheel(0, -300);
  await toy.keyboard.up('Control');
  await toy.waitForTimeout(200);
  const wheelX = await edgeX();
  const level = await toy.textContent('#zoom-level');
  check(Math.abs(wheelX - zoomedX) < 1.5 && parseFloat(level) > 4, `Ctrl+wheel zooms about the mouse (${level}; boundary ${zoomedX.toFixed(1)} → ${wheelX.toFixed(1)} px)`);
  await toy.getByRole('button', { name: 'fit the timeline' }).click();
  check(Math.abs(await edgeX() - fitX) < 1 && await toy.textContent('#zoom-level') === '1×', 'fit shows the whole duration again');

  // Drag the square's boundary from 3 s to 2.4 s: the first split's fractions follow.
  const edgeBox = await toy.getByRole('slider', { name: 'boundary 0 of s#0' }).boundingBox();
  const track = await toy.locator('#rows .row', { hasText: 's#0' }).locator('.track').boundingBox();
  await toy.mouse.move(edgeBox.x + edgeBox.width / 2, edgeBox.y + edgeBox.height / 2);
  await toy.mouse.down();
  await toy.mouse.move(track.x + track.width * 2.4 / 6, edgeBox.y + edgeBox.height / 2, { steps: 6 });
  await toy.mouse.up();
  await toy.waitForFunction(() => /retimed/.test(document.getElementById('status').textContent));
  const retimed = await toy.getByRole('textbox', { name: 'grammar' }).inputValue();
  const fr = /timesplit\(([\d.]+), ([\d.]+)\)\s+: \[all, \(s, c\)\]/.exec(retimed);
  check(fr && Math.abs(fr[1] - 0.4) < 0.01 && Math.abs(+fr[1] + +fr[2] - 1) < 1e-9,
    `dragging a boundary rewrites the timesplit's fractions, their sum kept (${fr && fr.slice(1).join(', ')})`);
  const dropped = await toy.getByRole('slider', { name: 'boundary 0 of s#0' }).getAttribute('aria-valuenow');
  check(Math.abs(dropped - 2.4) < 0.07, `the boundary is drawn where it was dropped (${dropped} s)`);
  if (shots) await toy.screenshot({ path: join(shots, 'studio-timeline.png') });
  // A boundary stepped with the keyboard: one frame later.
  await toy.getByRole('slider', { name: 'boundary 0 of s#0' }).press('ArrowRight');
  await toy.waitForFunction((m) => {
    const e = document.querySelector('[aria-label="boundary 0 of s#0"]');
    return e && Math.abs(e.getAttribute('aria-valuenow') - m - 1 / 30) < 0.01;
  }, +dropped, { timeout: 5000 }).then(() => check(true, 'a boundary moves a frame with →'), () => check(false, 'a boundary moves a frame with →'));
  await toy.getByRole('button', { name: 'Save' }).click();
  await toy.waitForFunction(() => /saved/.test(document.getElementById('status').textContent));
  const toyChecked = checkFile(toyFile);
  check(toyChecked.status === 0, `gmotion check accepts the retimed grammar ${toyChecked.stderr}`);

  // Undo and redo walk one history of visual and typed edits.
  const toyText = () => toy.getByRole('textbox', { name: 'grammar' }).inputValue();
  const stepped1 = await toyText();
  const serverText = () => toy.evaluate(async () => (await (await fetch('/api/grammar', { headers: { 'X-Gmotion-Token': new URLSearchParams(location.search).get('token') } })).text()));
  await toy.evaluate(() => document.activeElement && document.activeElement.blur());   // away from any field
  await toy.keyboard.press('Control+z');
  await toy.waitForTimeout(400);
  const undone1 = await toyText();
  await toy.keyboard.press('Control+z');
  await toy.waitForTimeout(400);
  const undone2 = await toyText();
  const original = readFileSync(join(root, 'grammars', 'toy.gm'), 'utf8');
  check(undone1 === retimed && undone2 === original && await serverText() === original,
    'Ctrl+Z undoes the keyboard step, then the drag (the server follows)');
  await toy.getByRole('button', { name: 'redo' }).click();
  await toy.waitForTimeout(400);
  await toy.keyboard.press('Control+y');
  await toy.waitForTimeout(400);
  check(await toyText() === stepped1 && await serverText() === stepped1, 'redo (button, then Ctrl+Y) brings both back');
  await toy.getByRole('combobox', { name: 'rule', exact: true }).selectOption('animate');
  await toy.getByRole('button', { name: 'Insert rule' }).click();
  await toy.waitForTimeout(400);
  const inserted = await toyText();
  await toy.getByRole('button', { name: 'undo' }).click();
  await toy.waitForTimeout(400);
  check(inserted.includes('-> [moved]') && await toyText() === stepped1, 'undo takes back an inserted rule');

  // A number's slider knows its parameter's domain: a spring's bounce stays in (−1, 1).
  const springy = stepped1.replace('fps 30\n', 'fps 30\nsmoothing spring(0.3, 0.1)\n');
  const box = toy.getByRole('textbox', { name: 'grammar' });
  await box.fill(springy);
  await toy.waitForSelector('#diagnostics .ok');
  const at0 = springy.indexOf('0.1)');
  await box.evaluate((g, p) => { g.focus(); g.setSelectionRange(p + 1, p + 1); }, at0);
  await toy.keyboard.press('ArrowRight');
  const bounce = toy.getByRole('slider', { name: 'bounce of spring' });
  const [lo, hi] = [await bounce.getAttribute('min'), await bounce.getAttribute('max')];
  await bounce.focus();
  await toy.keyboard.press('End');
  await toy.waitForTimeout(600);
  const sprung = await toyText();
  check(+lo > -1 && +hi < 1 && /spring\(0\.3, 0\.99\)/.test(sprung) && /no problems/.test(await toy.textContent('#diagnostics')),
    `the bounce slider spans (−1, 1) open (${lo} … ${hi}; at its end the text says ${/spring\([^)]*\)/.exec(sprung)})`);
  if (shots) await toy.screenshot({ path: join(shots, 'studio-slider.png') });

  // Drag a stagger: c#1's spin starts later; the offset `0.15 * id` is scaled as a whole.
  const spin = toy.getByRole('slider', { name: 'change start 1 of c#1' });
  const from = +(await spin.getAttribute('aria-valuenow'));
  const sb = await spin.boundingBox();
  const ctrack = await toy.locator('#rows .row', { hasText: 'c#1' }).locator('.track').boundingBox();
  await toy.mouse.move(sb.x + sb.width / 2, sb.y + sb.height / 2);
  await toy.mouse.down();
  await toy.mouse.move(ctrack.x + ctrack.width * (from + 0.3) / 6, sb.y + sb.height / 2, { steps: 6 });
  await toy.mouse.up();
  await toy.waitForFunction(() => /moved line/.test(document.getElementById('status').textContent));
  const staggered = await toyText();
  const stag = /animate\(affine, local, ([^,]+), rotate/.exec(staggered);
  const b = stag && /^([\d.]+) \* id$/.exec(stag[1]);
  const after = +(await toy.getByRole('slider', { name: 'change start 1 of c#1' }).getAttribute('aria-valuenow'));
  check(b && Math.abs(b[1] - 0.45) < 0.03 && Math.abs(after - from - 0.3) < 0.03,
    `dragging a stagger scales it (${stag && stag[1]}; c#1's spin from ${from.toFixed(3)} to ${after.toFixed(3)} s)`);
  if (shots) await toy.screenshot({ path: join(shots, 'studio-stagger.png') });
  await toy.evaluate(() => document.activeElement && document.activeElement.blur());
  await toy.keyboard.press('Control+z');
  await toy.waitForTimeout(400);
  check(/0\.15 \* id/.test(await toyText()), 'undo takes the stagger back');
  await toy.keyboard.press('Control+y');
  await toy.waitForTimeout(400);
  await toy.getByRole('button', { name: 'Save' }).click();
  await toy.waitForFunction(() => /saved/.test(document.getElementById('status').textContent));
  const staggerChecked = checkFile(toyFile);
  check(staggerChecked.status === 0 && readFileSync(toyFile, 'utf8') === staggered, `gmotion check accepts the staggered grammar ${staggerChecked.stderr.split('\n')[0]}`);

  // A thousand shapes: every row is reachable, a few in the page at a time.
  // Handles on the canvas: the square dragged at 0.8 s moves its rule's translate so that
  // the frame at 0.8 s follows the mouse (the spring smoothing taken out
  // first, so the frame shows the rule's own progress); a circle turned with its rotate handle's keys
  // and scaled with its scale handle; a colour picked; an easing control point dragged
  // (x clamped to [0, 1]) and a named easing chosen; each undone and redone.
  const tinted = staggered.replace('smoothing spring(0.3, 0.99)\n', '').replace(/\n*$/, '\n') + 'animate(fill, local, 0, #e4572e) : [tran, s] -> [tinted]\n';
  await box.fill(tinted);
  await toy.waitForFunction(() => S && S.grammar.includes('tinted') && /no problems/.test(document.getElementById('diagnostics').textContent));
  const boxesAt = (t) => toy.evaluate(async (t) => (await (await fetch(api('boxes?t=' + t))).json()).boxes, t);
  const tstage = await toy.locator('#overlay').boundingBox();
  const onStage = ([x, y]) => [tstage.x + tstage.width * x / 520, tstage.y + tstage.height * y / 320];
  const sq = await toy.evaluate(() => S.shapes.findIndex((s) => s.tag === 's'));
  // 0.8 s: the square on its way, clear of the circles (drawn above it).
  await toy.getByRole('slider', { name: 'time', exact: true }).fill('133');
  const b0 = (await boxesAt(0.8))[sq];
  const grab = onStage([b0[0] + b0[2] / 2, b0[1] + b0[3] / 2]);
  await toy.mouse.move(...grab);
  await toy.mouse.down();
  await toy.mouse.move(grab[0] + tstage.width * 40 / 520, grab[1] + tstage.height * 20 / 320, { steps: 6 });
  if (shots) await toy.screenshot({ path: join(shots, 'studio-handles.png') });
  await toy.mouse.up();
  await toy.waitForFunction(() => /set line \d+'s value/.test(document.getElementById('status').textContent));
  const dragged = await toyText();
  const tr = /animate\(affine, world, 0, translate\(([-\d.]+), ([-\d.]+)\), ease=ease-in-out\)/.exec(dragged);
  const b1 = (await boxesAt(0.8))[sq];
  check(tr && tr[1] !== '260' && Math.abs(b1[0] - b0[0] - 40) < 2.5 && Math.abs(b1[1] - b0[1] - 20) < 2.5,
    `dragging the square rewrites its translate and the frame at 0.8 s follows (${tr && tr.slice(1).join(', ')}; moved ${(b1[0] - b0[0]).toFixed(1)}, ${(b1[1] - b0[1]).toFixed(1)})`);
  await toy.getByRole('button', { name: 'undo' }).click();
  await toy.waitForTimeout(400);
  const undoneMove = await toyText();
  await toy.getByRole('button', { name: 'redo' }).click();
  await toy.waitForTimeout(400);
  check(undoneMove === tinted && await toyText() === dragged && await serverText() === dragged, 'undo and redo take the drag back and bring it again');

  // The selected square's rules at the frame shown, listed in the panel; one chosen.
  const ruleButtons = toy.getByRole('button', { name: /^rule on line \d+$/ });
  await ruleButtons.nth(1).waitFor({ timeout: 5000 }).catch(() => {});
  const listed = await ruleButtons.allTextContents();
  await ruleButtons.nth(1).click().catch(() => {});
  const shownColour = await toy.getByLabel('colour', { exact: true }).inputValue();
  check(listed.length === 2 && /^affine/.test(listed[0]) && /^fill/.test(listed[1]) && shownColour === '#e4572e',
    `the selected square's rules are listed, its fill's colour shown (${listed.join(', ')}; ${shownColour})`);
  // A circle in its spin: the rotate handle's → turns it 5° at the frame shown.
  const c0 = await toy.evaluate(() => S.shapes.findIndex((s) => s.tag === 'c' && s.id === 0));
  await toy.getByRole('slider', { name: 'time', exact: true }).fill('333');   // 2.0 s
  const cb = (await boxesAt(2.0))[c0];
  await toy.mouse.click(...onStage([cb[0] + cb[2] / 2, cb[1] + cb[3] / 2]));
  await toy.getByRole('button', { name: 'rotate c#0' }).press('ArrowRight');
  await toy.waitForFunction(() => /set line \d+'s value to rotate/.test(document.getElementById('status').textContent));
  const turned = /rotate\(([-\d.]+)\) scale\(1\.6\)/.exec(await toyText());
  check(turned && +turned[1] > 95, `the rotate handle turns the spin's rotate (${turned && turned[0]})`);
  // The boxes are drawn again once the new frame's arrive: wait for the handle to settle.
  await toy.waitForTimeout(300);
  const handle = await toy.getByRole('button', { name: 'scale c#0' }).boundingBox({ timeout: 5000 });
  const hc = [handle.x + handle.width / 2, handle.y + handle.height / 2];
  await toy.mouse.move(...hc);
  await toy.mouse.down();
  const ccx = onStage([cb[0] + cb[2] / 2, cb[1] + cb[3] / 2]);
  await toy.mouse.move(ccx[0] + (hc[0] - ccx[0]) * 1.3, ccx[1] + (hc[1] - ccx[1]) * 1.3, { steps: 5 });
  await toy.mouse.up();
  await toy.waitForFunction(() => /set line \d+'s value to rotate\([^)]*\) scale\((?!1\.6\))/.test(document.getElementById('status').textContent));
  const scaled = /rotate\([-\d.]+\) scale\(([\d.]+)\)/.exec(await toyText());
  check(scaled && +scaled[1] > 1.8, `the scale handle scales the spin's scale (${scaled && scaled[0]})`);

  // The colour of the fill rule at the caret.
  const caretOn = async (needle) => {
    const at = (await toyText()).indexOf(needle);
    await box.evaluate((g, p) => { g.focus(); g.setSelectionRange(p, p); g.dispatchEvent(new Event('click')); }, at);
  };
  await caretOn('animate(fill');
  const colour = toy.getByLabel('colour', { exact: true });
  check(await colour.inputValue() === '#e4572e', `the colour picker shows the rule's colour (${await colour.inputValue()})`);
  await colour.fill('#3355ff');
  await toy.waitForFunction(() => /set line \d+'s value to #3355ff/.test(document.getElementById('status').textContent));
  const picked = await toyText();
  check(picked.includes('animate(fill, local, 0, #3355ff) : [tran, s]'), 'picking a colour rewrites the rule\'s colour');
  await toy.getByRole('button', { name: 'undo' }).click();
  await toy.waitForTimeout(400);
  const colourBack = await colour.inputValue();
  const unpicked = await toyText();
  await toy.getByRole('button', { name: 'redo' }).click();
  await toy.waitForTimeout(400);
  check(unpicked.includes('0, #e4572e)') && colourBack === '#e4572e' && await toyText() === picked && await serverText() === picked,
    `undo and redo take the colour back (the picker showing ${colourBack}) and bring it again`);

  // The easing curve of the move.
  await caretOn('animate(affine, world');
  const easing = toy.getByRole('combobox', { name: 'easing', exact: true });
  check(await easing.inputValue() === 'ease-in-out', `the easing editor shows the rule's easing (${await easing.inputValue()})`);
  const cp = await toy.getByRole('slider', { name: 'easing control point 1' }).boundingBox();
  const curveBox = await toy.getByRole('group', { name: 'easing curve' }).boundingBox();
  await toy.mouse.move(cp.x + cp.width / 2, cp.y + cp.height / 2);
  await toy.mouse.down();
  await toy.mouse.move(curveBox.x - 40, cp.y - curveBox.height * 0.2, { steps: 5 });   // left of the box
  await toy.mouse.up();
  await toy.waitForFunction(() => /set line \d+'s ease to cubic/.test(document.getElementById('status').textContent));
  const curved = await toyText();
  const cu = /ease=cubic\(([-\d.]+), ([-\d.]+), ([-\d.]+), ([-\d.]+)\)/.exec(curved);
  check(cu && +cu[1] === 0 && +cu[2] > 0 && cu[3] === '0.58' && cu[4] === '1' && cu.slice(1).every((v) => v === String(+(+v).toFixed(2))),
    `dragging a control point writes cubic(…), x clamped to [0, 1], two decimals (${cu && cu[0]})`);
  if (shots) await toy.screenshot({ path: join(shots, 'studio-easing.png') });
  await toy.getByRole('button', { name: 'undo' }).click();
  await toy.waitForTimeout(400);
  const uneased = await toyText();
  const easeBack = await easing.inputValue();
  await toy.getByRole('button', { name: 'redo' }).click();
  await toy.waitForTimeout(400);
  check(uneased.includes('ease=ease-in-out)') && easeBack === 'ease-in-out' && await toyText() === curved && await serverText() === curved,
    `undo and redo take the curve back (the editor showing ${easeBack}) and bring it again`);
  await easing.selectOption('ease-out');
  await toy.waitForFunction(() => /set line \d+'s ease to ease-out/.test(document.getElementById('status').textContent));
  check((await toyText()).includes('ease=ease-out) : [a, s]'), 'choosing a named easing writes its name');
  // The background: no rule moves it, so a drag proposes one in the form, adding nothing.
  const unproposed = await toyText();
  const bg = onStage([480, 40]);
  await toy.mouse.move(...bg);
  await toy.mouse.down();
  await toy.mouse.move(bg[0] - tstage.width * 30 / 520, bg[1], { steps: 4 });
  await toy.mouse.up();
  await toy.waitForFunction(() => /a new rule is proposed/.test(document.getElementById('status').textContent));
  const toyForm = toy.locator('#rule-form');
  const proposed = await toyForm.getByLabel('value', { exact: true }).inputValue();
  check(/^translate\(-3\d(\.\d)?, 0\)$/.test(proposed) && await toyForm.getByLabel('shapes', { exact: true }).inputValue() === 'background'
    && await toyText() === unproposed, `a drag on a shape no rule moves proposes a rule in the form (${proposed}), the text unchanged`);
  await toy.getByRole('button', { name: 'Save' }).click();
  await toy.waitForFunction(() => /saved/.test(document.getElementById('status').textContent));
  const handled = checkFile(toyFile);
  check(handled.status === 0, `gmotion check accepts the grammar the handles, picker and curve wrote ${handled.stderr.split('\n')[0]}`);

  const many = await browser.newPage({ viewport: { width: 1280, height: 1000 }, deviceScaleFactor: 1 });
  many.on('pageerror', (e) => errors.push(String(e)));
  await many.goto(await studio(join(dir, 'many.svg'), join(dir, 'many.gm')));
  await many.waitForFunction(() => /1000 shapes/.test(document.getElementById('status').textContent));
  const inPage = await many.$$eval('#rows .row', (rs) => rs.length);
  await many.$eval('#timeline', (tl) => { tl.scrollTop = tl.scrollHeight; });
  await many.waitForTimeout(200);
  const lastRow = await many.$$eval('#rows .row .name', (ns) => ns.map((n) => n.textContent));
  check(lastRow.includes('r#999') && inPage < 60, `every row is reachable (${inPage} rows in the page; the last is ${lastRow[lastRow.length - 1]})`);
  const bottom = await many.evaluate(timelinePixels, 'r#999');
  check(bottom.bars.length > 0 && bottom.bars.every((b) => b.ok), `scrolled to the end, the canvas draws the last row's bars (${JSON.stringify(bottom.bars)})`);
  // Scrolled a few rows at a time (the rows still in view kept, those scrolled in added),
  // up and down: the page holds the rows of the window in view, each once, in order.
  let windowOk = true, seenWindow = '';
  for (const step of [-90, -36, -18, -200, 54, 18, -500, 1000]) {
    await many.$eval('#timeline', (tl, d) => { tl.scrollTop += d; }, step);
    // The rows follow a scroll once the page is idle (at most ~100 ms later): wait for the
    // row in view to exist, then check the whole window.
    const top = await many.$eval('#timeline', (tl) => Math.floor(tl.scrollTop / 18));
    await many.waitForFunction((want) => [...document.querySelectorAll('#rows .row')].some((r) => +r.dataset.i === want),
      Math.min(999, top + 2), { timeout: 2000 }).catch(() => {});
    const idx = await many.$$eval('#rows .row', (rs) => rs.map((r) => +r.dataset.i));
    const contiguous = idx.every((v, k) => k === 0 || v === idx[k - 1] + 1);
    if (!contiguous || !idx.includes(Math.min(999, top + 2))) { windowOk = false; seenWindow = `${idx[0]}…${idx[idx.length - 1]} at row ${top}`; }
  }
  check(windowOk, `scrolling keeps exactly the rows in view, each once, in order ${seenWindow}`);

  // An 800 × 800 scene: the preview fits, the timeline stays in view.
  const big = await browser.newPage({ viewport: { width: 1280, height: 800 }, deviceScaleFactor: 1 });
  big.on('pageerror', (e) => errors.push(String(e)));
  await big.goto(await studio(join(dir, 'big.svg'), join(dir, 'big.gm')));
  await big.waitForFunction(() => /version 1 /.test(document.getElementById('status').textContent));
  await big.waitForTimeout(300);
  const stageBox = await big.locator('#stage').boundingBox();
  const timeline = await big.locator('#timeline').boundingBox();
  check(stageBox.height <= 0.45 * 800 + 1 && timeline.y < 800,
    `an 800 × 800 scene fits (preview ${Math.round(stageBox.height)} px high, timeline at ${Math.round(timeline.y)} px in an 800 px window)`);
  check(errors.length === 0, `no script errors ${errors.join('; ')}`);
} catch (e) {
  console.log(`FAIL ${e.stack || e}`);
  failed = true;
} finally {
  await browser.close();
  for (const c of children) c.kill();
}
process.exit(failed ? 1 : 0);
