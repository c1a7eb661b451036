#!/usr/bin/env bash
# Train the default denoiser's learned reading (reading_model.h) and write its weights into
# src/denoise/reading_weights.inc: synthetic noise on data/spot.obj and generated shapes only (never the
# shared models), on the CPU (2 cores: a few minutes), deterministic for a given seed.
# Usage: scripts/train_reading.sh [--seed N] [--quick]   (then rebuild: bash scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/generator.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -G "$(generator build)" -DCMAKE_BUILD_TYPE=Release -DGEOTEX_BUILD_BENCH=ON >/dev/null
cmake --build build -j"$jobs" --target reading_bench
OMP_WAIT_POLICY=passive build/bench/reading_bench train "$@" --out src/denoise/reading_weights.inc
