#!/usr/bin/python3
"""CPU seconds and peak memory of every computing command on the hard meshes of hard_meshes.py.

Usage: hard_bench.py GEOTEX [--sizes 100000,1000000] [--kinds fan,disjoint,needles,comb] [--cap 60]
       [--only SUBSTRING] [--dir DIR]
Each run is one thread, under /usr/bin/time -v and a CPU cap (RLIMIT_CPU, seconds); prints a markdown
table row per (mesh, command): CPU user+sys, peak resident set, exit code (or 'cap' when it hit the cap).
"""

import argparse
import json
import os
import re
import resource
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import hard_meshes  # noqa: E402


def commands(mesh, handles, base):
    return [
        ("info", ["info", mesh]),
        ("smooth", ["smooth", mesh, "-o", "OUT.ply"]),
        ("smooth cotan", ["smooth", mesh, "--laplacian", "cotan", "-o", "OUT.ply"]),
        ("noise", ["noise", mesh, "-o", "OUT.ply"]),
        ("denoise mrf", ["denoise", mesh, "--method", "mrf", "-o", "OUT.ply"]),
        ("denoise mrf-normal", ["denoise", mesh, "--method", "mrf-normal", "-o", "OUT.ply"]),
        ("denoise surfel", ["denoise", mesh, "--method", "surfel", "-o", "OUT.ply"]),
        ("surfels", ["surfels", mesh, "-o", "OUT.ply"]),
        ("deform", ["deform", mesh, "--handles", handles, "-o", "OUT.ply"]),
        ("param", ["param", mesh, "-o", "OUT.obj"]),
        ("project onto sphere", ["project", mesh, base, "-o", "OUT.ply"]),
        ("texture extract", ["texture", "extract", mesh, "-o", "OUT.ply"]),
        ("texture apply", ["texture", "apply", "TEX.ply", "-o", "OUT.ply"]),
        ("resize", ["resize", mesh, "--scale", "2,1,1", "-o", "OUT.ply"]),
        ("compare", ["compare", mesh, mesh]),
        ("render", ["render", mesh, "-o", "OUT.png"]),
    ]


def run(geotex, args, cap, out_dir):
    def limit():
        resource.setrlimit(resource.RLIMIT_CPU, (cap, cap + 1))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    args = [a.replace("OUT", os.path.join(out_dir, "out")).replace("TEX.ply", os.path.join(out_dir, "tex.ply"))
            for a in args]
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_WAIT_POLICY="passive", OPENBLAS_NUM_THREADS="1")
    p = subprocess.run(["/usr/bin/time", "-v", geotex, "-q", "--threads", "1"] + args, capture_output=True,
                       text=True, errors="replace", preexec_fn=limit, env=env, stdin=subprocess.DEVNULL)
    err = p.stderr
    user = float(re.search(r"User time \(seconds\): ([\d.]+)", err).group(1))
    system = float(re.search(r"System time \(seconds\): ([\d.]+)", err).group(1))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", err).group(1))
    status = re.search(r"Exit status: (\d+)", err)
    signalled = "Command terminated by signal" in err
    code = "cap" if signalled and user + system >= cap - 1 else (("signal" if signalled else status.group(1)))
    first = next((l for l in err.splitlines() if l.startswith("geotex: ")), "")
    return user + system, rss / 1024.0, code, first


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("geotex")
    ap.add_argument("--sizes", default="100000,1000000")
    ap.add_argument("--kinds", default="fan,disjoint,needles,comb")
    ap.add_argument("--cap", type=int, default=60)
    ap.add_argument("--only", default="")
    ap.add_argument("--dir", default="/tmp/geotex-hard")
    a = ap.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    handles = os.path.join(a.dir, "handles.json")
    with open(handles, "w") as f:
        json.dump({"handles": [{"vertices": [0], "translate": [0.1, 0, 0]},
                               {"vertices": [1], "translate": [0, 0, 0]}]}, f)
    base = os.path.join(a.dir, "sphere.ply")
    subprocess.run([a.geotex, "-q", "generate", "sphere", "--level", "3", "-o", base], check=True)
    print("| mesh | command | CPU s | peak MiB | exit |\n|---|---|---|---|---|", flush=True)
    for n in [int(s) for s in a.sizes.split(",")]:
        for kind in a.kinds.split(","):
            mesh = os.path.join(a.dir, f"{kind}-{n}.ply")
            if not os.path.exists(mesh):
                hard_meshes.write_ply(mesh, *hard_meshes.mesh(kind, n))
            for name, args in commands(mesh, handles, base):
                if a.only not in name:
                    continue
                if name == "texture apply":  # needs the texture extracted just before
                    if not os.path.exists(os.path.join(a.dir, "tex.ply")):
                        continue
                if name == "texture extract":
                    tex = os.path.join(a.dir, "tex.ply")
                    if os.path.exists(tex):
                        os.remove(tex)
                cpu, mib, code, first = run(a.geotex, args, a.cap, a.dir)
                if name == "texture extract" and code == "0":
                    os.replace(os.path.join(a.dir, "out.ply"), os.path.join(a.dir, "tex.ply"))
                shown = {"cap": f"> {a.cap} s cap"}.get(code, code)
                note = f" ({first[8:90]})" if code not in ("0", "cap") and first else ""
                print(f"| {kind} {n:.0e} | {name} | {cpu:.2f} | {mib:.0f} | {shown}{note} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
