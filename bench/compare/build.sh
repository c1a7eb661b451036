#!/usr/bin/env bash
# Build the comparison programs (OpenMesh smoother, CGAL smooth_shape, CGAL parametrization) with g++.
# Not part of the main CMake build: CGAL is only needed here (bench/setup_compare.sh installs it).
# Usage: bench/compare/build.sh [OUTDIR]   (default OUTDIR: /tmp/geotex-compare-bin)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
out=${1:-/tmp/geotex-compare-bin}
mkdir -p "$out"
CXX=${CXX:-g++}
flags=(-std=c++17 -O3 -DNDEBUG -DCGAL_EIGEN3_ENABLED -I/usr/include/eigen3 -I/usr/include/suitesparse -w)
build() {  # name libs...
  local name=$1; shift
  if [ "$out/$name" -nt "$here/$name.cpp" ]; then return; fi
  echo "build: $name"
  $CXX "${flags[@]}" "$here/$name.cpp" -o "$out/$name" "$@"
}
build openmesh_smooth -lOpenMeshCore -lOpenMeshTools &
build cgal_param -lgmp -lmpfr &
wait
build cgal_smooth_shape -lcholmod -lgmp -lmpfr
echo "build: binaries in $out"
