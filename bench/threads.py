#!/usr/bin/env python3
"""Largest output difference between 1 and 2 OpenMP threads, per operation, relative to the bounding-box
diagonal, on two shared models with noise (issue 33). The operations are those of
python/tests/core/test_determinism.py (the test asserts < 1e-9 on a generated cube).

Usage: PYTHONPATH=build/python /usr/bin/python3 bench/threads.py [DATA_DIR]   (writes a table on stdout)"""

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "python" / "tests"))
import geotex  # noqa: E402
from test_determinism import thread_cases, _first_array  # noqa: E402


def main() -> None:
    data = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT.parent / "shared" / "data"
    models = ["fandisk.obj", "spot.obj"]
    print("| operation | " + " | ".join(models) + " |")
    print("|---|" + "---|" * len(models))
    rows = {}
    for m in models:
        V, F = geotex.read_mesh(str(data / m))
        diag = float(np.linalg.norm(V.max(0) - V.min(0)))
        sigma = 0.2  # in mean edge lengths (geotex noise's unit)
        Vn = geotex.add_noise(V, F, sigma=sigma, seed=1)
        for name, call in thread_cases(Vn, F):
            a, b = _first_array(call(1)), _first_array(call(2))
            rows.setdefault(name, []).append(float(np.abs(a - b).max()) / diag)
    # parametrize needs a disk: a generated bumpy plate (the two models are closed).
    P, Q = geotex.generate("bumpy-plate", level=3)
    diag = float(np.linalg.norm(P.max(0) - P.min(0)))
    for name, call in thread_cases(geotex.add_noise(P, Q, sigma=0.2, seed=1), Q):
        if name == "param":
            a, b = _first_array(call(1)), _first_array(call(2))
            rows["param (bumpy-plate disk, both columns)"] = [float(np.abs(a - b).max()) / diag] * len(models)
    for name, ds in rows.items():
        print(f"| {name} | " + " | ".join(f"{d:.1e}" for d in ds) + " |")


if __name__ == "__main__":
    main()
