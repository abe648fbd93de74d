// Generation-only (not run by the tests): makes the real Basis Universal KTX2 files of
// tests/ktx2/ — a procedural RGBA test pattern (written here, so no licence question),
// encoded by Binomial's Basis Universal encoder (the WebAssembly build the npm package
// `ktx2-encoder` 0.6.0 ships) — and prints, for test_ktx2_files.cpp, the FNV-1a 64 hash of
// every level as Binomial's transcoder (npm `three` 0.187.0, examples/jsm/libs/basis)
// decodes it to RGBA32.
//
//   mkdir /tmp/enc && cd /tmp/enc && npm install ktx2-encoder@0.6.0 three@0.187.0
//   node tests/ktx2/encode_samples.mjs /tmp/enc/node_modules tests/ktx2
//
// docs/testing.md says the same.
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import vm from 'node:vm';
import zlib from 'node:zlib';
import { createRequire } from 'node:module';
import { pathToFileURL } from 'node:url';

const [modules, outDir] = process.argv.slice(2);
if (!modules || !outDir) {
  console.error('usage: node encode_samples.mjs NODE_MODULES OUT_DIR');
  process.exit(2);
}

// ---- The pattern ------------------------------------------------------------------------
// Gradients in red and green, a blue checkerboard, a disc with a hard edge, and bars and
// glyph-like strokes 1 to 3 texels wide (ETC1S's hardest case: edges inside 4×4 blocks).
// With `alpha`: a horizontal alpha ramp, a transparent hole and opaque/clear stripes.
function pattern(w, h, alpha) {
  const rgba = new Uint8Array(w * h * 4);
  for (let y = 0; y < h; ++y)
    for (let x = 0; x < w; ++x) {
      let r = Math.floor((x * 255) / (w - 1));
      let g = Math.floor((y * 255) / (h - 1));
      let b = ((x >> 4) ^ (y >> 4)) & 1 ? 200 : 40;
      const dx = x - w * 0.7, dy = y - h * 0.35, rr = Math.min(w, h) * 0.2;
      if (dx * dx + dy * dy < rr * rr) { r = 250; g = 220; b = 30; }
      // "text": strokes in a band across the lower third
      if (y >= Math.floor(h * 0.62) && y < Math.floor(h * 0.62) + 12 && x >= 6 && x < w - 6) {
        const cx = (x - 6) % 9, cy = y - Math.floor(h * 0.62), glyph = Math.floor((x - 6) / 9) % 5;
        const stroke = (glyph === 0 && cx < 2) || (glyph === 1 && (cy < 2 || cy > 9) && cx < 7) ||
                       (glyph === 2 && Math.abs(cx - Math.floor(cy / 2)) < 1) ||
                       (glyph === 3 && (cx === 0 || cx === 6 || cy === 5)) || (glyph === 4 && cx > 2 && cx < 6);
        if (stroke) { r = 10; g = 10; b = 10; }
      }
      if (x % 32 === 31) { r = 255; g = 255; b = 255; }  // 1-texel vertical lines
      let a = 255;
      if (alpha) {
        a = Math.floor((x * 255) / (w - 1));
        const hx = x - w * 0.25, hy = y - h * 0.3;
        if (hx * hx + hy * hy < (h * 0.15) ** 2) a = 0;
        if (y >= h - 12) a = (x >> 3) & 1 ? 255 : 0;
      }
      const i = (y * w + x) * 4;
      rgba[i] = r; rgba[i + 1] = g; rgba[i + 2] = b; rgba[i + 3] = a;
    }
  return rgba;
}

// A PNG of the pattern (8-bit RGBA, filter 0), to look at (written to the temporary folder).
function png(w, h, rgba) {
  const crcTable = Array.from({ length: 256 }, (_, n) => {
    let c = n;
    for (let k = 0; k < 8; ++k) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    return c >>> 0;
  });
  const crc = (buf) => {
    let c = 0xffffffff;
    for (const b of buf) c = crcTable[(c ^ b) & 255] ^ (c >>> 8);
    return (c ^ 0xffffffff) >>> 0;
  };
  const chunk = (type, data) => {
    const out = Buffer.alloc(12 + data.length);
    out.writeUInt32BE(data.length, 0);
    out.write(type, 4, 'latin1');
    data.copy(out, 8);
    out.writeUInt32BE(crc(out.subarray(4, 8 + data.length)), 8 + data.length);
    return out;
  };
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(w, 0); ihdr.writeUInt32BE(h, 4);
  ihdr[8] = 8; ihdr[9] = 6;
  const raw = Buffer.alloc(h * (1 + w * 4));
  for (let y = 0; y < h; ++y) Buffer.from(rgba.buffer, y * w * 4, w * 4).copy(raw, y * (1 + w * 4) + 1);
  return Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), chunk('IHDR', ihdr),
                        chunk('IDAT', zlib.deflateSync(raw, { level: 9 })), chunk('IEND', Buffer.alloc(0))]);
}

