"""Issue 14 through Python: one test per class of bad input (the CLI's are in
tests/cli/bad_input_classes_test.cpp). Anything that could crash the interpreter runs in a child process,
so that a segfault or an abort is a failed test, not a dead test run."""

import os
import stat
import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest

import geotex


# AddressSanitizer reserves terabytes of address space for its shadow memory, so an address-space cap
# cannot apply under scripts/sanitize.sh (which sets GEOTEX_SANITIZE): caps are dropped there, and the
# out-of-memory test, which is about nothing but the cap, is skipped.
SANITIZED = bool(os.environ.get("GEOTEX_SANITIZE"))


def run_child(code, timeout=120, memory_bytes=None):
    """Run `code` in a fresh interpreter (same PYTHONPATH); returns the CompletedProcess.
    memory_bytes caps the address space (RLIMIT_AS) of the child (not under a sanitizer)."""
    prelude = "import resource\n"
    if memory_bytes and not SANITIZED:
        prelude += f"resource.setrlimit(resource.RLIMIT_AS, ({memory_bytes}, {memory_bytes}))\n"
    return subprocess.run([sys.executable, "-c", prelude + textwrap.dedent(code)], capture_output=True, text=True,
                          timeout=timeout, env=dict(os.environ, OMP_NUM_THREADS="2", OMP_WAIT_POLICY="passive"))


def assert_clean_exit(p):
    assert p.returncode == 0, f"exit {p.returncode} (negative: killed by a signal)\nstdout: {p.stdout}\nstderr: {p.stderr}"


# ---- class 1: a warning or an exception raised while the GIL is released --------------------------

# Every public function that takes a mesh, called on a mesh with one duplicate face (the face is
# dropped with a UserWarning). On main geotex.smooth() raised that warning without the GIL: a segfault.
EVERY_MESH_FUNCTION = """
import json, sys, warnings
import numpy as np
import geotex

V, F = geotex.generate("sphere", level=1)
Fd = np.vstack([F, F[:1]])                      # one duplicate face
Vp, Fp = geotex.generate("plane", level=1)    # an open disk (param, texture)
Fpd = np.vstack([Fp, Fp[:1]])
tex = geotex.texture_extract(Vp, Fp)
h, t = np.asarray(tex.height), np.asarray(tex.tilt)
texd = dict(V_base=Vp, F=Fpd, height=h, tilt=t, lean=tex.lean)  # the texture over faces with a duplicate
out = sys.argv[1] if len(sys.argv) > 1 else "/tmp"
calls = {
    "info": lambda: geotex.info(V, Fd),
    "write_mesh": lambda: geotex.write_mesh(out + "/w.ply", V, Fd),
    "add_noise": lambda: geotex.add_noise(V, Fd, sigma=0.1),
    "compare": lambda: geotex.compare(V, Fd, V, F),
    "face_normals": lambda: geotex.face_normals(V, Fd),
    "vertex_normals": lambda: geotex.vertex_normals(V, Fd),
    "edges": lambda: geotex.edges(V, Fd),
    "boundary_loops": lambda: geotex.boundary_loops(V, Fd),
    "connected_components": lambda: geotex.connected_components(V, Fd),
    "umbrella_laplacian": lambda: geotex.umbrella_laplacian(V, Fd),
    "cotan_laplacian": lambda: geotex.cotan_laplacian(V, Fd),
    "mean_curvature_normals": lambda: geotex.mean_curvature_normals(V, Fd),
    "smooth": lambda: geotex.smooth(V, Fd),
    "smooth explicit": lambda: geotex.smooth(V, Fd, implicit=False, laplacian="umbrella", lambda_=0.5),
    "deform": lambda: geotex.deform(V, Fd, handles=[0, 1, 2, 3], targets=V[:4] + 0.1),
    "parametrize": lambda: geotex.parametrize(Vp, Fpd),
    "phong_project": lambda: geotex.phong_project(V, Fd, P=V[:5] * 1.1),
    "one_form_fit": lambda: geotex.one_form_fit(V, Fd, T=np.cross(V, [0, 0, 1.0])),
    "auto_diffusion_function": lambda: geotex.auto_diffusion_function(V, Fd, eigenpairs=10),
    "denoise_mrf": lambda: geotex.denoise_mrf(V, Fd),
    "denoise_mrf_normal": lambda: geotex.denoise_mrf_normal(V, Fd),
    "denoise_surfel": lambda: geotex.denoise_surfel(V, Fd),
    "texture_extract": lambda: geotex.texture_extract(Vp, Fpd),
    "texture_apply": lambda: geotex.texture_apply(texd),
    "texture_edit": lambda: geotex.texture_edit(texd, op="scale-height", factor=2.0),
    "texture_transfer": lambda: geotex.texture_transfer(texd, (Vp, Fpd), source_radius=0.3, target_radius=0.3),
    "resize": lambda: geotex.resize(V, Fd, scale=(2, 1, 1)).V,
    "render": lambda: geotex.render(V, Fd, path=out + "/r.png", width=64, height=64),
    "view": lambda: geotex.view([(V, Fd)], out + "/v.html"),
}
try:
    geotex.view([(V, F)], out + "/probe.html")
except OSError as e:   # the viewer's script is optional (node at build time)
    if "not built" in str(e):
        del calls["view"]
mode = sys.argv[2] if len(sys.argv) > 2 else "record"
done = {}
for name, call in calls.items():
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("error" if mode == "error" else "always")
        try:
            call()
            result = "ok"
        except UserWarning as e:          # warnings as errors: the warning propagates as an exception
            result = "raised"
        except (ValueError, TypeError, OSError, RuntimeError) as e:
            result = "error: " + type(e).__name__ + ": " + str(e)
        done[name] = [result, sum("duplicate" in str(x.message) for x in w)]
print(json.dumps(done))
"""


