#!/usr/bin/env python3
"""Held-out cases of issue 24's fifteenth session (the noise per region): the cylinder under depth noise along its
own axis and along an oblique one, the level-3 sphere under oblique depth noise, and fandisk under white σ 0.3
beside a clean spot (one mesh). Prints the input's and the default's error (../shared/eval/geval.py msae), the
mesh's normal_sigma, the medians of the result's noise_map over the two regions of each case (the caps / the side;
facing the axis / not; fandisk / spot) and the noise choice lines.

  PYTHONPATH=build/python /usr/bin/python3 bench/denoise_region_noise.py [CASE,...] [--forced] [OPTION=VALUE ...]

--forced adds both forced readings."""
import os, sys
import numpy as np
import geotex
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "eval"))
import geval
D = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data")
OBL = (0.3, 0.4, 0.866)

def err(X, F, V):
    return geval.normal_error((np.asarray(X, float), F), (V, F))["msae_deg"]

def gen(name, level):
    V, F = geotex.generate(name, level=level)
    return np.asarray(V, float), np.asarray(F)

def mixed():
    V1, F1 = geotex.read_mesh(os.path.join(D, "fandisk.obj"))
    V2, F2 = geotex.read_mesh(os.path.join(D, "spot.obj"))
    V1, V2 = np.asarray(V1, float), np.asarray(V2, float)
    F1, F2 = np.asarray(F1), np.asarray(F2)
    def me(V, F):
        E = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
        return np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1).mean()
    V2 = V2 * (me(V1, F1) / me(V2, F2))
    V2 = V2 - V2.mean(0) + V1.mean(0) + np.array([np.ptp(V1[:, 0]) + np.ptp(V2[:, 0]), 0, 0])
    Xn1 = np.asarray(geotex.add_noise(V1, F1, sigma=0.3, seed=11))
    V = np.vstack([V1, V2]); F = np.vstack([F1, F2 + len(V1)])
    Xn = np.vstack([Xn1, V2])
    part = np.r_[np.zeros(len(V1)), np.ones(len(V2))]
    return V, F, Xn, part

CASES = {
  "cyl2_axis0.3": lambda: (lambda V, F: (V, F, np.asarray(geotex.add_noise(V, F, sigma=0.3, direction="depth", axis=(0, 0, 1), seed=11)), (np.abs(V[:, 2]) > 0.499).astype(float)))(*gen("cylinder", 2)),
  "cyl2_depth0.2": lambda: (lambda V, F: (V, F, np.asarray(geotex.add_noise(V, F, sigma=0.2, direction="depth", axis=OBL, seed=7)), (np.abs(V[:, 2]) > 0.499).astype(float)))(*gen("cylinder", 2)),
  "cyl2_depth0.5": lambda: (lambda V, F: (V, F, np.asarray(geotex.add_noise(V, F, sigma=0.5, direction="depth", axis=OBL, seed=7)), (np.abs(V[:, 2]) > 0.499).astype(float)))(*gen("cylinder", 2)),
  "sph3_depth0.3": lambda: (lambda V, F: (V, F, np.asarray(geotex.add_noise(V, F, sigma=0.3, direction="depth", axis=OBL, seed=11)), (np.abs(V @ np.array(OBL)) / np.linalg.norm(V, axis=1) > 0.7).astype(float)))(*gen("sphere", 3)),
  "mixed": mixed,
}

def main():
    names = sys.argv[1].split(",") if len(sys.argv) > 1 and sys.argv[1] and "=" not in sys.argv[1] and not sys.argv[1].startswith("--") else list(CASES)
    kw = dict(a.split("=") for a in sys.argv[2:] if "=" in a)
    kw = {k: float(v) for k, v in kw.items()}
    forced = "--forced" in sys.argv
    for n in names:
        V, F, Xn, part = CASES[n]()
        r = geotex.denoise(Xn, F, **kw)
        m = np.asarray(getattr(r, "noise_map", np.zeros(len(V))))
        line = f"{n}: input {err(Xn, F, V):.3f} default {err(r.V, F, V):.3f} sigma {r.noise['normal_sigma']:.4f}"
        line += f" map part1 median {np.median(m[part > 0]):.4f} part0 median {np.median(m[part == 0]):.4f}"
        if forced:
            line += f" creased {err(geotex.denoise(Xn, F, creased=True, **kw).V, F, V):.3f} smooth {err(geotex.denoise(Xn, F, creased=False, **kw).V, F, V):.3f}"
        print(line, flush=True)
        for c in r.choices:
            if "noise" in c: print("   ", c)

main()
