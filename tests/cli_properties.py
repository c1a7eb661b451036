#!/usr/bin/python3
"""Property test of the geotex CLI over generated and damaged meshes (issue 14).

Every subcommand runs on every mesh of a small zoo (generated shapes, and copies damaged by hand:
duplicate, degenerate and non-manifold faces, NaN and huge coordinates, isolated vertices, several
components, fans of high valence, random soups and slivers) under a time cap and an address-space
cap, and each run must satisfy:

  * the exit code is 0, 1 or 2 (never a signal, a hang or an internal error);
  * a failure prints one clear line `geotex: ...` (besides warnings);
  * the input files are byte-identical afterwards;
  * the output folder holds no leftover (no temporary; nothing at all after a failure);
  * on success every output is complete: meshes with finite coordinates and valid faces, PNG with
    its end chunk, HTML with its end tag.

`texture edit` and `texture animate` run on the texture that `texture extract` lifts off the mesh (the
case then holds both runs); `transfer`, `atlas` and `synthesize` lay a small generated texture (a
spiky plane's) onto the mesh, with refinement off for the two whole-surface ones (it only makes
them slower here).
`project` projects each mesh onto itself and onto the unit sphere (the off-centre mesh lies 1e7 away:
near-linear since the normal-cone pruning, bench/bad-input.md).

With --hard the zoo is instead the valid but hard meshes of issue 30 at 10^5 faces (bench/hard_meshes.py:
a fan around one vertex, disjoint triangles, a needle soup), each run under a CPU cap of 20 s (RLIMIT_CPU in
the child: a run past it dies of SIGXCPU and fails as a signal). KNOWN_OVER_CAP lists the runs still past it
(bench/bad-input.md); they are reported, not failed, and one that comes within the cap is reported too.

Usage: cli_properties.py GEOTEX [--seed N] [--jobs N] [--hard] [--share K] [--verbose]
"""

import argparse
import concurrent.futures
import hashlib
import json
import math
import os
import random
import resource
import shutil
import signal
import subprocess
import sys
import tempfile

TIME_CAP_S = 60           # a hang guard, far above any run here (they take well under a second)
if os.environ.get("GEOTEX_SANITIZE"):
    TIME_CAP_S = 300      # AddressSanitizer runs are 5-20x slower (scripts/sanitize.sh)
MEMORY_CAP = 3 << 30      # address space of each run (OpenMP and BLAS reserve some without using it)
CPU_CAP_S = None          # --hard: RLIMIT_CPU of each run (issue 30)
HARD_FACES = 100000
KEEPS_CONNECTIVITY = {"noise", "smooth", "denoise", "deform", "project", "resize"}
# (mesh, command) runs of the hard zoo still past the CPU cap (bench/bad-input.md, "left undone"). None
# since 2026-12-06 (h-hard2; `cli_properties.py build/geotex --hard --jobs 2`): the last five (the fan's
# two resizes, the needles' project, resize x2 adf and texture atlas) came within it; the needles'
# texture atlas is the closest, at about 17 s of user CPU and 3 s of system CPU run alone.
KNOWN_OVER_CAP = set()


# ---- the zoo --------------------------------------------------------------------------------------

