#!/usr/bin/python3
"""What a smooth FREE-FORM map reaches under the stretch cap (issue 25, fifteenth session): each face may take its
own stretch, not the slabs of an axis warp (bench/resize_bound.py bounds those).

Usage: resize_freeform_bound.py ORIG AXIS [--free Q] [--mu MU] [--cap 4] [--features MAP] [--start OUT]
                                [--ref OUT ...] [--out RESULT.ply] [--face-floor 10] [--smooth λ] [--in-plane]
                                [--sweep]
  ORIG      the original as geotex reads it (`geotex noise IN -o ORIG.ply --sigma 0`), resized ×2 along AXIS
  MAP       geotex's importance map (`geotex resize ... --save-features MAP.txt`) in place of the ruler's weight
  OUT       an output (geotex's auto) to start from and anchor to, in place of the plain stretch: a stage after it
  --ref     outputs to report the same figures for

The map: a local-global solve (ASAP/ARAP-like) of Σ_f a_f ‖J_f − T_f‖², J_f the face's 3×2 Jacobian in its own
tangent frame. The faces of least importance per area (the ruler's weight: mean vertex detail of
geval.detail_distortion; or geotex's map) covering the share Q of the area are FREE: their target is the nearest map
with singular values in [SMIN, cap] (a projection: no cost up to the cap); every other face's target is the nearest
similarity U m Vᵀ, m = (σ1 + σ2)/2. Each fit keeps the face's orientation (no mirror targets). The shape is kept by an
anchor to the start surface (the plain stretch, or OUT): each vertex held against the start's normal with weight MU
(per mean edge length², times its area) and, a hundredth as much, in the tangent plane — it may slide along the
surface; a vertex on a rim or a sharp edge (dihedral > CREASE°) slides only along that line; where such lines meet,
it is held (`--smooth λ` adds λ Σ_v A_v |L(X − anchor)|_v² / mel², L the uniform Laplacian: a smooth displacement;
`--in-plane` projects each Jacobian onto its anchor face's plane before the fit: a face may not buckle out of it).
A global step that would turn a face over against the plain stretch is halved until none does. Then a
per-axis affine map makes the box exact, and the ruler measures: ratio, turned faces, σ1 / asked (max and 99.9 % of
the area: the stretch cap), the smallest σ2, the jump of log σ1 between faces sharing an edge (max, 99th
percentile: smoothness), each vertex's distance to the plain stretch's surface (the shape kept) and how far it moved
from its plain-stretch place (mean edge lengths).

This is the best of a searched family, not a proof of a lower bound: a value a smooth, unturned map under the cap
reaches. With the ruler's weights and the plain stretch as anchor it answers "does any free-form map reach 0.5";
with MAP and OUT it is a prototype of a stage after geotex's auto.
"""

import argparse
import itertools
import os
import sys

import numpy as np
from scipy.sparse import bmat, coo_matrix, diags, identity
from scipy.sparse.linalg import splu
from scipy.spatial import cKDTree

sys.path.insert(0, os.environ.get("GEVAL_DIR", "/work/shared/eval"))
import geval  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from resize_bound import ruler_weight  # noqa: E402

SMIN = 0.8      # a free face's smallest singular value (the ×2 resize never asks to shrink)
CREASE = 30.0   # degrees: a sharper edge is a feature line
GUARD = 0.3     # faces the start holds near edge-on to the plain stretch (cos below) keep the start's Jacobian
ROUNDS = 40


def face_normals(V, F):
    return np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])


def mean_edge(V, F):
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    return np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1).mean()


def gradient_operator(V0, F):
    """D (2m × n): row 2f+k of D X gives column k of face f's 3×2 Jacobian in its own tangent frame."""
    e1 = V0[F[:, 1]] - V0[F[:, 0]]; e2 = V0[F[:, 2]] - V0[F[:, 0]]
    nrm = np.cross(e1, e2)
    u = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
    nn = nrm / np.linalg.norm(nrm, axis=1, keepdims=True); v = np.cross(nn, u)
    P = np.stack([np.stack([(e1 * u).sum(1), (e1 * v).sum(1)], 1), np.stack([(e2 * u).sum(1), (e2 * v).sum(1)], 1)], 2)
    G = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]) @ np.linalg.inv(P)  # m × 3 × 2
    m = len(F)
    rows = (2 * np.arange(m)[:, None, None] + np.arange(2)[None, None, :]).repeat(3, 1)
    cols = F[:, :, None].repeat(2, 2)
    return coo_matrix((G.ravel(), (rows.ravel(), cols.ravel())), shape=(2 * m, len(V0))).tocsr()


