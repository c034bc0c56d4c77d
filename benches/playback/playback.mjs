// The playback benchmark: how long a web player takes to load a Lottie file and to draw one
// of its frames, in headless Chromium (software rendering, as on a machine without a GPU).
//
//   node benches/playback/playback.mjs [--players svg,canvas,dotlottie] [--frames N]
//        [--rounds R] [--width W] FILE.json …
//
// For each file and player: the file's size raw and gzipped; the load time (from handing the
// parsed document to the player to its first frame on screen, median of R loads); and the
// time to draw a frame: the player plays N frames in order (every frame of the animation by
// default), one per frame of the page, and the interval between two consecutive frames of the page
// (script, style, layout, paint and raster: everything the browser does to show the frame)
// is recorded. Chromium runs with its frame rate limit off, so an interval is the work, not
// the display's refresh. The median and the 90th percentile over N·R intervals are printed,
// one JSON line per file and player, then a table.
//
// Players: lottie-web 5.13 with its svg and canvas renderers, and @lottiefiles/dotlottie-web
// (ThorVG compiled to wasm, drawing into a canvas), all from tests/conformance/node_modules
// (installed by tests/conformance/install.sh); nothing is fetched from the network.
import { readFileSync } from 'node:fs';
import { gzipSync } from 'node:zlib';
import { basename, dirname, join } from 'node:path';
import { createRequire } from 'node:module';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const modules = join(here, '../../tests/conformance/node_modules');
const require = createRequire(join(modules, 'noop.js'));
const { chromium } = require('playwright-core');

const args = process.argv.slice(2);
const option = (name, fallback) => {
  const at = args.indexOf(name);
  if (at < 0) return fallback;
  const value = args[at + 1];
  args.splice(at, 2);
  return value;
};
const players = option('--players', 'svg,canvas,dotlottie').split(',');
const frames = Number(option('--frames', '0'));
const rounds = Number(option('--rounds', '3'));
const width = Number(option('--width', '0'));
if (args.length === 0 || args.some((a) => a.startsWith('--'))) {
  console.error('usage: playback.mjs [--players svg,canvas,dotlottie] [--frames N] [--rounds R] [--width W] FILE.json …');
  process.exit(2);
}

const builds = {
  svg: join(modules, 'lottie-web/build/player/lottie_svg.min.js'),
  canvas: join(modules, 'lottie-web/build/player/lottie_canvas.min.js'),
};
const dotlottie = join(modules, '@lottiefiles/dotlottie-web/dist');
const origin = 'http://playback.test';

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync',
    // Without these the page's frames are paced by a 60 Hz clock and every interval
    // reads 16.7 ms however little the player did.
    '--disable-frame-rate-limit', '--disable-gpu-vsync'],
});

async function newPage(player, w, h) {
  const page = await browser.newPage({ deviceScaleFactor: 1, viewport: { width: w, height: h } });
  await page.route('**/*', (route) => {
    const url = new URL(route.request().url());
    if (url.origin !== origin) return route.abort();
    const body = {
      '/': () => ({ contentType: 'text/html', body: '<!doctype html><html><body style="margin:0"><div id="c" style="width:100vw;height:100vh"></div><canvas id="k"></canvas></body></html>' }),
      '/lottie.js': () => ({ contentType: 'text/javascript', body: readFileSync(builds[player]) }),
      '/index.js': () => ({ contentType: 'text/javascript', body: readFileSync(join(dotlottie, 'index.js')) }),
      '/dotlottie-player.wasm': () => ({ contentType: 'application/wasm', body: readFileSync(join(dotlottie, 'dotlottie-player.wasm')) }),
    }[url.pathname];
    return body ? route.fulfill(body()) : route.fulfill({ status: 404, body: '' });
  });
  await page.goto(origin + '/');
  if (player === 'dotlottie') {
    await page.evaluate(async (origin) => {
      const { DotLottie } = await import(origin + '/index.js');
      DotLottie.setWasmUrl(origin + '/dotlottie-player.wasm');
      window.DotLottie = DotLottie;
    }, origin);
  } else {
    await page.addScriptTag({ url: origin + '/lottie.js' });
  }
  return page;
}

