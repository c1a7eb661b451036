#!/usr/bin/env bash
# Time and peak memory of every geotex capability at ~10^4, 10^5 and 10^6 faces, and (with COMPARE=1)
# the closest operation of other tools from Debian packages, run back to back with geotex on the same
# input files. Prints markdown tables (wall s, user+sys CPU s, peak RSS MB) on stdout; raw figures go
# to $WORK/runs.tsv. Figures and their reading: bench/capabilities.md. Each comparison runs geotex with
# its default threads (OpenMP, all cores) and with --threads 1, since the other tools run on one core.
#
# Usage: bench/capabilities.sh                       (geotex capabilities only)
#        COMPARE=1 bench/capabilities.sh             (+ OpenMesh, CGAL, MeshLab; run
#                                                     bench/setup_compare.sh first)
# Environment:
#   GEOTEX   geotex binary                (default: build/geotex)
#   WORK     scratch folder for inputs and outputs (default: /tmp/geotex-capabilities)
#   SIZES    any of 1e4 1e5 1e6           (default: "1e4 1e5 1e6")
#   COMPARE  1 = also run the other tools (binaries built by bench/compare/build.sh into
#            $WORK/compare-bin; meshlabserver under xvfb-run)
#   TIMEOUT  seconds before a single command is stopped and recorded as "timeout" (default 1800)
#   REPEAT   runs of each command; the table keeps the one with the least CPU time (default 1)
#   DATA     denoising pairs for the quality rows (default: ../shared/data/denoise next to the repo)
#   QUALITY  0 = skip those quality rows (default 1)
#   ONLY     bash regex: run only the commands whose label matches (re-measure a pair; the tables keep
#            the last run of each label)
# Inputs (`geotex generate`; the cube also through `geotex noise --sigma 0.3 --seed 1`):
#   1e4: cube level 3 (19,200 faces), spiky-plane level 2 (12,800), spiky-sphere level 2 (20,480)
#   1e5: cube level 4 (76,800),       spiky-plane level 3 (51,200), spiky-sphere level 3 (81,920)
#   1e6: cube level 6 (1,228,800),    spiky-plane level 5 (819,200), spiky-sphere level 5 (1,310,720)
set -uo pipefail

repo=$(cd "$(dirname "$0")/.." && pwd)
GEOTEX=${GEOTEX:-$repo/build/geotex}
WORK=${WORK:-/tmp/geotex-capabilities}
SIZES=${SIZES:-"1e4 1e5 1e6"}
COMPARE=${COMPARE:-0}
TIMEOUT=${TIMEOUT:-1800}
REPEAT=${REPEAT:-1}
DATA=${DATA:-$repo/../shared/data/denoise}
mkdir -p "$WORK"
tsv=$WORK/runs.tsv
[ -f "$tsv" ] || printf 'size\tgroup\tlabel\tfaces\twall_s\tcpu_s\trss_mb\tstatus\tload\tnote\n' >"$tsv"

[ -x "$GEOTEX" ] || { echo "capabilities: no geotex binary at $GEOTEX (set GEOTEX)" >&2; exit 1; }
if [ "$COMPARE" = 1 ]; then
  bin=$WORK/compare-bin
  bash "$repo/bench/compare/build.sh" "$bin" >&2 || { echo "capabilities: building bench/compare failed" >&2; exit 1; }
  command -v meshlabserver >/dev/null && command -v xvfb-run >/dev/null ||
    { echo "capabilities: meshlabserver/xvfb-run missing: run bench/setup_compare.sh" >&2; exit 1; }
fi

load1() { cut -d' ' -f1 /proc/loadavg; }
faces_of() { "$GEOTEX" info "$1" | awk '/^faces/{print $2}'; }

