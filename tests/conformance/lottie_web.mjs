// Plays Lottie files in lottie-web inside one headless Chromium and writes the requested
// frames as transparent PNGs.
//
//   node lottie_web.mjs JOBS.json
//   node lottie_web.mjs --serve   (one JSON job list per line on stdin, each answered by a
//                                  line {"errors": [...]} on stdout once its PNGs are written;
//                                  exits at the end of stdin. The Rust tests keep one running
//                                  for the whole test binary: testkit/src/players.rs.)
//
// JOBS.json: [{"json": "a.json", "width": 300, "frames": [0, 5], "out": ["a-0.png", "a-5.png"]}, …]
// A job may add "renderer": "svg" (the default) or "canvas"; each uses lottie-web's own
// build for that renderer (lottie_svg.min.js, lottie_canvas.min.js).
// Each renderer's jobs run on pages of their own (PAGES in all, at least one a renderer),
// both renderers at once; a job that fails (bad JSON, player exception) is reported
// (stderr, or the answer's errors) with its file and the run goes on, leaving its PNGs
// unwritten.
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

// Pages that hold one renderer's build (both builds define the global `lottie`), kept
// between job lists: loading a build into a fresh page cost more than playing a small file.
const idle = { svg: [], canvas: [] };

async function pageWith(renderer) {
  const kept = idle[renderer].pop();
  if (kept && !kept.isClosed()) return kept;
  // A page's first load waits for Chromium's renderer process: on a machine busy with
  // other jobs that start once took past playwright's 30 s default, failing a whole run
  // that had nothing wrong with it. Two tries of two minutes each before giving up.
  for (let attempt = 1; ; attempt++) {
    const page = await browser.newPage({ deviceScaleFactor: 1 });
    try {
      await page.setContent(
        '<!doctype html><html><body style="margin:0;background:transparent"><div id="c"></div></body></html>',
        { timeout: 120000 });
      await page.addScriptTag({ path: players[renderer] });
      return page;
    } catch (err) {
      await page.close().catch(() => {});
      if (attempt >= 2) throw err;
      console.error(`lottie_web: a ${renderer} page did not load (${err.message.split('\n')[0]}); trying again`);
    }
  }
}

async function worker(renderer, queue, errors) {
  const page = await pageWith(renderer);
  for (;;) {
    const job = queue.shift();
    if (!job) break;
    try {
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
        // The viewport is the player's box: a page shot skips the element shot's waits for
        // a stable, visible element (half of the time of a small file's frames).
        // Generous: a file with tens of thousands of shapes takes long on two busy cores.
        await page.screenshot({ path: job.out[i], omitBackground: true, timeout: 300000 });
      }
    } catch (e) {
      errors.push(`lottie-web: ${job.json}: ${String(e.message || e).split('\n')[0]}`);
    }
  }
  idle[renderer].push(page);
}

// Each renderer's jobs on pages of their own, both renderers at once; within a renderer,
// biggest files first, so that a huge one does not start last and hold up the end.
async function playAll(jobs) {
  const size = (j) => { try { return statSync(j.json).size; } catch { return 0; } };
  const errors = [];
  const queues = { svg: [], canvas: [] };
  for (const job of jobs) {
    const renderer = job.renderer || 'svg';
    if (!Object.hasOwn(queues, renderer)) {
      errors.push(`lottie-web: ${job.json}: unknown renderer ${JSON.stringify(renderer)} (svg or canvas)`);
    } else {
      queues[renderer].push(job);
    }
  }
  const used = Object.values(queues).filter((q) => q.length > 0).length;
  const each = Math.max(1, Math.round(pages / Math.max(1, used)));
  const workers = [];
  for (const [renderer, queue] of Object.entries(queues)) {
    queue.sort((a, b) => size(b) - size(a));
    for (let k = 0; k < Math.min(each, queue.length); k++) workers.push(worker(renderer, queue, errors));
  }
  await Promise.all(workers);
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
