# One step of the default denoiser against the default with that step off (the previous release), on clean
# and noisy models: mean face-normal error (degrees) against the clean model, noise geotex.add_noise(seed=7),
# and the share the step reports (a result field).
#   PYTHONPATH=build/python /usr/bin/python3 bench/denoise_step.py OPTION=OFF SHARE [model ...] > table.md
# e.g. step 6a: coherence_weight=0 change_kept_share; step 5c: strong_floor=0 strong_share.
# model: a file under ../shared/data, or gen:NAME[@LEVEL] (geotex.generate(NAME, level=LEVEL)).
import os, sys, time, warnings
import numpy as np
import geotex
warnings.simplefilter("ignore")
DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data")
NOISE = {"clean": {}, "g0.05": dict(sigma=0.05), "g0.1": dict(sigma=0.1), "g0.2": dict(sigma=0.2),
         "g0.3": dict(sigma=0.3), "g0.5": dict(sigma=0.5), "g0.7": dict(sigma=0.7),
         "n0.3": dict(sigma=0.3, direction="normal"), "imp": dict(sigma=0.6, impulsive_fraction=0.1),
         "striped0.3": dict(sigma=0.3, pattern="striped"), "lowfreq0.3": dict(sigma=0.3, pattern="low-frequency"),
         "depth0.1": dict(sigma=0.1, direction="depth")}


def normals(P, F):
    n = np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def error(P, F, T):
    return np.degrees(np.arccos(np.clip((normals(P, F) * normals(T, F)).sum(1), -1, 1))).mean()


def load(name):
    if name.startswith("gen:"):
        gen, _, level = name[4:].partition("@")
        return geotex.generate(gen, level=int(level)) if level else geotex.generate(gen)
    return geotex.read_mesh(os.path.join(DATA, name))


off_name, _, off_value = sys.argv[1].partition("=")
off = {off_name: float(off_value)}
share = sys.argv[2]
models = sys.argv[3:] or ["spot.obj", "cheburashka.obj", "cow.obj", "stanford-bunny.obj", "beetle.obj", "fandisk.obj",
                          "teapot.obj", "woody.obj", "gen:sphere", "gen:torus", "gen:spiky-sphere", "igea.ply"]
print(f"| model | noise | input | previous ({off_name} {off_value}) | **default** | ratio | {share} | CPU s prev / new |")
print("|---|---|---|---|---|---|---|---|")
ratios = {}
for m in models:
    V, F = load(m)
    V, F = np.asarray(V), np.asarray(F)
    for kind, kw in NOISE.items():
        X = np.asarray(geotex.add_noise(V, F, seed=7, **kw)) if kw else V
        t0 = time.process_time()
        prev = geotex.denoise(X, F, **off)
        t1 = time.process_time()
        new = geotex.denoise(X, F)
        t2 = time.process_time()
        e0, e1 = error(np.asarray(prev.V), F, V), error(np.asarray(new.V), F, V)
        ratio = e1 / e0 if e0 > 1e-9 else 1.0
        ratios.setdefault(kind, []).append(ratio)
        print(f"| {m} | {kind} | {error(X, F, V):.2f} | {e0:.2f} | **{e1:.2f}** | {ratio:.3f} | "
              f"{new[share]:.2f} | {t1 - t0:.2f} / {t2 - t1:.2f} |", flush=True)
print()
print("| noise | mean ratio | worst | better (< 0.99) | worse (> 1.01) |")
print("|---|---|---|---|---|")
for kind, r in ratios.items():
    r = np.array(r)
    print(f"| {kind} | {r.mean():.3f} | {r.max():.3f} | {(r < 0.99).sum()} | {(r > 1.01).sum()} |")
