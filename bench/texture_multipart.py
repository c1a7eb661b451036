#!/usr/bin/env python3
# A generated multi-part model (issue 26): a spiky sphere, 30 small spheres of 1-6 mean edges, 4 finer flat
# sheets, written to multipart.ply; then bench/texture_base_area.py multipart.ply.
import numpy as np, geotex, warnings
warnings.simplefilter('ignore')
parts = []
(Vs, Fs), _ = geotex.generate("spiky-sphere", level=1, with_base=True); parts.append((Vs, Fs))
h = geotex.mean_edge_length(Vs, Fs)
rng = np.random.default_rng(1)
for k in range(30):  # buttons, small spheres of 1-6 edges, and thin sheets
    Vi, Fi = geotex.generate("sphere", level=1); parts.append((Vi * h * rng.uniform(0.5, 3) + [3 + k % 6 * 0.4, k // 6 * 0.4, 0], Fi))
for k in range(4):
    Vp, Fp = geotex.generate("plane"); parts.append((Vp * 0.3 + [-3, k * 0.7, 0], Fp))
V = np.vstack([p[0] for p in parts]); off = np.cumsum([0] + [len(p[0]) for p in parts])[:-1]
F = np.vstack([p[1] + o for p, o in zip(parts, off)])
geotex.write_mesh("multipart.ply", V, F)
