#!/usr/bin/env bash
# Set everything up and run the whole test suite: install packages, build, run CTest (and pytest
# for the Python module when it is built). Exits non-zero if anything fails.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
# Tests run in parallel, each with OpenMP threads: let idle threads sleep instead of spinning
# (spinning threads of one test steal the cores of the other; bench/README.md).
export OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-passive}
ctest --test-dir build --output-on-failure -j"$jobs"
