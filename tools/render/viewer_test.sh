#!/bin/sh
# The viewer test (tests/cases/viewer.cmake): runs 'kgyro view' under Xvfb with scripted
# input (a click that spawns a box, space to pause, a shift-click that spawns a circle),
# then checks its own report and the pixels of the screenshot it read back from its
# window. Exits 77 (skipped) when Xvfb is not installed.
# Usage: viewer_test.sh KGYRO PROBE SCENE OUTDIR
set -eu
kgyro=$1 probe=$2 scene=$3 out=$4

if ! command -v xvfb-run >/dev/null 2>&1 || ! command -v Xvfb >/dev/null 2>&1; then
  echo "SKIP: Xvfb is not installed (Debian: apt-get install xvfb)"
  exit 77
fi
mkdir -p "$out"
shot="$out/viewer.png"
log="$out/viewer.log"
rm -f "$shot" "$log"

# 480x360 pixels showing x in [-18, 10], y in [-2, 19]: 17.14 px/m, centre (-4, 8.5).
# The scene pauses after 4 steps, before anything has fallen a pixel.
xvfb-run -a -s "-screen 0 640x480x24" \
  "$kgyro" view "$scene" --backend cpu --size 480x360 --view -18,-2,10,19 --frames 12 \
  --script "wait 3; click 100 60; key space; shift-click 380 60; wait 2" \
  --screenshot "$shot" >"$log" 2>&1 || { cat "$log"; exit 1; }
cat "$log"
grep -q "12 frames" "$log"
grep -q "(2 added)" "$log"
grep -q "paused" "$log"

# at 248 317: the pyramid's bottom-left box, (-3.5, 0.5); at 240 345: the ground, y = -1;
# at 100 60 and 380 66: the spawned box and circle; at 20 200: empty space, (-16.8, 7.3);
# any text in the top rows: the statistics line.
"$probe" "$shot" size 480 360 \
  at 248 317 body \
  at 240 345 static \
  at 100 60 body \
  at 380 66 body \
  at 20 200 background \
  any 0 0 480 20 text
