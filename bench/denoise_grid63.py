"""Issue 24's grid: the default denoiser against both forced readings on synthetic noise of the nine shared models.

Usage: PYTHONPATH=build/python python3 bench/denoise_grid63.py [models,comma,separated] [--default-only]
       [--data=DIR] (the shared models; default ../shared/data, as bench/denoise_reading.py)
Prints one JSON line per case (model, noise, creased, smooth, default, ratio to the better forced reading).
Noise: geotex.add_noise(seed=7), Gaussian σ 0.05-0.7 (mean edge lengths) and impulsive (σ 0.6 on 10 %).
"""
import json, sys, warnings
from pathlib import Path
import geotex

sys.path.insert(0, str(Path(__file__).resolve().parent))
from denoise_reading import load  # noqa: E402

warnings.simplefilter("ignore")
MODELS = ["fandisk.obj", "woody.obj", "spot.obj", "cheburashka.obj", "teapot.obj", "cow.obj", "stanford-bunny.obj",
          "beetle.obj", "igea.ply"]
NOISES = [("g0.05", dict(sigma=0.05)), ("g0.1", dict(sigma=0.1)), ("g0.2", dict(sigma=0.2)), ("g0.3", dict(sigma=0.3)),
          ("g0.5", dict(sigma=0.5)), ("g0.7", dict(sigma=0.7)), ("imp", dict(sigma=0.6, impulsive_fraction=0.1))]
args = [a for a in sys.argv[1:] if not a.startswith("--")]
default_only = "--default-only" in sys.argv
data = Path(next((a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith("--data=")), "../shared/data"))
for m in (args[0].split(",") if args and args[0] else MODELS):
    V, F = load(data, m)
    for name, kw in NOISES:
        Vn = geotex.add_noise(V, F, seed=7, **kw)
        err = lambda r: geotex.compare(r.V, F, V, F)["mean_normal_error_deg"]
        row = dict(model=m, noise=name, default=err(geotex.denoise(Vn, F)))
        if not default_only:
            row["creased"], row["smooth"] = err(geotex.denoise(Vn, F, creased=True)), err(geotex.denoise(Vn, F, creased=False))
            row["ratio"] = row["default"] / min(row["creased"], row["smooth"])
        print(json.dumps(row), flush=True)
