#!/usr/bin/env bash
# Installs the Debian packages KineticGyro needs, only those missing.
# Idempotent: a machine that has everything runs no apt command at all.
# Usage: scripts/install-deps.sh [core|test|demo|bench|all]
set -euo pipefail

core="cmake make gcc clang pkg-config libcjson-dev zlib1g-dev"
test_extra="ocl-icd-opencl-dev opencl-headers pocl-opencl-icd libclang-rt-14-dev libstb-dev xvfb libsdl2-dev"
bench_extra="libbox2d-dev libchipmunk-dev gnuplot-nox g++"
# Only `make bench` needs valgrind (scripts/callgrind.sh: the step's instruction counts).
bench_only="valgrind"

case "${1:-all}" in
  core)  wanted="$core" ;;
  test)  wanted="$core $test_extra $bench_extra" ;;
  demo)  wanted="$core $test_extra" ;;
  bench) wanted="$core $test_extra $bench_extra $bench_only" ;;
  all)   wanted="$core $test_extra $bench_extra $bench_only" ;;
  *) echo "usage: $0 [core|test|demo|bench|all]" >&2; exit 2 ;;
esac

missing=""
for pkg in $wanted; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing="$missing $pkg"
done
[ -z "$missing" ] && exit 0

echo "kgyro: installing missing Debian packages:$missing"
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; else SUDO=; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# shellcheck disable=SC2086
$SUDO apt-get install -y -qq --no-install-recommends $missing >/dev/null
