#!/usr/bin/python3
"""Where a ×2 stretch could go at no cost under the ruler (issue 25, sixteenth session): the ruler's weight density,
the faces a flat face's interior could offer, and the best slab allocation when the slabs may differ around the axis.

Usage: resize_bands.py ORIG.ply AXIS [--caps 3,4,6] [--bins 32] [--sectors 1,2,4,8,16] [--out OUT.ply ...]
                       [--render-weight W.txt] [--split U:T:BETA --cap 4 --write OUT.ply
                       --features MAP.txt]
  ORIG      the original as geotex reads it (`geotex noise IN -o ORIG.ply --sigma 0`), resized ×2 along AXIS
  OUT       resized outputs: the share of the ruler's sum each weight-density class carries, its faces' mean
            log(s1/s2) and mean log s1 (s1 ≥ s2 the singular values of the face's map)
  W         writes the ruler's weight density per vertex (area-weighted mean of its faces'; a text file for
            `geotex render ORIG --field-file W`)
  --split   a two-band warp, written to OUT: the faces below / above the fraction T of the extent along the axis U
            (x|y|z) each get their own bang-bang slab allocation under σ ≤ cap, and each vertex the blend of the two
            maps with a smoothstep over the width BETA (a fraction of U's extent) centred at T: the cut across the
            model steps along the stretched axis between the bands, and the step is a shear spread over BETA;
            with MAP (`geotex resize ... --save-features MAP.txt`) the allocation uses geotex's importance (area ×
            mean vertex importance) in place of the ruler's weight. Prints each band's slab σ, one digit per slab
            (twice σ, rounded: the allocation as the sixteenth session's scratch switch read it)

(1) Density: each face's ruler weight (geval.detail_distortion: area × mean vertex detail) over its area, mean 1 over
the surface. A ×2 stretch can only be cheap where the density is low over a whole cut across the model.
(2) Flat interiors: the share of the area whose three vertices all have detail below t mean edges (a face with a
loud vertex is weighted even if its interior is flat: a triangle spanning a flat face edge to edge has no quiet
vertex).
(3) Sector bound: the model is cut into S sectors by the angle about the axis (through the bounding box's centre);
each sector gets its own bang-bang slab allocation under σ ≤ cap (resize_bound.py's, per sector), i.e. the cut
across the model may step along the axis from sector to sector. "model" is the concave cost model with the sectors
torn apart (a lower bound for a slab allocation per sector, x_a' = g_k(x_a) on sector k); "realised" maps each
vertex by its own sector's g and measures with the ruler's code (the steps between sectors are then shears, no
longer free).
"""

