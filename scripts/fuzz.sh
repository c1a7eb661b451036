#!/usr/bin/env bash
# Fuzz every geotex reader with libFuzzer (clang, AddressSanitizer + UndefinedBehaviorSanitizer) for a
# bounded time. Usage: scripts/fuzz.sh [SECONDS_PER_TARGET=60] [TARGET ...]
# Targets: the mesh readers Obj Ply Off Stl and the PLY data parser PlyData (fuzz/fuzz_read.cpp); the
# user-file readers Handles Numbers PlyExtras Texture (fuzz/fuzz_files.cpp: deform handles, feature /
# field / point text files, PLY extras read by resize, surfels, compare --labels and view, texture files).
# Seeds: files written by the geotex CLI (build/geotex, built if missing, or $GEOTEX_CLI) plus hand-written handles.
# A crash leaves its input in build-fuzz/crashes/; copy it to tests/fuzz_regressions/ with the prefix of
# its reader (see tests/fuzz_regressions_test.cpp: the test replays every file through every reader).
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(Obj Ply Off Stl PlyData Handles Numbers PlyExtras Texture)
out=build-fuzz
mkdir -p "$out/crashes"
command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (apt-get install clang libclang-rt-14-dev)"; exit 1; }
geotex="${GEOTEX_CLI:-./build/geotex}"  # the CLI that writes the seeds
[ -x "$geotex" ] || bash scripts/build.sh >/dev/null

# ---- Seed corpus (every reader gets files the CLI wrote) ----
seeds="$out/seeds"
mkdir -p "$seeds"
for fmt in obj ply off stl; do
  mkdir -p "$seeds/$fmt"
  $geotex -q generate cube --level 0 -o "$seeds/$fmt/cube.$fmt"
  $geotex -q generate sphere --level 0 -o "$seeds/$fmt/sphere.$fmt"
  [ "$fmt" = ply ] || [ "$fmt" = stl ] && $geotex -q noise "$seeds/$fmt/cube.$fmt" -o "$seeds/$fmt/cube-ascii.$fmt" --ascii
done
mkdir -p "$seeds/plydata" "$seeds/plyextras" "$seeds/texture" "$seeds/numbers" "$seeds/handles"
$geotex -q denoise "$seeds/ply/cube.ply" -o "$seeds/plydata/d.ply" --edges "$seeds/plydata/edges.ply" --ascii 2>/dev/null || true
cp "$seeds/ply/"*.ply "$seeds/plydata/"
# Texture files (vertex 'height', edge 'tilt'): texture apply/edit/transfer, resize --features, view layers.
$geotex -q texture extract "$seeds/ply/cube.ply" -o "$seeds/texture/cube-texture.ply"
$geotex -q generate spiky-plane --level 0 -o "$seeds/spiky.ply"
$geotex -q texture extract "$seeds/spiky.ply" -o "$seeds/texture/spiky-texture.ply"
# Oriented points (surfels output: x y z nx ny nz) and point text files (surfels input).
grep '^v ' "$seeds/obj/cube.obj" | cut -c3- > "$seeds/numbers/cube.xyz"
$geotex -q surfels "$seeds/numbers/cube.xyz" -o "$seeds/plyextras/surfels.ply" --iterations 2 --ascii
cp "$seeds/texture/"*.ply "$seeds/plydata/edges.ply" "$seeds/ply/cube-ascii.ply" "$seeds/plyextras/"
cp "$seeds/obj/cube.obj" "$seeds/numbers/"
# Feature weights and field files for the 152 vertices of the level-0 cube.
awk 'BEGIN { print "# feature weights"; for (i = 0; i < 152; ++i) print (i % 7 == 0) ? 1 : 0 }' > "$seeds/numbers/features.txt"
awk 'BEGIN { for (i = 0; i < 152; ++i) printf "%g%s", i / 151.0, (i % 8 == 7) ? "\n" : ", " }' > "$seeds/numbers/field.txt"
# Deformation handles (the format of geotex::parse_handles), for the same cube.
cat > "$seeds/handles/vertices.json" <<'EOF'
{"handles": [{"vertices": [0, 10], "targets": [[-0.5, -0.5, 0], [0.5, -0.5, 0.2]]}, {"vertices": [120], "weight": 2}]}
EOF
cat > "$seeds/handles/regions.json" <<'EOF'
{"handles": [{"box": {"min": [-1, -1, -1], "max": [-0.4, 1, 1]}},
             {"sphere": {"center": [0.5, 0, 0], "radius": 0.3}, "translate": [0, 0, 0.3], "scale": 1.5,
              "center": [0.5, 0, 0], "rotate": {"axis": [0, 1, 0], "angle_deg": 30, "center": [0.5, 0, 0]}}]}
