#!/usr/bin/python3
"""The painted plate of ResizeSimilarity.PaintedWeightsGetSimilarities… (tests/resize/resize_test.cpp) and variations of
it, resized by the default (auto) through the Python module on PYTHONPATH: the worst core face's s1/s2 − 1 (the faces
with painted weight 1 at all three corners) at ×2 x, ×2 y, ×1.5 x and ×2 z, and faces turned against the plain stretch.

Usage: PYTHONPATH=build/python bench/resize_painted_plate.py
The plate is geotex's plane(n, 2.0) triangulation with bumps h (1 − d²/r²)² and the test's painted map: 1 within r of a
bump's centre, a smoothstep to 0 at 1.8 r (issue 25; bench/resize.md, thirteenth session).
"""
import numpy as np
import geotex


def plate(n, r=0.25, h=0.15, spacing=1.0, bumps=2):
    idx = lambda i, j: i * (n + 1) + j  # noqa: E731
    V = np.array([(2 * (i / n - 0.5), 2 * (j / n - 0.5), 0.0) for i in range(n + 1) for j in range(n + 1)])
    F = []
    for i in range(n):
        for j in range(n):
            if (i + j) % 2 == 0:
                F += [(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)), (idx(i, j), idx(i + 1, j + 1), idx(i, j + 1))]
            else:
                F += [(idx(i, j), idx(i + 1, j), idx(i, j + 1)), (idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1))]
    F = np.array(F)
    f = np.zeros(len(V))
    for a in range(bumps):
        for b in range(bumps):
            c = np.array(((a - 0.5 * (bumps - 1)) * spacing, (b - 0.5 * (bumps - 1)) * spacing))
            d = np.linalg.norm(V[:, :2] - c, axis=1)
            V[:, 2] += np.where(d < r, h * np.clip(1 - d * d / (r * r), 0, None) ** 2, 0)
            t = np.clip((1.8 * r - d) / (0.8 * r), 0, 1)
            f = np.maximum(f, t * t * (3 - 2 * t))
    return V, F, f


def anisotropy(F, X, Y):
    """s1/s2 − 1 of each face's map from X (in its own plane) to Y."""
    e1, e2 = X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]]
    u = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
    v = np.cross(np.cross(e1, e2), e1); v /= np.linalg.norm(v, axis=1, keepdims=True)
    P = np.stack([np.stack([(e1 * u).sum(1), (e2 * u).sum(1)], 1), np.stack([(e1 * v).sum(1), (e2 * v).sum(1)], 1)], 1)
    Q = np.stack([Y[F[:, 1]] - Y[F[:, 0]], Y[F[:, 2]] - Y[F[:, 0]]], 2)
    S = np.linalg.svd(Q @ np.linalg.inv(P), compute_uv=False)
    return S[:, 0] / S[:, 1] - 1


def turned(F, Y, C):
    n1 = np.cross(Y[F[:, 1]] - Y[F[:, 0]], Y[F[:, 2]] - Y[F[:, 0]])
    n0 = np.cross(C[F[:, 1]] - C[F[:, 0]], C[F[:, 2]] - C[F[:, 0]])
    return int(((n1 * n0).sum(1) < 0).sum())


if __name__ == "__main__":
    print("n\tr\th\tbumps\t×2 x\t×2 y\t×1.5 x\t×2 z")
    for n, r, h, spacing, bumps in [(24, .25, .15, 1., 2), (32, .25, .15, 1., 2), (40, .25, .15, 1., 2),
                                    (48, .25, .15, 1., 2), (64, .25, .15, 1., 2), (32, .25, .3, 1., 2),
                                    (32, .2, .15, .6, 3), (40, .2, .15, .6, 3), (32, .3, .05, 1., 2)]:
        V, F, f = plate(n, r, h, spacing, bumps)
        core = f[F].min(1) >= 1
        cells = []
        for s in [(2, 1, 1), (1, 2, 1), (1.5, 1, 1), (1, 1, 2)]:
            Y = np.asarray(geotex.resize(V, F, features=f, scale=s).V)
            c = (V.max(0) + V.min(0)) / 2
            k = turned(F, Y, (V - c) * s + c)
            cells.append("%.2f%%" % (100 * anisotropy(F, V, Y)[core].max()) + (" (%d turned)" % k if k else ""))
        print("\t".join([str(n), str(r), str(h), str(bumps)] + cells))
