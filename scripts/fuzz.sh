#!/usr/bin/env bash
# Fuzz every geotex reader with libFuzzer (clang, AddressSanitizer + UndefinedBehaviorSanitizer) for a
# bounded time. Usage: scripts/fuzz.sh [SECONDS_PER_TARGET=60]
# Seeds: meshes written by the geotex CLI (build it first: scripts/build.sh). A crash leaves its input
# in build-fuzz/crashes/; copy it to tests/fuzz_regressions/ (the fuzz_regressions test reads them all).
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-60}"
out=build-fuzz
mkdir -p "$out/crashes"
command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (apt-get install clang libclang-rt-14-dev)"; exit 1; }
[ -x build/geotex ] || bash scripts/build.sh >/dev/null

# Seed corpus: generated shapes in every format.
seeds="$out/seeds"
mkdir -p "$seeds"
for fmt in obj ply off stl; do
  mkdir -p "$seeds/$fmt"
  ./build/geotex -q generate cube --level 0 -o "$seeds/$fmt/cube.$fmt"
  ./build/geotex -q generate sphere --level 0 -o "$seeds/$fmt/sphere.$fmt"
  [ "$fmt" = ply ] || [ "$fmt" = stl ] && ./build/geotex -q noise "$seeds/$fmt/cube.$fmt" -o "$seeds/$fmt/cube-ascii.$fmt" --ascii
done
./build/geotex -q generate cube --level 0 -o "$seeds/cube-labels-src.ply"
mkdir -p "$seeds/plydata"
./build/geotex -q denoise "$seeds/cube-labels-src.ply" -o "$seeds/plydata/d.ply" --edges "$seeds/plydata/edges.ply" --ascii 2>/dev/null || true
cp "$seeds/ply/"*.ply "$seeds/plydata/"

flags="-std=c++20 -O1 -g -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -Iinclude -I/usr/include/eigen3 -D_USE_MATH_DEFINES"
objs="$out/objs"
mkdir -p "$objs"
for src in src/io.cpp src/mesh.cpp; do
  clang++ ${flags/-fsanitize=fuzzer,/-fsanitize=fuzzer-no-link,} -c "$src" -o "$objs/$(basename "$src" .cpp).o"
done
status=0
for target in Obj Ply Off Stl PlyData; do
  lower=$(echo "$target" | tr 'A-Z' 'a-z')
  def="-DGEOTEX_FUZZ_FORMAT=$target"
  [ "$target" = PlyData ] && def="-DGEOTEX_FUZZ_PLYDATA"
  clang++ $flags $def fuzz/fuzz_read.cpp "$objs"/*.o -lOpenMeshCore -lfmt -o "$out/fuzz_$lower"
  corpus="$out/corpus_$lower"
  mkdir -p "$corpus"
  echo "fuzz: $target for ${secs}s"
  if ! ASAN_OPTIONS=detect_leaks=1 "$out/fuzz_$lower" "$corpus" "$seeds/$lower" -max_total_time="$secs" \
       -max_len=65536 -rss_limit_mb=2048 -timeout=10 -artifact_prefix="$out/crashes/$lower-" -print_final_stats=1 \
       > "$out/fuzz_$lower.log" 2>&1; then
    echo "fuzz: $target FOUND A CRASH: see $out/fuzz_$lower.log and $out/crashes/"
    status=1
  fi
  grep -E "stat::number_of_executed_units|stat::new_units_added" "$out/fuzz_$lower.log" | tr '\n' ' '
  echo
done
[ $status -eq 0 ] && echo "fuzz: no crash in any target (${secs}s each)"
exit $status
