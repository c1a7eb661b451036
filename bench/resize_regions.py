#!/usr/bin/python3
"""Where a resize's detail-distortion ratio sits by importance, and how the important surface is connected (issue 25).

Usage: resize_regions.py ORIG.ply OUT.ply MAP.txt AXIS [--thresholds 0.8,0.9,0.95]
  ORIG  the original as geotex reads it (`geotex noise IN -o ORIG.ply --sigma 0`), OUT its ×2 resize along AXIS (x|y|z)
  MAP   the importance map used (`geotex resize ... --save-features MAP.txt`)

Prints the ruler's ratio (/work/shared/eval/geval.py detail_distortion, its weights as in bench/resize_bound.py), then
per class of the map's face mean f: the share of the area, of the ruler's weight and of the ratio, and the area-weighted
mean log(s1/s2) of the output against the plain stretch's; then, per threshold, the connected components of the faces
with f at or above it (faces sharing a vertex) and the largest components' shares of the area. A component spanning
the model cannot keep one similarity under a stretch: the question "one similarity per important region" asks.
"""

import argparse
import os
import sys

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

sys.path.insert(0, os.environ.get("GEVAL_DIR", "/work/shared/eval"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import geval  # noqa: E402
from resize_bound import ruler_weight  # noqa: E402


def components(F, n, faces):
    """Connected components of the faces \\p faces (indices into F) that share a vertex: (count, label per face)."""
    rows = np.repeat(np.arange(len(faces)), 3)
    M = coo_matrix((np.ones(len(rows)), (rows, F[faces].ravel())), shape=(len(faces), n)).tocsr()
    return connected_components(M @ M.T, directed=False)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("orig"); p.add_argument("out"); p.add_argument("map"); p.add_argument("axis", choices="xyz")
    p.add_argument("--thresholds", default="0.8,0.9,0.95")
    a = p.parse_args()
    S = np.ones(3); S["xyz".index(a.axis)] = 2
    V0, F = geval.read_mesh(a.orig)
    V1, _ = geval.read_mesh(a.out)
    w, area, _ = ruler_weight(V0, F)
    a0, _ = geval._anisotropy(F, V0, V0 * S)
    a1, _ = geval._anisotropy(F, V0, V1)
    m0 = (w * a0).sum()
    v = np.loadtxt(a.map)[F].mean(1)
    print("%s ×2 %s: ratio %.3f" % (os.path.basename(a.out), a.axis, (w * a1).sum() / m0))
    print("  map f       area  weight  share  log(s1/s2) out / plain")
    for lo, hi in [(0, .2), (.2, .4), (.4, .6), (.6, .8), (.8, 1.01)]:
        s = (v >= lo) & (v < hi)
        A = max(area[s].sum(), 1e-300)
        print("  [%.1f, %.1f)  %.2f  %.2f    %.3f  %.2f / %.2f" % (
            lo, min(hi, 1), area[s].sum() / area.sum(), w[s].sum(), (w[s] * a1[s]).sum() / m0,
            (area[s] * a1[s]).sum() / A, (area[s] * a0[s]).sum() / A))
    for t in map(float, a.thresholds.split(",")):
        faces = np.where(v >= t)[0]
        if len(faces) == 0:
            continue
        k, label = components(F, len(V0), faces)
        share = np.sort(np.bincount(label, weights=area[faces]))[::-1] / area.sum()
        print("  f ≥ %.2f: %d components, the largest %s of the area" % (t, k, np.round(share[:5], 3).tolist()))


if __name__ == "__main__":
    main()
