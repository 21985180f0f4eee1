#!/usr/bin/env bash
# The showcase, run headless by `make demo` after the build: renders each demo scene to
# out/NAME.gif (animated) and out/NAME.png (last frame), times the steps on the CPU and,
# when `kgyro info` reports an OpenCL device, on OpenCL too, and prints a table.
# Usage: scripts/demo.sh [BUILD_DIR]   (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
kgyro="$build/kgyro"
out=out

if [ ! -x "$kgyro" ]; then
  echo "demo: $kgyro not found; build first (make demo does)" >&2
  exit 1
fi

# NAME|SCENE|render options. Each view is fixed so that the whole motion stays in frame.
scenes=(
  "demo_pyramid|samples/demo_pyramid.json|--view -15,-1.5,25,28.5 --every 3"
  "demo_rain|samples/demo_rain.json|--view -20,-1.5,20,28.5 --every 4"
  "demo_chain|samples/chain_terrain.json|--view -22,-1,22,12 --size 800x240 --steps 300 --every 2"
  "demo_bridge|samples/joint_bridge.json|--view -16,-1,16,13 --size 640x320 --steps 360 --every 3"
  "demo_ragdoll|samples/joint_ragdoll.json|--view -8,-0.5,10,8.5 --size 640x320 --every 2"
  "demo_windmill|samples/joint_windmill.json|--view -13,-1,13,17 --size 520x480 --steps 480 --every 3"
  "demo_car|samples/joint_car.json|--view -10,-1,50,11 --size 900x200 --steps 780 --every 4"
)
# The tile-map platform level (the Tiled level samples/platformer.tmj with slopes, one-way
# platforms, bodies, particles and a wind applicator), wide to fit the level.
if [ -f samples/demo_platformer.json ]; then
  scenes+=("demo_platformer|samples/demo_platformer.json|--view -1,-0.5,49,24.5 --size 800x400 --every 3")
fi

# The mean step time that kgyro render printed, or "-" when it did not run there.
mean_ms() { sed -n 's/.*step time: mean \([0-9.]*\) ms.*/\1/p' <<<"$1"; }

has_opencl_device() {
  local info
  info=$("$kgyro" info 2>/dev/null) || return 1
  grep -qi "device" <<<"$info" && ! grep -qiE "no (opencl )?devices?|(^|[^0-9])0 devices|devices?: *0([^0-9]|$)" <<<"$info"
}

opencl=no
if has_opencl_device; then
  opencl=yes
fi

mkdir -p "$out"
rows=()
start=$SECONDS
for entry in "${scenes[@]}"; do
  IFS='|' read -r name scene options <<<"$entry"
  echo "demo: rendering $name ($scene)"
  # shellcheck disable=SC2086
  report=$("$kgyro" render "$scene" --backend cpu --gif "$out/$name.gif" --png "$out/$name.png" $options)
  bodies=$(sed -n 's/.*, \([0-9]*\) bodies, .*/\1/p' <<<"$report")
  steps=$(sed -n 's/.* bodies, \([0-9]*\) steps .*/\1/p' <<<"$report")
  cpu=$(mean_ms "$report")
  cl="-"
  if [ "$opencl" = yes ]; then
    # shellcheck disable=SC2086
    report=$("$kgyro" render "$scene" --backend opencl --png "$out/$name-opencl.png" $options)
    if grep -q "steps on OpenCL" <<<"$report"; then
      cl=$(mean_ms "$report")
    else
      cl="fell back"
    fi
  fi
  rows+=("$(printf '%-16s %7s %6s %14s %14s' "$name" "$bodies" "$steps" "$cpu" "$cl")")
done

echo
echo "Step times (mean wall-clock ms per step; OpenCL only where kgyro info reports a device):"
printf '%-16s %7s %6s %14s %14s\n' scene bodies steps "CPU ms/step" "OpenCL ms/step"
printf '%s\n' "${rows[@]}"
# A game's loop over the same level: a player that runs and jumps by ray and shape casts,
# hears its landings as hit events and finds the goal through a sensor (samples/platformer_player.c).
if [ -x "$build/platformer_player" ]; then
  echo
  echo "demo: samples/platformer_player.c, a player in samples/platformer.tmj"
  "$build/platformer_player" samples/platformer.tmj | tail -n 4
fi
echo
echo "demo: done in $((SECONDS - start)) s. Pictures:"
for entry in "${scenes[@]}"; do
  name=${entry%%|*}
  echo "  $out/$name.gif  (animation)    $out/$name.png  (last frame)"
done
echo "Play with a scene: $kgyro view samples/demo_pyramid.json"