EOF

# ---- Build: the library once (only what changed), then one binary per target ----
cxx="clang++ -std=c++20 -O1 -g -fno-omit-frame-pointer -Iinclude -I/usr/include/eigen3 -D_USE_MATH_DEFINES -Wno-unknown-pragmas"
san="address,undefined -fno-sanitize-recover=undefined"
objs="$out/objs"
mkdir -p "$objs"
# An object is stale when its source or any header it included (its -MMD file) is newer.
stale_object() {
  local o=$1 src=$2 dep
  [ -f "$o" ] && [ -f "$o.d" ] && [ ! "$src" -nt "$o" ] || return 0
  for dep in $(sed -e 's/^[^:]*://' -e 's/\\$//' "$o.d"); do [ "$dep" -nt "$o" ] && return 0; done
  return 1
}
# Sources no fuzz target links are skipped (a shorter build); a link error names any that become needed.
skip=" render resources surfel surfel_points surfel_retrieval mrf mrf_normal noise metrics "
stale=()
libobjs=()
for src in src/*/*.cpp; do
  b=$(basename "$src" .cpp)
  [[ "$skip" == *" $b "* ]] && continue
  libobjs+=("$objs/$b.o")
  if stale_object "$objs/$b.o" "$src"; then stale+=("$src"); fi
done
if [ ${#stale[@]} -gt 0 ]; then
  echo "fuzz: compiling ${#stale[@]} library sources with clang (sanitizers, fuzzer coverage)"
  # Tried twice: clang reads sources through mmap, and a source edited during its compile kills it (SIGBUS).
  # The object gets the compile's start time, so that a header edited during the compile makes it stale.
  o="$objs/\$(basename {} .cpp).o"
  compile="$cxx -fsanitize=fuzzer-no-link,$san -MMD -MF $o.d -c {} -o $o"
  printf '%s\n' "${stale[@]}" | xargs -P"$(nproc 2>/dev/null || echo 2)" -I{} sh -c \
    "t=\$(date +%s); { $compile || $compile; } && touch -d @\$t $o"
  rm -f "$out/libgeotex_fuzz.a"
fi
[ -f "$out/libgeotex_fuzz.a" ] || ar rcs "$out/libgeotex_fuzz.a" "${libobjs[@]}"

status=0
for target in "${targets[@]}"; do
  lower=$(echo "$target" | tr 'A-Z' 'a-z')
  case "$target" in
    Obj|Ply|Off|Stl) src=fuzz/fuzz_read.cpp; def="-DGEOTEX_FUZZ_FORMAT=$target"; seed="$seeds/$lower" ;;
    PlyData) src=fuzz/fuzz_read.cpp; def="-DGEOTEX_FUZZ_PLYDATA"; seed="$seeds/plydata" ;;
    Handles|Numbers|PlyExtras|Texture) src=fuzz/fuzz_files.cpp; def="-DGEOTEX_FUZZ_FILE_$target=1"; seed="$seeds/$lower" ;;
    *) echo "fuzz: unknown target $target"; exit 2 ;;
  esac
  $cxx -fsanitize=fuzzer,$san $def "$src" "$out/libgeotex_fuzz.a" -lOpenMeshCore -lfmt -o "$out/fuzz_$lower"
  corpus="$out/corpus_$lower"
  mkdir -p "$corpus"
  echo "fuzz: $target for ${secs}s"
  if ! ASAN_OPTIONS=detect_leaks=1 "$out/fuzz_$lower" "$corpus" "$seed" -max_total_time="$secs" \
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
