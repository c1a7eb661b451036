#!/usr/bin/env bash
# Install the Debian packages geotex needs to build, test and run (idempotent: skips what is present).
# Usage: scripts/setup.sh            (needs root or sudo; safe to run again)
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git ccache
  libopenmesh-dev libeigen3-dev libsuitesparse-dev libspectra-dev libnanoflann-dev
  libcli11-dev libfmt-dev nlohmann-json3-dev libpng-dev zlib1g-dev libtinygltf-dev
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  libopenblas0-pthread libopenblas-dev
  pybind11-dev python3-dev python3-numpy python3-scipy python3-pytest python3-distributed
  python3-pip python3-venv python3-setuptools python3-wheel python3-mypy
  clang libclang-rt-14-dev
)

source "$(dirname "$0")/apt_ensure.sh"
apt_ensure setup "${packages[@]}"

# CHOLMOD's supernodal factorization calls BLAS; the reference BLAS is ~50x slower. Report which is active.
blas=$(update-alternatives --query libblas.so.3-x86_64-linux-gnu 2>/dev/null | awk '/^Value:/{print $2}')
echo "setup: BLAS in use: ${blas:-unknown}"

# The web viewer (node, npm packages, chromium for its test). Not fatal: without it `geotex view`
# says the bundle is missing and the browser test skips.
bash "$(dirname "$0")/setup_viewer.sh" || echo "setup: WARNING: viewer setup failed; geotex view and its browser test are unavailable"
