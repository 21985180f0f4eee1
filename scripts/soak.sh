#!/usr/bin/env bash
# `make soak`: the soak program (tests/soak/soak.c) for SOAK_MINUTES (default 10), in two
# builds at once, one per core:
#   - release (build-soak): NaN, energy, handles and the growth of the resident set;
#   - clang with ASan+UBSan (build-soak-asan): the same checks, any sanitizer report,
#     and LeakSanitizer's leak check when the program exits (no RSS check there: the
#     ASan quarantine grows the RSS on its own).
# SOAK_VALGRIND_MINUTES > 0 adds a run of the release program under valgrind
# --leak-check=full for that long (default 0: LeakSanitizer already checks leaks).
# SOAK_SEED picks the random scenes (default 1). Logs: build-soak/soak-*.log.
set -euo pipefail
cd "$(dirname "$0")/.."

minutes="${SOAK_MINUTES:-10}"
valgrind_minutes="${SOAK_VALGRIND_MINUTES:-0}"
seed="${SOAK_SEED:-1}"
jobs="${JOBS:-$(nproc 2>/dev/null || echo 2)}"
seconds=$(awk -v m="$minutes" 'BEGIN { printf "%d", m * 60 }')
# The soak steps on the CPU backend only; tools, benchmarks and OpenCL are not needed.
common=(-DKGYRO_BUILD_TOOLS=OFF -DKGYRO_BUILD_BENCH=OFF -DKGYRO_OPENCL=OFF)

build() {
  local dir="$1"; shift
  cmake -S . -B "$dir" "${common[@]}" "$@" >/dev/null
  cmake --build "$dir" -j"$jobs" --target kg_soak >"$dir/soak-build.log" 2>&1 || { cat "$dir/soak-build.log"; exit 1; }
}

build build-soak -DCMAKE_BUILD_TYPE=Release
CC=clang build build-soak-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DKGYRO_SANITIZE=ON

echo "soak: ${minutes} min, release and ASan+UBSan+LSan side by side (seed $seed)"
build-soak/tests/kg_soak --seconds "$seconds" --seed "$seed" >build-soak/soak-release.log 2>&1 &
release_pid=$!
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  build-soak-asan/tests/kg_soak --seconds "$seconds" --seed "$seed" --no-memory-check \
  >build-soak/soak-asan.log 2>&1 &
asan_pid=$!
status=0
wait "$release_pid" || status=1
wait "$asan_pid" || status=1
for log in build-soak/soak-release.log build-soak/soak-asan.log; do
  echo "--- $log"
  tail -25 "$log"
done

if [ "$valgrind_minutes" != "0" ]; then
  vg_seconds=$(awk -v m="$valgrind_minutes" 'BEGIN { printf "%d", m * 60 }')
  echo "--- valgrind, ${valgrind_minutes} min"
  valgrind --leak-check=full --errors-for-leak-kinds=definite,indirect --error-exitcode=1 \
    build-soak/tests/kg_soak --seconds "$vg_seconds" --seed "$seed" --no-memory-check 2>&1 | tail -20 || status=1
fi

if [ $status -ne 0 ]; then
  echo "soak: FAILED" >&2
  exit 1
fi
echo "soak: passed"
