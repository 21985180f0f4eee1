#!/usr/bin/env bash
# `make device-check`: the OpenCL backend on the machine's real device, in one command.
# Installs what is missing (from the .deb files in .debs/ when there is no network),
# makes the vendor's OpenCL library visible to the ICD loader, builds (Release), runs
# every OpenCL test, then benches rain_N and particles_N from 1,000 bodies up on the
# device and on the CPU. Writes to out/device-check/: log.txt, results.csv, table.md,
# scaling.png. Safe to run twice: each step does only what is still missing.
#
#   bash scripts/device-check.sh [BUILD_DIR]   the check (BUILD_DIR default: build)
#   bash scripts/device-check.sh --fetch-debs  fill .debs/ here, to carry to a machine offline
#
# Environment: DEVICE_CHECK_MAX (largest N; default 1000000 with 8 CPUs or more, else
# 100000), DEVICE_CHECK_BACKENDS (cpu,opencl), DEVICE_CHECK_STEPS (60),
# DEVICE_CHECK_TESTS (1; 0 skips the tests), DEVICE_CHECK_BUDGET (seconds a run may step before the
# larger sizes of its series are skipped; 10), DEVICE_CHECK_TIMEOUT (a run is killed
# after it; 90), JOBS (parallel build and test jobs; nproc).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
debs="$root/.debs"
out="$root/out/device-check"
# Only what the build and the run need beyond a compiler and CMake: the ICD loader
# (libOpenCL.so.1 is dlopen'ed at run time, never linked: no ocl-icd-opencl-dev), the
# C headers (CL/cl.h), cJSON for the command line, and pkg-config to find cJSON.
deb_packages="ocl-icd-libopencl1 opencl-c-headers libcjson1 libcjson-dev pkg-config pkgconf pkgconf-bin libpkgconf3"

fetch_debs() {
  mkdir -p "$debs"
  cd "$debs"
  # shellcheck disable=SC2086
  apt-get download $deb_packages
  ls -l "$debs"
}

# What the build and the run need, checked directly (not through dpkg: the device image
# may have them from elsewhere).
missing_deps() {
  local m=""
  ldconfig -p 2>/dev/null | grep -q 'libOpenCL\.so\.1 ' || m="$m libOpenCL.so.1"
  [ -f /usr/include/CL/cl.h ] || m="$m CL/cl.h"
  command -v pkg-config >/dev/null || m="$m pkg-config"
  pkg-config --exists libcjson 2>/dev/null || m="$m libcjson"
  echo "$m"
}

install_deps() {
  local missing debs_to_install=() f pkg
  missing=$(missing_deps)
  [ -z "$missing" ] && { echo "deps: all present"; return; }
  echo "deps: missing:$missing"
  # Offline first: the .debs carried in .debs/, those whose package is not installed.
  for f in "$debs"/*.deb; do
    [ -e "$f" ] || continue
    pkg=$(dpkg-deb -f "$f" Package)
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || debs_to_install+=("$f")
  done
  if [ ${#debs_to_install[@]} -gt 0 ]; then
    echo "deps: dpkg -i ${debs_to_install[*]##*/}"
    # A dependency the image satisfies differently leaves a package unconfigured but
    # unpacked, which is enough here: the checks below decide.
    dpkg -i "${debs_to_install[@]}" || echo "deps: dpkg reported problems; checking what is there"
    ldconfig
  fi
  missing=$(missing_deps)
  if [ -n "$missing" ] && command -v apt-get >/dev/null; then
    echo "deps: still missing:$missing; trying apt-get (needs network)"
    bash "$root/scripts/install-deps.sh" test
    missing=$(missing_deps)
  fi
  if [ -n "$missing" ]; then
    echo "deps: missing:$missing (run scripts/device-check.sh --fetch-debs on a machine with apt, carry .debs/)" >&2
    exit 1
  fi
}

# The ICD loader finds vendors through /etc/OpenCL/vendors/*.icd. A GPU machine whose
# driver is mounted into the image (NVIDIA's /usr/local/nvidia) may have the library but
# no .icd file: one naming it is written. (The H200 image lists PoCL's CPU device first
# and NVIDIA's second, through CUDA's own loader, which ignores OCL_ICD_VENDORS: the
# bench picks the GPU by its index, show_device below.)
find_nvidia_opencl() {
  local dir
  for dir in /usr/local/nvidia/lib64 /usr/local/nvidia/lib /usr/lib/x86_64-linux-gnu /usr/lib64; do
    [ -e "$dir/libnvidia-opencl.so.1" ] && { echo "$dir/libnvidia-opencl.so.1"; return; }
  done
  ldconfig -p 2>/dev/null | awk '/libnvidia-opencl\.so\.1 /{print $NF; exit}' | grep . ||
    find /usr /lib /opt -name 'libnvidia-opencl.so.1' 2>/dev/null | head -n 1
}

