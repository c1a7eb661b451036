#!/bin/sh
# Issue 27: tentacle and spike exemplars onto every shared model and the generated ones (sphere, torus, a thin
# cylinder) with defaults only (no share,
# no scale; only the direction field's guide). Usage: bench/synthesis_defaults.sh BUILD_DIR WORK_DIR
# [TARGET...] (data from ../shared/data or $GEOTEX_DATA). Prints per run: CPU, the report's counts, and
# geval.py's self-intersections (the external ruler) against the refined base. $SYNTH_ARGS is added to
# each synthesize (e.g. SYNTH_ARGS="--avoid-crossings false --drop-collisions false": the placement before
# collisions were avoided). Then bench/inward_faces.py: the relief's faces turned against the base, on the meshes
# alone (and the radial test on every face), and the same for each exemplar.
set -e
G=${1:-build}/geotex
W=${2:-/tmp/synthesis_defaults}
shift 2 || true
D=${GEOTEX_DATA:-$(dirname "$0")/../../shared/data}
E=${GEVAL:-$(dirname "$0")/../../shared/eval/geval.py}
mkdir -p "$W"
$G -q generate tentacle-plane --level 0 -o "$W/tp.ply" --base-output "$W/tp_base.ply"
$G -q texture extract "$W/tp.ply" --base "$W/tp_base.ply" -o "$W/tp_tex.ply"
$G -q generate spiky-plane --level 0 -o "$W/sp.ply" --base-output "$W/sp_base.ply"
$G -q texture extract "$W/sp.ply" --base "$W/sp_base.ply" -o "$W/sp_tex.ply"
$G -q generate sphere -o "$W/sphere.ply"
$G -q generate torus -o "$W/torus.ply"
# A thin cylinder: the generated one (radius 0.5, height 1, along z) narrowed to radius 0.1 (as in
# Synthesis.NoSelfIntersectionOnAThinCylinder).
$G -q --format obj generate cylinder -o - | awk '$1 == "v" { print "v", 0.2 * $2, 0.2 * $3, $4; next } { print }' \
  > "$W/thin-cylinder.obj"
for e in tp sp; do  # the exemplars' own faces turned against their base (the same measure as inward_share)
  echo "$e exemplar: $(GEVAL="$E" /usr/bin/python3 "$(dirname "$0")/inward_faces.py" "$W/$e.ply" "$W/${e}_base.ply")"
done
run() {  # exemplar target
  name=$(basename "$1" _tex.ply)_$(basename "$2" | sed 's/\..*//')
  /usr/bin/time -f "$name cpu %U s user %S s sys" $G texture synthesize "$W/$1" --target "$2" -o "$W/$name.ply" \
    --texture-out "$W/${name}_t.ply" --report "$W/$name.json" $SYNTH_ARGS 2>&1 | grep -E "estimate|cpu|error"
  /usr/bin/python3 -c "import json,sys; r=json.load(open(sys.argv[1])); print(' '.join(f'{k}={r[k]}' for k in
    ['vertices','added_vertices','estimated_vertices','exemplar_share','self_intersecting','base_self_intersecting',
     'excess_self_intersecting','shrunk_share','retried_placements','dropped_patches','dropped_vertices','repaired_vertices','filled_patches','bare_share',
     'refined_share','kept_out_share','kept_out_creases','kept_out_thin','kept_out_pits','kept_out_domes','inward_share',
     'exemplar_inward_share','folded','seconds']))" "$W/$name.json"
  /usr/bin/python3 "$E" self-intersections "$W/$name.ply" --base "$W/${name}_t.ply"  # the texture file holds the refined base
  GEVAL="$E" /usr/bin/python3 "$(dirname "$0")/inward_faces.py" "$W/$name.ply" "$W/${name}_t.ply" --radial
}
for t in ${@:-$W/sphere.ply $W/torus.ply $W/thin-cylinder.obj $D/spot.obj $D/cow.obj $D/stanford-bunny.obj \
    $D/fandisk.obj $D/cheburashka.obj $D/igea.ply $D/beetle.obj $D/teapot.obj $D/woody.obj}; do
  run tp_tex.ply "$t"
  run sp_tex.ply "$t"
done
