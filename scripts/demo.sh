#!/usr/bin/env bash
# Set everything up and run `geotex demo` on generated shapes. Usage: scripts/demo.sh [OUTPUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-geotex-demo}"
bash scripts/setup.sh
GEOTEX_TARGETS=geotex_cli bash scripts/build.sh
./build/geotex demo -o "$out"
