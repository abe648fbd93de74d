#!/bin/sh
# The viewer's glTF session: models.txt replayed under Xvfb with boxes.gltf on the command
# line and wedge.gltf dropped (SDL_DROPFILE through SDL's queue), every screenshot checked
# against the library's image of the same state (e2e_check --models), and the one error line
# of a dropped file that does not load.
# usage: run_models.sh VIEWER E2E_CHECK TESTS_DIR OUT_DIR — exits 77 (skipped) without xvfb-run.
set -eu
viewer=$1 check=$2 here=$3 out=$4
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "xvfb-run not found (Debian package xvfb): test skipped"
  exit 77
fi
rm -rf "$out"
mkdir -p "$out"
cd "$out"
cp "$here/wedge.gltf" wedge.gltf
xvfb-run -a -s "-screen 0 640x480x24" "$viewer" "$here/boxes.gltf" --width 320 --height 180 --threads 1 \
  --script "$here/models.txt" >stdout.txt 2>stderr.txt || { cat stdout.txt stderr.txt; exit 1; }
cat stdout.txt
# xvfb-run and the X server may add their own lines; the viewer's about the missing file is one.
if [ "$(grep -c '^viewer: ' stderr.txt)" -ne 1 ] || ! grep -q '^viewer: missing.glb: ' stderr.txt; then
  echo "FAIL: expected one line about missing.glb on stderr, got:"; cat stderr.txt; exit 1
fi
grep -q '^viewer: opened wedge.gltf (mesh 7 of 7)$' stdout.txt || { echo "FAIL: no 'opened wedge.gltf (mesh 7 of 7)'"; exit 1; }
grep -q '^viewer: opened wedge.gltf (mesh 8 of 8)$' stdout.txt || { echo "FAIL: no 'opened wedge.gltf (mesh 8 of 8)'"; exit 1; }
"$check" --models "$out" "$here/boxes.gltf" "$here/wedge.gltf"