@pytest.mark.parametrize("mode", ["record", "error"])
def test_class1_dropped_face_warning_from_every_binding(tmp_path, mode):
    script = tmp_path / "every.py"
    script.write_text(EVERY_MESH_FUNCTION)
    p = subprocess.run([sys.executable, str(script), str(tmp_path), mode], capture_output=True, text=True, timeout=300,
                       env=dict(os.environ, OMP_NUM_THREADS="2", OMP_WAIT_POLICY="passive"))
    assert_clean_exit(p)
    import json
    done = json.loads(p.stdout)
    for name, (result, n_warnings) in done.items():
        if mode == "record":
            assert result == "ok", f"{name}: {result}"
            assert n_warnings >= 1, f"{name}: no warning about the dropped face"
        else:
            assert result == "raised", f"{name}: {result}"  # the warning as an exception, before any work


def test_class1_exceptions_from_progress_callbacks_while_the_gil_is_released():
    # The progress callback runs inside the released region (it takes the GIL); its exception, and a
    # pending KeyboardInterrupt, must end the call as a Python exception, not abort the interpreter.
    p = run_child("""
        import signal, os
        import geotex
        V, F = geotex.generate("sphere", level=2)
        class Stop(Exception): pass
        def boom(fraction, stage): raise Stop(stage)
        for name, call in [("smooth", lambda: geotex.smooth(V, F, steps=5, progress=boom)),
                           ("mrf", lambda: geotex.denoise_mrf(V, F, progress=boom)),
                           ("surfel", lambda: geotex.denoise_surfel(V, F, progress=boom)),
                           ("adf", lambda: geotex.auto_diffusion_function(V, F, eigenpairs=10, progress=boom))]:
            try:
                call()
                print(name, "finished")          # a function may report no progress at all
            except Stop:
                print(name, "stopped")
        # raise_signal: to this thread, at once (os.kill lets the kernel pick any thread, OpenMP's too).
        # A shell that starts the tests in the background (cmd &) starts them with SIGINT ignored, and
        # Python then installs no handler: an ignored SIGINT is rightly not an interrupt, so install it.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        def interrupt(fraction, stage): signal.raise_signal(signal.SIGINT)
        try:
            geotex.denoise_mrf(V, F, progress=interrupt)
            print("mrf not interrupted")
        except KeyboardInterrupt:
            print("mrf interrupted")
    """)
    assert_clean_exit(p)
    assert "smooth stopped" in p.stdout and "mrf stopped" in p.stdout and "mrf interrupted" in p.stdout, p.stdout


