#!/usr/bin/env bash
# The softpbr command line, end to end (run by ctest as cli_GROUP):
#   driver.sh GROUP SOFTPBR SOURCE_DIR WORK_DIR
# Groups:
#   scenes  every examples/scenes/*.json renders to its golden hash (cli/tests/scenes.hashes)
#           and golden PNG (cli/tests/goldens/), the same for any --threads/--tile-size;
#           gallery.json and gallery_spot.json give the library's own gallery goldens
#           (tests/goldens/*.hash: the JSON files are make_gallery() exactly)
#   errors  every error case: its one-line message, its exit code, and no output file
#           created or truncated (textures: cli/tests/hostile/*-texture.png, below)
#   frames  shards cover a frame list exactly once, with the same images as one run; a
#           re-run skips complete frames
#   kill    a render killed with SIGKILL mid-way leaves only complete frames; a re-run
#           completes the job with the same images as an uninterrupted run
#   diff    softpbr diff: exit 0 within tolerance, 1 outside, 2 on error; --out
#   info    softpbr info on models, glTF files and scenes, and its errors
#   pipes   a named pipe with no writer as every kind of input (models, buffers, images,
#           environment maps, diff inputs, meshes, scene files): refused at once
#   version softpbr --version / softpbr version: the CMake project version, compiler, build
#           type (SOFTPBR_EXPECT_BUILD_TYPE from ctest) and the SIMD targets of this CPU
#   batch   several glTF models to thumbnails in one run: {name}, {index} and folder/
#           outputs, --shard over the inputs, a bad input among good ones
#   model_diff  softpbr diff of two models: identical, a changed material seen from one view
#           (the worst), a moved node, --json, --out, errors
#   scenario    render --scenario: Khronos Render Fidelity scenarios (orbit, skybox, config.json)
#   thumbnail   the desktop thumbnailer installed into a prefix and run as its .thumbnailer
#           Exec line says, on good and hostile files (truncated, FIFO, /dev/zero); --timeout
# SOFTPBR_UPDATE_GOLDENS=1 rewrites cli/tests/scenes.hashes and goldens/*.png (look at them!).
set -u
group=$1 softpbr=$2 src=$3 work=$4
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }
scenes=$src/examples/scenes

# expect_error CODE 'EXPECTED STDERR LINE' ARGS... — runs softpbr, checks the exit code and
# that stderr is exactly that one line.
expect_error() {
  local code=$1 line=$2; shift 2
  "$softpbr" "$@" >stdout.txt 2>stderr.txt
  local rc=$? got
  got=$(cat stderr.txt)
  if [ "$rc" -ne "$code" ]; then fail "softpbr $* exited $rc, expected $code (stderr: $got)"; return; fi
  if [ "$got" != "$line" ]; then fail "softpbr $*: stderr was
  $got
expected
  $line"; return; fi
  pass "exit $code: $line"
}

