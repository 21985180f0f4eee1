#!/usr/bin/env bash
# make bench: the Box2D benchmark scenes and the scaling series (rain_N, particles_N) in
# kgyro (every backend that works here) and the peer engines, Box2D 2.4 and Chipmunk 7.
# Writes out/bench/results.csv, results_stages.csv, report.txt and the charts
# (scaling.png: step time vs bodies, log-log; scenes.png; stages.png), then the
# instruction counts of large_pyramid's step under callgrind (scripts/callgrind.sh:
# out/bench/callgrind.csv).
#
#   bash scripts/bench.sh [BUILD_DIR] [more `kgyro bench` options, e.g. --threads 2]
#   BENCH_QUICK=1 bash scripts/bench.sh build    # about a minute and a half: short runs, N <= 20,000
#
# The full run stays under about 15 minutes on a 2-core machine: one run per scene and
# engine (the median and 95th percentile are then over the run's steps), the benchmark
# scenes with their own step counts, and each scaling series growing N from 1,000
# towards 1,000,000 until a run of an engine steps longer than the budget; that engine
# then sits out the larger sizes of that series. BENCH_RUNS=3 takes more runs.
set -euo pipefail
cd "$(dirname "$0")/.."

build=${1:-build}
shift || true
kgyro="$build/kgyro"
out=out/bench
if [ ! -x "$kgyro" ]; then
  echo "bench: $kgyro not found; build first (make build)" >&2
  exit 1
fi

if [ "${BENCH_QUICK:-0}" = 1 ]; then
  scene_steps=":60"; runs=1; series_steps=30; budget=2; timeout=60
  sizes="1000 2000 5000 10000 20000"
else
  scene_steps=""; runs=${BENCH_RUNS:-1}; series_steps=60; budget=6; timeout=90
  sizes="1000 2000 5000 10000 20000 50000 100000 200000 500000 1000000"
fi

scenes=()
for scene in large_pyramid many_pyramids smash tumbler; do
  scenes+=("$scene$scene_steps")
done
for n in $sizes; do
  scenes+=("rain_$n:$series_steps" "particles_$n:$series_steps")
done

mkdir -p "$out"
rm -f "$out/results.csv"
status=0
"$kgyro" bench "${scenes[@]}" --engines kgyro,box2d,chipmunk --backend cpu,opencl --runs "$runs" \
  --budget "$budget" --timeout "$timeout" --profile --csv "$out/results.csv" --plot "$out" "$@" \
  | tee "$out/report.txt" || status=$?

# A run that failed or crashed is a result too (its row says so); only a bench that
# produced no table fails `make bench`.
if [ ! -s "$out/results.csv" ]; then
  echo "bench: no results (kgyro bench exited with $status)" >&2
  exit 1
fi
if [ "$status" -ne 0 ]; then
  echo "bench: some runs failed or crashed; see the status column of $out/results.csv" >&2
fi

# The step's instruction counts under callgrind (large_pyramid, 1 thread): deterministic,
# where the times above move with the machine's load. Same in BENCH_QUICK (about 30 s).
if ! bash scripts/callgrind.sh "$build" | tee -a "$out/report.txt"; then
  echo "bench: scripts/callgrind.sh failed; see out/bench/callgrind/" >&2
  exit 1
fi
echo "bench: $out/results.csv, $out/callgrind.csv, $out/report.txt and the charts in $out"