def jacobians(D, X, m):
    return np.stack([(D @ X[:, i]).reshape(m, 2) for i in range(3)], 1)  # m × 3 × 2


def feature_lines(Vp, F):
    """Each vertex's direction along a rim or sharp edge through it (0 elsewhere), and the corners where > 2 meet."""
    n, m = len(Vp), len(F)
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), 1)
    o = np.argsort(E[:, 0] * n + E[:, 1], kind="stable"); ks = (E[:, 0] * n + E[:, 1])[o]
    fo = np.tile(np.arange(m), 3)[o]
    key, first, cnt = np.unique(ks, return_index=True, return_counts=True)
    Fn = face_normals(Vp, F); Fn /= np.maximum(np.linalg.norm(Fn, axis=1, keepdims=True), 1e-300)
    two = cnt == 2
    cosd = np.ones(len(key)); cosd[two] = (Fn[fo[first[two]]] * Fn[fo[first[two] + 1]]).sum(1)
    line = (cnt == 1) | (two & (cosd < np.cos(np.radians(CREASE))))
    be = np.stack([key[line] // n, key[line] % n], 1)
    corner = np.bincount(be.ravel(), minlength=n) > 2
    tan = np.zeros((n, 3)); d = Vp[be[:, 1]] - Vp[be[:, 0]]
    d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-300)
    for i in range(2):  # from the line's two edges at a vertex, signs made consistent
        sgn = np.sign((tan[be[:, i]] * d).sum(1)); sgn[sgn == 0] = 1
        np.add.at(tan, be[:, i], d * sgn[:, None])
    on = (np.linalg.norm(tan, axis=1) > 0) & ~corner
    tan[on] /= np.linalg.norm(tan[on], axis=1, keepdims=True)
    tan[~on] = 0
    return tan, corner


def anchor(Vp, F, mu, mel):
    """The shape term's matrix (3n × 3n, coordinates stacked x; y; z) and right-hand side: μ Σ_v A_v (n_v·(x_v −
    p_v))² + μ/100 Σ_v A_v |x_v − p_v|² (lengths in mean edges); on a feature line, held against all but the line's
    direction; at a corner, held."""
    n = len(Vp)
    Fn = face_normals(Vp, F)
    Nv = np.zeros_like(Vp)
    for i in range(3):
        np.add.at(Nv, F[:, i], Fn)
    Av = np.linalg.norm(Nv, axis=1) / 6
    Nv /= np.maximum(np.linalg.norm(Nv, axis=1, keepdims=True), 1e-300)
    tan, corner = feature_lines(Vp, F)
    on = np.linalg.norm(tan, axis=1) > 0
    k = mu / mel ** 2
    I3 = np.eye(3)
    M = k * Av[:, None, None] * (Nv[:, :, None] * Nv[:, None, :] + I3 / 100)
    M[on] = k * Av[on, None, None] * (I3 - tan[on, :, None] * tan[on, None, :] + I3 / 100)
    M[corner] = k * Av[corner, None, None] * I3
    A = (bmat([[diags(M[:, a, b]) for b in range(3)] for a in range(3)])
         + identity(3 * n) * (k * 1e-6 * Av.mean())).tocsc()  # a vertex in no face stays put
    return A, A @ Vp.T.ravel()


def displacement_smoothing(Vp, F, lam, mel):
    """λ Σ_v A_v |(L d)_v|² / mel², L the uniform graph Laplacian, d = X − Vp: the displacement from the anchor's
    surface must be smooth, so a slide along the surface cannot ripple (3n × 3n, coordinates stacked)."""
    n = len(Vp)
    E = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]); E = np.concatenate([E, E[:, ::-1]])
    Adj = coo_matrix((np.ones(len(E)), (E[:, 0], E[:, 1])), shape=(n, n)).tocsr(); Adj.data[:] = 1
    deg = np.asarray(Adj.sum(1)).ravel(); deg[deg == 0] = 1
    Lu = identity(n) - diags(1 / deg) @ Adj
    Av = np.zeros(n); np.add.at(Av, F.ravel(), np.repeat(np.linalg.norm(face_normals(Vp, F), axis=1) / 6, 3))
    Q = (Lu.T @ diags(Av) @ Lu) * (lam / mel ** 2)
    B = bmat([[Q, None, None], [None, Q, None], [None, None, Q]]).tocsc()
    return B, B @ Vp.T.ravel()


