"""Issue 27: faces turned against the base, measured on the meshes alone (no report): among the relief's faces
(a corner displaced by over 5 % of the largest displacement), the area share of those whose normal points
against the base's normal at the same face (and turned beyond 120 and 150 degrees from it). MESH and BASE share their connectivity (a synthesis output and
its refined base, or an exemplar and its base). With --radial, also the share of all faces whose normal points
towards the centroid (the test the issue's line was first read with; a sphere only).
Usage: inward_faces.py MESH BASE [--radial] (geval.py's readers: $GEVAL or ../../shared/eval/geval.py)."""
import importlib.util
import json
import os
import sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location(
    "geval", os.environ.get("GEVAL", os.path.join(here, "../../shared/eval/geval.py")))
geval = importlib.util.module_from_spec(spec)
spec.loader.exec_module(geval)


def main(argv):
    V, F = geval.read_mesh(argv[0])
    B, G = geval.read_mesh(argv[1])
    if V.shape != B.shape or not np.array_equal(F, G):
        sys.exit("MESH and BASE must share their connectivity")
    d = np.linalg.norm(V - B, axis=1)
    relief = (d[F] > 0.05 * d.max()).any(axis=1)
    nv = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    nb = np.cross(B[F[:, 1]] - B[F[:, 0]], B[F[:, 2]] - B[F[:, 0]])
    area = 0.5 * np.linalg.norm(nv, axis=1)
    cos = (nv * nb).sum(axis=1) / np.maximum(np.linalg.norm(nv, axis=1) * np.linalg.norm(nb, axis=1), 1e-300)
    against = cos < 0
    share = lambda m: float(area[relief & m].sum() / max(area[relief].sum(), 1e-300))
    out = {"relief_faces": int(relief.sum()), "inward_share": share(against),
           "inward_faces": int((relief & against).sum()),
           # turned further: beyond 120 and 150 degrees from the base's normal (a turned foot, a fold)
           "beyond_120": share(cos < -0.5), "beyond_150": share(cos < -np.sqrt(3) / 2)}
    if "--radial" in argv:
        c = V[F].mean(axis=1) - V.mean(axis=0)
        out["radial_inward_share"] = float(((nv * c).sum(axis=1) < 0).mean())
    print(json.dumps(out))


if __name__ == "__main__":
    main(sys.argv[1:])