def read_obj(path):
    V, F = [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                V.append([float(x) for x in t[1:4]])
            elif t[0] == "f":
                F.append([int(x.split("/")[0]) - 1 for x in t[1:]])
    return V, F


def obj_text(V, F, raw=None):
    """OBJ text; `raw` replaces given vertex lines' coordinates by strings (e.g. 'nan')."""
    lines = []
    for i, p in enumerate(V):
        if raw and i in raw:
            lines.append("v " + raw[i])
        else:
            lines.append("v %r %r %r" % tuple(p))
    lines += ["f " + " ".join(str(i + 1) for i in f) for f in F]
    return "\n".join(lines) + "\n"


def fan(k, height=0.2):
    V = [[0.0, 0.0, height]] + [[math.cos(2 * math.pi * i / k), math.sin(2 * math.pi * i / k), 0.0] for i in range(k)]
    F = [[0, 1 + i, 1 + (i + 1) % k] for i in range(k)]
    return V, F


def soup(rng, n, thin=False):
    V, F = [], []
    for _ in range(n):
        a = [rng.uniform(-1, 1) for _ in range(3)]
        b = [x + rng.uniform(-0.3, 0.3) for x in a]
        c = [x + rng.uniform(-0.3, 0.3) for x in a] if not thin else [x + 1e-7 * rng.random() + (y - x) * 0.5 for x, y in zip(a, b)]
        base = len(V)
        V += [a, b, c]
        F.append([base, base + 1, base + 2])
    # Share some vertices so that it is not only isolated triangles.
    for f in F[: n // 2]:
        f[2] = rng.randrange(len(V))
    return V, F


def make_hard_zoo(folder, seed):
    """The hard meshes of issue 30 at HARD_FACES faces, as binary PLY (bench/hard_meshes.py)."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench"))
    import hard_meshes
    zoo = {}
    for kind in ("fan", "disjoint", "needles"):
        path = os.path.join(folder, f"hard-{kind}.ply")
        hard_meshes.write_ply(path, *hard_meshes.mesh(kind, HARD_FACES, seed))
        zoo["hard-" + kind] = path
    return zoo


def make_zoo(geotex, folder, seed):
    rng = random.Random(seed)
    zoo = {}

    def gen(shape, level, name):
        path = os.path.join(folder, name + ".obj")
        subprocess.run([geotex, "-q", "generate", shape, "--level", str(level), "--seed", str(seed), "-o", path], check=True)
        zoo[name] = path
        return read_obj(path)

    V, F = gen("sphere", 1, "sphere")
    Vp, Fp = gen("plane", 1, "plane")
    gen("torus", 0, "torus")
    gen("spiky-sphere", 0, "spiky")

    def put(name, V, F, raw=None):
        path = os.path.join(folder, name + ".obj")
        with open(path, "w") as f:
            f.write(obj_text(V, F, raw))
        zoo[name] = path

    put("duplicate-faces", V, F + F[:3] + [list(reversed(F[4]))])
    put("degenerate-faces", V + [[V[0][0], V[0][1], V[0][2]]], F + [[0, 0, 1], [0, 1, len(V)]])
    put("nan-vertex", V, F, raw={5: "nan 0 0"})
    put("non-manifold-edge", V + [[0.0, 0.0, 3.0]], F + [[F[0][0], F[0][1], len(V)]])
    put("isolated-vertices", V + [[5.0, 5.0, 5.0], [6.0, 5.0, 5.0], [5.0, 6.0, 5.0]], F)
    n = len(V)
    put("two-components", V + [[x + 3.0, y, z] for x, y, z in V], F + [[a + n, b + n, c + n] for a, b, c in F])
    put("coincident-copies", V + V, F + [[a + n, b + n, c + n] for a, b, c in F])  # duplicate geometry
    put("huge-scale", [[1e150 * x for x in p] for p in V], F)
    put("tiny-scale", [[1e-150 * x for x in p] for p in V], F)
    put("off-centre", [[x + 1e7, y - 3e6, z + 5e5] for x, y, z in V], F)
    put("fan-300", *fan(300))
    put("flat-fan-200", *fan(200, height=0.0))
    put("soup", *soup(rng, 60))
    put("slivers", *soup(rng, 40, thin=True))
    put("open-plane-flipped", Vp, [list(reversed(f)) if i % 7 == 0 else f for i, f in enumerate(Fp)])
    return zoo


# ---- the commands ---------------------------------------------------------------------------------

HANDLES = json.dumps({"handles": [{"vertices": [0], "translate": [0.1, 0, 0]},
                                  {"vertices": [1], "translate": [0, 0, 0]}]})


def commands(mesh, aux):
    """(name, arguments, [outputs]) for one input mesh; OUT/ stands for the run's output folder."""
    c = [
        ("info", ["info", mesh], []),
        ("info --json --strict", ["info", "--json", "--strict", mesh], []),
        ("noise", ["noise", mesh, "-o", "OUT/n.obj"], ["OUT/n.obj"]),
        ("smooth", ["smooth", mesh, "-o", "OUT/s.obj"], ["OUT/s.obj"]),
        ("smooth cotan", ["smooth", mesh, "--laplacian", "cotan", "-o", "OUT/s.obj"], ["OUT/s.obj"]),
        ("denoise", ["denoise", mesh, "-o", "OUT/d.obj", "--edges", "OUT/e.ply"], ["OUT/d.obj", "OUT/e.ply"]),
        ("denoise mrf-normal", ["denoise", mesh, "--method", "mrf-normal", "-o", "OUT/d.obj"], ["OUT/d.obj"]),
        ("denoise surfel", ["denoise", mesh, "--method", "surfel", "-o", "OUT/d.obj"], ["OUT/d.obj"]),
        ("surfels", ["surfels", mesh, "-o", "OUT/p.ply"], ["OUT/p.ply"]),
        ("param", ["param", mesh, "-o", "OUT/u.obj"], ["OUT/u.obj"]),
        ("deform", ["deform", mesh, "--handles", aux["handles"], "-o", "OUT/f.obj"], ["OUT/f.obj"]),
        ("project", ["project", mesh, mesh, "-o", "OUT/j.obj"], ["OUT/j.obj"]),
        ("project onto sphere", ["project", mesh, aux["base"], "-o", "OUT/j.obj"], ["OUT/j.obj"]),
        ("compare", ["compare", mesh, aux["base"]], []),
        ("resize", ["resize", mesh, "-o", "OUT/r.obj"], ["OUT/r.obj"]),
        ("resize x2 adf", ["resize", mesh, "--scale", "2,1,1", "--features", "adf", "--save-features", "OUT/w.txt",
                           "-o", "OUT/r.obj"], ["OUT/r.obj", "OUT/w.txt"]),
        ("resize thesis", ["resize", mesh, "--scale", "1,1,0.5", "--preset", "thesis", "-o", "OUT/r.obj"],
         ["OUT/r.obj"]),
        ("texture extract+apply", ["texture", "extract", mesh, "-o", "OUT/t.ply"], ["OUT/t.ply"]),
        ("texture extract+edit", ["texture", "extract", mesh, "-o", "OUT/t.ply"], ["OUT/t.ply"],
         ["texture", "edit", "OUT/t.ply", "--op", "wrap", "-o", "OUT/e.ply", "--mesh", "OUT/em.obj"],
         ["OUT/e.ply", "OUT/em.obj"]),
        ("texture extract+animate", ["texture", "extract", mesh, "-o", "OUT/t.ply"], ["OUT/t.ply"],
         ["texture", "animate", "OUT/t.ply", "--frames", "2", "--format", "obj", "-o", "OUT/fr"],
         ["OUT/fr_0000.obj", "OUT/fr_0001.obj"]),
        ("texture transfer", ["texture", "transfer", aux["texture"], mesh, "--source-radius", "0.5",
                              "--target-radius", "0.3", "--texture-out", "OUT/tt.ply", "-o", "OUT/tr.obj"],
         ["OUT/tr.obj", "OUT/tt.ply"]),
        ("texture atlas", ["texture", "atlas", aux["texture"], mesh, "--source-radius", "0.5", "--target-radius", "0.8",
                           "--refine-ratio", "0", "-o", "OUT/at.obj"], ["OUT/at.obj"]),
        ("texture synthesize", ["texture", "synthesize", aux["texture"], "--target", mesh, "--refine-ratio", "0",
                                "--candidates", "8", "--report", "OUT/sy.json", "-o", "OUT/sy.obj"],
         ["OUT/sy.obj", "OUT/sy.json"]),
        ("render", ["render", mesh, "-o", "OUT/i.png"], ["OUT/i.png"]),
        ("view", ["view", mesh, "-o", "OUT/v.html"], ["OUT/v.html"]),
    ]
    return c


def digest(paths):
    h = {}
    for p in paths:
        with open(p, "rb") as f:
            h[p] = hashlib.sha256(f.read()).hexdigest()
    return h


def limits():
    # Under AddressSanitizer (scripts/sanitize.sh sets GEOTEX_SANITIZE) the shadow memory alone reserves
    # terabytes of address space: no cap there.
    if not os.environ.get("GEOTEX_SANITIZE"):
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY_CAP, MEMORY_CAP))
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    if CPU_CAP_S:
        resource.setrlimit(resource.RLIMIT_CPU, (CPU_CAP_S, CPU_CAP_S + 1))