@pytest.mark.parametrize("call", [
    'geotex.denoise(Vn, F, method="mrf")',
    'geotex.denoise(Vn, F, method="mrf-normal")',
    'geotex.denoise(Vn, F, method="surfel")',
    'geotex.denoise(Vn, F)',
])
def test_class1_ctrl_c_stops_a_long_computation_within_seconds(call):
    # Issue 30 item 7: a SIGINT sent to the process (as Ctrl-C is: to any of its threads) one second into a
    # long call raised KeyboardInterrupt only at the call's next progress report, 7-19 s later. The call
    # must end with KeyboardInterrupt soon after the signal. "Soon" is counted in the process's CPU time
    # (every thread's), not on the wall clock: on a loaded machine the wall clock runs on while the call
    # waits for a core, but the work it does after the signal is what a late check would show. 3 s of
    # CPU per core the process may use is generous (a check is every few ms; the old code went on for 7-19 s
    # on every core). Per core: OpenMP's waiting threads spin, and on a loaded machine they spin longer.
    p = run_child(f"""
        import os, signal, threading, time
        import geotex
        signal.signal(signal.SIGINT, signal.default_int_handler)  # see the test above
        V, F = geotex.generate("sphere", level=6)  # 2.6 M vertices: every method still runs seconds after the signal
        Vn = geotex.add_noise(V, F, sigma=0.3)
        sent = []
        def interrupt():
            sent.append(time.process_time())
            os.kill(os.getpid(), signal.SIGINT)
        threading.Timer(1.0, interrupt).start()
        try:
            {call}
            print("finished", "after the signal" if sent else "before the signal")
        except KeyboardInterrupt:
            print(f"interrupted after {{time.process_time() - sent[0]:.2f}} s of CPU on {{len(os.sched_getaffinity(0))}} cores")
    """, timeout=600)
    assert_clean_exit(p)
    assert p.stdout.startswith("interrupted after"), p.stdout + p.stderr
    # Under AddressSanitizer every sweep is several times slower, and so is the gap between two checks.
    words = p.stdout.split()
    assert float(words[2]) < (15.0 if SANITIZED else 3.0) * int(words[7]), p.stdout


# ---- class 2: a failed run destroys files --------------------------------------------------------

def test_class2_a_failed_write_leaves_every_file_as_it_was(tmp_path):
    V, F = geotex.generate("cube", level=1)
    keep = tmp_path / "keep.ply"
    geotex.write_mesh(keep, V, F)
    before = keep.read_bytes()
    # A result that cannot be written (non-finite) does not replace the existing file.
    bad = V.copy()
    bad[0, 0] = np.inf
    with pytest.raises(geotex.InvalidInput):
        geotex.write_mesh(keep, bad, F)
    assert keep.read_bytes() == before
    # A read-only file is refused, not replaced (rename would replace it).
    picture = tmp_path / "keep.png"
    picture.write_bytes(b"an older picture")
    keep.chmod(0o444)
    picture.chmod(0o444)
    try:
        with pytest.raises(geotex.IoError, match="read-only"):
            geotex.write_mesh(keep, V * 2, F)
        with pytest.raises(geotex.IoError, match="read-only"):
            geotex.render(V, F, path=picture, width=32, height=32)
        assert keep.read_bytes() == before
        assert picture.read_bytes() == b"an older picture"
    finally:
        keep.chmod(0o644)
        picture.chmod(0o644)
    # A folder that does not exist fails, leaving nothing behind.
    with pytest.raises(geotex.IoError, match="does not exist"):
        geotex.render(V, F, path=tmp_path / "missing" / "r.png", width=32, height=32)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.ply", "keep.png"]


# ---- class 3: leftovers, modes, links, special files, long names ---------------------------------

def test_class3_the_output_path_is_kept_as_the_user_made_it(tmp_path):
    V, F = geotex.generate("cube", level=0)
    private = tmp_path / "private.obj"
    private.write_text("old")
    private.chmod(0o600)
    geotex.write_mesh(private, V, F)
    assert stat.S_IMODE(private.stat().st_mode) == 0o600
    link = tmp_path / "link.obj"
    link.symlink_to("private.obj")
    geotex.write_mesh(link, V * 2, F)
    assert link.is_symlink()
    assert np.allclose(geotex.read_mesh(private)[0], V * 2)
    fifo = tmp_path / "fifo.ply"
    os.mkfifo(fifo)
    with pytest.raises(geotex.IoError, match="FIFO"):
        geotex.write_mesh(fifo, V, F)   # refused at once: a FIFO would block or be replaced
    assert stat.S_ISFIFO(fifo.stat().st_mode)
    long_name = tmp_path / ("n" * 251 + ".obj")   # 255 bytes, NAME_MAX
    geotex.write_mesh(long_name, V, F)
    assert np.array_equal(geotex.read_mesh(long_name)[1], F)
    # No temporary left behind.
    assert not [p.name for p in tmp_path.iterdir() if p.name.startswith(".")]


# ---- class 4: NaN and inf in numeric options --------------------------------------------------------

