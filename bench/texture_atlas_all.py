#!/usr/bin/env python3
"""Issue 26: damage of atlases (folded and self-intersecting faces, against the bare target's own) over every
shared model, through the CLI's --report, with defaults (overlap cut, unfold on). Source: the tentacle plate
(level 0); target radius 0.05 x the model's bounding-box diagonal; each run capped at CAP seconds of wall time.
Run: PYTHONPATH=build/python /usr/bin/python3 bench/texture_atlas_all.py build/geotex /work/shared/data OUTDIR [CAP]
Independent count: /usr/bin/python3 /work/shared/eval/geval.py self-intersections OUTDIR/NAME-atlas.ply
--base OUTDIR/NAME-texture.ply (the texture file's vertices are the refined bare target)."""
import json, os, resource, subprocess, sys, time

import numpy as np

geotex, data, out = sys.argv[1], sys.argv[2], sys.argv[3]
cap = float(sys.argv[4]) if len(sys.argv) > 4 else 600
os.makedirs(out, exist_ok=True)


def run(*args, timeout=None):
    r = subprocess.run([geotex, *args], capture_output=True, text=True, timeout=timeout)
    return r.returncode, r.stderr


def vertices(path):
    import warnings

    import geotex as g  # PYTHONPATH=build/python

    warnings.filterwarnings("ignore")  # the models' repairs on reading
    return np.asarray(g.read_mesh(path)[0])


tp, tpb, tex = (os.path.join(out, n) for n in ("tp.ply", "tpb.ply", "tptex.ply"))
run("generate", "tentacle-plane", "--level", "0", "-o", tp, "--base-output", tpb)
run("texture", "extract", tp, "--base", tpb, "-o", tex)
print("| target | vertices | target radius | textured vertices | folded (target's own) | self-intersecting (target's own) | "
      "lowered vertices (rounds) | CPU s |")
print("|---|---|---|---|---|---|---|---|")
for name in sorted(os.listdir(data)):
    if not name.endswith((".obj", ".ply")):
        continue
    path = os.path.join(data, name)
    V = vertices(path)
    diag = float(np.linalg.norm(V.max(0) - V.min(0)))
    report, result = os.path.join(out, name + ".json"), os.path.join(out, name + "-atlas.ply")
    texture = os.path.join(out, name + "-texture.ply")  # its vertices: the (refined) bare target, geval's --base
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    try:
        rc, err = run("texture", "atlas", tex, path, "-o", result, "--source-near", "0,0,0", "--source-radius", "1",
                      "--target-radius", f"{0.05 * diag:.6g}", "--report", report, "--texture-out", texture,
                      timeout=cap)
    except subprocess.TimeoutExpired:
        print(f"| {name} | {len(V)} | {0.05 * diag:.3g} | stopped at {cap:.0f} s | | | | |")
        continue
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if rc != 0:
        print(f"| {name} | {len(V)} | {0.05 * diag:.3g} | exit {rc}: {err.strip().splitlines()[-1][:90]} | | | | |")
        continue
    j = json.load(open(report))
    d = j.get("damage", j)
    print(f"| {name} | {len(V)} | {0.05 * diag:.3g} | {j.get('vertices', '')} | {d['folded']} ({d['base_folded']}) | "
          f"{d['self_intersecting']} ({d['base_self_intersecting']}) | {j.get('unfolded_vertices', '')} "
          f"({j.get('unfold_rounds', '')}) | {cpu:.1f} |", flush=True)
