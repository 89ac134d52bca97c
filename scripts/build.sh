#!/usr/bin/env bash
# Configure and build freestand into build/ (Release). Used by demo.sh and test.sh.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=$(nproc 2>/dev/null || echo 2)
mkdir -p "$root/build"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release > "$root/build/configure.log" 2>&1 \
  || { cat "$root/build/configure.log"; exit 1; }
cmake --build "$root/build" -j "$jobs"
