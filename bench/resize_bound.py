#!/usr/bin/python3
"""Why a resize misses the ruler's detail-distortion target: the ruler's weight against geotex's importance map,
where the stretch went, and the best ratio an axis-aligned slab allocation could reach (issue 25).

Usage: resize_bound.py ORIG.ply AXIS [--features MAP.txt] [--out OUT.ply ...] [--caps 3,4] [--bins 16,32,64]
                       [--slabs 16]
  ORIG      the original as geotex reads it (`geotex noise IN -o ORIG.ply --sigma 0`), resized ×2 along AXIS (x|y|z)
  MAP       the importance map used (`geotex resize ... --save-features MAP.txt`): compared with the ruler's weight
  OUT       resized outputs (ORIG's vertices and faces): ratio, turned faces and largest singular value over the asked
            factor (the stretch cap), and each slab's stretch (output extent over input extent)

The bound: the ruler's weights (/work/shared/eval/geval.py detail_distortion: face area × mean vertex distance to a
40-step Laplacian-smoothed copy, in mean edge lengths) and its per-face anisotropy under x_a' = g(x_a), g piecewise
linear over `bins` equal slabs along the axis, every other coordinate kept: a face with unit normal n under a
stretch σ along the axis has singular values 1 and √(1 + (σ² − 1)(1 − n_a²)). That cost is concave in σ, so the best
allocation under the cap σ ≤ cap is bang-bang: the cheapest slabs (each face's cost split over the slabs it spans by
extent) take the cap, one slab the remainder, the rest 1. That allocation is then applied to the vertices and
measured with the ruler's own code ("realised"): a tear-like map with no transition, so it is a lower bound for what
any smooth axis-aligned warp under the cap could reach with the ruler's weights, not a goal.
"""

import argparse
import os
import sys

import numpy as np
from scipy.sparse import coo_matrix, diags

sys.path.insert(0, os.environ.get("GEVAL_DIR", "/work/shared/eval"))
import geval  # noqa: E402


def ruler_weight(V0, F):
    """The ruler's per-face weight (normalised), face areas and per-vertex detail, as in geval.detail_distortion."""
    n = len(V0)
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]); E = np.concatenate([E, E[:, ::-1]])
    A = coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n)).tocsr(); A.data[:] = 1
    deg = np.asarray(A.sum(1)).ravel(); deg[deg == 0] = 1
    W = diags(1 / deg) @ A
    mel = np.linalg.norm(V0[E[:, 0]] - V0[E[:, 1]], axis=1).mean()
    Vs = V0.copy()
    for _ in range(40):
        Vs = 0.5 * Vs + 0.5 * (W @ Vs)
    detail = np.linalg.norm(V0 - Vs, axis=1) / mel
    _, area = geval._anisotropy(F, V0, V0)
    w = area * detail[F].mean(1)
    return w / w.sum(), area, detail


def singular_values(F, Va, Vb):
    e1 = Va[F[:, 1]] - Va[F[:, 0]]; e2 = Va[F[:, 2]] - Va[F[:, 0]]
    nrm = np.cross(e1, e2); u = e1 / np.maximum(np.linalg.norm(e1, axis=1, keepdims=True), 1e-300)
    nn = nrm / np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300); v = np.cross(nn, u)
    P = np.stack([np.stack([(e1 * u).sum(1), (e1 * v).sum(1)], 1), np.stack([(e2 * u).sum(1), (e2 * v).sum(1)], 1)], 2)
    Q = np.stack([Vb[F[:, 1]] - Vb[F[:, 0]], Vb[F[:, 2]] - Vb[F[:, 0]]], 2)
    ok = np.abs(np.linalg.det(P)) > 1e-30
    s = np.ones((len(F), 2)); s[ok] = np.linalg.svd(Q[ok] @ np.linalg.inv(P[ok]), compute_uv=False)
    return s