// ---- Encoding ---------------------------------------------------------------------------
const encoderUrl = pathToFileURL(path.join(modules, 'ktx2-encoder/dist/basis/basis_encoder.js')).href;
const BASIS = (await import(encoderUrl)).default;
const enc = await BASIS();
enc.initializeBasis();

function encode(w, h, rgba, uastc) {
  const e = new enc.BasisEncoder();
  e.setDebug(false);
  e.setStatusOutput(false);
  e.setCreateKTX2File(true);
  e.setTexType(0);  // 2D
  e.setUASTC(uastc);
  e.setMipGen(true);
  e.setPerceptual(true);
  e.setKTX2AndBasisSRGBTransferFunc(true);
  if (uastc) {
    e.setKTX2UASTCSupercompression(true);  // Zstandard
    e.setPackUASTCFlags(1);
  } else {
    e.setQualityLevel(128);
    e.setETC1SCompressionLevel(2);
  }
  if (e.setSliceSourceImage(0, rgba, w, h, 0) === false) throw new Error('setSliceSourceImage failed');
  const out = new Uint8Array(w * h * 8 + 65536);
  const n = e.encode(out);
  e.delete();
  if (n <= 0) throw new Error('encode failed');
  return out.slice(0, n);
}

// ---- The reference decode ---------------------------------------------------------------
// Loaded as CommonJS whatever the nearest package.json says (three's says "module").
const basisDir = path.join(modules, 'three/examples/jsm/libs/basis');
const transcoderJs = path.join(basisDir, 'basis_transcoder.js');
const cjs = { exports: {} };
vm.runInThisContext(`(function (module, exports, require, __filename, __dirname) {${fs.readFileSync(transcoderJs, 'utf8')}\n})`)(
    cjs, cjs.exports, createRequire(transcoderJs), transcoderJs, basisDir);
const TRANSCODER = cjs.exports;
const T = await TRANSCODER({ wasmBinary: fs.readFileSync(path.join(basisDir, 'basis_transcoder.wasm')) });
T.initializeBasis();

function fnv1a(bytes) {
  let h = 0xcbf29ce484222325n;
  for (const b of bytes) h = BigInt.asUintN(64, (h ^ BigInt(b)) * 0x100000001b3n);
  return h;
}

function reference(bytes) {
  const f = new T.KTX2File(bytes);
  if (!f.isValid() || !f.startTranscoding()) throw new Error('the transcoder refuses the file');
  const levels = [];
  for (let l = 0; l < Math.max(1, f.getLevels()); ++l) {
    const dst = new Uint8Array(f.getImageTranscodedSizeInBytes(l, 0, 0, 13));
    if (!f.transcodeImage(dst, l, 0, 0, 13, 0, -1, -1)) throw new Error(`level ${l}: the transcoder failed`);
    const info = f.getImageLevelInfo(l, 0, 0);
    levels.push({ width: info.origWidth, height: info.origHeight, hash: fnv1a(dst) });
  }
  f.close();
  f.delete();
  return levels;
}

const samples = [
  { name: 'etc1s_pattern_256x192', w: 256, h: 192, alpha: false, uastc: false },
  { name: 'etc1s_alpha_pattern_150x100', w: 150, h: 100, alpha: true, uastc: false },
  { name: 'uastc_zstd_pattern_128x128', w: 128, h: 128, alpha: true, uastc: true },
];
for (const s of samples) {
  const rgba = pattern(s.w, s.h, s.alpha);
  const bytes = encode(s.w, s.h, rgba, s.uastc);
  fs.writeFileSync(path.join(outDir, `${s.name}.ktx2`), bytes);
  const look = path.join(os.tmpdir(), `${s.name}.source.png`);  // the encoder's input, to look at
  fs.writeFileSync(look, png(s.w, s.h, rgba));
  for (const [l, lv] of reference(bytes).entries())
    console.log(`    {"${s.name}.ktx2", ${l}, ${lv.width}, ${lv.height}, 0x${lv.hash.toString(16).padStart(16, '0')}ull},`);
  console.error(`${s.name}.ktx2: ${bytes.length} bytes (its source: ${look})`);
}
