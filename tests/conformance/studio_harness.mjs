// What the studio's browser tests share: starting `gmotion studio` and Chromium.
import { spawn } from 'node:child_process';
import { createInterface } from 'node:readline';
import { chromium } from 'playwright-core';

// Starts `gmotion studio --no-open` (the binary `gm`) on `scene` and `grammar`, pushes
// the process to `children` (for the caller to stop) and returns the page's address, token
// included, from the first line it prints.
export async function startStudio(gm, scene, grammar, children) {
  return startStudioWith(gm, [scene, grammar], children);
}

// Starts `gmotion studio --no-open --port 0 ARGS` as startStudio does.
export async function startStudioWith(gm, args, children) {
  const child = spawn(gm, ['studio', '--no-open', '--port', '0', ...args], { stdio: ['ignore', 'pipe', 'pipe'] });
  children.push(child);
  let err = '';
  child.stderr.on('data', (d) => { err += d; });
  const first = await new Promise((resolve, reject) => {
    createInterface({ input: child.stdout }).once('line', resolve);
    child.once('exit', (code) => reject(new Error(`gmotion studio exited (${code}): ${err}`)));
  });
  const m = /^studio: (http:\/\/127\.0\.0\.1:\d+\/\?token=[0-9a-f]+)$/.exec(first);
  if (!m) throw new Error(`unexpected first line: ${first}`);
  return m[1];
}

// Debian's Chromium, headless, with nothing reaching the network on its own.
export function launchChromium() {
  return chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
}