def run(geotex, args, env):
    try:
        p = subprocess.run([geotex, "--threads", "1"] + args, capture_output=True, text=True, errors="replace",
                           timeout=TIME_CAP_S, preexec_fn=limits, env=env, stdin=subprocess.DEVNULL)
        return p.returncode, p.stderr
    except subprocess.TimeoutExpired as e:
        return "timeout", (e.stderr or b"").decode(errors="replace") if isinstance(e.stderr, bytes) else (e.stderr or "")


def error_lines(stderr):
    return [l for l in stderr.splitlines()
            if l.strip() and not l.startswith("geotex: warning: ") and not l.startswith("geotex: note: ")
            and not l.startswith(("geotex: stats: ", "wrote ", "read ")) and "\r" not in l and "%" not in l]


def check_mesh_obj(path):
    V, F = read_obj(path)
    if not V:
        return "no vertices"
    if not all(math.isfinite(x) for p in V for x in p):
        return "non-finite coordinate"
    if F and not all(0 <= i < len(V) for f in F for i in f):
        return "face index out of range"
    return None


def check_output(geotex, path, env):
    if not os.path.isfile(path) or os.path.getsize(path) == 0:
        return "missing or empty"
    if path.endswith(".obj"):
        return check_mesh_obj(path)
    if path.endswith(".png"):
        with open(path, "rb") as f:
            b = f.read()
        return None if b.startswith(b"\x89PNG\r\n\x1a\n") and b[-12:][4:8] == b"IEND" else "PNG incomplete"
    if path.endswith(".json"):
        def refuse(c):
            raise ValueError(c)
        try:
            with open(path) as f:
                json.load(f, parse_constant=refuse)
        except ValueError as e:
            return f"not strict JSON ({e})"
        return None
    if path.endswith(".txt"):
        with open(path) as f:
            values = [float(t) for line in f if not line.startswith("#") for t in line.replace(",", " ").split()]
        return None if values and all(math.isfinite(v) for v in values) else "empty or non-finite weights"
    if path.endswith(".html"):
        with open(path, "rb") as f:
            return None if f.read().rstrip().endswith(b"</html>") else "HTML incomplete"
    if path.endswith(".ply"):
        # geotex's reader refuses what is incomplete or non-finite; the file is a mesh or a point set.
        code, err = run(geotex, ["-q", "info", path], env)
        if code == 0:
            return None
        code2, err2 = run(geotex, ["-q", "surfels", path, "-o", path + ".check.ply"], env)
        if os.path.exists(path + ".check.ply"):
            os.remove(path + ".check.ply")
        return None if code2 == 0 else "unreadable: " + err.strip()
    return None