case $group in
scenes)
  hashes=$src/cli/tests/scenes.hashes
  [ "${SOFTPBR_UPDATE_GOLDENS:-}" = 1 ] && : >"$hashes.new"
  for scene in "$scenes"/*.json; do
    name=$(basename "$scene" .json)
    out=$("$softpbr" render "$scene" -o "$name.png" --threads 2 --tile-size 64) || { fail "$name: render failed"; continue; }
    hash=${out##*hash }
    # The same bits for other thread counts and tile sizes (at a quarter of the size, to be quick).
    small=$("$softpbr" render "$scene" -o small.png --width 320 --height 180)
    for opts in "--threads 1 --tile-size 16" "--threads 3 --tile-size 256"; do
      other=$("$softpbr" render "$scene" -o other.png --width 320 --height 180 $opts)
      [ "${other##*hash }" = "${small##*hash }" ] || fail "$name: $opts gives hash ${other##*hash }, not ${small##*hash }"
    done
    if [ "${SOFTPBR_UPDATE_GOLDENS:-}" = 1 ]; then
      echo "$name $hash" >>"$hashes.new"
      cp "$name.png" "$src/cli/tests/goldens/$name.png"
      continue
    fi
    want=$(awk -v n="$name" '$1 == n { print $2 }' "$hashes")
    if [ "$hash" = "$want" ]; then pass "$name: hash $hash"; else fail "$name: hash $hash, golden ${want:-missing} (SOFTPBR_UPDATE_GOLDENS=1 ctest -R cli_scenes to accept)"; fi
    "$softpbr" diff "$src/cli/tests/goldens/$name.png" "$name.png" -q || fail "$name: PNG differs from cli/tests/goldens/$name.png"
  done
  [ "${SOFTPBR_UPDATE_GOLDENS:-}" = 1 ] && mv "$hashes.new" "$hashes"
  # The JSON galleries are the library's gallery scenes, bit for bit (tests/goldens, 640x360).
  for name in gallery gallery_spot; do
    out=$("$softpbr" render "$scenes/$name.json" -o "$name-small.png" --width 640 --height 360)
    want=$(cat "$src/tests/goldens/$name.hash")
    [ "${out##*hash }" = "$want" ] && pass "$name.json = make_gallery ($want)" || fail "$name.json at 640x360: ${out##*hash }, make_gallery's golden $want"
  done
  # The complete scene of docs/scene-format.md renders (the models folder beside it).
  cp -r "$scenes/models" models
  awk '/^## A complete small scene/ { on = 1 } on && /^```$/ && started { exit } started { print } on && /^```json$/ { started = 1 }' \
    "$src/docs/scene-format.md" >snippet.json
  "$softpbr" render -o snippet.png snippet.json --width 80 --height 60 -q && [ -s snippet.png ] \
    && pass "the docs' complete scene renders (-o before the scene works too)" || fail "docs/scene-format.md's scene does not render"
  # Three formats from one render; progress goes to stderr only on a terminal.
  "$softpbr" render "$scenes/lights.json" -o all.png -o all.hdr -o all.exr --width 64 --height 40 >stdout.txt 2>stderr.txt || fail "png+hdr+exr render failed"
  [ -s all.png ] && [ -s all.hdr ] && head -c 10 all.hdr | grep -q '#?RADIANCE' || fail "png+hdr: missing or wrong files"
  [ "$(od -An -tx1 -N4 all.exr | tr -d ' ')" = 762f3101 ] || fail "all.exr does not start with the OpenEXR magic number"
  [ -s stderr.txt ] && fail "stderr not empty without a terminal: $(cat stderr.txt)"
  [ "$(wc -l <stdout.txt)" -eq 3 ] || fail "expected one stdout line per output"
  # The .exr holds the float colour exactly: encoded as RGBE it is the .hdr, bit for bit;
  # and it is the same file for any thread count and tile size.
  "$softpbr" diff all.hdr all.exr -q && pass ".exr, RGBE-encoded, equals the .hdr" || fail ".exr and .hdr of one render differ"
  "$softpbr" render "$scenes/lights.json" -o other.exr --width 64 --height 40 --threads 1 --tile-size 8 -q
  cmp -s all.exr other.exr && pass ".exr identical for other threads/tiles" || fail ".exr differs with --threads 1 --tile-size 8"
  # A multisampled render's .hdr and .exr hold the linear box resolve (they failed with
  # "pixel data disagree"); its PNG with the linear resolve, no tone map and gamma 1 is the
  # same average, encoded to 8 bits: both are checked against each other through diff.
  "$softpbr" render "$scenes/lights.json" -o msaa.exr -o msaa.hdr --msaa 4 --width 64 --height 40 -q \
    && [ "$(od -An -tx1 -N4 msaa.exr | tr -d ' ')" = 762f3101 ] && "$softpbr" diff msaa.hdr msaa.exr -q \
    && pass "--msaa 4 writes the resolved .exr and .hdr" || fail "--msaa 4 -o msaa.exr -o msaa.hdr failed"
  "$softpbr" render "$scenes/lights.json" -o msaa1.exr --msaa 4 --width 64 --height 40 --threads 1 --tile-size 8 -q
  cmp -s msaa.exr msaa1.exr && pass "the resolved .exr is identical for other threads/tiles" || fail "the --msaa 4 .exr differs with --threads 1 --tile-size 8"
  # The printed hash with --msaa is the resolved image's: the same whether the PNG is
  # written too (tone mapped per tile from the same blocks) or not, for any threads and
  # tiles, for tiles too large for a block (planes) and different from the 1x hash.
  h_exr=$("$softpbr" render "$scenes/lights.json" -o h.exr --msaa 4 --width 64 --height 40 | sed -n 's/.*hash //p')
  h_png=$("$softpbr" render "$scenes/lights.json" -o h.png -o h2.exr --msaa 4 --width 64 --height 40 --threads 1 --tile-size 8 | sed -n '1s/.*hash //p')
  h_big=$("$softpbr" render "$scenes/lights.json" -o h3.png --msaa 4 --width 64 --height 40 --tile-size 256 | sed -n 's/.*hash //p')
  h_one=$("$softpbr" render "$scenes/lights.json" -o h4.png --width 64 --height 40 | sed -n 's/.*hash //p')
  [ -n "$h_exr" ] && [ "$h_exr" = "$h_png" ] && [ "$h_exr" = "$h_big" ] && [ "$h_exr" != "$h_one" ] && cmp -s h.exr h2.exr && cmp -s h.exr msaa.exr \
    && pass "--msaa 4 prints the resolved image's hash, alike with and without a PNG, for any threads and tiles" \
    || fail "--msaa 4 hashes: exr $h_exr, png $h_png, 256-pixel tiles $h_big, 1x $h_one"
  ;;

errors)
  cp -r "$scenes/models" models
  # Hostile textures, each a few bytes: a 64x64 PNG cut inside its IDAT chunk; IHDRs
  # declaring 100000x100000 (stb_image's header scan refuses more than 2^30 bytes of pixels
  # before it gives the size, so the reason is stb's) and 100000x16, over one row of data.
  cp "$src"/cli/tests/hostile/*-texture.png .
  printf 'newmtl m\nKd 1 1 1\nmap_Kd gone.png\n' >tex.mtl
  printf 'mtllib tex.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n' >tex.obj
  printf 'KEEP' >keep.png
  # scene_with 'JSON' — a small valid scene with one replaced fragment
  base='{"camera": {"position": [0, 0, 3]}, "lights": [{"type": "point", "position": [1, 1, 2], "intensity": 5}], "objects": [{"mesh": {"type": "cube"}, "material": {"preset": "gold", "roughness": 0.5}}], "render": {"width": 32, "height": 24}}'
  scene_with() { local from=$1 to=$2; echo "${base/"$from"/"$to"}" >bad.json; }
  scene_with '' ''
  "$softpbr" render bad.json -o ok.png -q || fail "the base error scene does not render"
  while IFS='|' read -r from to code line; do
    [ -z "$from" ] && continue
    scene_with "$from" "$to"
    expect_error "$code" "$line" render bad.json -o keep.png
  done <<'EOF'
"roughness": 0.5|"roughness": 2|3|bad.json: /objects/0/material/roughness: expected a number in [0, 1], got 2
"roughness": 0.5|"roughness": "NaN"|3|bad.json: /objects/0/material/roughness: expected a number in [0, 1], got "NaN"
"roughness": 0.5|"rougness": 0.5|3|bad.json: /objects/0/material/rougness: unknown key "rougness" (did you mean "roughness"?)
"roughness": 0.5|"roughness": 0.5, "shiny": true|3|bad.json: /objects/0/material/shiny: unknown key "shiny" (expected one of: preset, base_color, metallic, roughness, ao, emissive, alpha, alpha_mode, alpha_cutoff, double_sided, base_color_texture, metallic_roughness_texture, normal_texture, normal_scale, occlusion_texture, occlusion_strength, emissive_texture, ior, specular, clearcoat, sheen, anisotropy, iridescence, transmission, volume, dispersion)
"roughness": 0.5|"roughness": 0.5, "base_color_texture": "truncated-texture.png"|3|bad.json: /objects/0/material/base_color_texture: truncated-texture.png: cannot decode (truncated: chunk 'IDAT' at byte 33 claims 7818 bytes, more than the file has left)
"roughness": 0.5|"roughness": 0.5, "normal_texture": {"image": "textures/missing.png"}|3|bad.json: /objects/0/material/normal_texture/image: textures/missing.png: no such file
"roughness": 0.5|"roughness": 0.5, "emissive_texture": "huge-texture.png"|3|bad.json: /objects/0/material/emissive_texture: huge-texture.png: image size 100000x100000 is outside 1x1 .. 16384x16384
"roughness": 0.5|"roughness": 0.5, "occlusion_texture": {"image": "wide-texture.png"}|3|bad.json: /objects/0/material/occlusion_texture/image: wide-texture.png: image size 100000x16 is outside 1x1 .. 16384x16384
"roughness": 0.5|"roughness": 0.5, "base_color_texture": {"image": "keep.png", "sampler": {"anisotropy": 32}}|3|bad.json: /objects/0/material/base_color_texture/sampler/anisotropy: expected an integer in [1, 16], got 32
"type": "cube"|"file": "tex.obj"|3|bad.json: /objects/0/mesh/file: tex.mtl:3: map_Kd: gone.png: no such file
"width": 32|"width": 0|3|bad.json: /render/width: expected an integer in [1, 16384], got 0
"width": 32|"width": -5|3|bad.json: /render/width: expected an integer in [1, 16384], got -5
"width": 32|"width": "32"|3|bad.json: /render/width: expected an integer in [1, 16384], got "32"
"width": 32|"width": 32.5|3|bad.json: /render/width: expected an integer in [1, 16384], got 32.5
"height": 24|"height": 1e400|3|bad.json: /render/height: the number 1e400 is out of range (beyond +-1.8e308)
"preset": "gold"|"preset": "gld"|3|bad.json: /objects/0/material/preset: expected one of gold, copper, silver, aluminium, iron, titanium, chromium, nickel, platinum, plastic_red, plastic_green, plastic_blue, rubber, white_paint, got "gld"
"type": "cube"|"type": "cone"|3|bad.json: /objects/0/mesh/type: expected one of uv_sphere, icosphere, cube, plane, torus, got "cone"
"type": "cube"|"file": "models/nope.obj"|3|bad.json: /objects/0/mesh/file: models/nope.obj: cannot open: no such file
"intensity": 5|"intensity": -1|3|bad.json: /lights/0/intensity: expected a number >= 0, got -1
"type": "point"|"type": "spot"|3|bad.json: /lights/0: missing key "direction"
"position": [0, 0, 3]|"position": [0, 0]|3|bad.json: /camera/position: expected an array of 3 numbers, got [0,0]
"position": [0, 0, 3]|"position": [0, 0, 0]|3|bad.json: /camera: camera target: must differ from position
"objects": [|"objects": 7, "x": [|3|bad.json: /x: unknown key "x" (expected one of: camera, lights, ambient, environment, ground, meshes, objects, render, animation)
"render": {|"render": [{|3|bad.json: invalid JSON: parse error at line 1, column 236: syntax error while parsing array - unexpected '}'; expected ']'
EOF
  # A 10^6-light scene: the count is refused with the limit, before any light is read.
  { printf '{"lights": ['; yes 0, | head -n 999999 | tr -d '\n'; printf '0], "objects": []}'; } >lights.json
  expect_error 3 "lights.json: /lights: too many entries: 1000000 (the limit is 256: every light is evaluated at every pixel)" \
    render lights.json -o keep.png
  # Memory is checked before allocating: a 16384² image (18 GiB estimated), a huge mesh.
  scene_with '' ''
  expect_error 3 "--width 16384 --height 16384: a 16384x16384 render of this scene needs an estimated 18.0 GiB, over the limit of 4.0 GiB (--max-memory)" \
    render bad.json -o keep.png --width 16384 --height 16384
  scene_with '{"type": "cube"}' '{"type": "uv_sphere", "segments": 4096, "rings": 4096}'
  expect_error 3 "bad.json: /objects/0/mesh: this mesh brings the scene's estimated memory to 896.3 MiB, over the limit of 256.0 MiB" \
    render bad.json -o keep.png --max-memory 256
  # Unreadable scenes, unwritable outputs.
  expect_error 3 "missing.json: cannot open the scene file: No such file or directory" render missing.json -o keep.png
  expect_error 3 "models: is a folder, not a scene file" render models -o keep.png
  expect_error 3 "/dev/zero: is a character device, not a regular file" render /dev/zero -o keep.png
  head -c 100 /dev/urandom >random.json
  "$softpbr" render random.json -o keep.png 2>stderr.txt; rc=$?
  [ $rc -eq 3 ] && grep -q "^random.json: " stderr.txt && [ "$(wc -l <stderr.txt)" -eq 1 ] && pass "binary garbage: one line, exit 3" || fail "random.json: exit $rc: $(cat -v stderr.txt)"
  scene_with '' ''
  # An output's missing folders are created as it is written (docs/cli.md), and only then:
  # a command that fails creates none; a file on the way is no folder.
  "$softpbr" render bad.json -o new/such/dir/out.png -q && [ -s new/such/dir/out.png ] \
    && pass "-o new/such/dir/out.png creates its folders" || fail "-o new/such/dir/out.png: no image"
  expect_error 3 "missing.json: cannot open the scene file: No such file or directory" render missing.json -o none/out.png
  [ ! -e none ] && pass "a failed render creates no output folder" || fail "a failed render created none/"
  expect_error 4 "keep.png/dir/out.png: cannot write: keep.png is not a folder" render bad.json -o keep.png/dir/out.png
  mkdir folder.png
  expect_error 4 "folder.png: cannot write: it is a folder" render bad.json -o folder.png
  # A write that fails half-way (a file size limit stands in for a full disk): exit 4, the
  # old file untouched, no temporary left.
  for ext in png hdr exr; do
    printf 'KEEP' >"keep.$ext"
    (trap '' XFSZ; ulimit -f 8; "$softpbr" render "$scenes/lights.json" -o "keep.$ext" --width 320 --height 200 >/dev/null 2>stderr.txt)
    rc=$?
    [ $rc -eq 4 ] && [ "$(cat stderr.txt)" = "keep.$ext: write failed (disk full?)" ] && [ "$(cat "keep.$ext")" = KEEP ] \
      && pass "failed .$ext write: exit 4, old file kept" || fail "failed .$ext write: exit $rc, $(cat stderr.txt)"
  done
  rm keep.hdr keep.exr
  # Command-line errors.
  expect_error 2 "out.jpg: unknown output format \".jpg\" (expected .png, .hdr or .exr)" render bad.json -o out.jpg
  expect_error 2 "--frames: expected A..B or A with 0 <= A <= B <= 9999999, got \"5..2\"" render bad.json -o f_#.png --frames 5..2
  expect_error 2 "--shard: expected i/N with 0 <= i < N (i counts from 0), got \"3/3\"" render bad.json -o f_#.png --frames 0..9 --shard 3/3
  expect_error 2 "out.png: with several frames an output needs a run of '#' for the frame number (e.g. out_####.png)" render bad.json -o out.png --frames 0..3
  expect_error 2 "--tile-size: expected an even size in [8, 4096], got 17" render bad.json -o keep.png --tile-size 17
  expect_error 2 "--tile-size: expected an even size in [8, 4096], got 4" render bad.json -o keep.png --tile-size 4
  expect_error 2 "--gamma: expected 0 (the sRGB curve) or a number in [0.1, 10], got 0.05" render bad.json -o keep.png --gamma 0.05
  expect_error 2 "--env-intensity: expected a number in [0, 1e6], got -1" render bad.json -o keep.png --env-intensity -1
  expect_error 2 "--width: expected a value in [1, 16384], got 0" render bad.json -o keep.png --width 0
  expect_error 2 "--tonemap: expected one of none, reinhard, aces, neutral, got \"filmic\"" render bad.json -o keep.png --tonemap filmic
  "$softpbr" render bad.json -o keep.png --no-such-option >/dev/null 2>&1; [ $? -eq 2 ] && pass "unknown option: exit 2" || fail "unknown option: not exit 2"
  "$softpbr" render --help | grep -q "Exit codes:" && pass "--help lists the exit codes" || fail "render --help has no exit codes"
  # Hostile outputs: only a regular file or a new name, never an input, never a device.
  expect_error 4 "/dev/null: cannot write: it is a character device, not a regular file (an output is a regular file or a new name)" \
    render bad.json -o /dev/null
  [ -c /dev/null ] && pass "/dev/null is still a device" || fail "/dev/null was replaced"
  mkfifo fifo.png
  timeout 20 "$softpbr" render bad.json -o fifo.png >/dev/null 2>stderr.txt; rc=$?
  [ $rc -eq 4 ] && [ -p fifo.png ] && [ "$(cat stderr.txt)" = "fifo.png: cannot write: it is a named pipe, not a regular file (an output is a regular file or a new name)" ] \
    && pass "a FIFO output: exit 4 at once, still a FIFO" || fail "FIFO output: exit $rc, $(cat stderr.txt)"
  if [ "$(id -u)" -eq 0 ]; then
    mknod node.png c 1 3
    expect_error 4 "node.png: cannot write: it is a character device, not a regular file (an output is a regular file or a new name)" render bad.json -o node.png
    [ -c node.png ] && pass "a mknod node stays a device" || fail "node.png was replaced"
  fi
  ln -s keep.png link.png
  expect_error 4 "link.png: cannot write: it is a symbolic link, not a regular file (an output is a regular file or a new name)" render bad.json -o link.png
  cp bad.json scene.png
  expect_error 4 "scene.png: cannot write: it is an input of this command (an output never replaces an input)" render scene.png -o scene.png
  cmp -s bad.json scene.png && pass "the scene named as its own output is untouched" || fail "scene.png was overwritten"
  ln bad.json hardlink.png
  expect_error 4 "hardlink.png: cannot write: it is the input bad.json of this command (an output never replaces an input)" render bad.json -o hardlink.png
  cp "$src/cli/tests/goldens/lights.png" tex-in.png
  scene_with '"roughness": 0.5' '"roughness": 0.5, "base_color_texture": "tex-in.png"'
  expect_error 4 "tex-in.png: cannot write: it is the input $PWD/tex-in.png of this command (an output never replaces an input)" render bad.json -o ok.png -o tex-in.png
  cmp -s tex-in.png "$src/cli/tests/goldens/lights.png" && pass "a texture named as an output is untouched" || fail "tex-in.png was overwritten"
  # A glTF model's external image is an input too.
  cp "$src/cli/tests/goldens/lights.png" gltf-img.png
  python3 - <<'PY'
import json, struct, base64
buf = struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack('<6f', 0, 0, 1, 0, 0, 1)
g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
     "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
     "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
     "textures": [{"source": 0}], "images": [{"uri": "gltf-img.png"}],
     "buffers": [{"uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode(), "byteLength": len(buf)}],
     "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
     "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                   {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}]}
open('tri.gltf', 'w').write(json.dumps(g))
PY
  expect_error 4 "gltf-img.png: cannot write: it is an input of this command (an output never replaces an input)" \
    render tri.gltf -o gltf-img.png --width 32 --height 24
  cmp -s gltf-img.png "$src/cli/tests/goldens/lights.png" && pass "a glTF's image named as an output is untouched" || fail "gltf-img.png was overwritten"
  # --max-memory bounds a glTF's textures (from their headers, before decoding) and its JSON.
  expect_error 3 "tri.gltf: /images/0: its texture (640x400) brings the model's buffers and textures to an estimated 2.4 MiB, over the memory limit of 2.0 MiB" \
    render tri.gltf -o memory.png --width 32 --height 24 --max-memory 2
  [ ! -e memory.png ] && pass "nothing written when a glTF's textures are over --max-memory" || fail "memory.png was written"
  python3 -c "
import json; g = json.load(open('tri.gltf')); g['extras'] = list(range(20000)); open('tri-extras.gltf', 'w').write(json.dumps(g))"
  expect_error 3 "tri-extras.gltf: parsing its JSON (20063 values) needs an estimated 3.8 MiB, over the memory limit of 1.0 MiB" \
    render tri-extras.gltf -o memory.png --width 32 --height 24 --max-memory 1
  # Bounds the automatic camera cannot frame in float: exit 3 naming the file (was exit 5,
  # "softpbr: internal error: camera position: ..."); a glTF 3.0 file is refused; --yaw
  # 1e25 frames as its exact remainder modulo 360 (issue 52).
  python3 -c "
import json; g = json.load(open('tri.gltf'))
g['nodes'][0]['matrix'] = [1e38, 0, 0, 0, 0, 1e38, 0, 0, 0, 0, 1e38, 0, 0, 0, 0, 1]; open('tri-scaled.gltf', 'w').write(json.dumps(g))
g = json.load(open('tri.gltf')); g['asset']['version'] = '3.0'; open('tri-v3.gltf', 'w').write(json.dumps(g))"
  expect_error 3 "tri-scaled.gltf: the automatic camera cannot frame the model's bounds (0, 0, 0) to (1e+38, 1e+38, 0) in float precision (camera position: must be less than 1e19 from the target (the view matrix squares the distance in float))" \
    render tri-scaled.gltf -o scaled.png --width 32 --height 24
  expect_error 3 "tri-v3.gltf: /asset/version: glTF 3.0 is not glTF 2: this reader reads glTF 2.x files only" \
    render tri-v3.gltf -o v3.png --width 32 --height 24
  reduced=$(python3 -c "
import struct; r = int(struct.unpack('<f', struct.pack('<f', 1e25))[0]) % 360; print(r - 360 if r > 180 else r)")
  far=$("$softpbr" render tri.gltf -o yaw-far.png --width 32 --height 24 --yaw 1e25) && near=$("$softpbr" render tri.gltf -o yaw-near.png --width 32 --height 24 --yaw "$reduced") \
    && [ "${far##*hash }" = "${near##*hash }" ] && pass "--yaw 1e25 renders as --yaw $reduced" || fail "--yaw 1e25: ${far:-failed}, --yaw $reduced: ${near:-failed}"
  # Out of the process's memory while tinygltf parses (a limit the estimate does not know):
  # one line naming the file, exit 3. Not under ASan, which reserves terabytes of address space.
  if ! ldd "$softpbr" 2>/dev/null | grep -q libasan; then
    python3 -c "
import json; g = json.load(open('tri.gltf')); g['extras'] = [[1.5, 2.5, 3.5, 4.5]] * 1000000; open('tri-huge.gltf', 'w').write(json.dumps(g))"
    (ulimit -v 600000; "$softpbr" render tri-huge.gltf -o memory.png --width 32 --height 24 --max-memory 100000 >/dev/null 2>stderr.txt; echo $? >rc.txt)
    [ "$(cat rc.txt)" = 3 ] && [ "$(cat stderr.txt)" = "tri-huge.gltf: out of memory while loading it (the process's memory or address-space limit)" ] \
      && pass "a glTF that runs out of memory: exit 3, one line" || fail "tri-huge.gltf under ulimit -v: exit $(cat rc.txt), stderr: $(cat stderr.txt)"
  fi
  scene_with '' ''
  expect_error 2 "./bad.png: given twice as an output (under another name)" render bad.json -o bad.png -o ./bad.png
  # Files that merely look like temporaries are not ours: never removed.
  touch .new.png.tmpl .new.png.tmp12345 .new.png.tmp-abcdefghij
  "$softpbr" render bad.json -o new.png -q && [ -e .new.png.tmpl ] && [ -e .new.png.tmp12345 ] && [ -e .new.png.tmp-abcdefghij ] \
    && pass "look-alike temporaries survive a render" || fail "a look-alike temporary was removed"
  rm -f .new.png.tmp* new.png
  # Two processes rendering to one name: both succeed, the file is one whole image.
  "$softpbr" render "$scenes/lights.json" -o race-ref.png --width 160 --height 100 -q
  for i in 1 2 3 4; do "$softpbr" render "$scenes/lights.json" -o race.png --width 160 --height 100 -q & done
  racefail=0; for i in 1 2 3 4; do wait -n || racefail=1; done
  [ $racefail -eq 0 ] && cmp -s race.png race-ref.png && [ -z "$(ls -A | grep '^\.race')" ] \
    && pass "four renders to one name: all exit 0, a whole image, no temporary left" || fail "concurrent renders to race.png broke"
  # Several outputs are all-or-nothing: the .exr cannot be written whole, the PNG stays.
  printf 'KEEP' >keep2.png; printf 'KEEP' >keep2.exr
  (trap '' XFSZ; ulimit -f 16; "$softpbr" render "$scenes/lights.json" -o keep2.png -o keep2.exr --width 160 --height 100 >/dev/null 2>stderr.txt)
  rc=$?
  [ $rc -eq 4 ] && [ "$(cat stderr.txt)" = "keep2.exr: write failed (disk full?)" ] && [ "$(cat keep2.png)" = KEEP ] && [ "$(cat keep2.exr)" = KEEP ] \
    && pass "-o a.png -o b.exr with the .exr failing: exit 4, neither replaced" || fail "all-or-nothing: exit $rc, $(cat stderr.txt), keep2.png $(head -c 4 keep2.png)"
  rm -f keep2.png keep2.exr
  # NAME_MAX: a 255-byte name is written (its temporary fits); 256 bytes fail before rendering.
  long=$(printf 'n%.0s' $(seq 1 251)).png
  "$softpbr" render bad.json -o "$long" -q && [ -s "$long" ] && pass "a 255-byte output name is written" || fail "a 255-byte output name failed"
  rm -f "$long"
  expect_error 4 "n$long: cannot write: the file name is 256 bytes, over the limit of 255 of its folder" render bad.json -o "n$long"
  expect_error 4 "keep.png/x.png: cannot write: keep.png is not a folder" render bad.json -o keep.png/x.png
  # Values are checked before any work: --exposure nan is a usage error even for a missing scene.
  expect_error 2 "--exposure: expected a value in [-64, 64], got nan" render missing.json -o keep.png --exposure nan
  expect_error 2 "--exposure: expected a value in [-64, 64], got inf" render bad.json -o keep.png --exposure inf
  expect_error 2 "--max-memory: expected a number of MiB in (0, 1e9], got nan" render bad.json -o keep.png --max-memory nan
  # One line from CLI11 too.
  "$softpbr" render bad.json -o keep.png --no-such-option >/dev/null 2>stderr.txt
  [ "$(wc -l <stderr.txt)" -eq 1 ] && grep -q "^softpbr: .*no-such-option.* (see --help)$" stderr.txt && pass "CLI11's error: one line" || fail "CLI11 error: $(cat stderr.txt)"
  # Huge keys, NUL bytes: one bounded line.
  { printf '{"'; head -c 10000000 /dev/zero | tr '\0' k; printf '": 1, "objects": []}'; } >hugekey.json
  "$softpbr" render hugekey.json -o keep.png 2>stderr.txt; rc=$?
  [ $rc -eq 3 ] && [ "$(wc -l <stderr.txt)" -eq 1 ] && [ "$(wc -c <stderr.txt)" -lt 1000 ] && pass "a 10 MB key: one short line" || fail "10 MB key: exit $rc, $(wc -c <stderr.txt) bytes"
  printf '{"objects": []}\0garbage' >nul.json
  expect_error 3 "nul.json: a NUL byte at byte 15 (a scene file is UTF-8 JSON text)" render nul.json -o keep.png
  scene_with '{"type": "cube"}' '{"file": "a\u0000b.obj"}'
  expect_error 3 'bad.json: /objects/0/mesh/file: expected a string without NUL characters (\u0000), got "a\u0000b.obj"' render bad.json -o keep.png
  # Silently wrong images are errors (docs/hostile-input.md).
  scene_with '"intensity": 5' '"intensity": 1e30, "color": [1e30, 1, 1]'
  expect_error 3 "bad.json: /lights/0/intensity: intensity x color is 1e+60, over 1e+30 (the light's radiance would overflow float: an all-black .hdr/.exr)" render bad.json -o keep.png
  scene_with '"position": [0, 0, 3]' '"position": [0, 0, 3], "near": 1e-8'
  expect_error 3 "bad.json: /camera/near: far/near is 1e+10, over 10000000 (the depth buffer's float precision would be lost: raise near)" render bad.json -o keep.png
  scene_with '"position": [0, 0, 3]' '"position": [0, 0, 3], "fov": 179.9999'
  "$softpbr" render bad.json -o fov.png -q && pass "fov 179.9999 renders (docs: (0, 180))" || fail "fov 179.9999 refused"
  printf 'newmtl m\nKd 0.5 banana 0.5\n' >banana.mtl
  printf 'mtllib banana.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n' >banana.obj
  scene_with '"type": "cube"' '"file": "banana.obj"'
  expect_error 3 "bad.json: /objects/0/mesh/file: banana.mtl:2: Kd value 'banana' is not a number" render bad.json -o keep.png
  # --root confines what a scene reads (symbolic links and .. resolved).
  scene_with '"type": "cube"' '"file": "../../../../../../etc/passwd"'
  expect_error 3 "bad.json: /objects/0/mesh/file: ../../../../../../etc/passwd: outside the folders the scene may read (.)" \
    render bad.json -o keep.png --root .
  "$softpbr" render bad.json -o echo.png 2>stderr.txt >/dev/null
  grep -q "root:" stderr.txt && fail "a warning echoed /etc/passwd: $(cat stderr.txt)" || pass "/etc/passwd as a mesh: its contents are not echoed"
  expect_error 2 "--root: nowhere is not a folder" render bad.json -o keep.png --root nowhere
  # Devices as models; a syntax error quotes at most 40 bytes of the text it read.
  scene_with '"type": "cube"' '"file": "/dev/zero"'
  expect_error 3 "bad.json: /objects/0/mesh/file: /dev/zero: cannot open: is a character device, not a regular file" render bad.json -o keep.png
  { printf '{"objects": [], "x": "'; head -c 100000 /dev/zero | tr '\0' a; } >longtok.json
  expect_error 3 "longtok.json: invalid JSON: parse error at line 1, column 100023: syntax error while parsing value - invalid string: missing closing quote; last read: '\"aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa..." \
    render longtok.json -o keep.png
  expect_error 2 "--pitch: expected degrees in [-89, 89], got nan" render missing.gltf -o keep.png --pitch nan
  expect_error 2 "--yaw: expected a finite number of degrees, got inf" render missing.gltf -o keep.png --yaw inf
  expect_error 2 "--camera: expected an index >= 0, got -1" render missing.gltf -o keep.png --camera -1
  printf 'v 3e38 3e38 3e38\nv -3e38 -3e38 -3e38\nv 3e38 -3e38 0\nf 1 2 3\n' >far.obj
  scene_with '{"type": "cube"}' '{"file": "far.obj", "fit": 2}'
  expect_error 3 "bad.json: /objects/0/mesh/fit: the mesh's bounds span more than float holds (coordinates beyond about +-1.7e38): it cannot be fitted" render bad.json -o keep.png
  # A colour beyond float after the exposure: a warning, not a silently black .hdr.
  scene_with '"roughness": 0.5' '"roughness": 0.5, "emissive": [1e30, 1e30, 1e30]'
  "$softpbr" render bad.json -o em.hdr --exposure 64 >/dev/null 2>stderr.txt
  grep -qx "softpbr: warning: em.hdr: [0-9]* pixels are not finite (a radiance beyond float, exposure included); .hdr and .exr store them as 0" stderr.txt \
    && pass "radiance beyond float: a warning naming the output" || fail "no warning for an overflowing exposure: $(cat stderr.txt)"
  # An OBJ is refused before parsing when its estimated parse memory passes --max-memory.
  awk 'BEGIN { for (i = 0; i < 20000; i++) print "v", i, i % 3, 0; for (i = 1; i + 2 <= 20000; i++) print "f", i, i + 1, i + 2 }' >big.obj
  scene_with '"type": "cube"' '"file": "big.obj"'
  "$softpbr" render bad.json -o keep.png --max-memory 4 2>stderr.txt; rc=$?
  [ $rc -eq 3 ] && grep -q "^bad.json: /objects/0/mesh/file: big.obj: parsing it needs an estimated 6.5 MiB, over the memory limit of 4.0 MiB$" stderr.txt \
    && pass "a big OBJ over --max-memory: refused before parsing" || fail "big OBJ: exit $rc, $(cat stderr.txt)"
  scene_with '' ''
  # No failure created or truncated an output.
  [ "$(cat keep.png)" = KEEP ] && pass "keep.png untouched by every failure" || fail "a failed render changed keep.png"
  for f in out.png out.jpg models/*.png .keep.png.tmp* .n*.tmp-* ; do [ -e "$f" ] && fail "a failed render left $f"; done
  ;;

frames)
  args=(render "$scenes/turntable.json" --width 48 --height 36 --frames 3..12)
  # all/ and shards/ do not exist: the first frame written creates each.
  "$softpbr" "${args[@]}" -q -o all/f_####.png --threads 1 || fail "the unsharded run failed"
  : >rendered.txt
  for i in 0 1 2; do
    "$softpbr" "${args[@]}" -o shards/f_####.png --shard $i/3 --threads 2 --tile-size 16 | grep hash >>rendered.txt
  done
  # Every frame 3..12 exactly once across the shards, and the same image as the single run.
  sort rendered.txt | awk '{ print $1 }' | uniq -d | grep -q . && fail "a frame was rendered by two shards"
  [ "$(wc -l <rendered.txt)" -eq 10 ] && pass "3 shards rendered 10 frames" || fail "shards rendered $(wc -l <rendered.txt) frames, not 10"
  for f in $(seq 3 12); do
    name=$(printf 'f_%04d.png' "$f")
    cmp -s "all/$name" "shards/$name" || fail "$name: shard output differs from the single run (or is missing)"
  done
  [ "$(ls shards | wc -l)" -eq 10 ] && pass "shards wrote exactly frames 3..12" || fail "shards/ holds $(ls shards | wc -l) files"
  cmp -s all/f_0003.png all/f_0004.png && fail "the animation does not move"
  # More shards than frames: still each frame exactly once (most shards render nothing).
  mkdir many && : >rendered.txt
  for i in $(seq 0 12); do "$softpbr" "${args[@]}" -o many/f_####.png --shard "$i/13" | grep hash >>rendered.txt; done
  [ "$(sort -u rendered.txt | wc -l)" -eq 10 ] && [ "$(wc -l <rendered.txt)" -eq 10 ] && [ "$(ls many | wc -l)" -eq 10 ] \
    && pass "13 shards over 10 frames: each frame once" || fail "13 shards: $(wc -l <rendered.txt) renders"
  # A file that looks like a temporary is not this process's: it is never removed (a killed
  # run leaves none for new frames: unnamed O_TMPFILE files linked straight to their names).
  touch shards/.f_0013.png.tmp12345
  "$softpbr" render "$scenes/turntable.json" --width 48 --height 36 --frames 3..13 -q -o shards/f_####.png
  [ -e shards/.f_0013.png.tmp12345 ] && pass "a look-alike temporary survives" || fail "a file that looked like a temporary was removed"
  rm -f shards/f_0013.png shards/.f_0013.png.tmp12345
  # Shard arithmetic at the extremes (UBSan found a signed overflow): N = 2^63 - 1.
  mkdir huge
  "$softpbr" render "$scenes/turntable.json" --width 48 --height 36 --frames 3..12 -o huge/f_####.png --shard 0/9223372036854775807 >out.txt \
    && [ "$(ls huge)" = f_0003.png ] && pass "--shard 0/(2^63-1): frame 3 only" || fail "--shard 0/2^63-1: $(ls huge) $(cat out.txt)"
  "$softpbr" render "$scenes/turntable.json" --width 48 --height 36 --frames 3..12 -o huge/f_####.png --shard 9223372036854775806/9223372036854775807 >out.txt \
    && grep -q "no frame of 3..12 is this shard's" out.txt && pass "an empty shard says so" || fail "empty shard: $(cat out.txt)"
  # Progress goes to stderr only when it is a terminal (script(1) gives the command one).
  mkdir tty
  "$softpbr" render "$scenes/turntable.json" --width 48 --height 36 --frames 3..5 -o tty/f_####.png >/dev/null 2>progress.txt \
    || fail "the render for the progress check failed"
  [ -s progress.txt ] && fail "progress written to a stderr that is not a terminal"
  if command -v script >/dev/null; then
    rm -f tty/*
    script -qc "'$softpbr' render '$scenes/turntable.json' --width 48 --height 36 --frames 3..5 -o tty/f_####.png >/dev/null" /dev/null >progress.txt
    grep -q "softpbr: frame 5, 3/3 done" progress.txt && pass "progress line on a terminal" || fail "no progress on a terminal: $(cat -v progress.txt)"
  fi
  # A re-run skips every complete frame; --force renders again.
  "$softpbr" "${args[@]}" -o shards/f_####.png | tail -1 | grep -q "10 frames: 0 rendered, 10 skipped" && pass "re-run skips complete frames" || fail "re-run did not skip"
  "$softpbr" "${args[@]}" -o shards/f_####.png --force | tail -1 | grep -q "10 rendered, 0 skipped" && pass "--force renders again" || fail "--force did not render"
  ;;

kill)
  args=(render "$scenes/turntable.json" --width 240 --height 180 --frames 0..59 --threads 1)
  mkdir ref out
  "$softpbr" "${args[@]}" -q -o ref/f_####.png || fail "the reference run failed"
  "$softpbr" "${args[@]}" -q -o out/f_####.png &
  pid=$!
  for _ in $(seq 1 400); do [ "$(ls out | wc -l)" -ge 5 ] && break; sleep 0.02; done
  kill -9 "$pid"
  wait "$pid" 2>/dev/null
  done_before=$(ls out | wc -l)
  [ "$done_before" -lt 60 ] && pass "killed after $done_before of 60 frames" || fail "the render finished before the kill"
  for f in out/*.png; do cmp -s "$f" "ref/${f#out/}" || fail "$f after the kill is not the complete frame"; done
  "$softpbr" "${args[@]}" -o out/f_####.png >rerun.txt || fail "the re-run failed"
  tail -1 rerun.txt | grep -q "60 frames: $((60 - done_before)) rendered, $done_before skipped" && pass "re-run rendered only the missing frames" || fail "re-run: $(tail -1 rerun.txt)"
  diff -r ref out >/dev/null && pass "after the re-run, out/ = the uninterrupted run" || fail "out/ differs from ref/ after the re-run"
  ls -A out | grep -q '^\.' && fail "temporary files left in out/: $(ls -A out | grep '^\.')"
  ;;

diff)
  "$softpbr" render "$scenes/gallery.json" -o a.png -o a.hdr --width 160 --height 90 -q
  "$softpbr" render "$scenes/gallery.json" -o b.png -o b.hdr --width 160 --height 90 --exposure 0.05 -q
  "$softpbr" render "$scenes/gallery.json" -o small.png --width 80 --height 45 -q
  # --gamma overrides render.gamma: gallery.json's own 2.2 given again is the same PNG, 0 (the sRGB curve) another.
  "$softpbr" render "$scenes/gallery.json" -o g22.png --width 160 --height 90 --gamma 2.2 -q
  "$softpbr" render "$scenes/gallery.json" -o gsrgb.png --width 160 --height 90 --gamma 0 -q
  cmp -s a.png g22.png && pass "--gamma 2.2 = the scene's gamma 2.2" || fail "--gamma 2.2 differs from the scene's own 2.2"
  cmp -s a.png gsrgb.png && fail "--gamma 0 left the PNG unchanged" || pass "--gamma 0: the sRGB curve, another PNG"
  check() { local code=$1; shift; "$softpbr" diff "$@" >out.txt 2>err.txt; local rc=$?
    [ $rc -eq "$code" ] && pass "diff $* → $rc" || fail "diff $* exited $rc, expected $code: $(cat out.txt err.txt)"; }
  check 0 a.png a.png
  grep -q identical out.txt || fail "identical images not reported as identical"
  check 1 a.png b.png
  check 0 a.png b.png --max-diff 255
  check 1 a.png b.png --max-diff 1
  check 0 a.png b.png --max-pixels 14400
  check 0 a.hdr a.hdr
  check 1 a.hdr b.hdr
  "$softpbr" render "$scenes/gallery.json" -o a.exr --width 160 --height 90 -q
  check 0 a.exr a.exr
  check 0 a.hdr a.exr
  check 1 b.hdr a.exr
  check 2 a.png a.exr
  printf 'not an exr' >bad.exr
  check 2 a.exr bad.exr
  check 2 a.exr /dev/zero.exr
  ln -s /dev/zero zero.exr
  check 2 a.exr zero.exr
  # Fuzzer findings (fuzz/README.md): a data window near ±2^31 (tinyexr overflows int on
  # it) is refused before decoding; pixel data that fails to decode is one error line.
  hostile=$src/cli/tests/hostile
  check 2 a.exr "$hostile/data-window-overflow.exr"
  grep -q "data-window-overflow.exr: data window (4096, -2147483648) - (1693613119, 1466004577) is not 1 to 16384 pixels on each side" err.txt \
    || fail "data window overflow: $(cat err.txt)"
  check 2 a.exr "$hostile/bad-pixel-data.exr"
  grep -q "bad-pixel-data.exr: not a readable OpenEXR file" err.txt || fail "bad pixel data: $(cat err.txt)"
  # A damaged PIZ chunk made tinyexr read past the file (ASan heap overflow): PIZ is refused.
  check 2 a.exr "$hostile/piz-bitmap-overread.exr"
  grep -q "piz-bitmap-overread.exr: PIZ-compressed OpenEXR files are not supported" err.txt \
    || fail "PIZ file: $(cat err.txt)"
  check 1 a.png small.png
  grep -q "different sizes, 160x90 and 80x45" out.txt || fail "size mismatch not described"
  check 2 a.png missing.png
  check 2 a.png a.hdr
  check 2 a.png b.png --max-diff -1
  check 2 a.png b.png --out nowhere/d.png
  grep -qx "nowhere/d.png: cannot write: the folder nowhere does not exist" err.txt || fail "--out nowhere/d.png: $(cat err.txt)"
  # A file where the folder should be: said so (it was "the folder a.png does not exist").
  check 2 a.png b.png --out a.png/d.png
  grep -qx "a.png/d.png: cannot write: a.png is not a folder" err.txt || fail "--out a.png/d.png: $(cat err.txt)"
  # --out never replaces an input; a folder or a device is not an image.
  cp a.png a-copy.png
  check 2 a-copy.png b.png --out a-copy.png
  grep -qx "a-copy.png: cannot write: it is the input a-copy.png (--out never replaces an input)" err.txt && cmp -s a.png a-copy.png || fail "--out over an input: $(cat err.txt)"
  mkdir somefolder
  check 2 a.png somefolder
  grep -qx "somefolder: is a folder, not an image" err.txt || fail "diff of a folder: $(cat err.txt)"
  check 2 a.png /dev/urandom
  grep -qx "/dev/urandom: is a character device, not a regular file" err.txt || fail "diff of /dev/urandom: $(cat err.txt)"
  check 2 a.png b.png --out /dev/null
  check 2 a.png b.png --max-pixels -1
  [ "$(wc -l <err.txt)" -eq 1 ] || fail "--max-pixels -1: not one line: $(cat err.txt)"
  # 16-bit PNGs differing only in their low bytes: compared on their 16-bit samples (they
  # were refused: golden images from other tools often are 16-bit).
  python3 - <<'PY'
import struct, zlib
def png16(path, low):
    raw = b''.join(b'\x00' + struct.pack('>HHH', 0x1200 | low, 0x3400, 0x5600) * 2 for _ in range(2))
    def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', 2, 2, 16, 2, 0, 0, 0)) +
                           chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))
png16('p16a.png', 0x01); png16('p16b.png', 0x02)
PY
  check 1 p16a.png p16b.png
  grep -qx "p16a.png vs p16b.png: DIFFERENT: 4 of 4 pixels differ by more than 0 (16-bit codes) (allowed: 0), largest difference 1, PSNR 102.35 dB" out.txt \
    || fail "16-bit PNG diff: $(cat out.txt err.txt)"
  check 0 p16a.png p16b.png --max-diff 1
  check 0 p16a.png p16a.png
  grep -qx "p16a.png vs p16a.png: identical (2x2, 16-bit samples)" out.txt || fail "16-bit PNG against itself: $(cat out.txt)"
  check 1 p16a.png p16b.png --out side16.png --side-by-side
  [ "$(od -An -tu1 -j16 -N4 side16.png | awk '{print $1 * 16777216 + $2 * 65536 + $3 * 256 + $4}')" -eq 6 ] \
    && pass "16-bit --side-by-side is 3 images wide" || fail "16-bit side-by-side image is not 6 wide"
  # A valid PNG with 3000 text chunks (libspng's chunk limits refused it): the same pixels.
  python3 - <<'PY'
import struct, zlib
def chunk(t, d): return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
src = open('a.png', 'rb').read()
open('texts.png', 'wb').write(src[:33] + chunk(b'tEXt', b'Comment\x00made by a tool') * 3000 + src[33:])
PY
  check 0 a.png texts.png
  grep -q identical out.txt || fail "a PNG with 3000 text chunks is not identical to itself without them: $(cat out.txt)"
  check 1 a.png b.png --out heat.png
  "$softpbr" diff heat.png heat.png -q && [ "$(od -An -tu1 -j16 -N4 heat.png | awk '{print $1 * 16777216 + $2 * 65536 + $3 * 256 + $4}')" -eq 160 ] \
    && pass "--out wrote a 160-wide heat map" || fail "--out heat map missing or wrong size"
  check 1 a.png b.png --out side.png --side-by-side
  [ "$(od -An -tu1 -j16 -N4 side.png | awk '{print $1 * 16777216 + $2 * 65536 + $3 * 256 + $4}')" -eq 480 ] \
    && pass "--side-by-side is 3 images wide" || fail "side-by-side image is not 480 wide"
  ;;

info)
  "$softpbr" info "$scenes/models/podium.obj" >out.txt || fail "info podium.obj failed"
  for want in "shapes     3" "vertices   42" "triangles  24" "bounds     min (-1, 0, -1) max (1, 2.05, 1)" "materials  3" "brass" "problems   0"; do
    grep -qF "$want" out.txt || fail "info podium.obj: no \"$want\" in: $(cat out.txt)"
  done
  printf 'v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\nl 1 2\n' >problems.obj
  "$softpbr" info problems.obj >out.txt || fail "info problems.obj failed"
  grep -q "1 zero-area triangles" out.txt && grep -q "problems   2" out.txt \
    && pass "info reports zero-area triangles and the loader's warnings" || fail "info problems.obj: $(cat out.txt)"
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n' >broken.obj
  "$softpbr" info broken.obj >/dev/null 2>err.txt; rc=$?
  [ $rc -eq 3 ] && grep -q "^broken.obj:4: " err.txt && [ "$(wc -l <err.txt)" -eq 1 ] && pass "broken OBJ: one line naming file:line, exit 3" || fail "broken.obj: exit $rc, $(cat err.txt)"
  "$softpbr" info "$scenes/gallery.json" >out.txt && grep -q "objects    35 (" out.txt && grep -q "lights     3" out.txt \
    && pass "info gallery.json" || fail "info gallery.json: $(cat out.txt)"
  expect_error 3 "missing.obj: cannot open: no such file" info missing.obj
  # glTF: what the file holds (cli/tests/make_gltf.py), image sizes from their headers.
  python3 "$src/cli/tests/make_gltf.py" "$src/cli/tests/goldens/lights.png" || fail "make_gltf.py failed"
  for model in two.gltf two.glb; do
    "$softpbr" info $model >out.txt 2>err.txt || { fail "info $model failed: $(cat err.txt)"; continue; }
    [ -s err.txt ] && fail "info $model wrote to stderr: $(cat err.txt)"
    where=$([ $model = two.gltf ] && echo "tex.png" || echo "bufferView 3") before=$failures
    for want in "^$model\$" "^  asset      glTF 2.0, generator \"softpbr make_gltf.py\"\$" "^  scenes     1 (default 0)\$" "^  nodes      5\$" \
        "^  meshes     2 (4 primitives, 6 triangles, each mesh counted once)\$" \
        "^    0   quads *2 primitives *4 triangles\$" "^    1   fan *2 primitives *2 triangles\$" \
        "^  drawn      5 primitives, 10 triangles (the scene's nodes)\$" \
        "^  bounds     min (-1, -1, 0) max (4, 4, 0) size (5, 5, 0)\$" "^  materials  2\$" \
        "^    0   textured *OPAQUE, textures base_color 0\$" "^    1   glass *BLEND, double-sided\$" \
        "^  textures   1 (1 image, 98.2 KiB encoded)\$" "^    0   albedo *png 640x400, image 0 ($where, 98.2 KiB)\$" \
        "^  extensions used: KHR_lights_punctual, EXT_made_up; required: none\$" \
        "^  extensions rendered: KHR_lights_punctual; ignored: EXT_made_up\$" \
        "^  cameras    1\$" "^    0   front *perspective\$" "^  lights     1\$" "^    0   bulb *point\$" \
        "^  animation  0 skins, 0 animations" "^  problems   2\$" \
        "^    $model: the extension EXT_made_up is not supported and is ignored\$" \
        "^    $model: /meshes/1/primitives/1: points and lines are not drawn\$"; do
      grep -q "$want" out.txt || fail "info $model: no line matching '$want' in:
$(cat out.txt)"
    done
    [ $failures -eq $before ] && pass "info $model: counts, materials, the texture's size from its header ($where), extensions, camera, light, problems"
  done
  # docs/scene-format.md's example is what the command prints (when ../shared/gltf is there).
  if [ -f "$src/../shared/gltf/WaterBottle/glTF/WaterBottle.gltf" ]; then
    (cd "$src" && "$softpbr" info ../shared/gltf/WaterBottle/glTF/WaterBottle.gltf) >wb.txt
    awk '/^\.\.\/shared\/gltf\/WaterBottle\/glTF\/WaterBottle.gltf$/ { on = 1 } on && /^```$/ { exit } on { print }' \
      "$src/docs/scene-format.md" >wb-doc.txt
    [ -s wb-doc.txt ] && cmp -s wb.txt wb-doc.txt && pass "docs/scene-format.md's info of WaterBottle is the command's output" \
      || fail "docs/scene-format.md's WaterBottle example differs: $(diff wb-doc.txt wb.txt)"
  fi
  # A bad glTF: the same line and exit code as render.
  for model in broken.gltf huge.glb missing.glb; do
    "$softpbr" render $model -o keep.png >/dev/null 2>render-err.txt; want_rc=$?
    "$softpbr" info $model >out.txt 2>err.txt; rc=$?
    [ $rc -eq 3 ] && [ $want_rc -eq 3 ] && [ ! -s out.txt ] && cmp -s err.txt render-err.txt && [ "$(wc -l <err.txt)" -eq 1 ] \
      && pass "info $model: exit 3 with render's line: $(cat err.txt)" || fail "info $model: exit $rc (render $want_rc), $(cat err.txt) vs $(cat render-err.txt)"
  done
  "$softpbr" info broken.gltf 2>&1 | grep -q "^broken.gltf: /accessors/0[/:]" && pass "broken.gltf's line names the JSON pointer" \
    || fail "broken.gltf: $("$softpbr" info broken.gltf 2>&1)"
  "$softpbr" info huge.glb 2>&1 | grep -q "30000x30000" && pass "huge.glb: refused by its header's size" || fail "huge.glb: $("$softpbr" info huge.glb 2>&1)"
  expect_error 2 "notes.txt: expected an .obj, .gltf or .glb model or a .json scene" info notes.txt
  # KHR_materials_variants: info lists them, render --variant shows one, an unknown one is
  # one line listing them (with the Khronos shoe, when the shared assets are there).
  shoe=${SOFTPBR_SHARED:-$src/../shared}/gltf/MaterialsVariantsShoe/glTF/MaterialsVariantsShoe.gltf
  if [ -f "$shoe" ]; then
    "$softpbr" info "$shoe" >out.txt
    grep -q "^  variants   3\$" out.txt && grep -q "^    0   midnight\$" out.txt && grep -q "^    1   beach\$" out.txt \
      && grep -q "^    2   street\$" out.txt && pass "info lists MaterialsVariantsShoe's variants" || fail "info shoe: $(cat out.txt)"
    "$softpbr" render "$shoe" -o beach.png --variant beach --width 64 --height 48 -q &&
      "$softpbr" render "$shoe" -o one.png --variant 1 --width 64 --height 48 -q &&
      "$softpbr" render "$shoe" -o street.png --variant street --width 64 --height 48 -q &&
      "$softpbr" diff beach.png one.png -q && ! "$softpbr" diff beach.png street.png -q \
      && pass "--variant beach is --variant 1, and not street" || fail "--variant renders"
    expect_error 3 "$shoe: /extensions/KHR_materials_variants/variants: no variant \"red\" (the variants: 0 \"midnight\", 1 \"beach\", 2 \"street\")" \
      render "$shoe" -o keep.png --variant red
  fi
  expect_error 2 "--variant: a glTF model's setting; in a scene file, a glTF object gives its own \"variant\"" \
    render "$scenes/lights.json" -o keep.png --variant beach
  # Compressed meshes (what gltfpack and gltf-transform write): listed as the file has them.
  for model in meshopt.glb draco.glb; do
    "$softpbr" info "$src/fuzz/corpus/gltf/$model" >out.txt 2>err.txt; rc=$?
    [ $rc -eq 0 ] && grep -Eq "^  drawn      [0-9]+ primitives?, [1-9][0-9]* triangles" out.txt \
      && pass "info $model (compressed): exit 0, its triangles listed" || fail "info $model: exit $rc, $(cat err.txt) $(cat out.txt)"
  done
  # Animations (issue 50): listed with their names, durations and channels; rendered at a
  # moment with the same bits for any threads, another image than without --time.
  model=${SOFTPBR_SHARED:-$src/../shared}/gltf/InterpolationTest/glTF-Binary/InterpolationTest.glb
  if [ -f "$model" ]; then
    "$softpbr" info "$model" >out.txt 2>err.txt || fail "info InterpolationTest failed: $(cat err.txt)"
    grep -q "^  animation  0 skins, 9 animations" out.txt && grep -Eq "^    8   Linear Translation +1\.667 s  1 channel\$" out.txt \
      && pass "info lists InterpolationTest's 9 animations" || fail "info InterpolationTest: $(cat out.txt)"
    a=$("$softpbr" render "$model" -o a.png --width 160 --height 120 --time 0.3)
    b=$("$softpbr" render "$model" -o b.png --width 160 --height 120 --time 0.3 --threads 1 --tile-size 16)
    c=$("$softpbr" render "$model" -o c.png --width 160 --height 120)
    d=$("$softpbr" render "$model" -o d.png --width 160 --height 120 --time 0.3 --animation "Linear Translation")
    [ -n "${a##*hash }" ] && [ "${a##*hash }" = "${b##*hash }" ] && [ "${a##*hash }" != "${c##*hash }" ] \
      && [ "${d##*hash }" != "${a##*hash }" ] && [ "${d##*hash }" != "${c##*hash }" ] \
      && pass "render --time: the same bits at 1 and all threads, not the unanimated image; --animation one only" \
      || fail "render --time: hashes ${a##*hash } ${b##*hash } ${c##*hash } ${d##*hash }"
    expect_error 3 "$model: /animations: no animation is named \"Walk\"" render "$model" -o x.png --time 1 --animation Walk
    [ ! -e x.png ] && pass "no output for an unknown animation" || fail "x.png written for an unknown animation"
    # An animation's frames (--fps): frame i at i/F; shards give the same files; a second run
    # resumes (nothing left to render); the frames differ from one another.
    "$softpbr" render "$model" -o fps/all_#.png --frames 0..3 --fps 2 --width 80 --height 60 >all.txt 2>err.txt \
      || fail "render --fps: $(cat err.txt)"
    "$softpbr" render "$model" -o fps/shard_#.png --frames 0..3 --fps 2 --width 80 --height 60 --shard 0/2 -q &&
      "$softpbr" render "$model" -o fps/shard_#.png --frames 0..3 --fps 2 --width 80 --height 60 --shard 1/2 -q || fail "render --fps --shard"
    same=1
    for i in 0 1 2 3; do cmp -s "fps/all_$i.png" "fps/shard_$i.png" || same=0; done
    [ $same -eq 1 ] && ! cmp -s fps/all_0.png fps/all_2.png && [ "$(grep -c hash all.txt)" -eq 4 ] \
      && pass "render --frames --fps: 4 frames that differ, the same from 2 shards" || fail "render --fps: $(cat all.txt)"
    "$softpbr" render "$model" -o fps/all_#.png --frames 0..3 --fps 2 --width 80 --height 60 >again.txt
    grep -q "^4 frames: 0 rendered, 4 skipped" again.txt && pass "render --fps resumes: nothing rendered again" \
      || fail "render --fps again: $(cat again.txt)"
    "$softpbr" render "$model" -o fps/turn_#.png --frames 2..2 --fps 2 --width 80 --height 60 --turntable -q
    ! cmp -s fps/turn_2.png fps/all_2.png && pass "--turntable with --fps turns the camera" || fail "--turntable with --fps: same image"
    expect_error 2 "--fps: frame f is the moment f / fps: give the frames' fps or one time, not both" \
      render "$model" -o x.png --fps 2 --time 1
  fi
  expect_error 2 "--fps: a glTF model's setting; a scene file's frames are its turntable's" \
    render "$scenes/lights.json" -o keep.png --fps 24
  # Several scenes (glTF's "scenes"): info lists them, --scene picks one.
  multi=${SOFTPBR_SHARED:-$src/../shared}/gltf/MultipleScenes/glTF/MultipleScenes.gltf
  if [ -f "$multi" ]; then
    "$softpbr" info "$multi" >out.txt
    grep -q "^  scenes     2 (default 1)\$" out.txt && grep -q "^    0   (unnamed)\$" out.txt && grep -q "^    1   (unnamed)\$" out.txt \
      && pass "info lists MultipleScenes' 2 scenes" || fail "info MultipleScenes: $(cat out.txt)"
    a=$("$softpbr" render "$multi" -o s0.png --scene 0 --width 64 --height 48)
    b=$("$softpbr" render "$multi" -o s1.png --width 64 --height 48)
    c=$("$softpbr" render "$multi" -o s1b.png --scene 1 --width 64 --height 48)
    [ "${a##*hash }" != "${b##*hash }" ] && [ "${b##*hash }" = "${c##*hash }" ] \
      && pass "render --scene 0 is another image; the default is scene 1" || fail "render --scene: ${a##*hash } ${b##*hash } ${c##*hash }"
    expect_error 3 "$multi: /scenes: no scene \"left\" (the scenes: 0, 1)" render "$multi" -o x.png --scene left
  fi
  expect_error 2 "--scene: a glTF model's setting; in a scene file, a glTF object gives its own \"scene\"" \
    render "$scenes/lights.json" -o keep.png --scene 1
  "$softpbr" render two.glb -o x.png --time 1e10 >/dev/null 2>err.txt; rc=$?
  [ $rc -eq 2 ] && grep -q "^--time: expected a finite number of seconds in \[-1e9, 1e9\]" err.txt \
    && pass "--time out of range: exit 2" || fail "--time 1e10: exit $rc, $(cat err.txt)"
  ;;
pipes)
  # A named pipe (FIFO) with no writer wherever a file is read: refused at once with one
  # line naming it (each run under `timeout`: a reader that waited on it hung for ever).
  python3 "$src/cli/tests/make_gltf.py" "$src/cli/tests/goldens/lights.png" || fail "make_gltf.py failed"
  mkfifo pipe.bin pipe.png pipe.glb pipe.hdr pipe.json pipe.obj
  # expect_refusal CODE 'EXPECTED STDERR LINE' ARGS...: expect_error within 20 s.
  expect_refusal() {
    local code=$1 line=$2 rc got; shift 2
    timeout 20 "$softpbr" "$@" >stdout.txt 2>stderr.txt; rc=$?
    got=$(cat stderr.txt)
    [ $rc -eq 124 ] && { fail "softpbr $*: still waiting after 20 s"; return; }
    [ $rc -eq "$code" ] && [ "$got" = "$line" ] && pass "exit $code at once: $line" \
      || fail "softpbr $*: exit $rc, stderr: $got (expected $code: $line)"
  }
  fifo=": is a named pipe (FIFO), not a regular file"
  sed 's/"two.bin"/"pipe.bin"/' two.gltf >buffer.gltf
  sed 's/"tex.png"/"pipe.png"/' two.gltf >image.gltf
  for command in render info; do
    out=$([ $command = render ] && echo "-o keep.png")
    expect_refusal 3 "buffer.gltf: /buffers/0/uri: pipe.bin$fifo" $command buffer.gltf $out
    expect_refusal 3 "pipe.glb$fifo" $command pipe.glb $out
  done
  expect_refusal 3 "image.gltf: /images/0/uri: pipe.png$fifo" render image.gltf -o keep.png
  expect_refusal 3 "--env: pipe.hdr$fifo" render two.glb -o keep.png --env pipe.hdr
  expect_refusal 2 "pipe.png$fifo" diff pipe.png tex.png
  printf '{"objects": [{"mesh": {"file": "pipe.obj"}}]}\n' >mesh.json
  expect_refusal 3 "mesh.json: /objects/0/mesh/file: pipe.obj: cannot open$fifo" render mesh.json -o keep.png
  # A scene file may be a pipe (<(generate-scene)); one with no writer gives nothing.
  expect_refusal 3 "pipe.json: is a pipe that gave nothing (a named pipe with no writer reads as empty)" render pipe.json -o keep.png
  timeout 60 "$softpbr" render <(cat "$scenes/gallery.json") -o piped.png --width 64 --height 36 >/dev/null 2>stderr.txt \
    && [ -s piped.png ] && pass "a scene from <(...) renders" || fail "a scene from <(...): $(cat stderr.txt)"
  # In a batch, the pipe is its own line and the next model renders.
  timeout 60 "$softpbr" render pipe.glb two.glb -o batch/ --width 64 --height 36 >/dev/null 2>stderr.txt; rc=$?
  [ $rc -eq 3 ] && [ "$(grep -v "^softpbr: warning: two.glb: " stderr.txt)" = "pipe.glb$fifo" ] && [ -s batch/two.png ] \
    && pass "batch: the pipe refused, the next model rendered" || fail "batch with a pipe: exit $rc, $(cat stderr.txt)"
  # A symbolic-link loop is a loop, not "no such file".
  ln -s loop.glb loop.glb
  expect_refusal 3 "loop.glb: too many levels of symbolic links (a link loop)" info loop.glb
  ;;

version)
  "$softpbr" --version >out.txt 2>err.txt; rc=$?
  [ $rc -eq 0 ] && [ ! -s err.txt ] && pass "--version exits 0, nothing on stderr" || fail "--version: exit $rc, $(cat err.txt)"
  want=$(sed -n 's/^project(softpbr VERSION \([0-9.]*\) .*/\1/p' "$src/CMakeLists.txt")
  [ -n "$want" ] && [ "$(head -n 1 out.txt)" = "softpbr $want" ] && pass "first line: softpbr $want (CMake's project version)" \
    || fail "--version's first line is \"$(head -n 1 out.txt)\", CMakeLists.txt says ${want:-nothing}"
  grep -Eq '^compiler   (GCC|Clang) [0-9]' out.txt && pass "compiler: $(grep ^compiler out.txt)" || fail "no compiler line: $(cat out.txt)"
  build=${SOFTPBR_EXPECT_BUILD_TYPE:-}
  grep -q "^build      ${build:-[A-Za-z]*} (\(not \)\?optimized), -ffp-contract=off$" out.txt \
    && pass "build type ${build:-(any)}: $(grep ^build out.txt)" || fail "build line for ${build:-any}: $(grep ^build out.txt)"
  grep -q "^simd       lane widths 1, 4, 8, 16; kernels compiled for baseline ([0-9]* lanes)" out.txt \
    && pass "simd line" || fail "simd line: $(cat out.txt)"
  # This CPU's widest target and default lane width, from /proc/cpuinfo for an x86-64 binary
  # (also in builds without AVX2/AVX-512 kernels: the renderer still picks the width, and
  # says so). The binary's own architecture line decides: an AArch64 build under qemu-user
  # runs beside an x86-64 shell.
  if grep -q "^compiler   .*, x86-64$" out.txt && [ -r /proc/cpuinfo ]; then
    flags=$(grep -m1 '^flags' /proc/cpuinfo)
    has() { case " ${flags#*:} " in *" $1 "*) return 0 ;; *) return 1 ;; esac; }
    if has avx512f && has avx512dq && has avx512vl && has avx512bw; then isa="avx512: 16"
    elif has avx2; then isa="avx2: 8"; else isa="baseline: "; fi
    grep -q "^this cpu   $isa" out.txt && pass "this cpu: $isa (as /proc/cpuinfo)" || fail "this cpu line \"$(grep '^this cpu' out.txt)\", /proc/cpuinfo says $isa"
    if grep -q 'avx512 (16)' out.txt; then
      grep -q "^this cpu   .* lanes by default (the image is the same for any width)$" out.txt || fail "this cpu line: $(cat out.txt)"
    elif [ "$isa" != "baseline: " ]; then
      grep -q "^this cpu   .* lanes by default, run by the baseline kernels (this build has no avx" out.txt \
        && pass "a build without x86 kernels says the baseline kernels run" || fail "this cpu line: $(cat out.txt)"
    fi
  else
    grep -q "^this cpu   baseline: [0-9]* lanes by default" out.txt && pass "this cpu: baseline (not an x86-64 binary)" \
      || fail "this cpu line: $(cat out.txt)"
  fi
  "$softpbr" version >out2.txt 2>err.txt && cmp -s out.txt out2.txt && pass "softpbr version = softpbr --version" || fail "softpbr version differs: $(cat out2.txt)"
  "$softpbr" --help | grep -q -- "--version" && pass "--help lists --version" || fail "--help does not list --version"
  ;;