def test_class4_nan_and_inf_options_are_refused(tmp_path):
    # In a child process: on main texture_transfer(rotation=nan) segfaulted.
    p = run_child("""
        import math
        import numpy as np
        import geotex
        V, F = geotex.generate("sphere", level=0)
        Vp, Fp = geotex.generate("plane", level=1)
        tex = geotex.texture_extract(Vp, Fp)
        h, t = tex.height, tex.tilt
        calls = {
            "smooth lambda_": lambda x: geotex.smooth(V, F, lambda_=x),
            "add_noise sigma": lambda x: geotex.add_noise(V, F, sigma=x),
            "denoise_mrf alpha": lambda x: geotex.denoise_mrf(V, F, alpha=x),
            "denoise_mrf phi0": lambda x: geotex.denoise_mrf(V, F, phi0=x),
            "render zoom": lambda x: geotex.render(V, F, width=32, height=32, zoom=x),
            "adf t": lambda x: geotex.auto_diffusion_function(V, F, t=x, eigenpairs=10),
            "texture_edit angle": lambda x: geotex.texture_edit(tex, op="set-tilt", angle=x),
            "texture_edit factor": lambda x: geotex.texture_edit(tex, op="scale-height", factor=x),
            "texture_edit direction": lambda x: geotex.texture_edit(tex, op="wrap", direction=(x, 0, 0)),
            "texture_transfer rotation": lambda x: geotex.texture_transfer(tex, (Vp, Fp), source_radius=0.3,
                                                                           target_radius=0.3, rotation=x),
            "texture_transfer radius": lambda x: geotex.texture_transfer(tex, (Vp, Fp), source_radius=x,
                                                                         target_radius=0.3),
            "resize scale": lambda x: geotex.resize(V, F, scale=(x, 1, 1)).V,
            "resize significance": lambda x: geotex.resize(V, F, scale=(2, 1, 1), significance=x).V,
            "threads": lambda x: geotex.smooth(V, F, threads=x),
        }
        for name, call in calls.items():
            # 1e308 (finite, but overflows when turned into radians) where the issue saw it crash.
            huge = (1e308,) if name.startswith(("texture", "smooth")) else ()
            for x in (math.nan, math.inf, -math.inf) + huge:
                try:
                    out = call(x)
                    arrays = [np.asarray(v) for v in (out if isinstance(out, tuple) else
                              [out[k] for k in out.keys()] if hasattr(out, "keys") else [out])]
                    finite = all(np.isfinite(a).all() for a in arrays if a.dtype.kind == "f")
                    print(name, x, "accepted", "finite" if finite else "NON-FINITE")
                except (ValueError, TypeError) as e:
                    print(name, x, "refused")
    """, timeout=300)
    assert_clean_exit(p)
    for line in p.stdout.splitlines():
        name_and_value, result = line.rsplit(" ", 1)
        if " nan " in f" {line} " or " inf " in f" {line} ":
            assert result == "refused", line   # NaN and inf are never a usable value
        else:
            assert result in ("refused", "finite"), line  # 1e308: refused or a finite result


def test_class4_counts_and_scale_factors_have_bounds():
    # The same option tables as the CLI: a count of 1e9 (frames: 6 GB in 15 s; eigenpairs, edge sweeps:
    # hours) or a height scale of 1e200 (texture_synthesize crashed) is refused before any work.
    V, F = geotex.generate("sphere", level=0)
    Vp, Fp = geotex.generate("spiky-plane", level=0)
    tex = geotex.texture_extract(Vp, Fp)
    calls = {
        "texture_animate frames": lambda: geotex.texture_animate(tex, frames=10**9),
        "auto_diffusion_function eigenpairs": lambda: geotex.auto_diffusion_function(V, F, eigenpairs=10**9),
        "denoise_mrf edge_sweeps": lambda: geotex.denoise_mrf(V, F, edge_sweeps=10**9),
        "resize dilate": lambda: geotex.resize(V, F, scale=(2, 1, 1), dilate=10**9).V,
        "texture_synthesize candidates": lambda: geotex.texture_synthesize(tex, (V, F), candidates=10**9),
        "texture_synthesize height_scale": lambda: geotex.texture_synthesize(tex, (V, F), height_scale=1e200),
        "texture_transfer height_scale": lambda: geotex.texture_transfer(tex, (V, F), source_radius=0.5,
                                                                         target_radius=0.3, height_scale=1e200),
    }
    for name, call in calls.items():
        with pytest.raises(ValueError, match="range"):
            call()
    # At the bound: computed, finite.
    r = geotex.texture_synthesize(tex, (V, F), height_scale=1e6, candidates=4)
    assert np.isfinite(r.V).all()


