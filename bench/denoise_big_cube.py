"""A cube of 12 n² faces (n = 913: 10.0 M faces, 5.0 M vertices), binary PLY: the grid of `geotex generate cube`, whose
levels jump from 4.9 M to 19.7 M faces. Issue 24, sixteenth session (the 10^7-face run, bench/denoise.md).

    /usr/bin/python3 bench/denoise_big_cube.py 913 big.ply && geotex noise big.ply --sigma 0.3 --seed 7 -o bign.ply
"""
import sys
import numpy as np
n = int(sys.argv[1]); out = sys.argv[2]
keys, tris = [], []
base = 0
u, v = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
for a in range(3):
    b, c = (a + 1) % 3, (a + 2) % 3
    for s in (0, n):
        P = np.zeros((n + 1, n + 1, 3), np.int64)
        P[..., a] = s; P[..., b] = u; P[..., c] = v
        keys.append((P[..., 0] * (n + 1) + P[..., 1]) * (n + 1) + P[..., 2])
        idx = base + np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
        i00, i10, i11, i01 = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
        t = np.stack([np.stack([i00, i10, i11], -1).reshape(-1, 3), np.stack([i00, i11, i01], -1).reshape(-1, 3)], 1).reshape(-1, 3)
        if s == 0: t = t[:, ::-1]
        tris.append(t); base += (n + 1) ** 2
keys = np.concatenate([k.ravel() for k in keys])
uniq, inv = np.unique(keys, return_inverse=True)
F = inv[np.concatenate(tris)].astype(np.int32)
k = uniq
V = np.stack([k // ((n + 1) ** 2), (k // (n + 1)) % (n + 1), k % (n + 1)], 1).astype(np.float64) / n - 0.5
with open(out, "wb") as f:
    f.write(f"ply\nformat binary_little_endian 1.0\nelement vertex {len(V)}\nproperty double x\nproperty double y\nproperty double z\nelement face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n".encode())
    f.write(V.astype("<f8").tobytes())
    rec = np.zeros(len(F), dtype=[("c", "u1"), ("i", "<i4", 3)]); rec["c"] = 3; rec["i"] = F
    f.write(rec.tobytes())
print(len(V), "vertices", len(F), "faces")
