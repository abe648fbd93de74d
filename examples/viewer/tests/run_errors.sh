#!/bin/sh
# Bad input to the viewer is one clear error line and a non-zero exit, before any window
# opens (so this test needs no display).   usage: run_errors.sh VIEWER OUT_DIR
set -u
viewer=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
cd "$out"
printf 'press 2\npress x\n' > bad_key.txt
printf 'frame 0\n' > bad_frames.txt
printf 'v 0 0 0\nf 1 2 3\n' > bad.obj
failed=0
# expect CODE "FIRST LINE PREFIX" ARGS...: the exit code and the start of stderr's first line.
expect() {
  code=$1 prefix=$2
  shift 2
  env -u DISPLAY SDL_VIDEODRIVER=none "$viewer" "$@" > stdout.txt 2> stderr.txt
  rc=$?
  first=$(head -n 1 stderr.txt)
  case "$first" in
    "$prefix"*) [ "$rc" -eq "$code" ] || { echo "FAIL: $*: exit $rc, expected $code"; failed=1; } ;;
    *) echo "FAIL: $*: stderr starts \"$first\", expected \"$prefix\""; failed=1 ;;
  esac
  [ -e never.png ] && { echo "FAIL: $*: wrote never.png"; failed=1; }
  return 0
}
expect 2 "viewer: bad_key.txt:2: unknown key \"x\"" --script bad_key.txt --screenshot never.png
expect 2 "viewer: bad_frames.txt:1: frame count \"0\"" --script bad_frames.txt
expect 2 "viewer: missing.txt: cannot read the script" --script missing.txt
expect 2 "viewer: unknown option --fast" --fast
expect 2 "viewer: --width expects a whole number in [16, 4096], not \"0\"" --width 0
expect 2 "viewer: --threads needs a value" --threads
expect 1 "viewer: bad.obj:2: " bad.obj --screenshot never.png
expect 1 "viewer: missing.obj" missing.obj --screenshot never.png
printf '{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {"POSITION": 7}}]}], "nodes": [{"mesh": 0}]}' > bad.gltf
expect 1 "viewer: bad.gltf: " bad.gltf --screenshot never.png
expect 1 "viewer: missing.glb: " missing.glb --screenshot never.png
[ "$failed" -eq 0 ] && echo "every bad input gave one error line and the right exit code"
exit "$failed"