# ---- class 5: encodings and array conversion -----------------------------------------------------

def test_class5_encodings_and_arrays_are_read_exactly(tmp_path):
    V, F = geotex.generate("cube", level=0)
    text = "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V) + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)
    for name, data in [("bom.obj", "\ufeff" + text), ("cr.obj", text.replace("\n", "\r")),
                       ("crlf.obj", text.replace("\n", "\r\n"))]:
        (tmp_path / name).write_bytes(data.encode("utf-8"))
        V2, F2 = geotex.read_mesh(tmp_path / name, strict=True)
        assert np.array_equal(V2, V) and np.array_equal(F2, F), name
    # No silent narrowing of indices or faces given as floats.
    with pytest.raises(geotex.InvalidInput, match="out of range"):
        geotex.info(V, F.astype(np.int64) + 2 ** 32)
    with pytest.raises(geotex.InvalidInput, match="integers"):
        geotex.info(V, F.astype(np.float64))
    with pytest.raises(geotex.InvalidInput):
        geotex.info(V, F.astype(np.uint64) + np.uint64(2 ** 63))
    # A PLY declaring x twice is refused, not read with interleaved coordinates.
    (tmp_path / "x2.ply").write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float x\n"
                                     "property float y\nproperty float z\nelement face 1\n"
                                     "property list uchar int vertex_indices\nend_header\n"
                                     "0 9 0 0\n1 9 0 0\n0 9 1 0\n3 0 1 2\n")
    with pytest.raises(geotex.IoError, match="declared twice"):
        geotex.read_mesh(tmp_path / "x2.ply")


# ---- class 6: non-finite results ----------------------------------------------------------------

def test_class6_results_are_finite_or_refused(tmp_path):
    V = np.array([[0, 0, 0], [1e200, 0, 0], [0, 1e200, 0], [0, 0, 1e200]])
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    for name, call in [("add_noise", lambda: geotex.add_noise(V, F, sigma=0.5)),
                       ("smooth", lambda: geotex.smooth(V, F)),
                       ("denoise_mrf", lambda: geotex.denoise_mrf(V, F).V)]:
        try:
            out = call()
        except (ValueError, RuntimeError):
            continue
        assert np.isfinite(out).all(), name
    # A texture with a NaN height is refused, not applied.
    Vp, Fp = geotex.generate("plane", level=1)
    tex = geotex.texture_extract(Vp, Fp)
    h = np.array(tex.height)
    h[0] = np.nan
    with pytest.raises(geotex.InvalidInput):
        geotex.texture_apply(dict(V_base=Vp, F=Fp, height=h, tilt=tex.tilt, lean=tex.lean))
    with pytest.raises(geotex.InvalidInput):
        geotex.write_mesh(tmp_path / "x.ply", np.full((3, 3), np.inf), np.array([[0, 1, 2]]))
    assert not (tmp_path / "x.ply").exists()


def test_class6_coordinates_outside_the_computable_range_are_refused():
    # Fourth powers of lengths leave double precision beyond 1e±75: every method says how to rescale
    # (on main texture_extract at 1e150 and resize at 1e-150 failed in the solver or on "no area").
    V, F = geotex.generate("sphere", level=1)
    for scale, advice in [(1e150, "scale the mesh down"), (1e-150, "scale the mesh up")]:
        for name, call in [("smooth", lambda: geotex.smooth(V * scale, F)),
                           ("denoise", lambda: geotex.denoise(V * scale, F)),
                           ("texture_extract", lambda: geotex.texture_extract(V * scale, F)),
                           ("resize", lambda: geotex.resize(V * scale, F, scale=(2, 1, 1)).V)]:
            with pytest.raises(geotex.InvalidInput, match=advice):
                call()
    for scale in (1e74, 1e-74):  # inside the range: computed, finite
        assert np.isfinite(geotex.smooth(V * scale, F)).all()
        assert np.isfinite(geotex.resize(V * scale, F, scale=(2, 1, 1)).V).all()


# ---- class 7: cost on small files, special files -------------------------------------------------

def fan(k):
    """A disk fan: one centre vertex of valence k."""
    a = np.linspace(0, 2 * np.pi, k, endpoint=False)
    V = np.vstack([[0, 0, 0.2], np.c_[np.cos(a), np.sin(a), np.zeros(k)]])
    F = np.array([[0, 1 + i, 1 + (i + 1) % k] for i in range(k)])
    return V, F


