#!/usr/bin/env python3
"""Issue 26: damage (folded and self-intersecting faces, against the bare target's own) of one-disk
transfers onto every shared model, through the CLI's --report. The source is the tentacle plate (level 1)
or igea's hair; each target disk is centred at the vertex farthest along +x and +z from the model's centre
(a side, usually a cheek or a flank) with radius 0.1 x the bounding-box diagonal.
Run: PYTHONPATH=build/python /usr/bin/python3 bench/texture_damage.py build/geotex /work/shared/data OUTDIR"""
import json, os, subprocess, sys

import numpy as np

geotex, data, out = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(out, exist_ok=True)


def run(*args):
    r = subprocess.run([geotex, *args], capture_output=True, text=True)
    return r.returncode, r.stderr


def vertices(path):
    import warnings

    import geotex  # PYTHONPATH=build/python

    warnings.filterwarnings("ignore")  # the models' repairs on reading
    return np.asarray(geotex.read_mesh(path)[0])


tp, tpb, tex = (os.path.join(out, n) for n in ("tp.ply", "tpb.ply", "tptex.ply"))
run("generate", "tentacle-plane", "--level", "1", "-o", tp, "--base-output", tpb)
run("texture", "extract", tp, "--base", tpb, "-o", tex)
print("| target | vertices | patch radius | added vertices | folded (target's own) | self-intersecting (target's own) | warnings |")
print("|---|---|---|---|---|---|---|")
for name in sorted(os.listdir(data)):
    if not name.endswith((".obj", ".ply")):
        continue
    path = os.path.join(data, name)
    V = vertices(path)
    c = V.mean(0)
    diag = float(np.linalg.norm(V.max(0) - V.min(0)))
    p = V[np.argmax((V - c) @ np.array([1.0, 0.0, 1.0]))]
    report = os.path.join(out, name + ".json")
    rc, err = run("texture", "transfer", tex, path, "-o", os.path.join(out, name + "-tentacles.ply"), "--source-near",
                  "0,0,0", "--source-radius", "1", "--target-near", ",".join(f"{x:.6g}" for x in p),
                  "--target-radius", f"{0.1 * diag:.6g}", "--report", report)
    if rc != 0:
        print(f"| {name} | {len(V)} | {0.1 * diag:.3g} | exit {rc}: {err.strip().splitlines()[-1][:90]} | | | |")
        continue
    j = json.load(open(report))
    print(f"| {name} | {len(V)} | {0.1 * diag:.3g} | {j['added_vertices']} | {j['folded']} ({j['base_folded']}) | "
          f"{j['self_intersecting']} ({j['base_self_intersecting']}) | {len(j['warnings'])} |")
