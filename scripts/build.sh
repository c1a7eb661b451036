#!/usr/bin/env bash
# Configure and build geotex (Release) into build/.
# Usage: scripts/build.sh [extra cmake args]; GEOTEX_TARGETS="geotex_cli" builds only those targets
# (the demo does: the CLI alone, not the tests).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/generator.sh
jobs=$(nproc 2>/dev/null || echo 2)
start=$(date +%s)
cmake -S . -B build -G "$(generator build)" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
targets=()
for t in ${GEOTEX_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build build -j"$jobs" "${targets[@]}"
echo "build: ${GEOTEX_TARGETS:-everything} in $(( $(date +%s) - start )) s"

# The Python module is in build/python (PYTHONPATH=build/python); to install it, see the README:
# `/usr/bin/python3 -m venv --system-site-packages venv && venv/bin/pip install --no-build-isolation .`
# (an older build wrote a .pth file into the system's site-packages; remove it)
site=$(/usr/bin/python3 -c 'import site; print(site.getsitepackages()[0])' 2>/dev/null || true)
if [ -n "$site" ] && [ -f "$site/geotex-build.pth" ]; then rm -f "$site/geotex-build.pth" 2>/dev/null || true; fi
