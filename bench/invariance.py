#!/usr/bin/env python3
"""Invariance of the defaults to units, placement and orientation (issues 24/25, fifteenth session).

A user supplies a model in millimetres or metres, far from the origin, y-up or z-up. For a similarity T the
default denoiser should give T(denoise(mesh)) and resize by a box scale should give T(resize(mesh)) (with the
scale's axes permuted when T swaps them). For each input and T this runs the default on T(mesh), maps the
result back with T^-1 and reports the largest vertex difference against the untransformed run in mean edge
lengths (max_diff), and the independent ruler's number for both runs (denoise: msae_deg against the clean
model; resize: detail-distortion's ratio), plus the denoiser's reading (creased_share) for both.

  PYTHONPATH=build/python /usr/bin/python3 bench/invariance.py [denoise|resize|all] [CASE,...] [T,...]

CASE: a name of DENOISE, or for resize a file under ../shared/data or gen:NAME@LEVEL (geotex.generate).
T: x1000, x0.001 (units), offset (+1e4 x the bounding-box diagonal along an oblique direction), rotx90 (y-up
<-> z-up), rot (an arbitrary rotation; denoise only). Resize scales y by 2 (the up axis of a y-up model);
under rotx90 the scale asked is z by 2. Prints a markdown table."""

import os
import sys
import time
import warnings

import numpy as np

import geotex

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "shared", "data")
sys.path.insert(0, os.path.join(HERE, "..", "..", "shared", "eval"))
import geval  # noqa: E402

DENOISE = {  # name: (noisy source, clean truth, noise options or None for a shared pair)
    "Block0.4": ("denoise/Block0.4/Noisy.obj", "denoise/Block0.4/Original.obj", None),
    "Fandisk0.3": ("denoise/Fandisk0.3/Noisy.obj", "denoise/Fandisk0.3/Original.obj", None),
    "Twelve0.5Imp": ("denoise/Twelve0.5Impulsive/Noisy.obj", "denoise/Twelve0.5Impulsive/Original.obj", None),
    "cow-n0.2": (None, "cow.obj", dict(sigma=0.2, seed=7)),
    "fandisk-n0.05": (None, "fandisk.obj", dict(sigma=0.05, seed=7)),
    "fandisk-striped0.3": (None, "fandisk.obj", dict(sigma=0.3, pattern="striped", seed=7)),
}
RESIZE = ["beetle.obj", "cow.obj", "fandisk.obj", "spot.obj", "teapot.obj"]
RESIZE_SCALE = np.array([1.0, 2.0, 1.0])


def rotation(axis, angle):
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


ROTX90 = np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]])  # y -> z, z -> -y: a y-up model made z-up
ROT = rotation((0.3, -0.5, 0.81), 1.1)


def transform(name, V):
    """(s, R, t) with T(x) = s R x + t."""
    diag = float(np.linalg.norm(V.max(0) - V.min(0)))
    eye, zero = np.eye(3), np.zeros(3)
    return {"x1000": (1000.0, eye, zero), "x0.001": (0.001, eye, zero),
            "offset": (1.0, eye, 1e4 * diag * np.array([0.6, -0.48, 0.64])),
            "rotx90": (1.0, ROTX90, zero), "rot": (1.0, ROT, zero)}[name]


def apply(T, V):
    s, R, t = T
    return s * V @ R.T + t


def invert(T, X):
    s, R, t = T
    return ((X - t) / s) @ R


def load(rel):
    if rel.startswith("gen:"):  # a generated shape, gen:NAME@LEVEL
        name, _, level = rel[4:].partition("@")
        V, F = geotex.generate(name, level=int(level or 0))
        return np.asarray(V, float), np.asarray(F)
    V, F = geotex.read_mesh(os.path.join(DATA, rel))
    return np.asarray(V, float), np.asarray(F)


def row(case, tname, mel, base, X, ruler_base, ruler_t, extra=""):
    diff = float(np.abs(X - base).max()) / mel if len(X) == len(base) else float("nan")
    print(f"| {case} | {tname} | {diff:.2e} | {ruler_base:.4f} | {ruler_t:.4f} | {extra} |", flush=True)
    return diff


def run_denoise(cases, tnames):
    print("| input | T | max_diff (edges) | msae_deg plain | msae_deg T | creased_share plain / T |")
    print("|---|---|---|---|---|---|")
    for case in cases:
        src, truth, noise = DENOISE[case]
        Vt, Ft = load(truth)
        if noise is None:
            V, F = load(src)
        else:
            V, F = Vt, Ft
            V = np.asarray(geotex.add_noise(V, F, **noise), float)
        mel = geotex.mean_edge_length(V, F)
        r0 = geotex.denoise(V, F)
        e0 = geval.normal_error((np.asarray(r0.V), np.asarray(r0.F)), (Vt, Ft))["msae_deg"]
        for tname in tnames:
            T = transform(tname, V)
            r = geotex.denoise(apply(T, V), F)
            X = invert(T, np.asarray(r.V, float))
            e = geval.normal_error((X, np.asarray(r.F)), (Vt, Ft))["msae_deg"]
            row(case, tname, mel, np.asarray(r0.V), X, e0, e, f"{r0.creased_share:.3f} / {r.creased_share:.3f}")


def run_resize(models, tnames):
    print("| model | T | max_diff (edges) | ratio plain | ratio T | method |")
    print("|---|---|---|---|---|---|")
    for model in models:
        V, F = load(model)
        mel = geotex.mean_edge_length(V, F)
        r0 = geotex.resize(V, F, scale=tuple(RESIZE_SCALE))
        q0 = geval.detail_distortion((V, F), (np.asarray(r0.V), F), RESIZE_SCALE)["ratio"]
        for tname in tnames:
            if tname == "rot":
                continue  # an arbitrary rotation changes what a box scale means
            T = transform(tname, V)
            S = np.abs(T[1]) @ RESIZE_SCALE  # the asked axes carried by the rotation (a permutation here)
            r = geotex.resize(apply(T, V), F, scale=tuple(S))
            X = invert(T, np.asarray(r.V, float))
            q = geval.detail_distortion((V, F), (X, F), RESIZE_SCALE)["ratio"]
            row(model, tname, mel, np.asarray(r0.V), X, q0, q, f"{r0.method} / {r.method}")


def main(argv):
    what = argv[0] if argv else "all"
    tnames = argv[2].split(",") if len(argv) > 2 else ["x1000", "x0.001", "offset", "rotx90", "rot"]
    warnings.simplefilter("ignore")
    t0 = time.time()
    if what in ("denoise", "all"):
        run_denoise(argv[1].split(",") if len(argv) > 1 and argv[1] else list(DENOISE), tnames)
    if what in ("resize", "all"):
        run_resize(argv[1].split(",") if len(argv) > 1 and argv[1] and what == "resize" else RESIZE, tnames)
    print(f"\n{time.time() - t0:.0f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
