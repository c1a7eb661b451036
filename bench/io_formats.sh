#!/usr/bin/env bash
# Reading and writing times of each mesh format at 1.3 M faces, and `info` on a file that keeps growing.
# Usage: bench/io_formats.sh [GEOTEX] [OLD_GEOTEX]   (results in bench/io.md)
set -euo pipefail
g=${1:-build/geotex}
old=${2:-}
d=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$d"' EXIT
for f in ply obj off stl glb gltf; do
  echo "generate sphere --level 5 -o w.$f: $( { /usr/bin/time -f '%e s wall, %M KiB peak' $g -q generate sphere --level 5 -o "$d/w.$f"; } 2>&1 | tail -1)"
done
gzip -k "$d/w.ply"
for f in ply ply.gz obj off stl glb gltf; do
  echo "$f: $(stat -c %s "$d/w.$f") bytes; $( { /usr/bin/time -f '%e s wall, %M KiB peak' $g -q info "$d/w.$f" >/dev/null; } 2>&1 | tail -1)"
done
echo "pipe generate | noise | info: $( { /usr/bin/time -f '%e s wall' bash -c "$g -q generate sphere --level 5 -o - | $g -q noise - -o - --sigma 0.3 | $g -q info - >/dev/null"; } 2>&1 | tail -1)"
# A growing OBJ: an appender adds vertex lines as fast as it can while info reads.
$g -q generate sphere --level 3 -o "$d/grow.obj"
head -c 16777216 < <(yes "v 1 2 3") > "$d/chunk" || true
for bin in "$g" $old; do
  cp "$d/grow.obj" "$d/g.obj"
  ( while :; do cat "$d/chunk" >> "$d/g.obj"; s=$(stat -c %s "$d/g.obj"); [ "$s" -lt 4000000000 ] || break; done ) &
  app=$!
  start=$(date +%s.%N)
  if timeout 60 $bin -q info "$d/g.obj" > "$d/info.txt" 2>&1; then r=ok; else r="exit $?"; fi
  end=$(date +%s.%N)
  kill $app 2>/dev/null || true; wait $app 2>/dev/null || true
  echo "growing OBJ, $bin: $r in $(echo "$end - $start" | bc) s; $(grep -m1 vertices "$d/info.txt" || head -c 200 "$d/info.txt")"
done
