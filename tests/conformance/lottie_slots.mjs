// Sets one slot of a Lottie file in lottie-web (canvas renderer: the document's `slots`
// entry replaced before loadAnimation, as lottie-web reads slots at load) and in
// dotlottie-web (setColorSlot after loading), both in headless Chromium, and compares every
// frame with the same file played unchanged. Prints one line of JSON:
// {"lottie-web": [FRAME…], "dotlottie-web": [FRAME…]}, a FRAME being {"changed": pixels
// that differ, "box": [x0, y0, x1, y1] of them (null if none), "off": changed pixels whose
// new colour is not the slot's (antialiased edges)}.
//
//   node lottie_slots.mjs FILE.json SLOT_ID R,G,B [PACKAGE.lottie THEME_ID]
//   node lottie_slots.mjs FILE.json SLOT_ID OPACITY
//
// R, G, B in 0..1; an opacity slot takes one number, in Lottie's percent (0..100), and
// dotlottie-web sets it with setScalarSlot ("off" then counts nothing: there is no one
// colour to expect). With a package (the same animation, with a theme setting the slot to
// that colour), dotlottie-web plays the package and applies the theme with setTheme
// instead of setting the slot.
import { readFileSync } from 'node:fs';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const dist = join(here, 'node_modules/@lottiefiles/dotlottie-web/dist');
const origin = 'http://dotlottie.test';
const [file, slot, rgb, pkg, themeId] = process.argv.slice(2);
const packageBytes = pkg ? [...readFileSync(pkg)] : null;
const color = rgb.split(',').map(Number);
// One number: a scalar (opacity) slot.
const scalar = color.length === 1 ? color[0] : null;
const text = readFileSync(file, 'utf8');

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run', '--disable-background-networking'],
});
const page = await browser.newPage({ deviceScaleFactor: 1 });
await page.route('**/*', (route) => {
  const url = new URL(route.request().url());
  if (url.origin !== origin) return route.abort();
  const files = {
    '/': ['text/html', '<!doctype html><html><body style="margin:0"><div id="c"></div><canvas id="d"></canvas></body></html>'],
    '/lottie.js': ['text/javascript', readFileSync(join(here, 'node_modules/lottie-web/build/player/lottie_canvas.min.js'))],
    '/index.js': ['text/javascript', readFileSync(join(dist, 'index.js'))],
    '/dotlottie-player.wasm': ['application/wasm', readFileSync(join(dist, 'dotlottie-player.wasm'))],
  };
  const f = files[url.pathname];
  return f ? route.fulfill({ contentType: f[0], body: f[1] }) : route.fulfill({ status: 404, body: '' });
});
await page.goto(origin + '/');
await page.addScriptTag({ url: origin + '/lottie.js' });
const result = await page.evaluate(async ({ text, slot, color, scalar, origin, packageBytes, themeId }) => {
  const { DotLottie } = await import(origin + '/index.js');
  DotLottie.setWasmUrl(origin + '/dotlottie-player.wasm');
  const doc = JSON.parse(text);
  const [w, h, frames] = [doc.w, doc.h, Math.round(doc.op - doc.ip)];
  const compare = (a, b) => {
    let changed = 0, off = 0, box = null;
    for (let i = 0; i < a.length; i += 4) {
      const d = Math.max(...[0, 1, 2, 3].map((c) => Math.abs(a[i + c] - b[i + c])));
      if (d <= 24) continue;
      changed++;
      const [x, y] = [(i / 4) % w, Math.floor(i / 4 / w)];
      box = box ? [Math.min(box[0], x), Math.min(box[1], y), Math.max(box[2], x), Math.max(box[3], y)] : [x, y, x, y];
      if (scalar === null && ([0, 1, 2].some((c) => Math.abs(b[i + c] - color[c] * 255) > 24) || b[i + 3] < 230)) off++;
    }
    return { changed, box, off };
  };
  // lottie-web, canvas renderer: the plain document and the one with the slot replaced.
  const lottieFrames = (data) => {
    const box = document.getElementById('c');
    box.innerHTML = '';
    box.style.cssText = `width:${w}px;height:${h}px`;
    const anim = lottie.loadAnimation({
      container: box, renderer: 'canvas', loop: false, autoplay: false, animationData: data,
      rendererSettings: { clearCanvas: true, dpr: 1 },
    });
    const out = [];
    for (let f = 0; f < frames; f++) {
      anim.goToAndStop(f, true);
      const c = box.querySelector('canvas');
      out.push(c.getContext('2d').getImageData(0, 0, w, h).data);
    }
    anim.destroy();
    return out;
  };
  const slotted = JSON.parse(text);
  slotted.slots[slot] = { p: { a: 0, k: scalar ?? color } };
  const [plain, set] = [lottieFrames(JSON.parse(text)), lottieFrames(slotted)];
  const lw = plain.map((p, f) => compare(p, set[f]));
  // dotlottie-web: the same document, the slot set with setSlots.
  const dotFrames = async (value) => {
    const canvas = document.getElementById('d');
    canvas.width = w;
    canvas.height = h;
    const player = new DotLottie({
      canvas, data: packageBytes ? new Uint8Array(packageBytes).buffer : text, autoplay: false, loop: false,
      renderConfig: { devicePixelRatio: 1, autoResize: false, freezeOnOffscreen: false },
    });
    await new Promise((resolve, reject) => {
      player.addEventListener('load', resolve);
      player.addEventListener('loadError', (e) => reject(new Error(String(e.error || 'loadError'))));
    });
    // setColorSlot, not setSlots: dotlottie-web 0.80's setSlots left the slot as it was
    // for a bare colour and for a property alike (getSlot read back the old value).
    if (value && themeId) {
      if (!player.setTheme(themeId)) throw new Error(`setTheme(${themeId}) failed`);
    } else if (value && scalar !== null) {
      if (!player.setScalarSlot(slot, scalar)) throw new Error(`setScalarSlot(${slot}) failed`);
    } else if (value && !player.setColorSlot(slot, [...value, 1])) {
      throw new Error(`setColorSlot(${slot}) failed`);
    }
    const out = [];
    for (let f = 0; f < frames; f++) {
      player.setFrame(f);
      out.push(canvas.getContext('2d').getImageData(0, 0, w, h).data);
    }
    player.destroy();
    return out;
  };
  const [dplain, dset] = [await dotFrames(null), await dotFrames(color)];
  const dw = dplain.map((p, f) => compare(p, dset[f]));
  return { 'lottie-web': lw, 'dotlottie-web': dw };
}, { text, slot, color, scalar, origin, packageBytes, themeId });
console.log(JSON.stringify(result));
await browser.close();
