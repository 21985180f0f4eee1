#!/usr/bin/env bash
# Builds and runs the libFuzzer targets (clang, ASan+UBSan): one per fuzz/fuzz_NAME.c.
#
#   scripts/fuzz.sh [--short] [NAME...]
#     --short   each target for FUZZ_SHORT_SECONDS (default 25): what `make test` runs
#     default   each target for FUZZ_SECONDS (default 300): `make fuzz`
#     NAME...   only these targets (default: every fuzz/fuzz_*.c)
#
# Per target NAME, all optional:
#   fuzz/corpus/NAME/   seed inputs kept in the repository
#   fuzz/NAME.seeds     more seed directories, one per line, relative to the repository
#   fuzz/NAME.dict      a libFuzzer dictionary
#   fuzz/NAME.options   extra libFuzzer flags (such as -max_len=128)
# The inputs found while fuzzing go to FUZZ_BUILD/corpus/NAME, never into the repository.
# A crash, leak, timeout or broken contract fails the run, and its input is copied to
# tests/regress/NAME/, where a ctest (tests/cases/fuzz_regress.cmake) replays it from
# then on. A summary with the executions per target is written to FUZZ_BUILD/summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${FUZZ_SECONDS:-300}"
if [ "${1:-}" = "--short" ]; then
  seconds="${FUZZ_SHORT_SECONDS:-25}"
  shift
fi
build="${FUZZ_BUILD:-build-fuzz}"
jobs="${JOBS:-$(nproc 2>/dev/null || echo 2)}"

build_targets() {
  CC=clang cmake -S fuzz -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
  cmake --build "$build" -j"$jobs" >"$build/build.log" 2>&1 || { cat "$build/build.log"; exit 1; }
}

# Seed directories of a target that exist and hold at least one file.
seed_dirs() {
  local name="$1" dir
  local dirs=("fuzz/corpus/$name" "tests/regress/$name")
  if [ -f "fuzz/$name.seeds" ]; then
    while read -r dir; do
      [ -n "$dir" ] && [ "${dir#\#}" = "$dir" ] && dirs+=("$dir")
    done <"fuzz/$name.seeds"
  fi
  for dir in "${dirs[@]}"; do
    [ -d "$dir" ] && [ -n "$(find "$dir" -maxdepth 1 -type f ! -name '.*' -print -quit)" ] && echo "$dir"
  done
  return 0
}

# The regression input of target NAME with the same bytes as a file, if any.
known_regression() {
  local name="$1" file="$2" known
  for known in "tests/regress/$name"/*; do
    [ -f "$known" ] && cmp -s "$known" "$file" && { echo "$known"; return 0; }
  done
  return 0
}

# Copies the inputs libFuzzer saved for a failure into tests/regress/NAME/, unless one
# is already there (a known bug, still open, fails again on its own input).
keep_failures() {
  local name="$1" artifact known
  mkdir -p "tests/regress/$name"
  for artifact in "$build/artifacts/$name"/*; do
    [ -f "$artifact" ] || continue
    known=$(known_regression "$name" "$artifact")
    if [ -n "$known" ]; then
      echo "fuzz: $name: fails on $known, a known regression input (its bug is still open)"
    else
      cp "$artifact" "tests/regress/$name/"
      echo "fuzz: $name: kept $(basename "$artifact") as tests/regress/$name/$(basename "$artifact")"
    fi
  done
}

run_target() {
  local name="$1" status=0
  local log="$build/logs/$name.log"
  mkdir -p "$build/corpus/$name" "$build/artifacts/$name" "$build/logs"
  rm -f "$build/artifacts/$name"/*
  local flags=(-max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1
               -artifact_prefix="$build/artifacts/$name/")
  [ -f "fuzz/$name.dict" ] && flags+=(-dict="fuzz/$name.dict")
  # shellcheck disable=SC2207
  [ -f "fuzz/$name.options" ] && flags+=($(cat "fuzz/$name.options"))
  mapfile -t seeds < <(seed_dirs "$name")
  echo "fuzz: $name for ${seconds}s (seeds: ${seeds[*]:-none})"
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/fuzz_$name" "${flags[@]}" "$build/corpus/$name" "${seeds[@]}" >"$log" 2>&1 || status=$?
  local execs corpus
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  corpus=$(find "$build/corpus/$name" -type f | wc -l)
  printf '%-10s %6ss %12s execs %7s corpus files  %s\n' "$name" "$seconds" "${execs:-?}" "$corpus" \
    "$([ $status -eq 0 ] && echo ok || echo FAILED)" | tee -a "$build/summary.txt"
  if [ $status -ne 0 ]; then
    tail -40 "$log"
    keep_failures "$name"
  fi
  return $status
}

mkdir -p "$build"
build_targets
if [ $# -gt 0 ]; then
  names=("$@")
else
  names=()
  for src in fuzz/fuzz_*.c; do
    [ -e "$src" ] || continue
    src="${src#fuzz/fuzz_}"
    names+=("${src%.c}")
  done
fi
: >"$build/summary.txt"
failed=0
for name in "${names[@]}"; do
  run_target "$name" || failed=1
done
if [ $failed -ne 0 ]; then
  echo "fuzz: FAILED; the inputs are in tests/regress/ (replayed by ctest from now on)" >&2
  exit 1
fi
echo "fuzz: all ${#names[@]} targets passed"
