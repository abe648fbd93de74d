// Test-only: the reference decode of a KTX2 file by Binomial's Basis Universal transcoder
// (the WebAssembly build the npm package `three` ships in examples/jsm/libs/basis/), for
// test_ktx2_reference.cpp. Writes every level's RGBA32 (transcoder format 13), level 0
// first, concatenated, to OUT.
//
//   node basis_reference.cjs BASIS_DIR IN.ktx2 OUT.rgba
//
// BASIS_DIR holds basis_transcoder.js and basis_transcoder.wasm (`npm pack three@0.187.0`,
// then package/examples/jsm/libs/basis). Exit 1 with a message when the transcoder refuses.
'use strict';
const fs = require('fs');
const path = require('path');
const [dir, input, output] = process.argv.slice(2);
const BASIS = require(path.resolve(dir, 'basis_transcoder.js'));
BASIS({ wasmBinary: fs.readFileSync(path.join(dir, 'basis_transcoder.wasm')) }).then((M) => {
  M.initializeBasis();
  const file = new M.KTX2File(new Uint8Array(fs.readFileSync(input)));
  if (!file.isValid() || !file.startTranscoding()) {
    console.error(`${input}: the transcoder refuses the file`);
    process.exit(1);
  }
  const parts = [];
  const levels = Math.max(1, file.getLevels());
  for (let level = 0; level < levels; ++level) {
    const dst = new Uint8Array(file.getImageTranscodedSizeInBytes(level, 0, 0, 13));
    if (!file.transcodeImage(dst, level, 0, 0, 13, 0, -1, -1)) {
      console.error(`${input}: level ${level}: the transcoder failed`);
      process.exit(1);
    }
    parts.push(Buffer.from(dst));
  }
  file.close();
  file.delete();
  fs.writeFileSync(output, Buffer.concat(parts));
});