# run SIZE GROUP LABEL FACES CMD...: time one command, append a row to runs.tsv, echo a progress line.
run() {
  local size=$1 group=$2 label=$3 faces=$4; shift 4
  if [ -n "${ONLY:-}" ] && ! [[ "$label" =~ $ONLY ]]; then return; fi
  local tf=$WORK/time.txt log=$WORK/last.log status=ok load rc i best="" bwall bk wall cpu rss note u s k
  load=$(load1)
  # REPEAT runs; keep the one with the least CPU time (the load of others only adds to it)
  for ((i = 0; i < REPEAT; i++)); do
    /usr/bin/time -f "%e %U %S %M" -o "$tf" timeout "$TIMEOUT" "$@" >"$log" 2>&1
    rc=$?
    read -r wall u s k < <(tail -1 "$tf")
    cpu=$(awk -v u="$u" -v s="$s" 'BEGIN{printf "%.2f", u+s}')
    if [ -z "$best" ] || awk -v a="$cpu" -v b="$best" 'BEGIN{exit !(a < b)}'; then
      best=$cpu; bwall=$wall; bk=$k; cp "$log" "$log.best"
    fi
    [ $rc -eq 0 ] || break
  done
  [ $rc -eq 124 ] && status="timeout>${TIMEOUT}s"
  [ $rc -ne 0 ] && [ $rc -ne 124 ] && status="exit$rc"
  cpu=$best; wall=$bwall; k=$bk; log=$log.best
  rss=$(awk -v k="$k" 'BEGIN{printf "%.0f", k/1024}')
  # the other tools' own timing line, or geotex param's distortion (--json)
  note=$( (grep -E '^read ' "$log" | head -1; grep -E '"(flipped|mean_angle_error_deg)"' "$log" | tr -d ' ",' |
          tr '\n' ' ') | tr '\t\n' '  ')
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$size" "$group" "$label" "$faces" "$wall" "$cpu" "$rss" \
    "$status" "$load" "$note" >>"$tsv"
  printf '[%s] %-4s %-44s %9s faces  wall %7ss  cpu %7ss  %6s MB  %s (load %s)\n' "$(date +%H:%M:%S)" "$size" \
    "$label" "$faces" "$wall" "$cpu" "$rss" "$status" "$load" >&2
  [ "$status" = ok ] || tail -3 "$log" >&2
}

# quality SIZE GROUP LABEL RESULT TRUTH: `geotex compare` figures (not timed) as a row with status "quality".
quality() {
  local size=$1 group=$2 label=$3 result=$4 truth=$5 q
  if [ -n "${ONLY:-}" ] && ! [[ "$label" =~ $ONLY ]]; then return; fi
  if [ ! -s "$result" ]; then return; fi
  q=$("$GEOTEX" compare "$result" "$truth" 2>&1 | awk '/^mean normal error/{e=$4} /^Ev/{v=$2} END{printf "%s deg, Ev %s", e, v}')
  printf '%s\t%s\t%s\t\t\t\t\tquality\t%s\t%s\n' "$size" "$group" "$label" "$(load1)" "$q" >>"$tsv"
  echo "    quality $label: $q" >&2
}

levels() {  # size -> "cube spiky-plane spiky-sphere" levels
  case $1 in 1e4) echo "3 2 2" ;; 1e5) echo "4 3 3" ;; 1e6) echo "6 5 5" ;; *) return 1 ;; esac
}