def realised_bound(V0, F, w, ax, lam, cap, bins, m0):
    e1 = V0[F[:, 1]] - V0[F[:, 0]]; e2 = V0[F[:, 2]] - V0[F[:, 0]]
    nrm = np.cross(e1, e2); nn = nrm / np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
    phi = 0.5 * np.log(1 + (cap * cap - 1) * (1 - nn[:, ax] ** 2))  # a face's log(s1/s2) at the cap
    lo, hi = V0[:, ax].min(), V0[:, ax].max()
    x = V0[F][:, :, ax]; x0, x1 = x.min(1), x.max(1)
    edges = np.linspace(lo, hi, bins + 1)
    cost = np.zeros(bins)
    for j in range(bins):
        ov = np.clip(np.minimum(x1, edges[j + 1]) - np.maximum(x0, edges[j]), 0, None)
        inside = ((x0 >= edges[j]) & (x0 < edges[j + 1])).astype(float)
        cost[j] = (w * phi * np.where(x1 > x0, ov / np.maximum(x1 - x0, 1e-300), inside)).sum()
    need = bins * (lam - 1) / (cap - 1)  # slabs at the cap
    order = np.argsort(cost); k = int(np.floor(need))
    sig = np.ones(bins); sig[order[:k]] = cap
    if k < bins:
        sig[order[k]] = 1 + (need - k) * (cap - 1)
    G = np.concatenate([[lo], lo + np.cumsum(sig * np.diff(edges))])
    V1 = V0.copy(); V1[:, ax] = np.interp(V0[:, ax], edges, G)
    a1, _ = geval._anisotropy(F, V0, V1)
    return float((w * a1).sum() / m0)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("orig"); p.add_argument("axis", choices="xyz")
    p.add_argument("--features"); p.add_argument("--out", nargs="*", default=[])
    p.add_argument("--caps", default="3,4"); p.add_argument("--bins", default="16,32,64")
    p.add_argument("--slabs", type=int, default=16)
    a = p.parse_args()
    ax = "xyz".index(a.axis); S = np.ones(3); S[ax] = 2
    V0, F = geval.read_mesh(a.orig)
    w, area, _ = ruler_weight(V0, F)
    a0, _ = geval._anisotropy(F, V0, V0 * S)
    m0 = float((w * a0).sum())
    print(f"{os.path.basename(a.orig)} ×2 {a.axis}: {len(F)} faces")
    ours = None
    if a.features:
        f = np.loadtxt(a.features); v = f[F].mean(1)
        ours = area * v; ours /= ours.sum()
        print("  corr(ruler weight, area × map) %.3f; ruler weight on faces with map ≥ 0.5: %.2f (their area %.2f)"
              % (np.corrcoef(w, ours)[0, 1], w[v >= 0.5].sum(), area[v >= 0.5].sum() / area.sum()))
    for cap in (float(c) for c in a.caps.split(",")):
        print("  realised bound, σ ≤ %g: " % cap + ", ".join(
            "%d slabs %.3f" % (b, realised_bound(V0, F, w, ax, 2, cap, b, m0)) for b in map(int, a.bins.split(","))))
    lo, hi = V0[:, ax].min(), V0[:, ax].max()
    edges = np.linspace(lo, hi, a.slabs + 1)
    b = np.minimum(((V0[F].mean(1)[:, ax] - lo) / (hi - lo) * a.slabs).astype(int), a.slabs - 1)
    outs = []
    for path in a.out:
        V1, F1 = geval.read_mesh(path)
        a1, _ = geval._anisotropy(F, V0, V1); s = singular_values(F, V0, V1)
        d = geval.detail_distortion((V0, F), (V1, F1), S)
        order = np.argsort(V0[:, ax])
        g = np.interp(edges, V0[order, ax], V1[order, ax])
        outs.append((os.path.basename(path), a1, np.diff(g) / np.diff(edges)))
        big = s[:, 0] / 2
        print("  %s: ratio %.3f, turned %d, largest singular value / asked factor: max %.2f, 99.9%% of the area %.2f"
              % (os.path.basename(path), d["ratio"], d["flipped_vs_plain"], big.max(),
                 np.sort(big)[np.searchsorted(np.cumsum(area[np.argsort(big)]) / area.sum(), 0.999)]))
    head = "  slab  ruler%  " + ("map%  " if ours is not None else "") + "area%  " + "  ".join(
        "σ,share%% %s" % n for n, _, _ in outs)
    print(head)
    for j in range(a.slabs):
        s = b == j
        row = "  %4d  %5.1f  " % (j, 100 * w[s].sum())
        if ours is not None:
            row += "%5.1f  " % (100 * ours[s].sum())
        row += "%5.1f  " % (100 * area[s].sum() / area.sum())
        row += "  ".join("%5.2f,%5.1f" % (st[j], 100 * (w[s] * a1[s]).sum() / m0) for _, a1, st in outs)
        print(row)


if __name__ == "__main__":
    main()
