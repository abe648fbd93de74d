#!/bin/sh
# The viewer's end-to-end test: replays session.txt in a real SDL window under Xvfb, then
# checks every screenshot against the library's image of the same state (e2e_check.cpp).
# usage: run_e2e.sh VIEWER E2E_CHECK SESSION OUT_DIR — exits 77 (skipped) without xvfb-run.
set -eu
viewer=$1 check=$2 session=$3 out=$4
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "xvfb-run not found (Debian package xvfb): test skipped"
  exit 77
fi
here=$(cd "$(dirname "$session")" && pwd)
rm -rf "$out"
mkdir -p "$out"
cd "$out"
# 24-bit screen: xvfb-run's default screen has 8 bits per pixel, which would change colours.
xvfb-run -a -s "-screen 0 640x480x24" "$viewer" "$here/tetrahedron.obj" --width 320 --height 180 --threads 1 \
  --script "$session" --screenshot final.png
"$check" "$out" "$here/tetrahedron.obj"
