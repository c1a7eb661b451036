"""Issue 24, headroom: the default denoiser against one-at-a-time variations of its smoothing knobs (an oracle:
the best of the sweep, which knows the truth), on synthetic noise of the shared organic models.

Usage: PYTHONPATH=build/python python3 bench/denoise_headroom.py [models,comma,separated] [--seed=7]
       [--noises=g0.05,g0.1,g0.2,g0.3,imp] [--data=DIR] (the shared models; default ../shared/data)
Prints one JSON line per run (model, noise, seed, the option changed, the mean face-normal error in degrees,
seconds); bench/denoise.md (thirteenth session) has the table it made. Noise: geotex.add_noise(seed), Gaussian
σ in mean edge lengths, imp = σ 0.6 on 10 % of the vertices.
"""
import json, sys, time, warnings
from pathlib import Path
import geotex

sys.path.insert(0, str(Path(__file__).resolve().parent))
from denoise_reading import load  # noqa: E402

warnings.simplefilter("ignore")
MODELS = ["stanford-bunny.obj", "spot.obj", "cow.obj", "cheburashka.obj", "igea.ply"]
# Each knob that sets how strongly the default smooths, below and above its default (AutoDenoiseOptions).
VARIATIONS = [{}, dict(mild_iterations=2), dict(mild_iterations=6), dict(mild_iterations=10),
              dict(fit_iterations=5), dict(fit_iterations=10), dict(fit_iterations=40), dict(fit_iterations=80),
              dict(relief_floor=0.0), dict(relief_floor=0.05), dict(relief_floor=0.4), dict(relief_floor=1e6),
              dict(light_fit_iterations=1), dict(light_fit_iterations=8), dict(light_iterations=0),
              dict(light_iterations=2), dict(strong_floor=0.0), dict(strong_floor=0.1), dict(coherence_weight=0.0),
              dict(coherence_weight=1.0), dict(keep_below=0.01), dict(keep_below=0.03)]
opt = dict(a[2:].split("=", 1) for a in sys.argv[1:] if a.startswith("--") and "=" in a)
args = [a for a in sys.argv[1:] if not a.startswith("--")]
data, seed = Path(opt.get("data", "../shared/data")), int(opt.get("seed", 7))
for m in (args[0].split(",") if args else MODELS):
    V, F = load(data, m)
    for name in opt.get("noises", "g0.05,g0.1,g0.2,g0.3,imp").split(","):
        kw = dict(sigma=0.6, impulsive_fraction=0.1) if name == "imp" else dict(sigma=float(name[1:]))
        Vn = geotex.add_noise(V, F, seed=seed, **kw)
        for v in VARIATIONS:
            t = time.time()
            err = geotex.compare(geotex.denoise(Vn, F, **v).V, F, V, F)["mean_normal_error_deg"]
            print(json.dumps(dict(model=m, noise=name, seed=seed, var=v, err=err, t=round(time.time() - t, 2))), flush=True)
