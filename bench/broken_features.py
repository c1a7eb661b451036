#!/usr/bin/env python3
"""Issue 27: broken features in a synthesis output, on the meshes alone.

Usage: broken_features.py OUT.ply BASE.ply EXEMPLAR.ply EXEMPLAR_BASE.ply SCALE
The connected regions of vertices displaced (OUT − BASE) by over 5 % of the exemplar's largest displacement
× SCALE (the report's scale: height_factor with height_scale 1), each by its peak and footprint (the sum of its
vertex areas); a region is broken when its peak is under half the exemplar's lowest whole feature (off the
plate's rim) × SCALE, or its footprint under half their smallest × SCALE² (as Synthesis.NoBrokenFeaturesOnASphere
asks; the synthesis removes under 3/4 of the raster's footprint). Prints JSON.
"""
import json
import sys

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

import geotex


def regions(V, F, D, tau):
    up = np.linalg.norm(D, axis=1) > tau
    e = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    e = e[up[e[:, 0]] & up[e[:, 1]]]
    n = len(V)
    A = sp.coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    _, lab = connected_components(A, directed=False)
    h = np.linalg.norm(D, axis=1)
    V, F = np.asarray(V), np.asarray(F)
    fa = 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    va = np.bincount(F.ravel(), np.repeat(fa / 3, 3), minlength=n)
    out = {}
    for v in np.flatnonzero(up):
        out.setdefault(lab[v], []).append(v)
    return [(np.array(vs), h[vs].max(), va[vs].sum()) for vs in out.values()], e


def main():
    out, base, ex, exb, scale = sys.argv[1:6]
    scale = float(scale)
    (MV, _), (BV, BF) = geotex.read_mesh(out), geotex.read_mesh(base)
    (EV, _), (EBV, EF) = geotex.read_mesh(ex), geotex.read_mesh(exb)
    ED = np.asarray(EV) - np.asarray(EBV)
    EF = np.asarray(EF)
    elargest = np.linalg.norm(ED, axis=1).max()
    # the plate's rim: vertices on edges used by one face
    e = np.sort(np.vstack([EF[:, [0, 1]], EF[:, [1, 2]], EF[:, [2, 0]]]), axis=1)
    u, c = np.unique(e, axis=0, return_counts=True)
    rim = np.zeros(len(ED), bool)
    rim[u[c == 1].ravel()] = True
    own, _ = regions(EBV, EF, ED, 0.05 * elargest)
    whole = [(p, a) for vs, p, a in own if len(vs) >= 4 and not rim[vs].any()]
    lowest, smallest = min(p for p, _ in whole), min(a for _, a in whole)
    D = np.asarray(MV) - np.asarray(BV)
    regs, _ = regions(BV, np.asarray(BF), D, 0.05 * elargest * scale)
    regs = [r for r in regs if len(r[0]) >= 4]
    broken = [r for r in regs if r[1] < 0.5 * lowest * scale or r[2] < 0.5 * smallest * scale**2]
    print(json.dumps({"regions": len(regs), "broken": len(broken),
                      "broken_vertices": int(sum(len(r[0]) for r in broken)),
                      "exemplar_lowest_over_largest": round(lowest / elargest, 3)}))


if __name__ == "__main__":
    main()
