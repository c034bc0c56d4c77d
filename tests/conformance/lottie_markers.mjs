// Asks lottie-web (svg renderer, headless Chromium) where each named marker of a Lottie file
// lands: for every NAME, goToAndStop(NAME, true) and the frame the player then shows. Prints
// one line of JSON: {"NAME": frame, …} (null for a name the player does not find).
//
//   node lottie_markers.mjs FILE.json NAME…
import { readFileSync } from 'node:fs';
import { join, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const [file, ...names] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath: '/usr/bin/chromium',
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run'],
});
const page = await browser.newPage();
await page.setContent('<!doctype html><html><body><div id="c" style="width:200px;height:200px"></div></body></html>');
await page.addScriptTag({ path: join(here, 'node_modules/lottie-web/build/player/lottie_svg.min.js') });
const landed = await page.evaluate(({ data, names }) => {
  const anim = lottie.loadAnimation({
    container: document.getElementById('c'), renderer: 'svg', loop: false, autoplay: false, animationData: data,
  });
  const out = {};
  for (const name of names) {
    const known = anim.markers.some((m) => m.payload && m.payload.name === name);
    anim.goToAndStop(0, true);
    anim.goToAndStop(name, true);
    out[name] = known ? anim.currentFrame : null;
  }
  return out;
}, { data: JSON.parse(readFileSync(file, 'utf8')), names });
console.log(JSON.stringify(landed));
await browser.close();
