#!/usr/bin/env bash
# Instruction counts of one kgyro step at steady state, under callgrind: deterministic
# figures to track the step's cost with, where the wall-clock times of `make bench`
# move by up to 2x on a shared machine. For large_pyramid (CPU backend, 1 thread, the
# engine's default sub-steps, sleeping off: exactly what `kgyro bench` times), prints
#
#   callgrind large_pyramid: step 278.9 M instructions, solve 247.0 M (steady state, 1 thread, steps 11..20)
#
# and writes out/bench/callgrind.csv (scene,steps,step_minstr,solve_minstr; steps is the
# range of steps averaged, e.g. 11-20). The step is kg_world_step's inclusive cost, the
# solve kg_stage_solve's. Building the world and the first steps (contacts forming)
# cost differently from a step at steady state, so the scene is run twice, for N and for
# 2N steps, and the figure is (cost over 2N steps - cost over N steps) / N: the mean of
# steps N+1..2N, everything before step N+1 (and after the last step) cancelling out.
# The two runs go in parallel; about 30 s of a 2-core machine at N = 10.
#
#   bash scripts/callgrind.sh [BUILD_DIR]
#   CALLGRIND_STEPS=40 bash scripts/callgrind.sh build   # another N
#
# The raw profiles stay in out/bench/callgrind/ (callgrind.out.STEPS.PID, one per process:
# `kgyro bench` runs the scene in a forked child); open one with
# `callgrind_annotate --inclusive=yes FILE` or kcachegrind.
set -euo pipefail
cd "$(dirname "$0")/.."

build=${1:-build}
kgyro="$build/kgyro"
scene=large_pyramid
n=${CALLGRIND_STEPS:-10}
out=out/bench
raw=$out/callgrind
if [ ! -x "$kgyro" ]; then
  echo "callgrind: $kgyro not found; build first (make build)" >&2
  exit 1
fi
if ! [[ "$n" =~ ^[1-9][0-9]*$ ]]; then
  echo "callgrind: CALLGRIND_STEPS must be a positive integer (got '$n')" >&2
  exit 2
fi
if ! command -v valgrind >/dev/null || ! command -v callgrind_annotate >/dev/null; then
  bash scripts/install-deps.sh bench
fi

rm -rf "$raw"
mkdir -p "$raw"

# One run of `steps` steps under callgrind; the bench's report and valgrind's log go to
# files. --timeout 0: no time limit (a step takes about half a second under callgrind).
profile() {
  local steps=$1
  valgrind --tool=callgrind --callgrind-out-file="$raw/callgrind.out.$steps.%p" \
    --log-file="$raw/valgrind.$steps.%p.log" \
    "$kgyro" bench "$scene:$steps" --engines kgyro --backend cpu --threads 1 --runs 1 --timeout 0 \
    >"$raw/bench.$steps.txt" 2>&1
}

# The inclusive instructions of function fn, summed over the processes of one run.
inclusive() {
  local steps=$1 fn=$2 total=0 file cost
  for file in "$raw"/callgrind.out."$steps".*; do
    cost=$(callgrind_annotate --inclusive=yes --threshold=100 --show-percs=no --auto=no "$file" |
      awk -v fn="$fn" '{ c = $1; gsub(",", "", c) }
        c ~ /^[0-9]+$/ && $2 ~ (":" fn "$") && c + 0 > best { best = c + 0 }
        END { printf "%.0f\n", best + 0 }')
    total=$((total + cost))
  done
  echo "$total"
}

profile "$n" & pid_n=$!
profile $((2 * n)) & pid_2n=$!
status=0
wait "$pid_n" || status=$?
wait "$pid_2n" || status=$?
if [ "$status" -ne 0 ]; then
  echo "callgrind: a run failed (exit $status); see $raw/bench.*.txt and $raw/valgrind.*.log" >&2
  tail -n 5 "$raw"/bench.*.txt >&2 || true
  exit 1
fi

declare -A cost
for fn in kg_world_step kg_stage_solve; do
  for steps in "$n" $((2 * n)); do
    cost[$fn.$steps]=$(inclusive "$steps" "$fn")
    if [ "${cost[$fn.$steps]}" -le 0 ]; then
      echo "callgrind: no cost for $fn in the run of $steps steps (renamed, inlined, or the binary stripped?)" >&2
      exit 1
    fi
  done
done

# Millions of instructions per step, one decimal.
per_step() { awk -v a="$1" -v b="$2" -v n="$n" 'BEGIN { printf "%.1f", (b - a) / n / 1e6 }'; }
step=$(per_step "${cost[kg_world_step.$n]}" "${cost[kg_world_step.$((2 * n))]}")
solve=$(per_step "${cost[kg_stage_solve.$n]}" "${cost[kg_stage_solve.$((2 * n))]}")

first=$((n + 1)); last=$((2 * n))
echo "scene,steps,step_minstr,solve_minstr" >"$out/callgrind.csv"
echo "$scene,$first-$last,$step,$solve" >>"$out/callgrind.csv"
echo "callgrind $scene: step $step M instructions, solve $solve M (steady state, 1 thread, steps $first..$last)"
