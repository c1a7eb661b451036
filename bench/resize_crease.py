#!/usr/bin/env python3
"""A crease number for a resize (issue 25, fifteenth session): how much sharper the result is than the plain stretch.

Usage: resize_crease.py ORIGINAL RESIZED SX,SY,SZ [--smooth DEG] [--region XLO,YLO,ZLO,XHI,YHI,ZHI] [--abs-lo A,V]

Per edge shared by two faces: the dihedral angle (degrees) in the result minus the plain stretch's (the input scaled
by SX,SY,SZ), over the edges that are smooth in the input (dihedral < --smooth, 10 by default) and, with --region,
whose first vertex lies in the input's box given; --abs-lo A,V keeps only edges with |coordinate A| >= V (the
teapot's body ends: --region -9,0.1,-9,9,2.2,9 --abs-lo 2,0.8). Prints the max, the 99th and 99.9th percentiles and the
three worst edges' input positions, as JSON. Reads meshes with the ruler's reader (/work/shared/eval/geval.py).
"""
import json
import sys

import numpy as np

sys.path.insert(0, "/work/shared/eval")
import geval  # noqa: E402


def dihedral(V, F):
    N = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    N /= np.linalg.norm(N, axis=1)[:, None] + 1e-300
    E = np.sort(np.stack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]], 1).reshape(-1, 2), 1)
    face = np.repeat(np.arange(len(F)), 3)
    key = E[:, 0].astype(np.int64) * len(V) + E[:, 1]
    o = np.argsort(key, kind="stable")
    pair = np.where(key[o][1:] == key[o][:-1])[0]
    a, b = face[o[pair]], face[o[pair + 1]]
    return E[o[pair]], np.degrees(np.arccos(np.clip((N[a] * N[b]).sum(1), -1, 1)))


def main(argv):
    args = [a for a in argv[1:]]
    opts = {"--smooth": "10", "--region": None, "--abs-lo": None}
    for k in list(opts):
        if k in args:
            i = args.index(k)
            opts[k] = args[i + 1]
            del args[i:i + 2]
    V0, F = geval.read_mesh(args[0])[:2]
    V1 = geval.read_mesh(args[1])[0]
    s = np.array([float(x) for x in args[2].split(",")])
    edges, a0 = dihedral(V0, F)
    _, ap = dihedral(V0 * s, F)
    _, a1 = dihedral(V1, F)
    sel = a0 < float(opts["--smooth"])
    p = V0[edges[:, 0]]
    if opts["--region"]:
        r = np.array([float(x) for x in opts["--region"].split(",")])
        sel &= (p >= r[:3]).all(1) & (p <= r[3:]).all(1)
    if opts["--abs-lo"]:
        axis, lo = opts["--abs-lo"].split(",")
        sel &= np.abs(p[:, int(axis)]) >= float(lo)
    d = a1 - ap
    worst = np.argsort(-np.where(sel, d, -np.inf))[:3]
    print(json.dumps({"edges": int(sel.sum()), "max": float(d[sel].max()), "p99": float(np.percentile(d[sel], 99)),
                      "p99.9": float(np.percentile(d[sel], 99.9)), "worst_at": [p[j].round(3).tolist() for j in worst]}))


if __name__ == "__main__":
    main(sys.argv)
