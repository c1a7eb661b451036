#!/usr/bin/env python3
"""The default denoiser's reading per region against both forced readings (issue 24), on synthetic noise
of the shared clean models: mean face-normal error (degrees) with each way of deciding the reading (the
hand-made rule, the learned model, the default combination), the creased share, CPU seconds.

Usage: PYTHONPATH=build/python /usr/bin/python3 bench/denoise_reading.py [DATA_DIR] [MODEL,...] [scanner]
(writes a markdown table on stdout; "mixed" is fandisk and spot, scaled to one edge length, in one mesh)."""

import sys
import time
from pathlib import Path

import numpy as np

import geotex

ROOT = Path(__file__).resolve().parent.parent
NOISES = [("g0.1", dict(sigma=0.1)), ("g0.2", dict(sigma=0.2)), ("g0.5", dict(sigma=0.5)),
          ("n0.3", dict(sigma=0.3, along_normal=True)), ("imp", dict(sigma=0.6, impulsive_fraction=0.1))]
# Scanner-like noise (not i.i.d.): correlated over ~8 edges, banded, and along one viewing axis.
SCANNER_NOISES = [("lowfreq0.3", dict(sigma=0.3, pattern="low-frequency")), ("striped0.3", dict(sigma=0.3, pattern="striped")),
                  ("depth0.3", dict(sigma=0.3, direction="depth", axis=(0.3, 0.4, 0.866)))]
MODELS = ["fandisk.obj", "gen:cube", "woody.obj", "spot.obj", "cheburashka.obj", "teapot.obj", "cow.obj", "mixed"]


def load(data, name):
    if name.startswith("gen:"):
        return geotex.generate(name[4:], level=4)
    if name == "mixed":
        A, FA = load(data, "fandisk.obj")
        B, FB = load(data, "spot.obj")
        B = B * (geotex.mean_edge_length(A, FA) / geotex.mean_edge_length(B, FB))
        B = B - B.mean(0) + A.mean(0) + [np.ptp(A, 0).max() * 1.5, 0, 0]
        return np.vstack([A, B]), np.vstack([FA, FB + len(A)])
    V, F = geotex.read_mesh(str(data / name))
    return np.asarray(V), np.asarray(F)


def main() -> None:
    data = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT.parent / "shared" / "data"
    models = sys.argv[2].split(",") if len(sys.argv) > 2 else MODELS
    noises = SCANNER_NOISES if len(sys.argv) > 3 and sys.argv[3] == "scanner" else NOISES
    err = lambda V, F, X: geotex.compare(X, F, V, F)["mean_normal_error_deg"]
    print("| model | noise | creased (forced) | smooth (forced) | rule | learned | **default (combined)** | ratio to the better "
          "forced: rule | learned | **combined** | creased share | CPU s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    ratios, rule_ratios, learned_ratios = [], [], []
    for m in models:
        V, F = load(data, m)
        for name, kw in noises:
            Vn = geotex.add_noise(V, F, seed=7, **kw)
            es = err(V, F, geotex.denoise(Vn, F, creased=True).V)
            em = err(V, F, geotex.denoise(Vn, F, creased=False).V)
            er = err(V, F, geotex.denoise(Vn, F, reading="rule").V)
            rule_ratios.append(er / min(es, em))
            el = err(V, F, geotex.denoise(Vn, F, reading="learned").V)
            learned_ratios.append(el / min(es, em))
            t = time.process_time()
            r = geotex.denoise(Vn, F)
            t = time.process_time() - t
            e = err(V, F, r.V)
            ratios.append(e / min(es, em))
            print(f"| {m} | {name} | {es:.2f} | {em:.2f} | {er:.2f} | {el:.2f} | **{e:.2f}** | {rule_ratios[-1]:.3f} "
                  f"| {learned_ratios[-1]:.3f} | **{ratios[-1]:.3f}** | {r.creased_share:.2f} | {t:.2f} |", flush=True)
    for label, rs in (("rule", rule_ratios), ("learned", learned_ratios), ("combined (default)", ratios)):
        print(f"\n{label}: ratio to the better forced reading: mean {np.mean(rs):.3f}, worst {np.max(rs):.3f}; "
              f"within 2%: {sum(x <= 1.02 for x in rs)} of {len(rs)}")


if __name__ == "__main__":
    import warnings
    warnings.simplefilter("ignore")
    main()