// Runs in the page: loads the document (a JSON string) in the player, waits for its first
// frame to be shown, then draws `frames` frames one per page frame and returns the load
// time and the intervals.
async function measure({ text, player, frames, w, h }) {
  const nextFrame = () => new Promise((resolve) => requestAnimationFrame(resolve));
  const doc = JSON.parse(text);
  const total = doc.op - doc.ip;
  await nextFrame();
  const start = performance.now();
  let seek;
  let done;
  if (player === 'dotlottie') {
    const canvas = document.getElementById('k');
    canvas.width = w;
    canvas.height = h;
    canvas.style.width = w + 'px';
    canvas.style.height = h + 'px';
    document.getElementById('c').style.display = 'none';
    const anim = new window.DotLottie({
      canvas, data: text, autoplay: false, loop: false,
      renderConfig: { devicePixelRatio: 1, autoResize: false, freezeOnOffscreen: false },
    });
    await new Promise((resolve, reject) => {
      anim.addEventListener('load', resolve);
      anim.addEventListener('loadError', (e) => reject(new Error(String(e.error))));
    });
    seek = (f) => anim.setFrame(f);
    done = () => anim.destroy();
  } else {
    const anim = window.lottie.loadAnimation({
      container: document.getElementById('c'), renderer: player, loop: false,
      autoplay: false, animationData: doc,
      rendererSettings: player === 'canvas' ? { clearCanvas: true } : {},
    });
    await new Promise((resolve) => anim.addEventListener('DOMLoaded', resolve));
    anim.goToAndStop(0, true);
    seek = (f) => anim.goToAndStop(f, true);
    done = () => anim.destroy();
  }
  await nextFrame();
  const load = performance.now() - start;
  const intervals = [];
  const scripts = [];
  let last = await nextFrame();
  for (let i = 1; i <= frames; i += 1) {
    // Played in order, as a page plays it: frame after frame from the start, wrapping
    // around, so a player gains what it saves on what did not change since the last frame.
    const before = performance.now();
    seek(doc.ip + (i % total));
    scripts.push(performance.now() - before);
    const now = await nextFrame();
    intervals.push(now - last);
    last = now;
  }
  done();
  return { load, intervals, scripts };
}

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2;
};
const percentile = (xs, p) => [...xs].sort((a, b) => a - b)[Math.min(xs.length - 1, Math.floor(p * xs.length))];

// Rounds outermost, so that the files and players alternate and a host that slows down
// for a while slows every one of them alike.
const results = new Map();
const docs = args.map((file) => {
  const bytes = readFileSync(file);
  return { file, bytes, text: bytes.toString('utf8'), doc: JSON.parse(bytes.toString('utf8')) };
});
for (let r = 0; r < rounds; r += 1) {
  for (const { file, text, doc } of docs) {
    const w = width || doc.w;
    const h = Math.max(1, Math.round(w * doc.h / doc.w));
    for (const player of players) {
      const page = await newPage(player, w, h);
      const got = await page.evaluate(measure, { text, player, frames: frames || doc.op - doc.ip, w, h });
      await page.close();
      const key = file + '\0' + player;
      const acc = results.get(key) || { loads: [], intervals: [], scripts: [] };
      acc.loads.push(got.load);
      acc.intervals.push(...got.intervals);
      acc.scripts.push(...got.scripts);
      results.set(key, acc);
    }
  }
}
const rows = [];
for (const { file, bytes } of docs) {
  for (const player of players) {
    const acc = results.get(file + '\0' + player);
    const row = {
      file: basename(file), player, bytes: bytes.length, gzip: gzipSync(bytes).length,
      load_ms: +median(acc.loads).toFixed(1), frame_ms: +median(acc.intervals).toFixed(2),
      frame_p90_ms: +percentile(acc.intervals, 0.9).toFixed(2),
      script_ms: +median(acc.scripts).toFixed(2), frames: acc.intervals.length,
    };
    console.log(JSON.stringify(row));
    rows.push(row);
  }
}
await browser.close();

console.log('\n| file | player | size (gzip) | load | frame median (p90) | player script |');
console.log('|---|---|---|---|---|---|');
for (const r of rows) {
  const kb = (n) => (n >= 1e6 ? (n / 1e6).toFixed(2) + ' MB' : (n / 1e3).toFixed(1) + ' kB');
  console.log(`| ${r.file} | ${r.player} | ${kb(r.bytes)} (${kb(r.gzip)}) | ${r.load_ms} ms | ${r.frame_ms} ms (${r.frame_p90_ms}) | ${r.script_ms} ms |`);
}