def one_case(geotex, work, case_id, mesh_name, mesh, cmd, env):
    name, args, outputs = cmd[:3]
    if name == "texture extract+apply":  # apply the extracted texture to its own base
        cmd = cmd + (["texture", "apply", "OUT/t.ply", "-o", "OUT/a.obj"], ["OUT/a.obj"])
    then, then_outputs = cmd[3:] if len(cmd) > 3 else (None, [])
    out = os.path.join(work, "out", case_id)
    os.makedirs(out)
    in_out = lambda l: [a.replace("OUT/", out + "/") for a in l]
    args, outputs, then_outputs = in_out(args), in_out(outputs), in_out(then_outputs)
    inputs = sorted(os.path.join(work, "in", f) for f in os.listdir(os.path.join(work, "in")))
    before = digest(inputs)
    problems = []
    code, err = run(geotex, args, env)
    # A second step on the first one's output (a texture lifted off the mesh), which must then succeed.
    if then and code == 0:
        code, err = run(geotex, in_out(then), env)
        outputs = outputs + then_outputs
        if code != 0:
            problems.append(f"{then[0]} {then[1]} of an extracted texture failed: " + err.strip())
    if code not in (0, 1, 2):
        problems.append(f"exit {code}" + (" (a signal)" if isinstance(code, int) and code < 0 else ""))
    elif code != 0:
        lines = error_lines(err)
        if len(lines) != 1 or not lines[0].startswith("geotex: "):
            problems.append("not one 'geotex: ' line: " + repr(err[-500:]))
        if "internal error" in err:
            problems.append("internal error: " + err.strip())
    if digest(inputs) != before:
        problems.append("an input file changed")
    left = sorted(os.listdir(out))
    if code == 0 and CPU_CAP_S and args[0] in KEEPS_CONNECTIVITY:
        # The hard zoo's commands that move vertices keep them all (a vertex count from the PLY header).
        with open(mesh, "rb") as f:
            header = f.read(400).split(b"end_header")[0].decode()
        n = int(header.split("element vertex ")[1].split()[0])
        for o in outputs:
            if o.endswith(".obj") and os.path.isfile(o) and len(read_obj(o)[0]) != n:
                problems.append(f"{os.path.basename(o)}: {len(read_obj(o)[0])} vertices, the input has {n}")
    if code == 0:
        extra = [f for f in left if os.path.join(out, f) not in outputs]
        if extra:
            problems.append(f"leftover files {extra}")
        for o in outputs:
            p = check_output(geotex, o, env)
            if p:
                problems.append(f"{os.path.basename(o)}: {p}")
    elif left and not then:
        problems.append(f"a failed run left {left}")
    shutil.rmtree(out)
    return case_id, mesh_name, name, code, problems, err


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("geotex")
    ap.add_argument("--seed", type=int, default=14)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="", help="run only commands whose name contains this")
    ap.add_argument("--hard", action="store_true", help="the hard meshes of issue 30 under a 20 s CPU cap")
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--share", type=int, default=int(os.environ.get("GEOTEX_PROPERTIES_SHARE", "1")),
                    help="run one in K of the (mesh, command) runs: those on every K-th diagonal of the mesh by "
                         "command grid, so that every command still runs on 1/K of the meshes and every mesh "
                         "through 1/K of the commands (scripts/sanitize.sh: 3; env GEOTEX_PROPERTIES_SHARE)")
    a = ap.parse_args()
    if a.share < 1:
        ap.error("--share must be at least 1")
    global CPU_CAP_S, TIME_CAP_S
    if a.hard:
        CPU_CAP_S = 20 * (5 if os.environ.get("GEOTEX_SANITIZE") else 1)
        TIME_CAP_S = max(TIME_CAP_S, 10 * CPU_CAP_S)  # the CPU cap decides; wall time waits on a shared machine
    geotex = os.path.abspath(a.geotex)
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_WAIT_POLICY="passive", OPENBLAS_NUM_THREADS="1")
    work = tempfile.mkdtemp(prefix="geotex-properties-")
    try:
        inp = os.path.join(work, "in")
        os.makedirs(inp)
        os.makedirs(os.path.join(work, "out"))
        zoo = make_zoo(geotex, inp, a.seed)
        base = zoo["sphere"]
        if a.hard:
            zoo = make_hard_zoo(inp, a.seed)
        aux = {"handles": os.path.join(inp, "handles.json"), "base": base,
               "texture": os.path.join(inp, "spiky-texture.ply")}
        spiky_plane = os.path.join(work, "spiky-plane.obj")
        subprocess.run([geotex, "-q", "generate", "spiky-plane", "--level", "0", "-o", spiky_plane], check=True)
        subprocess.run([geotex, "-q", "texture", "extract", spiky_plane, "-o", aux["texture"]], check=True)
        with open(aux["handles"], "w") as f:
            f.write(HANDLES)
        cases = []
        for i, (mesh_name, mesh) in enumerate(sorted(zoo.items())):
            for j, cmd in enumerate(commands(mesh, aux)):
                if a.only in cmd[0] and (i + j) % a.share == 0:
                    cases.append((mesh_name, mesh, cmd))
        failures = 0
        counts = {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
            futures = [pool.submit(one_case, geotex, work, f"c{k}", m, p, c, env) for k, (m, p, c) in enumerate(cases)]
            for fut in concurrent.futures.as_completed(futures):
                case_id, mesh_name, name, code, problems, err = fut.result()
                counts[code] = counts.get(code, 0) + 1
                known = (mesh_name, name) in KNOWN_OVER_CAP
                if known and code in (-signal.SIGXCPU, "timeout"):
                    print(f"known over the cap: {name} on {mesh_name}")
                    continue
                if known and not problems:
                    print(f"now within the cap (remove from KNOWN_OVER_CAP): {name} on {mesh_name}")
                if problems:
                    failures += 1
                    print(f"FAIL {name} on {mesh_name}: exit {code}: " + "; ".join(problems))
                elif a.verbose:
                    print(f"ok   {name} on {mesh_name}: exit {code}" + (": " + error_lines(err)[0] if code else ""))
        print(f"{len(cases)} runs over {len(zoo)} meshes; exit codes {dict(sorted(counts.items(), key=str))}; "
              f"{failures} failed the properties")
        return 1 if failures else 0
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
