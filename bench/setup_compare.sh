#!/usr/bin/env bash
# Install the other tools the comparison benchmark (bench/capabilities.sh --compare) runs against:
# CGAL (header-only, smooth_shape + Surface_mesh_parameterization), MeshLab 2020.09 (meshlabserver)
# and xvfb (meshlabserver needs an X display even for batch filters).
# Not part of scripts/setup.sh: CI does not build or run the comparison.
# Usage: bench/setup_compare.sh   (needs root or sudo; idempotent)
set -euo pipefail

packages=(libcgal-dev libgmp-dev libmpfr-dev libboost-dev meshlab xvfb xauth)

source "$(dirname "$0")/../scripts/apt_ensure.sh"
apt_ensure setup_compare "${packages[@]}"
echo "setup_compare: done"
