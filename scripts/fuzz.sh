#!/usr/bin/env bash
# Fuzz every geotex reader with libFuzzer (clang, AddressSanitizer + UndefinedBehaviorSanitizer) for a
# bounded time. Usage: scripts/fuzz.sh [SECONDS_PER_TARGET=60] [TARGET ...]
# Targets: the mesh readers Obj Ply Off Stl, the PLY data parser PlyData and the read-write-read
# property RoundTrip (fuzz/fuzz_read.cpp); the
# user-file readers Handles Numbers PlyExtras Texture (fuzz/fuzz_files.cpp: deform handles, feature /
# field / point text files, PLY extras read by resize, surfels, compare --labels and view, texture files).
# Seeds: files written by the geotex CLI (build/geotex, built if missing, or $GEOTEX_CLI), hand-written
# handles, and the text quirks of issue 14 made from them (BOM, CRLF, lone CR, PLY properties declared
# twice, fractional / huge / NaN indices and list counts). fuzz/mesh.dict gives every target the words.
# A crash leaves its input in build-fuzz/crashes/; copy it to tests/fuzz_regressions/ with the prefix of
# its reader (see tests/cli/fuzz_regressions_test.cpp: the test replays every file through every reader).
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-60}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(Obj Ply Off Stl PlyData RoundTrip Handles Numbers PlyExtras Texture)
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

# ---- Seeds with the text quirks of issue 14 (the readers must take the encodings, refuse the rest) ----
quirks() {  # quirks DIR: a BOM, CRLF and lone-CR copy of every text file in DIR
  local f base
  for f in "$1"/*; do
    [ -f "$f" ] || continue
    base=$(basename "$f")
    case "$base" in bom-*|crlf-*|cr-*) continue ;; esac
    head -c 5 "$f" | grep -q -e '^ply' -e '^OFF' -e '^solid' -e '^v ' -e '^#' -e '^{' -e '^[-0-9]' || continue
    LC_ALL=C grep -q -P '[^\x09\x0A\x0D\x20-\x7E]' "$f" && case "$base" in *.ply) ;; *) continue ;; esac
    { printf '\xEF\xBB\xBF'; cat "$f"; } > "$1/bom-$base"
    sed 's/$/\r/' "$f" > "$1/crlf-$base"
    tr '\n' '\r' < "$f" > "$1/cr-$base"
  done
}
for d in obj off ply stl plydata plyextras numbers handles texture; do quirks "$seeds/$d"; done
# PLY declarations and indices that must be refused (duplicates, fractions, huge, NaN, bad counts).
ply_head='ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n'
ply_rows='0 0 0\n1 0 0\n0 1 0\n0 0 1\n'
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 9 0 0\n1 9 0 0\n0 9 1 0\n3 0 1 2\n' > "$seeds/ply/x-twice.ply"
printf "${ply_head}element vertex 1\nproperty double x\nproperty double y\nproperty double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n${ply_rows}0 0 0\n3 0 1 2\n" > "$seeds/ply/element-twice.ply"
for idx in 2.5 1e300 nan -3e9 inf; do
  printf "${ply_head}element face 1\nproperty list uchar double vertex_indices\nend_header\n${ply_rows}3 0 1 $idx\n" > "$seeds/ply/index-$idx.ply"
done
printf "${ply_head}element face 1\nproperty list uchar int vertex_indices\nend_header\n${ply_rows}3 0 1.5 2\n" > "$seeds/ply/int-field-fraction.ply"
printf "${ply_head}element face 1\nproperty list uchar int vertex_indices\nend_header\n${ply_rows}2.5 0 1 2\n" > "$seeds/ply/count-fraction.ply"
printf "${ply_head}element face 1\nproperty list uchar int vertex_indices\nend_header\n${ply_rows}300 0 1 2\n" > "$seeds/ply/count-over-uchar.ply"
printf "${ply_head}element tristrips 1\nproperty list int double vertex_indices\nend_header\n${ply_rows}5 0 1 2 -1 1e300\n" > "$seeds/ply/strip-huge.ply"
# Binary: a float list count of 2.5 and a double index of 2.5 (little endian), and a lone-CR header.
python3 - "$seeds/ply" <<'PY'
import struct, sys
d = sys.argv[1]
head = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\nelement face 1\n"
verts = struct.pack("<12d", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
open(d + "/bin-count-fraction.ply", "wb").write(head + b"property list float int vertex_indices\nend_header\n" + verts + struct.pack("<f3i", 2.5, 0, 1, 2))
open(d + "/bin-index-fraction.ply", "wb").write(head + b"property list uchar double vertex_indices\nend_header\n" + verts + struct.pack("<B3d", 3, 0, 1, 2.5))
x0 = struct.unpack("<d", b"\x0a" + b"\x00" * 6 + b"\x3f")[0]  # the body starts with 0x0A
body = struct.pack("<12d", x0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1) + struct.pack("<B3i", 3, 0, 1, 2)
open(d + "/bin-cr-header.ply", "wb").write(head.replace(b"\n", b"\r") + b"property list uchar int vertex_indices\rend_header\r" + body)
PY
cp "$seeds/ply/"*.ply "$seeds/plydata/" 2>/dev/null || true
# RoundTrip: the first byte picks the reader (0 obj, 1 ply, 2 off, 3 stl), the rest is the file.
mkdir -p "$seeds/roundtrip"
i=0
for fmt in obj ply off stl; do
  for f in "$seeds/$fmt"/*; do
    { printf "\\$(printf %03o $i)"; cat "$f"; } > "$seeds/roundtrip/$fmt-$(basename "$f")"
  done
  i=$((i + 1))
done

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
skip=" resources surfel surfel_points surfel_retrieval mrf mrf_normal noise metrics "
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
    RoundTrip) src=fuzz/fuzz_read.cpp; def="-DGEOTEX_FUZZ_ROUNDTRIP"; seed="$seeds/roundtrip" ;;
    Handles|Numbers|PlyExtras|Texture) src=fuzz/fuzz_files.cpp; def="-DGEOTEX_FUZZ_FILE_$target=1"; seed="$seeds/$lower" ;;
    *) echo "fuzz: unknown target $target"; exit 2 ;;
  esac
  $cxx -fsanitize=fuzzer,$san $def "$src" "$out/libgeotex_fuzz.a" -lOpenMeshCore -lfmt -lpng -lz -o "$out/fuzz_$lower"
  corpus="$out/corpus_$lower"
  mkdir -p "$corpus"
  echo "fuzz: $target for ${secs}s"
  if ! ASAN_OPTIONS=detect_leaks=1 "$out/fuzz_$lower" "$corpus" "$seed" -max_total_time="$secs" -dict=fuzz/mesh.dict \
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
