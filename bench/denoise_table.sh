#!/bin/bash
# Every denoiser on the shared noisy/clean pairs, side by side with the six published peers, in one session
# (bench/denoise.md). Prints TSV rows: pair, method, mean normal error (deg), Ev (of the bbox diagonal),
# label precision, recall (methods that label), CPU s of the whole process (user + sys), wall s.
#   bench/denoise_table.sh [BUILD [PEERS_BIN [PAIRS...]]]
# BUILD: a geotex build with -DGEOTEX_BUILD_BENCH=ON (default build); PEERS_BIN: gd_denoise from
# ../shared/peers/build.sh (default /tmp/geotex-peers/gd_denoise; peers are skipped when absent).
set -uo pipefail
BUILD=${1:-build}
GD=${2:-/tmp/geotex-peers/gd_denoise}
shift 2 2>/dev/null
PAIRS=${*:-Fandisk0.3 Block0.4 Twelve0.5Impulsive Bunny0.2}
DATA=${GEOTEX_DATA:-$(dirname "$0")/../../shared/data}/denoise
OUT=${OUT:-/tmp/denoise_table}
mkdir -p "$OUT"
G=$BUILD/geotex
B=$BUILD/bench/denoise_bench
export OMP_WAIT_POLICY=passive

row() {  # row PAIR NAME RESULT [LABELS]; $OUT/time holds "user sys wall"
  local pair=$1 name=$2 result=$3 labels=${4:-}
  local score
  score=$($B score "$result" "$DATA/$pair/Original.obj" $labels 2>/dev/null) || score="failed"
  read -r u s w < "$OUT/time"
  echo -e "$pair\t$name\t$score\t$(awk -v u="$u" -v s="$s" 'BEGIN {printf "%.2f", u + s}')\t$w"
}

for pair in $PAIRS; do
  in=$DATA/$pair/Noisy.obj
  echo "0 0 0" > "$OUT/time"; row "$pair" "noisy input" "$in"
  # geotex: the default (auto) and each method at its defaults and its thesis preset.
  for spec in "auto" "surfel" "surfel@thesis" "mrf" "mrf@thesis" "mrf-normal" "mrf-normal@thesis"; do
    m=${spec%@*}; preset=; [ "$spec" != "$m" ] && preset="--preset ${spec#*@}"
    res=$OUT/$pair.$spec.ply; lab=$OUT/$pair.$spec.labels.ply
    /usr/bin/time -f "%U %S %e" -o "$OUT/time" $B run $m "$in" --out "$res" --edges "$lab" $preset >/dev/null 2>&1 || { echo -e "$pair\t$spec\tfailed"; continue; }
    # Labels on a dual mesh (surfel thesis preset) do not compare with the truth's edges.
    if [ "$spec" = "surfel@thesis" ]; then row "$pair" "geotex $spec" "$res"; else row "$pair" "geotex $spec" "$res" "$lab"; fi
  done
  if [ -x "$GD" ]; then
    for m in BMD NIFP FE BNF L0 GMNF; do
      res=$OUT/$pair.$m.obj
      /usr/bin/time -f "%U %S %e" -o "$OUT/time" timeout 900 "$GD" $m "$in" "$res" >/dev/null 2>&1 || { echo -e "$pair\t$m\tfailed"; continue; }
      row "$pair" "$m" "$res"
    done
  fi
done