def solve(V0, F, S, dens, area, cap, mu, free, start=None, face_floor=10.0, smooth=0.0, in_plane=False):
    """The free-form map (see the module's text); dens: each face's importance per area."""
    n, m = len(V0), len(F)
    D = gradient_operator(V0, F)
    mel = mean_edge(V0, F)
    Vp = V0 * S if start is None else start
    Np, Nplain = face_normals(Vp, F), face_normals(V0 * S, F)
    Nu = Np / np.maximum(np.linalg.norm(Np, axis=1, keepdims=True), 1e-300)
    A, rhs_anchor = anchor(Vp, F, mu, mel)
    if smooth > 0:
        B, rhs_b = displacement_smoothing(Vp, F, smooth, mel)
        A, rhs_anchor = (A + B).tocsc(), rhs_anchor + rhs_b
    order = np.argsort(dens)
    is_free = np.zeros(m, bool)
    is_free[order[np.cumsum(area[order]) / area.sum() <= free]] = True
    cosp = (Nplain * Np).sum(1) / np.maximum(np.linalg.norm(Nplain, axis=1) * np.linalg.norm(Np, axis=1), 1e-300)
    guard = cosp < GUARD
    c = np.where(guard, 10.0, 1.0)
    J0 = jacobians(D, Vp, m)
    # each face's term weighs at least face_floor × a mean face: by area alone, folding a sliver costs nothing
    Wd = diags(np.repeat(np.maximum(area, face_floor * area.mean()) * c, 2))
    L = D.T @ Wd @ D
    solver = splu((bmat([[L, None, None], [None, L, None], [None, None, L]]) + A).tocsc())
    X = Vp.copy()
    for _ in range(ROUNDS):
        J = jacobians(D, X, m)
        if in_plane:  # targets lie in the anchor face's plane: an important face may rotate in it, not buckle out
            J = J - Nu[:, :, None] * (Nu[:, :, None] * J).sum(1, keepdims=True)
        U, s, Vt = np.linalg.svd(J, full_matrices=False)
        # the fit keeps the face's orientation (as 2D ARAP's det R > 0): a folded face's target is not its mirror
        img = np.cross(U[:, :, 0], U[:, :, 1]) * np.sign(np.linalg.det(Vt))[:, None]
        U[(img * Np).sum(1) < 0, :, 1] *= -1
        sim = np.clip(s.mean(1), SMIN, cap)[:, None].repeat(2, 1)
        T = U @ (np.where(is_free[:, None], np.clip(s, SMIN, cap), sim)[:, :, None] * Vt)
        T[guard] = J0[guard]
        rhs = np.concatenate([D.T @ (Wd @ T[:, i, :].ravel()) for i in range(3)])
        Xn = solver.solve(rhs + rhs_anchor).reshape(3, n).T
        step = 1.0  # halved until no face turns over against the plain stretch (the start turns none)
        while step > 1e-3:
            Xt = X + step * (Xn - X)
            if ((face_normals(Xt, F) * Nplain).sum(1) > 0).all():
                X = Xt
                break
            step /= 2
    lo0, hi0 = V0.min(0) * S, V0.max(0) * S  # the exact box: a per-axis affine map
    lo, hi = X.min(0), X.max(0)
    return lo0 + (X - lo) * (hi0 - lo0) / np.maximum(hi - lo, 1e-300)


def edge_jumps(values, F, n):
    """|values[f] − values[g]| over the pairs of faces sharing an edge."""
    E = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), 1)
    key = E[:, 0] * (n + 1) + E[:, 1]
    o = np.argsort(key, kind="stable"); ks = key[o]; fid = np.tile(np.arange(len(F)), 3)[o]
    same = ks[1:] == ks[:-1]
    return np.abs(values[fid[1:][same]] - values[fid[:-1][same]])