setup_icd() {
  local vendors=/etc/OpenCL/vendors lib
  lib=$(find_nvidia_opencl)
  if [ -n "$lib" ] && ! grep -qs nvidia "$vendors"/*.icd; then
    if [ -w /etc ] || [ -w "$vendors" ]; then
      mkdir -p "$vendors"
      echo "$lib" >"$vendors/nvidia.icd"
    else # not root: a private vendors folder, which ocl-icd takes from OCL_ICD_VENDORS
      vendors="$out/icd"
      mkdir -p "$vendors"
      echo "$lib" >"$vendors/nvidia.icd"
      export OCL_ICD_VENDORS="$vendors"
    fi
    # The library's own dependencies (libcuda, the PTX compiler) sit beside it.
    LD_LIBRARY_PATH="${lib%/*}${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
    export LD_LIBRARY_PATH
    echo "icd: wrote $vendors/nvidia.icd -> $lib"
  fi
  ls "$vendors"/*.icd >/dev/null 2>&1 && echo "icd:" "$vendors"/*.icd || echo "icd: no .icd file in $vendors" >&2
}

build() {
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  MAKEFLAGS='' cmake --build "$build" -j"$jobs" # MAKEFLAGS: no "Entering directory" noise from make
  [ -x "$build/kgyro" ] || { echo "build: $build/kgyro was not built" >&2; exit 1; }
}

# The device the tests and the bench use is OpenCL device 0 (the first `kgyro info` lists).
show_device() {
  local info
  info=$("$build/kgyro" info)
  echo "$info"
  case "$info" in *"device 0:"*) ;; *) echo "device-check: no OpenCL device found" >&2; exit 1 ;; esac
  gpu_device=$(echo "$info" | sed -n 's/^ *device \([0-9]*\): .*(GPU.*/\1/p' | head -n 1)
  if [ -n "$gpu_device" ]; then # the tests' OpenCL worlds and the bench on the GPU
    export KGYRO_OPENCL_DEVICE="$gpu_device"
    echo "device-check: OpenCL device $gpu_device, the first GPU listed (KGYRO_OPENCL_DEVICE)"
  fi
}

# DEVICE_CHECK_TESTS=0 skips the tests (a short lease: the bench alone).
run_tests_if_asked() {
  if [ "${DEVICE_CHECK_TESTS:-1}" = 0 ]; then
    echo "tests: skipped (DEVICE_CHECK_TESTS=0)"
  else
    run_tests
  fi
}

# Every test labelled opencl (tests/cases/opencl.cmake), on the GPU where there is one
# (KGYRO_OPENCL_DEVICE, show_device). They skip (exit 77) without a
# device, which ctest counts as passing: a skip fails the check here. A failure is
# reported at the end, after the bench has run: both are worth having from one lease.
run_tests() {
  (cd "$build" && ctest -L opencl --output-on-failure -j"$jobs") >"$out/ctest.txt" 2>&1 || tests_failed=1
  cat "$out/ctest.txt"
  if grep -q -E "Not Run|Skipped" "$out/ctest.txt"; then
    echo "device-check: an OpenCL test was skipped (no device?)" >&2
    tests_failed=1
  fi
}

run_bench() {
  local max=${DEVICE_CHECK_MAX:-} scenes=() n
  [ -n "$max" ] || { [ "$(nproc)" -ge 8 ] && max=1000000 || max=100000; }
  for family in rain particles; do
    for n in 1000 10000 100000 1000000; do
      [ "$n" -le "$max" ] && scenes+=("${family}_$n")
    done
  done
  # One run each, largest sizes cut by the budget: the whole check must stay under about
  # 9 minutes on a GPU machine. The bench exits non-zero when a row is not ok (a skipped
  # size): the table says which, so that does not stop the check. OpenCL runs on the
  # first GPU listed, else device 0.
  "$build/kgyro" bench "${scenes[@]}" --engines kgyro --backend "${DEVICE_CHECK_BACKENDS:-cpu,opencl}" \
    --device "${gpu_device:-0}" --runs 1 --steps "${DEVICE_CHECK_STEPS:-60}" --budget "${DEVICE_CHECK_BUDGET:-10}" \
    --timeout "${DEVICE_CHECK_TIMEOUT:-90}" --csv "$out/results.csv" --plot "$out" || true
  [ -s "$out/results.csv" ] || { echo "device-check: the bench wrote no results" >&2; exit 1; }
}