for size in $SIZES; do
  read -r lc lp ls < <(levels "$size") || { echo "capabilities: unknown size $size" >&2; exit 1; }
  d=$WORK/$size
  mkdir -p "$d"
  # ---- inputs -------------------------------------------------------------------------------------
  [ -s "$d/cube.ply" ] || "$GEOTEX" -q generate cube --level "$lc" -o "$d/cube.ply"
  [ -s "$d/cube-noisy.ply" ] || "$GEOTEX" -q noise "$d/cube.ply" -o "$d/cube-noisy.ply" --sigma 0.3 --seed 1
  [ -s "$d/spiky-plane.ply" ] || "$GEOTEX" -q generate spiky-plane --level "$lp" -o "$d/spiky-plane.ply"
  [ -s "$d/spiky-sphere.ply" ] ||
    "$GEOTEX" -q generate spiky-sphere --level "$ls" -o "$d/spiky-sphere.ply" --base-output "$d/sphere-base.ply"
  fc=$(faces_of "$d/cube-noisy.ply"); fp=$(faces_of "$d/spiky-plane.ply"); fs=$(faces_of "$d/spiky-sphere.ply")
  echo "== $size: cube $fc, spiky-plane $fp, spiky-sphere $fs faces; $(uptime)" >&2
  G=("$GEOTEX" -q)
  o=$d/out
  mkdir -p "$o"

  # ---- geotex capabilities (each followed by its comparison, back to back) -------------------------
  run "$size" cap "info (read PLY, topology report)" "$fc" "${G[@]}" info "$d/cube-noisy.ply"
  run "$size" cap "noise (read + noise + write PLY)" "$fc" "${G[@]}" noise "$d/cube.ply" -o "$o/noisy2.ply"

  run "$size" cap "smooth (1 implicit cotan step)" "$fc" "${G[@]}" smooth "$d/cube-noisy.ply" -o "$o/smooth.ply"
  if [ "$COMPARE" = 1 ]; then
    run "$size" smooth-cgal "geotex smooth, barycentric mass, rescale" "$fc" "${G[@]}" smooth "$d/cube-noisy.ply" \
      -o "$o/smooth-bary.ply" --mass barycentric --rescale
    run "$size" smooth-cgal "geotex smooth, barycentric mass, rescale (1 thread)" "$fc" "$GEOTEX" -q --threads 1 \
      smooth "$d/cube-noisy.ply" -o "$o/smooth-bary1.ply" --mass barycentric --rescale
    run "$size" smooth-cgal "CGAL smooth_shape (BiCGSTAB+ILUT, default)" "$fc" \
      "$bin/cgal_smooth_shape" "$d/cube-noisy.ply" "$o/cgal-smooth.ply" 1 1 bicgstab
    run "$size" smooth-cgal "CGAL smooth_shape (CHOLMOD)" "$fc" \
      "$bin/cgal_smooth_shape" "$d/cube-noisy.ply" "$o/cgal-smooth-cholmod.ply" 1 1 cholmod
    quality "$size" smooth-cgal "CGAL (BiCGSTAB) vs geotex result" "$o/cgal-smooth.ply" "$o/smooth-bary.ply"
    quality "$size" smooth-cgal "CGAL (CHOLMOD) vs geotex result" "$o/cgal-smooth-cholmod.ply" "$o/smooth-bary.ply"
    run "$size" smooth-openmesh "geotex smooth, explicit umbrella, 0.5, 10 steps" "$fc" "${G[@]}" smooth \
      "$d/cube-noisy.ply" -o "$o/smooth-umbrella.ply" --laplacian umbrella --explicit --lambda 0.5 --steps 10
    run "$size" smooth-openmesh "geotex smooth, explicit umbrella, 0.5, 10 steps (1 thread)" "$fc" "$GEOTEX" -q \
      --threads 1 smooth "$d/cube-noisy.ply" -o "$o/smooth-umbrella1.ply" --laplacian umbrella --explicit \
      --lambda 0.5 --steps 10
    run "$size" smooth-openmesh "OpenMesh JacobiLaplaceSmootherT, 10 iterations" "$fc" \
      "$bin/openmesh_smooth" "$d/cube-noisy.ply" "$o/openmesh-smooth.ply" 10
    quality "$size" smooth-openmesh "OpenMesh vs geotex result" "$o/openmesh-smooth.ply" "$o/smooth-umbrella.ply"
  fi

  run "$size" cap "denoise mrf (defaults)" "$fc" "${G[@]}" denoise "$d/cube-noisy.ply" -o "$o/mrf.ply" --method mrf
  if [ "$COMPARE" = 1 ]; then
    run "$size" denoise-meshlab "denoise mrf (defaults) (1 thread)" "$fc" "$GEOTEX" -q --threads 1 denoise \
      "$d/cube-noisy.ply" -o "$o/mrf1.ply" --method mrf
    run "$size" denoise-meshlab "MeshLab TwoStep Smooth (defaults 3/60/20/20)" "$fc" \
      xvfb-run -a meshlabserver -i "$d/cube-noisy.ply" -o "$o/meshlab.ply" -s "$repo/bench/compare/meshlab_twostep.mlx"
    quality "$size" denoise-meshlab "geotex mrf vs clean cube" "$o/mrf.ply" "$d/cube.ply"
    quality "$size" denoise-meshlab "MeshLab TwoStep vs clean cube" "$o/meshlab.ply" "$d/cube.ply"
  fi
  run "$size" cap "denoise surfel (15 iterations)" "$fc" "${G[@]}" denoise "$d/cube-noisy.ply" -o "$o/surfel.ply" \
    --method surfel --iterations 15

  run "$size" cap "texture extract (given base)" "$fs" "${G[@]}" texture extract "$d/spiky-sphere.ply" \
    --base "$d/sphere-base.ply" -o "$o/texture.ply"
  run "$size" cap "texture apply" "$fs" "${G[@]}" texture apply "$o/texture.ply" -o "$o/textured.ply"

  run "$size" cap "resize --scale 2,1,1 (auto features, sliding)" "$fp" "${G[@]}" resize "$d/spiky-plane.ply" \
    -o "$o/resized.ply" --scale 2,1,1

  run "$size" cap "param (conformal, disk)" "$fp" "${G[@]}" param "$d/spiky-plane.ply" -o "$o/param.obj" --json
  if [ "$COMPARE" = 1 ]; then
    run "$size" param-cgal "param (conformal, disk) (1 thread)" "$fp" "$GEOTEX" -q --threads 1 param \
      "$d/spiky-plane.ply" -o "$o/param1.obj" --json
    run "$size" param-cgal "CGAL Discrete_conformal_map (BiCGSTAB+ILUT)" "$fp" \
      "$bin/cgal_param" "$d/spiky-plane.ply" "$o/cgal-dcm.obj" dcm
    run "$size" param-natural "geotex param --method natural" "$fp" "${G[@]}" param "$d/spiky-plane.ply" \
      -o "$o/param-natural.obj" --method natural --json
    run "$size" param-natural "geotex param --method natural (1 thread)" "$fp" "$GEOTEX" -q --threads 1 param \
      "$d/spiky-plane.ply" -o "$o/param-natural1.obj" --method natural --json
    run "$size" param-natural "CGAL LSCM (SimplicialLDLT)" "$fp" \
      "$bin/cgal_param" "$d/spiky-plane.ply" "$o/cgal-lscm.obj" lscm
  fi
