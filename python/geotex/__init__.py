"""geotex: 3D shape modeling with high-level descriptors (after V. Andersen, DTU 2011).

Meshes are numpy arrays: V (#V×3 float64 positions) and F (#F×3 int triangles). Every function
takes keyword options with the same defaults as the command line (`geotex <command> --help`).
Errors raise geotex.InvalidInput (a ValueError), geotex.IoError (an OSError) or
geotex.SolverError (a RuntimeError); all derive from geotex.Error except the first two, which
derive from the Python built-ins.

    import geotex
    V, F = geotex.generate("cube")
    Vn = geotex.add_noise(V, F, sigma=0.3)
    Vs = geotex.smooth(Vn, F, steps=3)
    print(geotex.compare(Vs, F, V, F)["mean_normal_error_deg"])
"""

from ._geotex import *  # noqa: F401,F403
from ._geotex import Error, InvalidInput, IoError, SolverError  # noqa: F401

__version__ = "0.1.0"
