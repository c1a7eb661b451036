#!/usr/bin/env bash
# Configure and build geotex (Release) into build/. Usage: scripts/build.sh [extra cmake args]
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"$jobs"

# Make `/usr/bin/python3 -c "import geotex"` work: point Debian Python's site folder at build/python.
if [ -d build/python/geotex ]; then
  site=$(/usr/bin/python3 -c 'import site; print(site.getsitepackages()[0])' 2>/dev/null || true)
  if [ -n "$site" ] && { mkdir -p "$site" 2>/dev/null && [ -w "$site" ]; }; then
    echo "$(pwd)/build/python" > "$site/geotex-build.pth"
  else
    echo "build: to import geotex from Python: export PYTHONPATH=$(pwd)/build/python"
  fi
fi
