#!/usr/bin/env python3
# The automatic base on real models (issue 26): area kept, per component, round trip, off-normal angle.
# PYTHONPATH=build/python /usr/bin/python3 bench/texture_base_area.py MESH...
import sys, numpy as np, geotex
def area(V, F):
    return 0.5 * np.linalg.norm(np.cross(V[F[:,1]]-V[F[:,0]], V[F[:,2]]-V[F[:,0]]), axis=1)
for path in sys.argv[1:]:
    V, F = geotex.read_mesh(path)
    t = geotex.texture_extract(V, F)
    Vb = np.asarray(t.V_base) if hasattr(t, 'V_base') else np.asarray(t.texture.V)
    a0, ab = area(V, F), area(Vb, F)
    comp = np.asarray(geotex.connected_components(V, F))
    fc = comp[F[:,0]]
    worst = min((ab[fc==c].sum()/max(a0[fc==c].sum(),1e-300), c) for c in np.unique(fc))
    print(f"{path.split('/')[-1]:22s} V {len(V):7d} comps {len(np.unique(fc)):3d} base area {ab.sum()/a0.sum():.3f} worst comp {worst[0]:.3f} (#{worst[1]}, {np.sum(fc==worst[1])} faces) max_error {t.max_error:.2e} off-normal {t.median_off_normal_deg:.1f}")