def test_class7_a_high_valence_vertex_and_a_fifo_do_not_hang(tmp_path):
    # A cap (not a speed threshold): on main a valence of 8k took 39 s in denoise, deform needed
    # 8 GB and texture_extract more than 2 GiB; each call here is a fraction of a second now, the cap is a hundred times more.
    p = run_child("""
        import numpy as np, geotex
        k = 4000
        a = np.linspace(0, 2 * np.pi, k, endpoint=False)
        V = np.vstack([[0, 0, 0.2], np.c_[np.cos(a), np.sin(a), np.zeros(k)]])
        F = np.array([[0, 1 + i, 1 + (i + 1) % k] for i in range(k)])
        geotex.smooth(V, F)
        geotex.denoise_mrf(V, F)
        geotex.deform(V, F, handles=[0, 1], targets=V[:2] + 0.1)
        geotex.phong_project(V, F, P=V[::40] + 0.01)
        geotex.texture_extract(V, F)
        print("done")
    """, timeout=120, memory_bytes=2 << 30)
    assert_clean_exit(p)
    fifo = tmp_path / "in.obj"
    os.mkfifo(fifo)
    p = run_child(f"""
        import geotex
        try:
            geotex.read_mesh({str(fifo)!r})
        except geotex.IoError as e:
            print("refused:", e)
    """, timeout=60)
    assert_clean_exit(p)
    assert "FIFO" in p.stdout


# ---- class 8: out of memory ------------------------------------------------------------------------

@pytest.mark.skipif(SANITIZED, reason="an address-space cap cannot apply under AddressSanitizer")
def test_class8_out_of_memory_is_a_memory_error():
    # std::bad_alloc under an address-space cap is MemoryError (our translator handles only geotex's
    # own errors), and the interpreter goes on after it.
    p = run_child("""
        import geotex
        V, F = geotex.generate("sphere", level=1)
        geotex.smooth(V, F)                                 # threads started while memory is free
        try:
            geotex.generate("torus", level=7)               # 12.6 M faces: 3.4 GiB
            print("generate fitted")
        except MemoryError:
            print("generate MemoryError")
        # Growing meshes until smoothing (a sparse Cholesky) or the mesh itself no longer fits: each
        # step either works or raises MemoryError (main: a SolverError when CHOLMOD ran out).
        for level in (3, 4, 5):
            try:
                Vl, Fl = geotex.generate("sphere", level=level)
                geotex.smooth(Vl, Fl)
                print("smooth", level, "fitted")
            except MemoryError:
                print("smooth", level, "MemoryError")
                break
        print("alive", geotex.info(V, F)["faces"])
    """, timeout=600, memory_bytes=1200 << 20)
    assert_clean_exit(p)
    assert "MemoryError" in p.stdout and "alive" in p.stdout, p.stdout + p.stderr


@pytest.mark.skipif(SANITIZED, reason="the sanitizer build factors with Eigen's SimplicialLDLT; the estimate is CHOLMOD's analysis")
def test_issue30_a_factorization_too_large_for_the_memory_left_is_refused_before_its_system_is_assembled():
    # deform of a 2.6 M-vertex sphere was killed for memory after 190 s: the symbolic analysis of the vertex
    # graph now estimates the Cholesky factor's size before the system is assembled, and refuses one that
    # does not fit with a MemoryError naming it. The
    # 41k-vertex sphere's linear edit needs about 0.5 GiB for its factor: refused with 150 MiB left beside
    # the process; the 2.5k-vertex sphere's fits.
    p = run_child("""
        import os
        import geotex
        def rss():
            for line in open("/proc/self/status"):
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) * 1024
        for level in (1, 3):
            V, F = geotex.generate("sphere", level=level)
            os.environ["GEOTEX_MAX_MEMORY"] = str(rss() + (150 << 20))
            try:
                X = geotex.deform(V, F, handles=[0, 1], targets=V[[0, 1]] + [[0.1, 0, 0], [0, 0, 0]])
                print(level, "deformed", X.shape == V.shape)
            except MemoryError as e:
                print(level, "MemoryError", f"factoring its {3 * len(V)} x {3 * len(V)} system" in str(e),
                      "needs about" in str(e), f"estimated from its {len(V)}-vertex graph" in str(e))
    """)
    assert_clean_exit(p)
    assert "1 deformed True" in p.stdout, p.stdout + p.stderr
    assert "3 MemoryError True True True" in p.stdout, p.stdout + p.stderr


