#!/bin/sh
# Texture synthesis measures (bench/synthesis.md): tentacle plate and igea exemplars onto a sphere, spot
# and cow. Usage: bench/synthesis.sh BUILD_DIR WORK_DIR (data from ../shared/data or $GEOTEX_DATA).
set -e
G=${1:-build}/geotex
W=${2:-/tmp/synthesis}
D=${GEOTEX_DATA:-$(dirname "$0")/../../shared/data}
mkdir -p "$W"
$G generate tentacle-plane --level 0 -o "$W/tp0.ply" --base-output "$W/tp0_base.ply"
$G texture extract "$W/tp0.ply" --base "$W/tp0_base.ply" -o "$W/tp0_tex.ply"
[ -f "$W/igea_tex.ply" ] || $G texture extract "$D/igea.ply" -o "$W/igea_tex.ply"
$G generate sphere -o "$W/sphere.ply"
run() {  # exemplar target share direction
  name=$(basename "$1" _tex.ply)_$(basename "$2" | sed 's/\..*//')
  /usr/bin/time -f "$name %U s user, %M KB" $G texture synthesize "$W/$1" --target "$2" -o "$W/$name.ply" \
    --exemplar-share "$3" --direction "$4" --report "$W/$name.json" 2>&1 | grep -v "^synthesize"
}
run tp0_tex.ply "$W/sphere.ply" 0.1 0,0,1
run tp0_tex.ply "$D/spot.obj" 0.1 0,1,0
run tp0_tex.ply "$D/cow.obj" 0.1 0,1,0
run igea_tex.ply "$W/sphere.ply" 0.2 0,0,1
run igea_tex.ply "$D/spot.obj" 0.2 0,1,0
run igea_tex.ply "$D/cow.obj" 0.2 0,1,0
