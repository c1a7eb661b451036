#!/usr/bin/env python3
"""Noise that differs by region (issue 24): one half of a model noisier than the other (split by a plane through the
centre), a gradient of σ along one axis, a noisy blob (about 15 % of the area) on a quiet model. Per region, the
independent ruler's face-normal angle (../shared/eval/geval.py's measure, per face) of the input, the default, both
forced readings (--creased, --no-creased) and the ideal per-region answer: the model denoised (default) under
uniform noise at the region's own σ (the same noise draw, scaled), read on that region; a noise-free region's ideal
is the input as it is (0°). Noise: geotex.add_noise(sigma=1, seed=7) scaled per vertex (random directions, mean edge
lengths).

  PYTHONPATH=build/python /usr/bin/python3 bench/denoise_mixed_levels.py [MODEL,...] [CASE,...] [--no-forced]
      [OPTION=VALUE ...]

MODEL: a file under ../shared/data or gen:NAME@LEVEL (geotex.generate); CASE: names of CASES below. An OPTION=VALUE
is passed to the default only. Prints a markdown table (regions: q the quieter, n the noisier) and a summary: the
mean over the cases of each region's error of the default over its ideal's (a noise-free region: over the input's
noisier region's ideal, so that 0° stays 0) and the clean regions' mean error."""

import os
import sys
import warnings

import numpy as np

import geotex

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "shared", "eval"))
import geval  # noqa: E402

sys.path.insert(0, HERE)
from denoise_scanner import OBLIQUE, load, value  # noqa: E402  (one loader for the scanner-noise benches)

# name: (kind, parameters). half: σ on the side of the plane through the centre along `axis` the normal points to
# (n), σ on the other (q); gradient: σ from q to n along `axis` (the regions: the two halves); blob: σ n within the
# ball about the vertex farthest along `axis` holding 15 % of the area, q elsewhere.
CASES = {
    "half0.3/0.05x": ("half", dict(n=0.3, q=0.05, axis=(1, 0, 0))),
    "half0.3/0x": ("half", dict(n=0.3, q=0.0, axis=(1, 0, 0))),
    "grad0.05-0.5x": ("gradient", dict(n=0.5, q=0.05, axis=(1, 0, 0))),
    "blob0.4/0.05": ("blob", dict(n=0.4, q=0.05, axis=(0, 1, 0))),
    # held out (never tuned on): other planes, other pairs
    "half0.5/0.1y": ("half", dict(n=0.5, q=0.1, axis=(0, 1, 0))),
    "half0.2/0obl": ("half", dict(n=0.2, q=0.0, axis=OBLIQUE)),
    "half0.3/0.05z": ("half", dict(n=0.3, q=0.05, axis=(0, 0, 1))),
    "blob0.3/0z": ("blob", dict(n=0.3, q=0.0, axis=(0, 0, 1))),
}
TUNED = ["half0.3/0.05x", "half0.3/0x", "grad0.05-0.5x", "blob0.4/0.05"]
MODELS = ["fandisk.obj", "stanford-bunny.obj", "cow.obj", "spot.obj", "gen:cube@4", "gen:cylinder@2"]


def face_angles(X, V, F):
    """Per face, the angle (degrees) between the result's and the truth's normals (geval.normal_error's msae_deg)."""
    fn, _ = geval.face_normals(np.asarray(X, float), F)
    ft, _ = geval.face_normals(V, F)
    return np.degrees(np.arccos(np.clip((fn * ft).sum(1), -1, 1)))


def sigma_field(kind, p, V, F):
    """Per vertex σ, and per face the region (True: the noisier), the regions' own σ (q, n) for the ideal runs."""
    a = np.asarray(p["axis"], float)
    a = a / np.linalg.norm(a)
    t = (V - 0.5 * (V.max(0) + V.min(0))) @ a
    if kind == "half":
        s = np.where(t > 0, p["n"], p["q"])
        noisy = s[F].mean(1) > 0.5 * (p["n"] + p["q"])
        return s, noisy, (p["q"], p["n"])
    if kind == "gradient":
        u = (t - t.min()) / max(np.ptp(t), 1e-300)
        s = p["q"] + (p["n"] - p["q"]) * u
        noisy = u[F].mean(1) > 0.5
        return s, noisy, (p["q"] + 0.25 * (p["n"] - p["q"]), p["q"] + 0.75 * (p["n"] - p["q"]))
    # blob: the ball about the vertex farthest along the axis holding 15 % of the area (by face centroids)
    _, area = geval.face_normals(V, F)
    d = np.linalg.norm(V[F].mean(1) - V[np.argmax(t)], axis=1)
    order = np.argsort(d)
    r = d[order[np.searchsorted(np.cumsum(area[order]), 0.15 * area.sum())]]
    s = np.where(np.linalg.norm(V - V[np.argmax(t)], axis=1) <= r, p["n"], p["q"])
    noisy = s[F].mean(1) > 0.5 * (p["n"] + p["q"])
    return s, noisy, (p["q"], p["n"])


def main():
    args = [a for a in sys.argv[1:] if "=" not in a and not a.startswith("--")]
    variant = {k: value(v) for k, _, v in (a.partition("=") for a in sys.argv[1:] if "=" in a)}
    forced = "--no-forced" not in sys.argv
    models = args[0].split(",") if args and args[0] else MODELS
    cases = args[1].split(",") if len(args) > 1 and args[1] else TUNED
    print("| model | case | region | input | creased (forced) | smooth (forced) | **default** | ideal (uniform at its "
          "σ) | default / ideal |")
    print("|---|---|---|---|---|---|---|---|---|")
    ratios, clean = [], []
    for m in models:
        V, F = load(m)
        D1 = np.asarray(geotex.add_noise(V, F, sigma=1.0, seed=7)) - V  # one draw, scaled per vertex
        for name in cases:
            kind, p = CASES[name]
            s, noisy, (sq, sn) = sigma_field(kind, p, V, F)
            Xn = V + s[:, None] * D1
            runs = {"input": Xn, "default": geotex.denoise(Xn, F, **variant).V}
            if forced:
                runs["creased"] = geotex.denoise(Xn, F, creased=True).V
                runs["smooth"] = geotex.denoise(Xn, F, creased=False).V
            ideal = {}
            for region, sig in (("q", sq), ("n", sn)):
                ideal[region] = (face_angles(geotex.denoise(V + sig * D1, F).V, V, F) if sig > 0
                                 else np.zeros(len(F)))
            ang = {k: face_angles(X, V, F) for k, X in runs.items()}
            for region, mask in (("q", ~noisy), ("n", noisy)):
                e = {k: a[mask].mean() for k, a in ang.items()}
                ei = ideal[region][mask].mean()
                ref = ei if ei > 0 else ideal["n"][noisy].mean()
                ratio = 1 + (e["default"] - ei) / ref
                ratios.append(ratio)
                if ei == 0:
                    clean.append(e["default"])
                cells = " | ".join(f"{e[k]:.3f}" if k in e else "-" for k in ("input", "creased", "smooth"))
                print(f"| {m} | {name} | {region} ({sq if region == 'q' else sn:g}) | {cells} | **{e['default']:.3f}** "
                      f"| {ei:.3f} | {ratio:.3f} |", flush=True)
    print(f"\ndefault over the ideal per region: mean {np.mean(ratios):.3f}, worst {np.max(ratios):.3f} "
          f"({len(ratios)} regions)" + (f"; noise-free regions' mean error {np.mean(clean):.3f}°" if clean else ""))


if __name__ == "__main__":
    warnings.simplefilter("ignore")
    main()