def report(V0, F, X, S, area):
    d = geval.detail_distortion((V0, F), (X, F), S)
    s = np.linalg.svd(jacobians(gradient_operator(V0, F), X, len(F)), compute_uv=False)
    big = s[:, 0] / S.max()
    order = np.argsort(big)
    p999 = big[order][np.searchsorted(np.cumsum(area[order]) / area.sum(), 0.999)]
    jumps = edge_jumps(np.log(s[:, 0]), F, len(V0))
    Vp, mel = V0 * S, mean_edge(V0, F)
    X = X - X.min(0) + Vp.min(0)  # geotex places the box elsewhere: compared in the plain stretch's place
    dist = cKDTree(geval.surface_samples(Vp, F, 12)).query(X)[0] / mel
    mv = np.linalg.norm(X - Vp, axis=1) / mel
    return [d["ratio"], d["flipped_vs_plain"], big.max(), p999, s[:, 1].min(), jumps.max(), np.percentile(jumps, 99),
            np.sqrt((dist ** 2).mean()), dist.max(), np.sqrt((mv ** 2).mean()), mv.max()]


FORMAT = ["%.3f", "%d", "%.2f", "%.2f", "%.2f", "%.2f", "%.2f", "%.2f", "%.2f", "%.1f", "%.1f"]
HEAD = "ratio\tturned\ts1max/2\ts1p999/2\ts2min\tjump_max\tjump_p99\tdev_rms\tdev_max\tmove_rms\tmove_max"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("orig"); ap.add_argument("axis", choices="xyz")
    ap.add_argument("--cap", type=float, default=4.0); ap.add_argument("--mu", type=float, default=0.1)
    ap.add_argument("--free", type=float, default=0.25); ap.add_argument("--sweep", action="store_true")
    ap.add_argument("--features"); ap.add_argument("--start"); ap.add_argument("--ref", nargs="*", default=[])
    ap.add_argument("--face-floor", type=float, default=10.0, help="a face's least weight, in mean face areas")
    ap.add_argument("--smooth", type=float, default=0.0, help="weight of the displacement's smoothness (0: none)")
    ap.add_argument("--in-plane", action="store_true", help="targets in the anchor face's plane")
    ap.add_argument("--out")
    a = ap.parse_args()
    S = np.ones(3); S["xyz".index(a.axis)] = 2
    V0, F = geval.read_mesh(a.orig)
    w, area, _ = ruler_weight(V0, F)
    dens = w / area if not a.features else np.loadtxt(a.features)[F].mean(1)
    start = geval.read_mesh(a.start)[0] if a.start else None
    print(f"{os.path.basename(a.orig)} ×2 {a.axis}, cap σ1 ≤ {a.cap:g}\nrun\tfree\tmu\t" + HEAD)
    for path in a.ref:
        r = report(V0, F, geval.read_mesh(path)[0], S, area)
        print(os.path.basename(path) + "\t\t\t" + "\t".join(f % v for f, v in zip(FORMAT, r)))
    grid = itertools.product([0.25, 0.4, 0.55], [0.1, 0.3, 1]) if a.sweep else [(a.free, a.mu)]
    for free, mu in grid:
        X = solve(V0, F, S, dens, area, a.cap, mu, free, start, a.face_floor, a.smooth, a.in_plane)
        r = report(V0, F, X, S, area)
        print(f"free-form\t{free:g}\t{mu:g}\t" + "\t".join(f % v for f, v in zip(FORMAT, r)), flush=True)
        if a.out and not a.sweep:
            with open(a.out, "w") as fh:
                fh.write(f"ply\nformat ascii 1.0\nelement vertex {len(X)}\nproperty double x\nproperty double y\n"
                         f"property double z\nelement face {len(F)}\nproperty list uchar int vertex_indices\n"
                         "end_header\n")
                np.savetxt(fh, X, fmt="%.17g")
                np.savetxt(fh, np.hstack([np.full((len(F), 1), 3), F]), fmt="%d")


if __name__ == "__main__":
    main()