done

# ---- quality of the denoisers on the real denoising pairs (not timed against size) -----------------
if [ "$COMPARE" = 1 ] && [ -d "$DATA" ] && [ "${QUALITY:-1}" = 1 ]; then
  for name in Fandisk0.3 Block0.4 Twelve0.5Impulsive; do
    [ -f "$DATA/$name/Noisy.obj" ] || continue
    o=$WORK/data/$name
    mkdir -p "$o"
    f=$(faces_of "$DATA/$name/Noisy.obj")
    # MeshLab 2020.09's OBJ importer aborts on these files (assertion in import_obj.h): both tools read
    # the same binary PLY copy (0 smoothing steps = a plain conversion, vertex order kept).
    "$GEOTEX" -q smooth "$DATA/$name/Noisy.obj" -o "$o/noisy.ply" --steps 0
    run data "denoise-$name" "geotex denoise mrf" "$f" "$GEOTEX" -q denoise "$o/noisy.ply" -o "$o/mrf.ply"
    run data "denoise-$name" "geotex denoise mrf (1 thread)" "$f" "$GEOTEX" -q --threads 1 denoise "$o/noisy.ply" \
      -o "$o/mrf1.ply"
    run data "denoise-$name" "MeshLab TwoStep Smooth (defaults)" "$f" xvfb-run -a meshlabserver \
      -i "$o/noisy.ply" -o "$o/meshlab.ply" -s "$repo/bench/compare/meshlab_twostep.mlx"
    quality data "denoise-$name" "geotex mrf" "$o/mrf.ply" "$DATA/$name/Original.obj"
    quality data "denoise-$name" "MeshLab TwoStep" "$o/meshlab.ply" "$DATA/$name/Original.obj"
    quality data "denoise-$name" "noisy input" "$DATA/$name/Noisy.obj" "$DATA/$name/Original.obj"
  done
fi

# ---- tables -------------------------------------------------------------------------------------------
/usr/bin/python3 "$repo/bench/compare/tables.py" "$tsv" 2>/dev/null || awk -F'\t' 'NR>1' "$tsv"
