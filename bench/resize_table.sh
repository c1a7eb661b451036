#!/usr/bin/env bash
# The issue 25 table in one command: every shared model (and the generated tentacle stick) resized ×2 along
# x, y and z by each method given, measured by the independent ruler (ratio to the plain stretch, faces
# turned over against it, box error) and /usr/bin/time (CPU seconds = user + system of the whole CLI run).
#
# Usage: bench/resize_table.sh [-m "similarity axis-similarity"] [-M "cow igea …"] [-a "x y z"] [-o DIR]
#                              [-- extra geotex resize flags]
#   GEOTEX   the CLI (default build/geotex)    DATA  the shared models (default /work/shared/data)
# Prints one TSV row per run: model axis method ratio turned box_error cpu_s faces excess (faces crossed beyond
# the input's own, geval.py self-intersections --base; keeps the outputs
# in DIR, default /tmp/resize_table, as MODEL-AXIS-METHOD.ply for renders).
set -euo pipefail
cd "$(dirname "$0")/.."
GEOTEX=${GEOTEX:-$PWD/build/geotex}
DATA=${DATA:-/work/shared/data}
GEVAL=${GEVAL:-/work/shared/eval/geval.py}
methods="similarity axis-similarity"
models="beetle cheburashka cow fandisk igea spot stanford-bunny teapot woody tentacle-stick"
axes="x y z"
out=/tmp/resize_table
while [ $# -gt 0 ]; do
  case "$1" in
    -m) methods=$2; shift 2 ;;
    -M) models=$2; shift 2 ;;
    -a) axes=$2; shift 2 ;;
    -o) out=$2; shift 2 ;;
    --) shift; break ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
extra=("$@")
mkdir -p "$out"
printf 'model\taxis\tmethod\tratio\tturned\tbox_error\tcpu_s\tfaces\texcess\n'
for m in $models; do
  orig=$out/$m.ply
  if [ ! -f "$orig" ]; then  # the ruler needs the vertices exactly as geotex reads them
    if [ "$m" = tentacle-stick ]; then "$GEOTEX" -q generate tentacle-stick -o "$orig"
    else
      src=$(ls "$DATA/$m".* | head -1)
      "$GEOTEX" -q noise "$src" -o "$orig" --sigma 0
    fi
  fi
  for a in $axes; do
    case $a in x) s=2,1,1 ;; y) s=1,2,1 ;; z) s=1,1,2 ;; esac
    for meth in $methods; do
      res=$out/$m-$a-$meth.ply
      /usr/bin/time -o "$out/time" -f '%U %S' "$GEOTEX" -q resize "$orig" -o "$res" --scale $s --method "$meth" \
        "${extra[@]}" >/dev/null 2>"$out/stderr"
      cpu=$(awk '{printf "%.2f", $1 + $2}' "$out/time")
      excess=$(/usr/bin/python3 "$GEVAL" self-intersections "$res" --base "$orig" |
        /usr/bin/python3 -c 'import json, sys; print(json.load(sys.stdin)["excess_faces_hit"])')
      /usr/bin/python3 "$GEVAL" detail-distortion "$orig" "$res" $s | /usr/bin/python3 -c '
import json, sys
d = json.load(sys.stdin)
# the box error over the axes the model extends along (woody is flat in z: its ratio there is 0/0)
err = max((abs(b / s - 1) for b, s in zip(d["box"], d["asked"]) if b == b and b > 0), default=float("nan"))
r = d["ratio"]
print("\t".join([sys.argv[1], sys.argv[2], sys.argv[3], "%.3f" % r if r is not None else "-",
                 str(d["flipped_vs_plain"]), "%.0e" % err, sys.argv[4], str(d["faces"]), sys.argv[5]]))' "$m" "$a" "$meth" "$cpu" "$excess"
    done
  done
done
