#!/usr/bin/python3
"""Valid but hard meshes for the cost checks of issue 30 (bench/bad-input.md, tests/cli_properties.py).

  fan       N triangles around one vertex (valence N): a cone over a circle
  disjoint  N separate triangles on a grid (N components)
  needles   N separate long thin triangles at random (aspect about 1e4)
  comb      two fans of N/2 triangles side by side (a square split around two high-valence vertices)

Usage: hard_meshes.py KIND N OUT.ply [--seed S]   (binary little-endian PLY, double coordinates)
Importable: `mesh(kind, n, seed)` returns (V #V by 3 float64, F #F by 3 int32).
"""

import argparse
import sys

import numpy as np


def fan(n):
    t = 2 * np.pi * np.arange(n) / n
    V = np.vstack([[0.0, 0.0, 0.2], np.column_stack([np.cos(t), np.sin(t), np.zeros(n)])])
    i = np.arange(n)
    F = np.column_stack([np.zeros(n, dtype=np.int64), 1 + i, 1 + (i + 1) % n])
    return V, F


def disjoint(n):
    side = int(np.ceil(np.sqrt(n)))
    k = np.arange(n)
    origin = np.column_stack([k % side, k // side, np.zeros(n)]).astype(float)
    corner = np.array([[0.0, 0.0, 0.0], [0.8, 0.0, 0.0], [0.0, 0.8, 0.1]])
    V = (origin[:, None, :] + corner[None, :, :]).reshape(-1, 3)
    F = np.arange(3 * n).reshape(n, 3)
    return V, F


def needles(n, seed):
    rng = np.random.default_rng(seed)
    a = rng.uniform(-1, 1, (n, 3))
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    b = a + 0.5 * d                                   # length 0.5
    w = np.cross(d, rng.normal(size=(n, 3)))
    w /= np.linalg.norm(w, axis=1)[:, None]
    c = 0.5 * (a + b) + 5e-5 * w                      # width 5e-5: aspect 1e4
    V = np.stack([a, b, c], axis=1).reshape(-1, 3)
    F = np.arange(3 * n).reshape(n, 3)
    return V, F


def comb(n):
    """The square [0,1] x [-1,1] split into two fans of valence about n/2: the upper half around spine
    vertex 0 = (0,0), the lower half around spine vertex 1 = (1,0), each over a row of n/2 tips."""
    h = n // 2 - 1
    s = np.linspace(0.0, 1.0, h + 1)
    top = np.column_stack([s, np.ones(h + 1), 0.05 * np.sin(40 * s)])
    bottom = np.column_stack([s, -np.ones(h + 1), 0.05 * np.cos(40 * s)])
    V = np.vstack([[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], top, bottom])
    t0, u0 = 2, 2 + h + 1
    k = np.arange(h)
    upper = np.column_stack([np.zeros(h, dtype=np.int64), t0 + k + 1, t0 + k])
    lower = np.column_stack([np.ones(h, dtype=np.int64), u0 + k, u0 + k + 1])
    F = np.vstack([upper, [[t0 + h, 0, 1]], lower, [[0, u0, 1]]])
    return V, F


def mesh(kind, n, seed=1):
    if kind == "fan":
        return fan(n)
    if kind == "disjoint":
        return disjoint(n)
    if kind == "needles":
        return needles(n, seed)
    if kind == "comb":
        return comb(n)
    raise ValueError(f"unknown kind {kind!r} (fan, disjoint, needles, comb)")


def write_ply(path, V, F):
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {len(V)}\nproperty double x\nproperty double y\nproperty double z\n"
              f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n").encode()
    faces = np.zeros(len(F), dtype=[("n", "u1"), ("i", "<i4", 3)])
    faces["n"] = 3
    faces["i"] = F
    with open(path, "wb") as f:
        f.write(header)
        f.write(np.ascontiguousarray(V, dtype="<f8").tobytes())
        f.write(faces.tobytes())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("kind", choices=["fan", "disjoint", "needles", "comb"])
    ap.add_argument("n", type=int, help="number of triangles")
    ap.add_argument("out")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    V, F = mesh(a.kind, a.n, a.seed)
    write_ply(a.out, V, F)
    print(f"{a.out}: {len(V)} vertices, {len(F)} faces")
    return 0


if __name__ == "__main__":
    sys.exit(main())
