#!/usr/bin/env bash
# Install the other tools the comparison benchmark (bench/capabilities.sh --compare) runs against:
# CGAL (header-only, smooth_shape + Surface_mesh_parameterization), MeshLab 2020.09 (meshlabserver)
# and xvfb (meshlabserver needs an X display even for batch filters).
# Not part of scripts/setup.sh: CI does not build or run the comparison.
# Usage: bench/setup_compare.sh   (needs root or sudo; idempotent)
set -euo pipefail

packages=(libcgal-dev libgmp-dev libmpfr-dev libboost-dev meshlab xvfb xauth)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup_compare: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "setup_compare: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup_compare: done"
