# Tried (issue 24, 2026-12-06): a per-region guard on the default denoiser's displacement, capped at k x the
# estimated noise (ring rms, in mean edge lengths), on clean and noisy shared models (bench/denoise.md,
# "Coarse models: a displacement guard, tried"). PYTHONPATH=build/python /usr/bin/python3 bench/denoise_coarse_guard.py
import sys, numpy as np, geotex, warnings
warnings.simplefilter("ignore")
def fn(P,F):
    n=np.cross(P[F[:,1]]-P[F[:,0]],P[F[:,2]]-P[F[:,0]]); return n/np.maximum(np.linalg.norm(n,axis=1,keepdims=True),1e-300)
def ang(V,F,T): return np.degrees(np.arccos(np.clip((fn(V,F)*fn(T,F)).sum(1),-1,1))).mean()
cases=[]
for m in ["beetle","cow","stanford-bunny","spot","fandisk"]:
    V,F=geotex.read_mesh(f"/work/shared/data/{m}.obj")
    cases.append((m+" clean",V,F,V))
    for s in [0.05,0.2,0.5]:
        cases.append((f"{m} g{s}",geotex.add_noise(V,F,sigma=s,seed=7),F,V))
V,F=geotex.generate("sphere",level=4); cases.append(("sphere g0.3",geotex.add_noise(V,F,sigma=0.3,seed=7),F,V))
import scipy.sparse as sp
for name,X,F,T in cases:
    r=geotex.denoise(X,F); Y=r.V; sig=r.noise["sigma"]
    h=geotex.mean_edge_length(X,F); n=len(X)
    # vertex adjacency
    I=np.concatenate([F[:,0],F[:,1],F[:,2],F[:,1],F[:,2],F[:,0]]); J=np.concatenate([F[:,1],F[:,2],F[:,0],F[:,0],F[:,1],F[:,2]])
    A=sp.csr_matrix((np.ones(len(I)),(I,J)),shape=(n,n)); A.data[:]=1; A=A+sp.eye(n)
    deg=np.asarray(A.sum(1)).ravel()
    D=Y-X; c2=(D**2).sum(1)/h**2
    rms=np.sqrt((A@c2)/deg)
    out=[f"{name:20s} sig {sig:.3f} in {ang(X,F,T):6.2f} out {ang(Y,F,T):6.2f} medchg/sig {np.median(np.sqrt(c2))/sig:5.2f} |"]
    for k in [1.0,1.5,2.0]:
        s=np.minimum(1,k*sig/np.maximum(rms,1e-300))
        Z=X+s[:,None]*D
        out.append(f" k{k}: {ang(Z,F,T):6.2f}")
    print("".join(out),flush=True)