batch)
  python3 "$src/cli/tests/make_gltf.py" "$src/cli/tests/goldens/lights.png" || fail "make_gltf.py failed"
  cp "$src/fuzz/corpus/gltf/triangle.gltf" tri.gltf
  size=(--width 64 --height 48)
  # Each input alone, for the batch's images to equal.
  for m in tri two; do "$softpbr" render $m.gltf -o single-$m.png "${size[@]}" -q || fail "render $m.gltf failed"; done
  "$softpbr" render two.glb -o single-two-glb.png "${size[@]}" -q || fail "render two.glb failed"
  # {name}: two inputs with one name are refused before anything is rendered.
  mkdir thumbs
  expect_error 2 "thumbs/two.png: the output of both two.gltf and two.glb (inputs 1 and 2; tell them apart with {index})" \
    render tri.gltf two.gltf two.glb -o "thumbs/{name}.png" "${size[@]}"
  [ -z "$(ls -A thumbs)" ] && pass "a name clash writes nothing" || fail "a name clash wrote $(ls thumbs)"
  expect_error 2 "out.png: with several inputs an output needs {name}, {index} or a folder ending in / (e.g. thumbs/{name}.png or thumbs/)" \
    render tri.gltf two.gltf -o out.png
  expect_error 2 "--frames: renders one scene; 2 inputs were given" render tri.gltf two.gltf -o "f/{name}_####.png" --frames 0..3
  expect_error 2 "thumbs/#/: a folder output has no frame number (write folder/{name}_####.png)" render tri.gltf -o "thumbs/#/"
  # A batch's output folder is created with its first image.
  "$softpbr" render tri.gltf two.gltf -o new-thumbs/ "${size[@]}" -q && [ "$(ls new-thumbs | tr '\n' ' ')" = "tri.png two.png " ] \
    && pass "-o new-thumbs/ creates the folder" || fail "-o new-thumbs/: $(ls new-thumbs 2>&1)"
  # {index} and {name}; a folder; the same bits as one input at a time (one renderer for all).
  "$softpbr" render tri.gltf two.gltf two.glb -o "thumbs/{index}-{name}.png" -o "thumbs/{index}.exr" "${size[@]}" >out.txt 2>err.txt \
    || fail "batch with {index}: exit $?, $(cat err.txt)"
  [ "$(ls thumbs | tr '\n' ' ')" = "0-tri.png 0.exr 1-two.png 1.exr 2-two.png 2.exr " ] && pass "{index}-{name}.png and {index}.exr: $(ls thumbs | tr '\n' ' ')" \
    || fail "batch outputs: $(ls thumbs | tr '\n' ' ')"
  cmp -s thumbs/0-tri.png single-tri.png && cmp -s thumbs/1-two.png single-two.png && cmp -s thumbs/2-two.png single-two-glb.png \
    && pass "each batch image = the same input rendered alone" || fail "batch images differ from single renders"
  grep -q "^3 inputs: 3 rendered, 0 skipped (already complete), 0 failed$" out.txt && grep -q "^thumbs/1-two.png: 64x48, hash " out.txt \
    && pass "batch summary line" || fail "batch stdout: $(cat out.txt)"
  grep -q "^softpbr: warning: two.gltf: the extension EXT_made_up is not supported and is ignored$" err.txt \
    && pass "an input's warnings name it" || fail "batch warnings: $(cat err.txt)"
  mkdir folder
  "$softpbr" render tri.gltf two.gltf -o folder/ "${size[@]}" -q && cmp -s folder/tri.png single-tri.png && cmp -s folder/two.png single-two.png \
    && [ "$(ls folder | wc -l)" -eq 2 ] && pass "-o folder/: folder/<name>.png" || fail "-o folder/: $(ls folder)"
  mkdir one
  "$softpbr" render two.gltf -o one/ "${size[@]}" -q && cmp -s one/two.png single-two.png && pass "one input, -o one/: one/two.png" || fail "-o one/: $(ls one)"
  # A re-run skips inputs whose outputs exist; --force renders them again.
  "$softpbr" render tri.gltf two.gltf -o folder/ "${size[@]}" >out.txt 2>&1
  grep -q "^folder/tri.png: exists, skipped$" out.txt && grep -q "^2 inputs: 0 rendered, 2 skipped (already complete), 0 failed$" out.txt \
    && pass "a re-run skips complete inputs" || fail "re-run: $(cat out.txt)"
  "$softpbr" render tri.gltf two.gltf -o folder/ "${size[@]}" --force >out.txt 2>&1
  grep -q "^2 inputs: 2 rendered" out.txt && pass "--force renders them again" || fail "--force: $(cat out.txt)"
  # A bad input among good ones: its one line (the same as rendering it alone), the good
  # ones written, the first failure's exit code.
  mkdir mixed
  "$softpbr" render broken.gltf -o x.png -q 2>broken-err.txt; broken_rc=$?
  "$softpbr" render missing.glb -o x.png -q 2>missing-err.txt
  "$softpbr" render tri.gltf broken.gltf missing.glb two.gltf -o "mixed/{name}.png" "${size[@]}" -q >out.txt 2>err.txt; rc=$?
  [ $rc -eq 3 ] && [ $broken_rc -eq 3 ] && [ "$(cat err.txt)" = "$(cat broken-err.txt missing-err.txt)" ] \
    && pass "bad inputs in a batch: exit 3, each input's own line: $(head -n 1 err.txt)" || fail "mixed batch: exit $rc, stderr $(cat err.txt)"
  [ "$(ls mixed | tr '\n' ' ')" = "tri.png two.png " ] && cmp -s mixed/two.png single-two.png \
    && pass "the good inputs are written, the bad ones not" || fail "mixed outputs: $(ls mixed)"
  # --shard i/N shares the inputs: every input exactly once over the shards.
  mkdir sharded
  for i in 0 1; do
    "$softpbr" render tri.gltf two.gltf two.glb -o "sharded/{index}.png" --shard $i/2 "${size[@]}" -q || fail "shard $i/2 failed"
    [ $i -eq 0 ] && { [ "$(ls sharded | tr '\n' ' ')" = "0.png 2.png " ] && pass "shard 0/2: inputs 0 and 2" || fail "shard 0/2 wrote $(ls sharded)"; }
  done
  cmp -s sharded/0.png single-tri.png && cmp -s sharded/1.png single-two.png && cmp -s sharded/2.png single-two-glb.png \
    && pass "shards 0/2 and 1/2 together: every input once, the same images" || fail "sharded: $(ls sharded)"
  out=$("$softpbr" render tri.gltf two.gltf -o "sharded/x{index}.png" --shard 3/4 "${size[@]}")
  [ "$out" = "shard 3/4: no input of the 2 is this shard's (nothing to render)
0 inputs: 0 rendered, 0 skipped (already complete), 0 failed" ] && pass "an empty shard says so" || fail "empty shard: $out"
  # The progress line counts models (on a terminal only: script(1) gives the command one).
  mkdir pr
  "$softpbr" render tri.gltf two.gltf -o pr/ --width 32 --height 24 >/dev/null 2>progress.txt
  grep -q "softpbr: model" progress.txt && fail "progress written to a stderr that is not a terminal"
  if command -v script >/dev/null; then
    rm -f pr/*
    script -qc "'$softpbr' render tri.gltf two.gltf -o pr/ --width 32 --height 24 >/dev/null" /dev/null >progress.txt
    grep -q "softpbr: model two.gltf, 2/2 done" progress.txt && pass "batch progress line on a terminal" || fail "no batch progress: $(cat -v progress.txt)"
  fi
  # Scene files and models mixed: each scene keeps its own render settings.
  "$softpbr" render "$scenes/lights.json" tri.gltf -o "mix/{name}.png" --width 80 --height 50 -q \
    && "$softpbr" render "$scenes/lights.json" -o lights-alone.png --width 80 --height 50 -q && cmp -s mix/lights.png lights-alone.png \
    && pass "a scene file in a batch: the same image as alone" || fail "scene file in a batch"
  # --missing-images warn (thumbnails of downloaded models): a texture whose file is not
  # there is left out with a warning, exit 0; the default refuses the model.
  sed 's/"tex.png"/"gone.png"/' two.gltf >gone.gltf
  printf 'mtllib gone.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n' >gone.obj
  printf 'newmtl a\nKd 0.5 0.2 0.1\nmap_Kd gone.png\n' >gone.mtl
  printf '{"objects": [{"mesh": {"file": "gone.obj"}}], "render": {"width": 32, "height": 24}}\n' >goneobj.json
  expect_error 3 "gone.gltf: /images/0/uri: gone.png: no such file" render gone.gltf -o keep.png
  expect_error 3 "goneobj.json: /objects/0/mesh/file: gone.mtl:3: map_Kd: gone.png: no such file" render goneobj.json -o keep.png
  "$softpbr" render gone.gltf goneobj.json tri.gltf -o missing/ --width 32 --height 24 --missing-images warn >/dev/null 2>stderr.txt; rc=$?
  [ $rc -eq 0 ] && [ -s missing/gone.png ] && [ -s missing/tri.png ] \
    && grep -qx "softpbr: warning: gone.gltf: /images/0/uri: gone.png: no such file (a missing image: its textures are left out)" stderr.txt \
    && grep -qx "softpbr: warning: gone.mtl:3: map_Kd: gone.png: no such file (a missing image: the map is left out)" stderr.txt \
    && pass "--missing-images warn: textures left out with a warning, exit 0" || fail "--missing-images warn: exit $rc, $(cat stderr.txt)"
  # The same model with its texture there renders as before; a bad value is a usage error.
  expect_error 2 "--missing-images: expected error or warn, got \"maybe\"" render two.gltf -o keep.png --missing-images maybe
  ;;
model_diff)
  # Two models rendered from the same views: a model against itself and an equal copy is
  # identical (exit 0); a changed back face differs only in the view that sees it (exit 1,
  # that view worst); a moved node differs everywhere; --json, --out, --max-pixels; errors.
  python3 "$src/cli/tests/make_diff_models.py" || fail "make_diff_models.py failed"
  check() { local code=$1; shift; timeout 120 "$softpbr" diff "$@" >out.txt 2>err.txt; local rc=$?
    [ $rc -eq "$code" ] && pass "diff $* → $rc" || fail "diff $* exited $rc, expected $code: $(cat out.txt err.txt)"; }
  small="--width 96 --height 96"
  check 0 cube.gltf cube.gltf $small
  grep -q "cube.gltf vs cube.gltf: identical (8 views at 96x96)" out.txt || fail "self diff: $(cat out.txt)"
  [ "$(grep -c '^[0-9]' out.txt)" -eq 8 ] || fail "the default is 8 views: $(cat out.txt)"
  check 0 cube.gltf cube_copy.gltf $small
  grep -q "What changed" out.txt && fail "an equal copy reported changes: $(cat out.txt)"
  # The back face: views 0 (front), 1 (yaw 90) and 3 (yaw 270) see nothing of it at pitch 0.
  check 1 cube.gltf cube_back.gltf $small --yaw 0,90,180,270 --pitch 0 --json d.json --out sheet.png
  grep -q "DIFFERENT: 1 of 4 views differ (worst: view 2, yaw 180" out.txt || fail "back face: $(cat out.txt)"
  grep -q "object 1 material" out.txt && grep -q "base_color (0.9, 0.1, 0.1, 1)" out.txt || fail "the material change is not reported: $(cat out.txt)"
  python3 - <<'PY' || fail "d.json: $(cat d.json)"
import json
d = json.load(open('d.json'))
assert d['worst_view'] == 2 and not d['identical'] and not d['within_tolerance'], d
v = d['views']
assert [x['pixels_differing'] == 0 for x in v] == [True, True, False, True], v
assert v[0]['psnr'] is None and v[2]['psnr'] < 40 and v[2]['share_differing'] > 0.05, v
assert any(c['property'] == 'object 1 material' for c in d['changes']), d['changes']
PY
  # The sheet: 4 rows of expected | actual | heat map, 288x384, the worst view (red back face) first.
  # The sheet: 4 rows of expected | actual | heat map, the worst view (the red back face) first.
  px=$(python3 "$src/cli/tests/png_pixel.py" sheet.png 48,48 144,48 240,48 | tr '\n' ' ')
  read -r size r1 g1 b1 a1 r2 g2 b2 a2 r3 g3 b3 a3 <<<"$px"
  [ "$size" = 288x384 ] && [ "$r2" -gt $((g2 + 60)) ] && [ "$r1" -lt $((g1 + 20)) ] && [ "$r3" -gt 0 ] \
    && pass "sheet.png: 4 rows, the back view first (grey | red | heat)" || fail "sheet.png: $px"
  check 0 cube.gltf cube_back.gltf $small --yaw 0,90,180,270 --pitch 0 --max-pixels 100000
  grep -q "within tolerance" out.txt || fail "--max-pixels: $(cat out.txt)"
  check 1 cube.gltf cube_moved.gltf $small --views 3
  grep -q "DIFFERENT: 3 of 3 views differ" out.txt || fail "a moved node: $(cat out.txt)"
  grep -q "bounds" out.txt || fail "moved bounds not reported: $(cat out.txt)"
  check 0 cube.gltf cube.glb $small --views 2 -q
  [ -s out.txt ] && fail "-q printed: $(cat out.txt)"
  # OBJ and scene files: against themselves.
  check 0 "$scenes/models/podium.obj" "$scenes/models/podium.obj" $small --views 2
  check 0 "$scenes/materials.json" "$scenes/materials.json" --width 64 --height 48 --views 1
  # Errors: one line, exit 2, no output.
  check 2 cube.gltf missing.gltf
  grep -qx "missing.gltf: no such file" err.txt || fail "missing model: $(cat err.txt)"
  check 2 cube.gltf sheet.png
  grep -qx "sheet.png: cannot compare an image with a model (.gltf, .glb, .obj or a scene .json)" err.txt || fail "image vs model: $(cat err.txt)"
  check 2 cube.gltf cube.gltf --views 0
  grep -qx -- "--views: expected 1 to 64 views, got 0" err.txt || fail "--views 0: $(cat err.txt)"
  check 2 cube.gltf cube.gltf --yaw 0,90 --pitch 0,10,20
  check 2 cube.gltf cube.gltf --pitch 95
  head -c 300 cube.glb >cut.glb
  check 2 cube.gltf cut.glb --out never.png
  [ -e never.png ] && fail "an error left never.png"
  mkfifo fifo.glb
  check 2 cube.gltf fifo.glb
  grep -qx "fifo.glb: is a named pipe (FIFO), not a regular file" err.txt || fail "fifo: $(cat err.txt)"
  check 2 cube.gltf cube.gltf --out cube.bin.png --json cube.bin
  grep -q "cube.bin: cannot write: it is an input" err.txt || fail "--json over an input: $(cat err.txt)"
  # Animated models: --time as `render --time` (the same moment for both); two moments of one
  # animation differ, the same moment is identical. --variant: an unknown name is an error.
  model=${SOFTPBR_SHARED:-$src/../shared}/gltf/InterpolationTest/glTF-Binary/InterpolationTest.glb
  if [ -f "$model" ]; then
    check 0 "$model" "$model" $small --views 2 --time 0.5
    # A copy whose LINEAR samplers step instead (the JSON chunk rewritten, the keys kept): the
    # same rest pose, another pose between keys.
    python3 - "$model" step.glb <<'PY' || fail "making step.glb failed"
import json, struct, sys
data = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<I", data, 12)[0]
doc = json.loads(data[20:20 + n])
for a in doc["animations"]:
    for s in a["samplers"]:
        if s.get("interpolation", "LINEAR") == "LINEAR":
            s["interpolation"] = "STEP"
text = json.dumps(doc).encode()
text += b" " * (-len(text) % 4)
rest = data[20 + n:]
out = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + len(rest)) + struct.pack("<II", len(text), 0x4E4F534A) + text + rest
open(sys.argv[2], "wb").write(out)
PY
    check 0 "$model" step.glb $small --views 2
    check 1 "$model" step.glb $small --views 2 --time 0.3
    check 0 "$model" step.glb $small --views 2 --time 0.3 --animation "Step Translation"
    check 2 "$model" step.glb $small --views 1 --time 1e10
    grep -q -- "--time: expected a finite number of seconds" err.txt || fail "diff --time 1e10: $(cat err.txt)"
  fi
  check 2 cube.gltf cube.gltf $small --views 1 --variant nosuch
  grep -q "nosuch" err.txt || fail "diff --variant nosuch: $(cat err.txt)"
  ;;
thumbnail)
  # The desktop thumbnailer installed into a prefix and run exactly as its .thumbnailer
  # file's Exec line says (%s %i %o put in), on a good model, a model without an extension,
  # a truncated one, a FIFO and /dev/zero; then --timeout.
  build=$(cd "$(dirname "$softpbr")/.." && pwd)
  # The command's component only (a matrix build tree does not build every installed target).
  cmake --install "$build" --prefix "$work/prefix" --component cli >install.log 2>&1 || fail "cmake --install: $(tail -3 install.log)"
  entry=$work/prefix/share/thumbnailers/softpbr.thumbnailer
  [ -f "$work/prefix/share/mime/packages/softpbr-models.xml" ] || fail "the MIME types are not installed"
  grep -qx "MimeType=model/gltf-binary;model/gltf+json;model/obj;" "$entry" || fail "MimeType: $(cat "$entry")"
  exec_line=$(sed -n 's/^Exec=//p' "$entry")
  case $exec_line in "$work/prefix/bin/softpbr "*) pass "Exec runs the installed command" ;; *) fail "Exec=$exec_line" ;; esac
  python3 "$src/cli/tests/make_diff_models.py" || fail "make_diff_models.py failed"
  # thumb IN OUT SIZE: runs the Exec line as a file manager does (each %-code one argument).
  thumb() {
    local words=() w
    read -r -a words <<<"$exec_line"
    for w in "${!words[@]}"; do
      case ${words[$w]} in %i) words[$w]=$1 ;; %o) words[$w]=$2 ;; %s) words[$w]=$3 ;; esac
    done
    timeout 60 "${words[@]}" >stdout.txt 2>stderr.txt
  }
  # png_check FILE SIZE: an RGBA PNG of SIZE x SIZE, transparent in its corner, opaque in its centre.
  png_check() {
    local c=$(($2 / 2))
    [ "$(python3 "$src/cli/tests/png_pixel.py" "$1" 0,0 $c,$c | tr '\n' ' ' | awk '{ print $1, $5, $9 }')" = "${2}x$2 0 255" ]
  }
  thumb cube.glb cube.png 128 && png_check cube.png 128 && pass "cube.glb: a 128x128 transparent thumbnail" || fail "cube.glb: $(cat stderr.txt)"
  cp cube.glb download
  thumb download download.png 256 && png_check download.png 256 && pass "a .glb without its extension (by its magic)" || fail "download: $(cat stderr.txt)"
  thumb cube.gltf cubegltf.png 64 && png_check cubegltf.png 64 && pass "cube.gltf" || fail "cube.gltf: $(cat stderr.txt)"
  thumb "$scenes/models/podium.obj" podium.png 128 && png_check podium.png 128 && pass "an OBJ model" || fail "podium.obj: $(cat stderr.txt)"
  if [ -n "${SOFTPBR_SHARED:-}" ] && [ -f "$SOFTPBR_SHARED/gltf/WaterBottle/glTF/WaterBottle.gltf" ]; then
    thumb "$SOFTPBR_SHARED/gltf/WaterBottle/glTF/WaterBottle.gltf" bottle.png 256 && png_check bottle.png 256 \
      && pass "WaterBottle.gltf" || fail "WaterBottle: $(cat stderr.txt)"
  fi
  # bad IN LINE: exit 3, that one line, the output not written (an old one kept as it was).
  bad() {
    echo old >keep.png
    thumb "$1" keep.png 128; local rc=$?
    [ $rc -eq 3 ] && [ "$(cat stderr.txt)" = "$2" ] && [ "$(cat keep.png)" = old ] && pass "exit 3: $2" \
      || fail "thumbnail $1: exit $rc, stderr $(cat stderr.txt), expected 3: $2"
  }
  head -c 500 cube.glb >cut.glb
  rc_line=$(timeout 60 "$softpbr" info cut.glb 2>&1 >/dev/null)
  bad cut.glb "$rc_line"
  mkfifo fifo.glb
  bad fifo.glb "fifo.glb: is a named pipe (FIFO), not a regular file"
  bad /dev/zero "/dev/zero: is a character device, not a regular file"
  printf 'garbage' >junk.glb
  thumb junk.glb junk.png 128; rc=$?
  [ $rc -eq 3 ] && [ ! -e junk.png ] && [ "$(wc -l <stderr.txt)" -eq 1 ] && pass "junk.glb: exit 3, one line" || fail "junk.glb: exit $rc: $(cat stderr.txt)"
  # --timeout: a limit that cannot be met gives up with one line, exit 3, no output.
  timeout 60 "$softpbr" thumbnail --timeout 0.001 -s 1024 cube.glb slow.png 2>stderr.txt; rc=$?
  [ $rc -eq 3 ] && [ ! -e slow.png ] && grep -qx "cube.glb: gave up after --timeout 0.001 s (the model takes too long to load or render)" stderr.txt \
    && pass "--timeout" || fail "--timeout: exit $rc: $(cat stderr.txt)"
  expect_error 2 "--size: expected 1 to 1024 pixels, got 4096" thumbnail -s 4096 cube.glb big.png
  # Memory: a limit below what the model needs is refused before rendering.
  "$softpbr" thumbnail -s 1024 --max-memory 1 cube.glb mem.png 2>stderr.txt; rc=$?
  [ $rc -eq 3 ] && [ ! -e mem.png ] && pass "--max-memory 1: exit 3: $(cat stderr.txt)" || fail "--max-memory 1: exit $rc: $(cat stderr.txt)"
  ;;
scenario)
  # Khronos Render Fidelity scenarios: the orbit's angles turn the camera as model-viewer's
  # (θ 180 sees the back face, θ 0 the front), renderSkybox draws the environment or leaves
  # the background transparent, a config of several picks one by name; errors name the key.
  python3 "$src/cli/tests/make_diff_models.py" || fail "make_diff_models.py failed"
  mkdir sub && mv cube_back.gltf cube.bin sub/
  scenario() {  # NAME THETA PHI SKYBOX: a scenario file sub/NAME.json for the cube with a red back
    printf '{"name": "%s", "model": "cube_back.gltf", "dimensions": {"width": 80, "height": 60}, "target": {"x": 0, "y": 0, "z": 0},
 "orbit": {"theta": %s, "phi": %s, "radius": 3}, "verticalFoV": 45, "renderSkybox": %s}\n' "$1" "$2" "$3" "$4" >"sub/$1.json"
  }
  pixel() { python3 "$src/cli/tests/png_pixel.py" "$1" "$2" | tail -1; }
  scenario front 0 90 false
  scenario back 180 90 true
  scenario side 90 90 false
  for name in front back side; do
    "$softpbr" render --scenario "sub/$name.json" -o "$name.png" -q 2>stderr.txt || fail "$name: $(cat stderr.txt)"
  done
  read -r r g b a <<<"$(pixel front.png 40,30)"; read -r _ _ _ ca <<<"$(pixel front.png 0,0)"
  [ "$a" = 255 ] && [ "$r" -lt $((g + 20)) ] && [ "$ca" = 0 ] && pass "theta 0: the grey front, transparent around" || fail "front: $r $g $b $a, corner alpha $ca"
  read -r r g b a <<<"$(pixel back.png 40,30)"; read -r _ _ _ ca <<<"$(pixel back.png 0,0)"
  [ "$r" -gt $((g + 60)) ] && [ "$ca" = 255 ] && pass "theta 180: the red back face, the environment behind" || fail "back: $r $g $b $a, corner alpha $ca"
  [ "$(python3 "$src/cli/tests/png_pixel.py" side.png | head -1)" = 80x60 ] && pass "dimensions 80x60" || fail "side.png size"
  cmp -s front.png side.png && fail "theta 90 gives the theta 0 image"
  # Several scenarios in one file (the project's config.json), one picked by name.
  printf '{"renderers": [], "scenarios": [%s, %s]}\n' "$(cat sub/front.json)" "$(cat sub/back.json)" >sub/config.json
  "$softpbr" render --scenario sub/config.json --scenario-name back -o picked.png -q && cmp -s picked.png back.png \
    && pass "--scenario-name picks a scenario of config.json" || fail "--scenario-name back: another image"
  # The command's options override the scenario's.
  "$softpbr" render --scenario sub/front.json -o wide.png --width 40 -q && [ "$(python3 "$src/cli/tests/png_pixel.py" wide.png | head -1)" = 40x60 ] \
    && pass "--width over the scenario's" || fail "--width with a scenario"
  expect_error 3 "sub/config.json: /scenarios: 2 scenarios: name one with --scenario-name" render --scenario sub/config.json -o x.png
  expect_error 3 "sub/config.json: /scenarios: no scenario named \"gone\"" render --scenario sub/config.json --scenario-name gone -o x.png
  sed 's/"phi": 90/"phi": 200/' sub/front.json >sub/badphi.json
  expect_error 3 "sub/badphi.json: /orbit/phi: expected a number in [0, 180], got 200" render --scenario sub/badphi.json -o x.png
  sed 's/"verticalFoV": 45, //' sub/front.json >sub/nofov.json
  expect_error 3 "sub/nofov.json: /: missing key \"verticalFoV\"" render --scenario sub/nofov.json -o x.png
  expect_error 2 "--scenario: names its model; give no scene besides it (got cube.gltf)" render cube.gltf --scenario sub/front.json -o x.png
  expect_error 3 "missing.json: no such file" render --scenario missing.json -o x.png
  [ -e x.png ] && fail "an error left x.png"
  ;;
*) echo "unknown group $group" >&2; exit 2 ;;
esac

[ $failures -eq 0 ] || { echo "$failures failure(s) in cli_$group" >&2; exit 1; }
echo "cli_$group: all passed"