def test_issue30_a_mesh_too_large_for_the_memory_left_is_refused_before_it_is_read(tmp_path):
    # The readers estimate what a mesh needs from its declared counts and refuse at once with a
    # MemoryError naming the estimate (a sparse 3 GB STL took 238 s to fail). GEOTEX_MAX_MEMORY caps what
    # geotex may take beyond the process's resident set: 26 MiB leaves the files (8-17 MiB) readable but
    # not the 327,680-face sphere (about 58 MiB); 4 GiB reads it.
    path = tmp_path / "s.ply"
    V, F = geotex.generate("sphere", level=4)
    geotex.write_mesh(path, V, F)
    for ext in ("obj", "off", "stl"):
        geotex.write_mesh(tmp_path / f"s.{ext}", V, F)
    p = run_child(f"""
        import os
        import geotex
        def rss():  # the resident set now, as geotex reads it
            for line in open("/proc/self/status"):
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) * 1024
        for ext in ("ply", "obj", "off", "stl"):
            os.environ["GEOTEX_MAX_MEMORY"] = str(rss() + (26 << 20))
            try:
                geotex.read_mesh({str(tmp_path)!r} + "/s." + ext)
                print(ext, "read under the cap")
            except MemoryError as e:
                print(ext, "MemoryError", "needs about" in str(e) and "faces" in str(e))
            os.environ["GEOTEX_MAX_MEMORY"] = "4G"
            print(ext, "faces", len(geotex.read_mesh({str(tmp_path)!r} + "/s." + ext)[1]))
    """)
    assert_clean_exit(p)
    for ext in ("ply", "obj", "off", "stl"):
        assert f"{ext} MemoryError True" in p.stdout, p.stdout + p.stderr
        assert f"{ext} faces {len(F)}" in p.stdout, p.stdout + p.stderr


# ---- issue 30, items 2 and 3: error lines that name the cause; growing inputs -----------------------

def test_issue30_error_lines_name_the_real_cause(tmp_path):
    # a NUL byte inside a number is shown escaped, not cut
    (tmp_path / "nul.obj").write_bytes(b"v 0 0 0\nv 1\x00.5 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(geotex.IoError, match=r"'1\\x00\.5'"):
        geotex.read_mesh(str(tmp_path / "nul.obj"))
    # a symlink loop, a device, a FIFO and a folder say what they are
    os.symlink(tmp_path / "b.obj", tmp_path / "a.obj")
    os.symlink(tmp_path / "a.obj", tmp_path / "b.obj")
    os.symlink("/dev/null", tmp_path / "null.ply")
    os.mkfifo(tmp_path / "fifo.ply")
    (tmp_path / "dir.obj").mkdir()
    for name, says in (("a.obj", "loop of symbolic links"), ("null.ply", "a device"), ("fifo.ply", "a FIFO"),
                       ("dir.obj", "is a directory")):
        with pytest.raises(geotex.IoError, match=says):
            geotex.read_mesh(str(tmp_path / name))
    # an ascii STL with indented lines is ascii
    facet = "  facet normal 0 0 1\n   outer loop\n    vertex 0 0 {0}\n    vertex 1 0 {0}\n    vertex 0 1 {0}\n" \
            "   endloop\n  endfacet\n"
    (tmp_path / "i.stl").write_text("  solid x\n" + facet.format(0) + facet.format(1) + "  endsolid x\n")
    V, F = geotex.read_mesh(str(tmp_path / "i.stl"))
    assert len(F) == 2
    # an index is printed as the exact integer it is
    V, F = geotex.generate("sphere", level=0)
    for dtype, value in ((np.uint64, 2**64 - 1), (np.int64, 2**63 - 1), (np.int64, -2**63)):
        bad = F.astype(dtype)
        bad[0, 0] = value
        with pytest.raises(geotex.InvalidInput, match=f"vertex index {value} out of range"):
            geotex.info(V, bad)
    # an index stored as a double in a PLY: the integer it is (2**64 - 1 reads as 2**64), not 1.8e+19
    (tmp_path / "fd.ply").write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                     "property float z\nelement face 1\nproperty list uchar double vertex_indices\n"
                                     "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 18446744073709551615\n")
    with pytest.raises(geotex.IoError, match="vertex index 18446744073709551616, not"):
        geotex.read_mesh(str(tmp_path / "fd.ply"))
    # ... and so are the other index arrays: edges to draw (main cast them to int: 2**32 + 1 became vertex 1,
    # a wrong line drawn without a word), edge pairs to score, deformation handles (main: a TypeError
    # of the binding, the value not named)
    for dtype, value in ((np.int64, 2**32 + 1), (np.uint64, 2**64 - 1), (np.int64, -1)):
        edges = np.array([[0, 1], [1, 2]], dtype=dtype)
        edges[1, 1] = value
        with pytest.raises(geotex.InvalidInput, match=f"edges: row 1 has vertex index {value} out of range"):
            geotex.render(V, F, edges=edges, width=32, height=32)
        with pytest.raises(geotex.InvalidInput, match=f"row 1 has vertex index {value} out of range"):
            geotex.score_edge_labels(edges, edges[:1])
        with pytest.raises(geotex.InvalidInput, match=f"handles: row 1 has vertex id {value} out of range"):
            geotex.deform(V, F, handles=np.array([0, value], dtype=dtype), targets=V[:2])


