#!/usr/bin/env python3
"""Scanner noise grid (issue 24): striped, low-frequency and depth-direction noise on CAD parts and organic
models; the default denoiser against itself with the reading forced each way (--creased, --no-creased). Error:
the independent ruler's mean face-normal error (../shared/eval/geval.py normal_error, msae_deg) against the
clean model; noise geotex.add_noise(seed=7).

  PYTHONPATH=build/python /usr/bin/python3 bench/denoise_scanner.py [MODEL,...] [NOISE,...] [OPTION=VALUE ...]

MODEL: a file under ../shared/data or gen:NAME@LEVEL (geotex.generate); NOISE: names of NOISES below. An
OPTION=VALUE is passed to the default only (a variant measured against the same forced readings). Prints a
markdown table and the summary (within 2 % of the better forced reading)."""

import os
import sys
import warnings

import numpy as np

import geotex

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "shared", "data")
sys.path.insert(0, os.path.join(HERE, "..", "..", "shared", "eval"))
import geval  # noqa: E402

OBLIQUE = (0.3, 0.4, 0.866)  # a viewing axis off the models' own axes
NOISES = {
    "striped0.2": dict(sigma=0.2, pattern="striped"),
    "striped0.3": dict(sigma=0.3, pattern="striped"),
    "striped0.5": dict(sigma=0.5, pattern="striped"),
    "striped0.3w4": dict(sigma=0.3, pattern="striped", wavelength=4),
    "striped0.3w16": dict(sigma=0.3, pattern="striped", wavelength=16),
    "striped0.3obl": dict(sigma=0.3, pattern="striped", axis=OBLIQUE),
    "lowfreq0.3": dict(sigma=0.3, pattern="low-frequency"),
    "lowfreq0.5w4": dict(sigma=0.5, pattern="low-frequency", wavelength=4),
    "depth0.2": dict(sigma=0.2, direction="depth", axis=OBLIQUE),
    "depth0.5": dict(sigma=0.5, direction="depth", axis=OBLIQUE),
}
MODELS = ["fandisk.obj", "gen:cube@4", "gen:cylinder@2", "woody.obj", "spot.obj", "cow.obj", "stanford-bunny.obj"]


def load(name):
    if name.startswith("gen:"):
        gen, _, level = name[4:].partition("@")
        V, F = geotex.generate(gen, level=int(level or 1))
    else:
        V, F = geotex.read_mesh(os.path.join(DATA, name))
    return np.asarray(V, float), np.asarray(F)


def value(text):
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return {"true": True, "false": False}.get(text, text)


def main():
    args = [a for a in sys.argv[1:] if "=" not in a]
    variant = {k: value(v) for k, _, v in (a.partition("=") for a in sys.argv[1:] if "=" in a)}
    models = args[0].split(",") if args and args[0] else MODELS
    noises = args[1].split(",") if len(args) > 1 and args[1] else list(NOISES)
    print("| model | noise | input | creased (forced) | smooth (forced) | **default** | ratio to the better forced "
          "| creased share |")
    print("|---|---|---|---|---|---|---|---|")
    ratios = []
    for m in models:
        V, F = load(m)
        err = lambda X: geval.normal_error((np.asarray(X, float), F), (V, F))["msae_deg"]
        for name in noises:
            Xn = np.asarray(geotex.add_noise(V, F, seed=7, **NOISES[name]))
            ec = err(geotex.denoise(Xn, F, creased=True).V)
            es = err(geotex.denoise(Xn, F, creased=False).V)
            r = geotex.denoise(Xn, F, **variant)
            ed = err(r.V)
            ratios.append(ed / min(ec, es))
            print(f"| {m} | {name} | {err(Xn):.2f} | {ec:.3f} | {es:.3f} | **{ed:.3f}** | {ratios[-1]:.3f} "
                  f"| {r.creased_share:.2f} |", flush=True)
    print(f"\nratio to the better forced reading: mean {np.mean(ratios):.3f}, worst {np.max(ratios):.3f}; "
          f"within 2 %: {sum(x <= 1.02 for x in ratios)} of {len(ratios)}")


if __name__ == "__main__":
    warnings.simplefilter("ignore")
    main()
