// Plays Lottie files in lottie-web inside one headless Chromium and writes the requested
// frames as transparent PNGs.
//
//   node lottie_web.mjs JOBS.json
//   node lottie_web.mjs --serve   (one JSON job list per line on stdin, each answered by a
//                                  line {"errors": [...]} on stdout once its PNGs are written;
//                                  exits at the end of stdin. The Rust tests keep one running
//                                  for the whole test binary: tests/support/players.rs.)
//
// JOBS.json: [{"json": "a.json", "width": 300, "frames": [0, 5], "out": ["a-0.png", "a-5.png"]}, …]
// A job may add "renderer": "svg" (the default) or "canvas"; each uses lottie-web's own
// build for that renderer (lottie_svg.min.js, lottie_canvas.min.js).
// Jobs run on a few pages in parallel; a job that fails (bad JSON, player exception) is
// reported (stderr, or the answer's errors) with its file and the run goes on, leaving its
// PNGs unwritten.
import { readFileSync, statSync } from 'node:fs';
import { createInterface } from 'node:readline';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const players = {
  svg: join(here, 'node_modules/lottie-web/build/player/lottie_svg.min.js'),
  canvas: join(here, 'node_modules/lottie-web/build/player/lottie_canvas.min.js'),
};
const serve = process.argv[2] === '--serve';
const pages = Number(process.env.PAGES || (serve ? 1 : 3));

const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  // playwright gives every launch a fresh temporary profile (--user-data-dir).
});

async function worker(queue, errors) {
  const page = await browser.newPage({ deviceScaleFactor: 1 });
  // The page holds one renderer's build at a time (both define the global `lottie`); it is
  // reloaded when a job wants the other (the queue is sorted so that this is rare).
  let loaded = null;
  for (;;) {
    const job = queue.shift();
    if (!job) break;
    try {
      const renderer = job.renderer || 'svg';
      if (!players[renderer]) throw new Error(`unknown renderer ${JSON.stringify(renderer)} (svg or canvas)`);
      if (loaded !== renderer) {
        await page.setContent('<!doctype html><html><body style="margin:0;background:transparent"><div id="c"></div></body></html>');
        await page.addScriptTag({ path: players[renderer] });
        loaded = renderer;
      }
      const data = JSON.parse(readFileSync(job.json, 'utf8'));
      const height = Math.max(1, Math.round(job.width * data.h / data.w));
      await page.setViewportSize({ width: job.width, height });
      await page.evaluate(({ data, width, height, renderer }) => {
        if (window.anim) window.anim.destroy();
        const c = document.getElementById('c');
        c.innerHTML = '';
        c.style.width = width + 'px';
        c.style.height = height + 'px';
        window.anim = lottie.loadAnimation({
          container: c, renderer, loop: false, autoplay: false, animationData: data,
          // Scale uniformly from the top-left corner, as resvg renders the references.
          rendererSettings: { preserveAspectRatio: 'xMinYMin meet', clearCanvas: true },
        });
      }, { data, width: job.width, height, renderer });
      for (let i = 0; i < job.frames.length; i++) {
        await page.evaluate((f) => window.anim.goToAndStop(f, true), job.frames[i]);
        // Generous: a file with tens of thousands of shapes takes long on two busy cores.
        await page.locator('#c').screenshot({ path: job.out[i], omitBackground: true, timeout: 300000 });
      }
    } catch (e) {
      errors.push(`lottie-web: ${job.json}: ${String(e.message || e).split('\n')[0]}`);
    }
  }
  await page.close();
}

// Jobs of one renderer together, so pages rarely switch builds; within a renderer, biggest
// files first, so that a huge one does not start last and hold up the end.
async function playAll(jobs) {
  const size = (j) => { try { return statSync(j.json).size; } catch { return 0; } };
  const kind = (j) => String(j.renderer || 'svg');
  const queue = jobs.slice().sort((a, b) => kind(a).localeCompare(kind(b)) || size(b) - size(a));
  const errors = [];
  await Promise.all(Array.from({ length: pages }, () => worker(queue, errors)));
  return errors;
}

if (serve) {
  for await (const line of createInterface({ input: process.stdin })) {
    if (!line.trim()) continue;
    const errors = await playAll(JSON.parse(line));
    process.stdout.write(JSON.stringify({ errors }) + '\n');
  }
} else {
  for (const e of await playAll(JSON.parse(readFileSync(process.argv[2], 'utf8')))) console.error(e);
}
await browser.close();