# results.csv -> table.md: one row per scene, CPU and OpenCL side by side.
write_table() {
  awk -F, 'NR > 1 {
      key = $1; if (!(key in seen)) { seen[key] = 1; order[++n] = key; bodies[key] = $4 }
      cell = ($22 == "ok") ? sprintf("%.2f (%.2f)", $11, $12) : $22
      if ($7 == "cpu") { cpu[key] = cell; cpu_ms[key] = $11; cpu_mb[key] = $15; ok_cpu[key] = $20 }
      else { cl[key] = cell; cl_ms[key] = $11; cl_mb[key] = $15; ok_cl[key] = $20 }
    }
    END {
      print "| scene | bodies | CPU ms (p95) | OpenCL ms (p95) | OpenCL / CPU | peak MB CPU / OpenCL | correct CPU / OpenCL |"
      print "|---|---|---|---|---|---|---|"
      for (i = 1; i <= n; ++i) {
        k = order[i]
        ratio = (cpu_ms[k] > 0 && cl_ms[k] > 0) ? sprintf("%.2f", cl_ms[k] / cpu_ms[k]) : "-"
        printf "| %s | %d | %s | %s | %s | %s / %s | %s / %s |\n", k, bodies[k], cpu[k], cl[k], ratio,
               cpu_mb[k] == "" ? "-" : cpu_mb[k], cl_mb[k] == "" ? "-" : cl_mb[k],
               ok_cpu[k] == "" ? "-" : ok_cpu[k], ok_cl[k] == "" ? "-" : ok_cl[k]
      }
    }' "$out/results.csv" >"$out/table.md"
}

# The bench draws scaling.png with gnuplot. A GPU image rarely has gnuplot (and its
# closure is too large to carry), but it has Python with matplotlib: draw it from there.
write_chart() {
  [ -s "$out/scaling.png" ] && return
  if python3 -c 'import matplotlib' 2>/dev/null; then
    python3 - "$out/results.csv" "$out/scaling.png" <<'EOF'
import csv, sys
import matplotlib; matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["status"] == "ok"]
for fam in sorted({r["family"] for r in rows}):
    for be in ("cpu", "opencl"):
        pts = sorted((int(r["bodies"]), float(r["median_ms"])) for r in rows if r["family"] == fam and r["backend"] == be)
        if pts:
            plt.plot(*zip(*pts), marker="o", label=f"{fam}_N {be}")
plt.xscale("log"); plt.yscale("log"); plt.xlabel("bodies"); plt.ylabel("median ms per step")
plt.grid(True, which="both", alpha=0.3); plt.legend(); plt.savefig(sys.argv[2], dpi=100)
EOF
    echo "chart: $out/scaling.png (matplotlib)"
  else
    echo "chart: no gnuplot and no matplotlib; draw it later with: gnuplot $out/scaling.gp"
  fi
}

main() {
  if [ "${1:-}" = "--fetch-debs" ]; then
    fetch_debs
    return
  fi
  build="${1:-build}"
  case "$build" in /*) ;; *) build="$root/$build" ;; esac
  jobs=${JOBS:-$(nproc)}
  tests_failed=0
  gpu_device=""
  mkdir -p "$out"
  rm -f "$out"/results*.csv "$out"/*.png "$out"/*.gp "$out"/table.md
  exec > >(tee "$out/log.txt") 2>&1
  local start=$SECONDS
  echo "device-check: $(date -u '+%Y-%m-%d %H:%M UTC'), $(uname -n), $(nproc) CPUs"
  install_deps
  setup_icd
  build
  show_device
  run_tests_if_asked
  run_bench
  write_table
  write_chart
  echo
  echo "device-check: done in $((SECONDS - start)) s; out/device-check/table.md:"
  cat "$out/table.md"
  if [ "$tests_failed" != 0 ]; then
    echo "device-check: an OpenCL test failed (out/device-check/ctest.txt)" >&2
    exit 1
  fi
}

main "$@"
