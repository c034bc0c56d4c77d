#!/usr/bin/env node
// Plays animated SVG (SMIL) documents in headless Chromium and screenshots chosen instants.
//
//   node smil.mjs FILE.svg WIDTH OUT_PREFIX T1 [T2 …]
//       writes OUT_PREFIX-<i>.png (i = index of the time, from 0) for each time in seconds
//   node smil.mjs --jobs JOBS.json
//       one browser for many files; JOBS.json is [{"svg", "width", "out_prefix", "times"}]
//   node smil.mjs --serve
//       reads one such job list per line on stdin and answers each with a line
//       {"errors": [...]} once its PNGs are written; exits at the end of stdin. The Rust
//       tests keep one running for the whole test binary (testkit/src/players.rs), so
//       that each shot does not pay Chromium's start.
//
// Each frame: the document is loaded, its animations paused, the clock set with
// `svg.pauseAnimations(); svg.setCurrentTime(t)` (the SMIL DOM), two animation frames
// awaited, then the page shot WIDTH px wide (height from the document's aspect ratio,
// rounded, the picture scaled by WIDTH / width from the top left as gmotion renders it) on
// a transparent background. Prints one line per file: `<svg> <frames written>`.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { createInterface } from 'node:readline';
import { pathToFileURL } from 'node:url';
import { chromium } from 'playwright-core';

const CHROMIUM = process.env.CHROMIUM || '/usr/bin/chromium';
const ARGS = [
  '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
];

function usage(msg) {
  console.error(`smil.mjs: ${msg}\nusage: node smil.mjs FILE.svg WIDTH OUT_PREFIX T1 [T2 …]\n       node smil.mjs --jobs JOBS.json`);
  process.exit(2);
}

function parseJobs(argv) {
  if (argv[0] === '--jobs') {
    if (argv.length !== 2) usage('--jobs takes one file');
    let jobs;
    try {
      jobs = JSON.parse(fs.readFileSync(argv[1], 'utf8'));
    } catch (e) {
      usage(`cannot read ${argv[1]}: ${e.message}`);
    }
    if (!Array.isArray(jobs)) usage(`${argv[1]}: expected a JSON array of jobs`);
    return jobs;
  }
  if (argv.length < 4) usage('expected FILE.svg WIDTH OUT_PREFIX and at least one time');
  return [{ svg: argv[0], width: Number(argv[1]), out_prefix: argv[2], times: argv.slice(3).map(Number) }];
}

// What is wrong with job `i`, or null.
function invalid(job, i) {
  const where = `job ${i} (${job?.svg})`;
  if (typeof job?.svg !== 'string' || !fs.existsSync(job.svg)) return `${where}: no such SVG file`;
  if (!Number.isInteger(job.width) || job.width < 1 || job.width > 8192) return `${where}: width must be a whole number of pixels in 1..8192`;
  if (typeof job.out_prefix !== 'string' || job.out_prefix === '') return `${where}: out_prefix missing`;
  if (!Array.isArray(job.times) || job.times.length === 0 || !job.times.every(Number.isFinite)) return `${where}: times must be finite numbers of seconds`;
  return null;
}

const serve = process.argv[2] === '--serve';
const jobs = serve ? [] : parseJobs(process.argv.slice(2));
jobs.forEach((job, i) => {
  const why = invalid(job, i);
  if (why) usage(why);
});

const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'gmotion-smil-'));
const context = await chromium.launchPersistentContext(profile, {
  executablePath: CHROMIUM,
  headless: true,
  args: ARGS,
  deviceScaleFactor: 1,
  viewport: { width: 300, height: 300 },
});
// Shoots `job` on `page`; returns what went wrong, or null.
async function shoot(page, job) {
  // A large animation takes Chromium long to load (see SMIL_MAX_BYTES in conformance.py).
  await page.goto(pathToFileURL(path.resolve(job.svg)).href, { timeout: 120000 });
  const size = await page.evaluate((width) => {
    const svg = document.documentElement;
    if (!(svg instanceof SVGSVGElement)) return null;
    svg.pauseAnimations();
    const vb = svg.viewBox.baseVal;
    const hasBox = vb && vb.width > 0 && vb.height > 0;
    const [x, y] = hasBox ? [vb.x, vb.y] : [0, 0];
    const w = hasBox ? vb.width : svg.width.baseVal.value;
    const h = hasBox ? vb.height : svg.height.baseVal.value;
    // gmotion renders the picture scaled by width / w from the top left into a canvas of
    // the rounded height. Sizing the root to whole pixels and stretching the viewBox to
    // the same aspect does exactly that (a fractional root height would be snapped).
    const height = Math.max(1, Math.round((width * h) / w));
    svg.setAttribute('width', String(width));
    svg.setAttribute('height', String(height));
    svg.setAttribute('viewBox', `${x} ${y} ${w} ${(height * w) / width}`);
    svg.setAttribute('preserveAspectRatio', 'xMinYMin meet');
    return { width, height };
  }, job.width);
  if (!size) return `smil.mjs: ${job.svg}: not an SVG document`;
  await page.setViewportSize(size);
  for (const [i, t] of job.times.entries()) {
    await page.evaluate(async (t) => {
      const svg = document.documentElement;
      svg.pauseAnimations();
      svg.setCurrentTime(t);
      await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
    }, t);
    await page.screenshot({ path: `${job.out_prefix}-${i}.png`, omitBackground: true });
  }
  return null;
}

let failed = false;
try {
  const page = context.pages()[0] ?? (await context.newPage());
  if (serve) {
    for await (const line of createInterface({ input: process.stdin })) {
      if (!line.trim()) continue;
      const errors = [];
      let list = [];
      try {
        list = JSON.parse(line);
      } catch (e) {
        errors.push(`smil.mjs: the job list is not JSON: ${e.message}`);
      }
      for (const [i, job] of (Array.isArray(list) ? list : []).entries()) {
        const why = invalid(job, i);
        try {
          const error = why ?? (await shoot(page, job));
          if (error) errors.push(error);
        } catch (e) {
          errors.push(`smil.mjs: ${job.svg}: ${e.message}`);
        }
      }
      process.stdout.write(`${JSON.stringify({ errors })}\n`);
    }
  } else {
    for (const job of jobs) {
      const error = await shoot(page, job);
      if (error) {
        console.error(error);
        failed = true;
        continue;
      }
      console.log(`${job.svg} ${job.times.length}`);
    }
  }
} finally {
  await context.close();
  fs.rmSync(profile, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
