// Opens a dotLottie package with @dotlottie/dotlottie-js (LottieFiles' library for making and
// reading .lottie files) and prints what it read, as one line of JSON: the manifest's version,
// each animation's id with its size, length and layer count, and the themes' ids.
//
//   node dotlottie_js.mjs FILE.lottie
import { readFileSync } from 'node:fs';
import { DotLottie } from '@dotlottie/dotlottie-js';

const buf = readFileSync(process.argv[2]);
const dotlottie = await new DotLottie().fromArrayBuffer(
  buf.buffer.slice(buf.byteOffset, buf.byteOffset + buf.byteLength));
const out = { version: dotlottie.version, animations: [], themes: dotlottie.themes.map((t) => t.id) };
for (const a of dotlottie.animations) {
  const data = await a.toJSON();
  out.animations.push({ id: a.id, w: data.w, h: data.h, op: data.op, layers: data.layers.length });
}
console.log(JSON.stringify(out));
