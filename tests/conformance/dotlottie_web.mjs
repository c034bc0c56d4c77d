// Plays dotLottie packages (.lottie) in @lottiefiles/dotlottie-web (LottieFiles' player, ThorVG
// compiled to wasm) inside headless Chromium and writes the requested frames as transparent
// PNGs. The player's module and its wasm are served from node_modules: nothing is fetched
// from the network (the player's CDN fallback is turned off by setWasmUrl).
//
//   node dotlottie_web.mjs JOBS.json
//
// JOBS.json: [{"lottie": "a.lottie", "animation": "id" (optional: the package's initial one),
//              "width": 300, "height": 200, "frames": [0, 5], "out": ["a-0.png", "a-5.png"]}, …]
// Also prints, per job, a line {"lottie": …, "manifest": …, "totalFrames": …, "markers": [...]}
// on stdout: what the player read from the package. A job that fails is
// reported on stderr with its file and the run goes on; the exit status is 1 if any failed.
import { readFileSync, writeFileSync } from 'node:fs';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const dist = join(here, 'node_modules/@lottiefiles/dotlottie-web/dist');
const origin = 'http://dotlottie.test';

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const page = await browser.newPage({ deviceScaleFactor: 1 });
// The page, the player's module and its wasm from the package; anything else is refused.
await page.route('**/*', (route) => {
  const url = new URL(route.request().url());
  if (url.origin !== origin) return route.abort();
  if (url.pathname === '/') {
    return route.fulfill({ contentType: 'text/html', body: '<!doctype html><html><body style="margin:0;background:transparent"><canvas id="c"></canvas></body></html>' });
  }
  if (url.pathname === '/index.js') {
    return route.fulfill({ contentType: 'text/javascript', body: readFileSync(join(dist, 'index.js')) });
  }
  if (url.pathname === '/dotlottie-player.wasm') {
    return route.fulfill({ contentType: 'application/wasm', body: readFileSync(join(dist, 'dotlottie-player.wasm')) });
  }
  return route.fulfill({ status: 404, body: '' });
});
await page.goto(origin + '/');
await page.evaluate(async (origin) => {
  const { DotLottie } = await import(origin + '/index.js');
  DotLottie.setWasmUrl(origin + '/dotlottie-player.wasm');
  window.DotLottie = DotLottie;
}, origin);

let failed = false;
for (const job of JSON.parse(readFileSync(process.argv[2], 'utf8'))) {
  try {
    // One round trip a job: the package goes in as base64 (a byte array as JSON costs ten
    // times its size), each frame comes back as the canvas's own PNG. setFrame draws
    // synchronously (the core renders, then putImageData), so the canvas holds the frame
    // as soon as it returns: no screenshot, no wait for the compositor.
    const data = readFileSync(job.lottie).toString('base64');
    const got = await page.evaluate(async ({ data, job }) => {
      if (window.player) window.player.destroy();
      const canvas = document.getElementById('c');
      canvas.style.width = job.width + 'px';
      canvas.style.height = job.height + 'px';
      canvas.width = job.width;
      canvas.height = job.height;
      const bytes = Uint8Array.from(atob(data), (c) => c.charCodeAt(0));
      const player = new window.DotLottie({
        canvas, data: bytes.buffer, autoplay: false, loop: false,
        renderConfig: { devicePixelRatio: 1, autoResize: false, freezeOnOffscreen: false },
        ...(job.animation ? { animationId: job.animation } : {}),
      });
      window.player = player;
      // A package whose animation the player cannot read (`{"v": "x"}`) fires neither
      // event: the job fails after a minute instead of holding up the run for ever.
      const loaded = () => new Promise((resolve, reject) => {
        player.addEventListener('load', resolve);
        player.addEventListener('loadError', (e) => reject(new Error(String(e.error || 'loadError'))));
        setTimeout(() => reject(new Error('neither loaded nor refused within 60 s')), 60000);
      });
      await loaded();
      // The config's animationId loses to a manifest's initial animation: ask by name.
      if (job.animation) {
        const again = loaded();
        player.loadAnimation(job.animation);
        await again;
      }
      const frames = [];
      for (const f of job.frames) {
        player.setFrame(f);
        frames.push(canvas.toDataURL('image/png'));
      }
      return {
        info: { manifest: player.manifest, totalFrames: player.totalFrames, markers: player.markers() },
        frames,
      };
    }, { data, job });
    console.log(JSON.stringify({ lottie: job.lottie, ...got.info }));
    got.frames.forEach((url, i) => writeFileSync(job.out[i], Buffer.from(url.slice(url.indexOf(',') + 1), 'base64')));
  } catch (e) {
    failed = true;
    console.error(`dotlottie-web: ${job.lottie}: ${String(e.message || e).split('\n')[0]}`);
  }
}
await browser.close();
process.exit(failed ? 1 : 0);
