#!/usr/bin/env bash
# The showcase: runs the sample scenes headless and says where the output went.
set -euo pipefail
build="${1:-build}"
mkdir -p out
"$build/kgyro" run samples/pyramid.json --csv out/pyramid.csv --every 10
