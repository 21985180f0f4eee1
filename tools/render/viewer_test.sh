#!/bin/sh
# The viewer test (tests/cases/viewer.cmake): runs 'kgyro view' under Xvfb with scripted
# input (a click that spawns a box, space to pause, a shift-click that spawns a circle),
# then checks its own report and the pixels of the screenshot it read back from its
# window; then switches a running scene to OpenCL and checks that every body came along;
# then shows the Tiled level samples/platformer.tmj with its tiles, and without after 't'.
# First checks that without a display it exits 1 with SDL's message. Exits 77 (skipped)
# after that check when Xvfb is not installed.
# Usage: viewer_test.sh KGYRO PROBE SCENE OUTDIR
set -eu
kgyro=$1 probe=$2 scene=$3 out=$4

# Under AddressSanitizer, leak checking is off for the viewer alone: SDL, X11 and D-Bus
# keep memory to the end of the process, some of it inside libraries already unloaded
# then, which no suppression can name. Every memory access is still checked.
if [ -n "${ASAN_OPTIONS:-}" ]; then
  export ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0"
fi
mkdir -p "$out"

# Without a display (and no SDL_VIDEODRIVER asking for a headless one) the viewer fails
# at once with SDL's reason and exit 1: it must neither hang nor run unseen.
code=0
env -u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER timeout 30 "$kgyro" view "$scene" \
  >"$out/no_display.log" 2>&1 || code=$?
if [ "$code" -ne 1 ] || ! grep -q "kgyro view: cannot open a window: .*not available" "$out/no_display.log"; then
  echo "without a display: exit $code (expected 1 and SDL's message):"
  cat "$out/no_display.log"
  exit 1
fi

if ! command -v Xvfb >/dev/null 2>&1; then
  echo "SKIP: Xvfb is not installed (Debian: apt-get install xvfb)"
  exit 77
fi
shot="$out/viewer.png"
log="$out/viewer.log"
rm -f "$shot" "$log" "$out/display"

# Xvfb on a free display: it picks the number and writes it to fd 3 (no xauth needed).
Xvfb -displayfd 3 -screen 0 640x480x24 -nolisten tcp 3>"$out/display" 2>"$out/xvfb.log" &
xvfb_pid=$!
trap 'kill "$xvfb_pid" 2>/dev/null' EXIT
for _ in $(seq 100); do
  [ -s "$out/display" ] && break
  sleep 0.1
done
if [ ! -s "$out/display" ]; then
  echo "Xvfb did not start:"
  cat "$out/xvfb.log"
  exit 1
fi
DISPLAY=":$(cat "$out/display")"
export DISPLAY

# 480x360 pixels showing x in [-16, 16], y in [-2, 22]: 15 px/m, pixel (240 + 15 x,
# 330 - 15 y). The scene pauses after 4 steps, before anything has moved a pixel.
"$kgyro" view "$scene" --backend cpu --size 480x360 --view -16,-2,16,22 --frames 12 \
  --script "wait 3; click 60 60; key space; shift-click 420 60; wait 2" \
  --screenshot "$shot" >"$log" 2>&1 || { cat "$log"; exit 1; }
cat "$log"
grep -q "12 frames" "$log"
grep -q "(2 added)" "$log"
grep -q "paused" "$log"
grep -q "video driver x11" "$log"

# at 187 322: the pyramid's bottom-left box, (-3.5, 0.5); at 240 345: the ground, y = -1;
# at 60 60 and 420 66: the spawned box and circle, at (-12, 18) and (12, 18);
# at 20 200: empty space, (-14.7, 8.7); any text in the top rows: the statistics line.
"$probe" "$shot" size 480 360 \
  at 187 322 body \
  at 240 345 static \
  at 60 60 body \
  at 420 66 body \
  at 20 200 background \
  any 0 0 480 20 text

# Switching backend while running: 'o' rebuilds the world on OpenCL with every body where
# it was, or stays on the CPU and says so when no OpenCL device works here (as
# 'kgyro render --backend opencl' finds out).
expected=CPU
if "$kgyro" render pyramid_2 --backend opencl --steps 1 --png "$out/opencl_probe.png" 2>/dev/null |
   grep -q "steps on OpenCL"; then
  expected=OpenCL
fi
scene_bodies=$(($(sed -n 's/.* \([0-9]*\) bodies (2 added).*/\1/p' "$log") - 2))
"$kgyro" view "$scene" --backend cpu --size 480x360 --view -16,-2,16,22 --frames 8 \
  --script "click 60 60; wait 2; key o; wait 2" --screenshot "$shot" >"$log" 2>&1 || { cat "$log"; exit 1; }
cat "$log"
grep -q "$((scene_bodies + 1)) bodies (1 added), $expected, running" "$log"
"$probe" "$shot" at 187 322 body at 60 60 body at 20 200 background

# Dragging: a box spawned at (-12, 18) is grabbed and held 2 m higher, at (-12, 20), by
# the mouse joint while 30 frames pass: it hangs there instead of falling to the ground
# (probed beside its centre, where the joint is drawn).
"$kgyro" view "$scene" --backend cpu --size 480x360 --view -16,-2,16,22 --frames 36 \
  --script "click 60 60; down 60 60; move 60 30; wait 30" --screenshot "$shot" >"$log" 2>&1 || { cat "$log"; exit 1; }
"$probe" "$shot" at 72 40 body at 60 320 background

# Tiles: 480x360 showing x in [0, 24], y in [0, 18], 20 px/m, pixel (20 x, 360 - 20 y);
# at 70 330 the ground tile (3, 1), at 176 316 the lower right of the slope tile (8, 2).
"$kgyro" view samples/platformer.tmj --backend cpu --size 480x360 --view 0,0,24,18 --frames 3 \
  --screenshot "$shot" >"$log" 2>&1 || { cat "$log"; exit 1; }
"$probe" "$shot" at 70 330 tile at 176 316 tile
"$kgyro" view samples/platformer.tmj --backend cpu --size 480x360 --view 0,0,24,18 --frames 3 \
  --script "key t" --screenshot "$shot" >"$log" 2>&1 || { cat "$log"; exit 1; }
"$probe" "$shot" at 70 330 background at 176 316 background