import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.environ.get("GEVAL_DIR", "/work/shared/eval"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import geval  # noqa: E402
from resize_bound import ruler_weight, singular_values  # noqa: E402


def slab_costs(V0, F, w, ax, cap, edges, faces):
    """Each slab's cost at the cap for the given faces (a face split over the slabs it spans by extent)."""
    e1 = V0[F[:, 1]] - V0[F[:, 0]]; e2 = V0[F[:, 2]] - V0[F[:, 0]]
    nrm = np.cross(e1, e2); nn = nrm / np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
    phi = 0.5 * np.log(1 + (cap * cap - 1) * (1 - nn[:, ax] ** 2))
    x = V0[F][:, :, ax]; x0, x1 = x.min(1), x.max(1)
    cost = np.zeros(len(edges) - 1)
    for j in range(len(cost)):
        ov = np.clip(np.minimum(x1, edges[j + 1]) - np.maximum(x0, edges[j]), 0, None)
        inside = ((x0 >= edges[j]) & (x0 < edges[j + 1])).astype(float)
        cost[j] = (faces * w * phi * np.where(x1 > x0, ov / np.maximum(x1 - x0, 1e-300), inside)).sum()
    return cost


def bang_bang(cost, lam, cap):
    bins = len(cost); need = bins * (lam - 1) / (cap - 1)
    order = np.argsort(cost); k = int(np.floor(need))
    sig = np.ones(bins); sig[order[:k]] = cap
    if k < bins:
        sig[order[k]] = 1 + (need - k) * (cap - 1)
    return sig, float(cost[order[:k]].sum() + (need - k) * cost[order[k]] if k < bins else cost.sum())


def sector_bound(V0, F, w, ax, cap, bins, sectors, m0):
    others = [i for i in range(3) if i != ax]
    c = 0.5 * (V0.max(0) + V0.min(0))
    ang_v = np.arctan2(V0[:, others[1]] - c[others[1]], V0[:, others[0]] - c[others[0]])
    sec_v = np.minimum(((ang_v + np.pi) / (2 * np.pi) * sectors).astype(int), sectors - 1)
    cen = V0[F].mean(1)
    ang_f = np.arctan2(cen[:, others[1]] - c[others[1]], cen[:, others[0]] - c[others[0]])
    sec_f = np.minimum(((ang_f + np.pi) / (2 * np.pi) * sectors).astype(int), sectors - 1)
    lo, hi = V0[:, ax].min(), V0[:, ax].max()
    edges = np.linspace(lo, hi, bins + 1)
    V1 = V0.copy(); model = 0.0
    for k in range(sectors):
        cost = slab_costs(V0, F, w, ax, cap, edges, (sec_f == k).astype(float))
        sig, cst = bang_bang(cost, 2, cap); model += cst
        G = np.concatenate([[lo], lo + np.cumsum(sig * np.diff(edges))])
        sel = sec_v == k
        V1[sel, ax] = np.interp(V0[sel, ax], edges, G)
    a1, _ = geval._anisotropy(F, V0, V1)
    return model / m0, float((w * a1).sum() / m0)


def two_band_warp(V0, F, w, ax, ui, t, beta, cap, bins=32):
    """x_a' = (1 − b(u)) g_0(x_a) + b(u) g_1(x_a): g_k the bang-bang allocation of band k's faces, b a smoothstep."""
    lo, hi = V0[:, ax].min(), V0[:, ax].max()
    edges = np.linspace(lo, hi, bins + 1)
    ulo, uhi = V0[:, ui].min(), V0[:, ui].max()
    upper = (V0[F].mean(1)[:, ui] - ulo) / (uhi - ulo) >= t
    G = []
    for band in (~upper, upper):
        sig, _ = bang_bang(slab_costs(V0, F, w, ax, cap, edges, band.astype(float)), 2, cap)
        G.append(np.concatenate([[lo], lo + np.cumsum(sig * np.diff(edges))]))
    r = np.clip(((V0[:, ui] - ulo) / (uhi - ulo) - (t - beta / 2)) / max(beta, 1e-9), 0, 1)
    b = r * r * (3 - 2 * r)
    V1 = V0.copy()
    V1[:, ax] = (1 - b) * np.interp(V0[:, ax], edges, G[0]) + b * np.interp(V0[:, ax], edges, G[1])
    return V1, [np.diff(g) / np.diff(edges) for g in G]


def write_ply(path, V, F):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (len(V), len(F)))
        for v in V:
            f.write("%.9g %.9g %.9g\n" % tuple(v))
        for t_ in F:
            f.write("3 %d %d %d\n" % tuple(t_))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("orig"); p.add_argument("axis", choices="xyz")
    p.add_argument("--caps", default="3,4,6"); p.add_argument("--bins", type=int, default=32)
    p.add_argument("--sectors", default="1,2,4,8,16"); p.add_argument("--out", nargs="*", default=[])
    p.add_argument("--render-weight"); p.add_argument("--split"); p.add_argument("--cap", type=float, default=4)
    p.add_argument("--write"); p.add_argument("--features")
    a = p.parse_args()
    ax = "xyz".index(a.axis); S = np.ones(3); S[ax] = 2
    V0, F = geval.read_mesh(a.orig)
    w, area, det = ruler_weight(V0, F)
    A = area / area.sum(); dens = w / A
    a0, _ = geval._anisotropy(F, V0, V0 * S)
    m0 = float((w * a0).sum())
    print(f"{os.path.basename(a.orig)} ×2 {a.axis}: {len(F)} faces, {len(V0)} vertices")
    o = np.argsort(dens); cum = np.cumsum(A[o])
    print("  (1) weight density (mean 1) at area quantiles 5/10/25/50 %%: %s; the plain stretch's mean "
          "log(s1/s2) %.3f" % (", ".join("%.2f" % dens[o][np.searchsorted(cum, q)] for q in (0.05, 0.1, 0.25, 0.5)),
                               m0))
    fmax = det[F].max(1)
    print("  (2) vertex detail p10/p50/p90 %s edges; area with all three vertices below 0.1/0.2/0.3/0.5 edges: %s"
          % ("/".join("%.2f" % q for q in np.percentile(det, [10, 50, 90])),
             "/".join("%.3f" % A[fmax < t].sum() for t in (0.1, 0.2, 0.3, 0.5))))
    for cap in (float(c) for c in a.caps.split(",")):
        rows = []
        for s in map(int, a.sectors.split(",")):
            mdl, real = sector_bound(V0, F, w, ax, cap, a.bins, s, m0)
            rows.append("%d: %.3f / %.3f" % (s, mdl, real))
        print("  (3) σ ≤ %g, %d slabs, sectors model / realised: %s" % (cap, a.bins, "; ".join(rows)))
    classes = [(0, 0.5), (0.5, 0.8), (0.8, 1.2), (1.2, 2), (2, np.inf)]
    for path in a.out:
        V1, _ = geval.read_mesh(path)
        a1, _ = geval._anisotropy(F, V0, V1)
        ext = np.log(np.maximum(singular_values(F, V0, V1)[:, 0], 1e-300))
        print("  %s: ratio %.3f" % (os.path.basename(path), (w * a1).sum() / m0))
        for lo_, hi_ in classes:
            s = (dens >= lo_) & (dens < hi_)
            if s.any():
                print("    density [%.1f, %.1f): area %.3f weight %.3f share of the ratio %.3f (plain %.3f) "
                      "mean log(s1/s2) %.2f (plain %.2f) mean log s1 %.2f"
                      % (lo_, hi_, A[s].sum(), w[s].sum(), (w[s] * a1[s]).sum() / m0, (w[s] * a0[s]).sum() / m0,
                         (A[s] * a1[s]).sum() / A[s].sum(), (A[s] * a0[s]).sum() / A[s].sum(),
                         (A[s] * ext[s]).sum() / A[s].sum()))
    if a.render_weight:
        vd = np.zeros(len(V0)); vc = np.zeros(len(V0))
        for k in range(3):
            np.add.at(vd, F[:, k], dens * area); np.add.at(vc, F[:, k], area)
        np.savetxt(a.render_weight, vd / np.maximum(vc, 1e-300), fmt="%.4f")
    if a.split:
        u, t, beta = a.split.split(":")
        wa = w
        if a.features:
            fm = np.loadtxt(a.features); wa = area * fm[F].mean(1); wa = wa / wa.sum()
        V1, sig = two_band_warp(V0, F, wa, ax, "xyz".index(u), float(t), float(beta), a.cap)
        d = geval.detail_distortion((V0, F), (V1, F), S)
        print("  two-band warp, split %s at %s, blend %s, σ ≤ %g: ratio %.3f, turned %d; 2σ per slab, lower band %s, "
              "upper %s"
              % (u, t, beta, a.cap, d["ratio"], d["flipped_vs_plain"], "".join("%d" % round(2 * x) for x in sig[0]),
                 "".join("%d" % round(2 * x) for x in sig[1])))
        if a.write:
            write_ply(a.write, V1, F)


if __name__ == "__main__":
    main()