def test_issue30_a_growing_file_is_read_as_it_was_opened(tmp_path):
    import threading
    V, F = geotex.generate("sphere", level=1)
    for ext in ("obj", "ply"):
        path = tmp_path / f"g.{ext}"
        geotex.write_mesh(str(path), V, F, binary=False)
        stop = threading.Event()
        started = threading.Event()

        def append():
            chunk = b"v 1 2 3\n" * 512  # 4 KiB appends, whole lines
            written = 0
            with open(path, "ab", buffering=0) as f:
                while not stop.is_set() and written < 256 << 20:
                    f.write(chunk)
                    written += len(chunk)
                    started.set()

        t = threading.Thread(target=append)
        t.start()
        started.wait()
        try:
            V2, F2 = geotex.read_mesh(str(path))
        except geotex.IoError as e:  # the size at open ended inside an appended line: said as such
            assert ext == "obj" and "truncated" in str(e), str(e)
            continue
        finally:
            stop.set()
            t.join()
        assert np.array_equal(F2, F)
        assert len(V2) < len(V) + (64 << 20) // 8


def test_issue30_standard_input_stops_at_the_declared_counts(tmp_path):
    # A pipe has no size to snapshot: read_mesh("-") reads a PLY up to its declared elements while the
    # writer goes on (main read until the writer stopped: never, here; the 120 s wait is only a hang guard).
    import threading
    V, F = geotex.generate("sphere", level=1)
    for name, binary in (("a.ply", False), ("b.ply", True)):
        path = tmp_path / name
        geotex.write_mesh(str(path), V, F, binary=binary)
        child = subprocess.Popen([sys.executable, "-c", "import geotex; V, F = geotex.read_mesh('-'); print(len(V), len(F))"],
                                 stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=False)
        cut_off = []

        def write():
            try:
                child.stdin.write(path.read_bytes())
                child.stdin.flush()
                while True:  # a writer that never stops by itself
                    child.stdin.write(b"1 2 3\n" * 16)
                    child.stdin.flush()
            except (BrokenPipeError, ValueError, OSError):
                cut_off.append(True)

        t = threading.Thread(target=write, daemon=True)
        t.start()
        try:
            child.wait(timeout=120)  # not communicate(): it would close the child's standard input
        except subprocess.TimeoutExpired:
            child.kill()
            pytest.fail(f"{name}: read_mesh('-') still reading after 120 s of a writer that never stops")
        t.join(10)
        out, err = child.stdout.read(), child.stderr.read()
        assert child.returncode == 0, err.decode()
        assert out.decode().split() == [str(len(V)), str(len(F))], out
        assert cut_off, name


def test_issue30_ctrl_c_stops_render_before_it_writes(tmp_path):
    # Issue 30 item 7: render had no cancellation point; a SIGINT during it raised KeyboardInterrupt only
    # after the whole picture was drawn and written. Now it stops while drawing: no file is written.
    out = tmp_path / "big.png"
    p = run_child(f"""
        import os, signal, threading
        import geotex
        signal.signal(signal.SIGINT, signal.default_int_handler)  # see test_class1_ctrl_c_...
        V, F = geotex.generate("sphere", level=3)
        sent = []
        def interrupt():
            sent.append(1)
            os.kill(os.getpid(), signal.SIGINT)
        threading.Timer(0.5, interrupt).start()
        try:
            geotex.render(V, F, {str(out)!r}, width=4096, height=4096)
            print("finished", "after the signal" if sent else "before the signal")
        except KeyboardInterrupt:
            print("interrupted")
    """, timeout=600)
    assert_clean_exit(p)
    assert p.stdout.strip() == "interrupted", p.stdout + p.stderr
    assert not out.exists(), "the picture was drawn and written before the interrupt was raised"
