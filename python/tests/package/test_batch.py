"""Batch runs: every geotex function taking a mesh is an operation; options are checked once, before any
file is read; a two-worker cluster over loopback gives the same files as one process; bad files are
reported and the batch goes on."""

import concurrent.futures as cf
import hashlib
import inspect
import multiprocessing
import multiprocessing.connection
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import geotex
from geotex import batch


def _digest(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("batch-in")
    for i in range(8):
        V, F = geotex.generate(["sphere", "cube", "torus", "cylinder"][i % 4], level=0, seed=i + 1)
        V = geotex.add_noise(V, F, sigma=0.2, seed=i)
        geotex.write_mesh(str(d / f"mesh{i:02d}.{['ply', 'obj', 'off'][i % 3]}"), V, F)
    (d / "corrupt-empty.obj").write_text("")
    (d / "corrupt-truncated.ply").write_bytes(
        b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        b"property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" + b"\0" * 10)
    (d / "corrupt-nan.obj").write_text("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
    (d / "notes.txt").write_text("not a mesh; ignored because of its extension")
    return d


# ---------------------------------------------------------------------------------------------
# Every operation


def test_every_function_taking_a_mesh_is_an_operation():
    ops = batch.operations()
    for name in geotex.__all__:
        fn = getattr(geotex, name)
        if not callable(fn) or inspect.isclass(fn):
            continue
        params = list(inspect.signature(fn).parameters)
        takes_mesh = bool(params) and params[0] in ("mesh", "result", "V_base", "P", "meshes", "texture")
        assert (name in ops) == takes_mesh, name
    for wanted in ("smooth", "denoise", "add_noise", "deform", "parametrize", "phong_project", "texture_extract",
                   "texture_apply", "texture_edit", "texture_transfer", "resize", "render", "view", "info"):
        assert wanted in ops, wanted
    for alias, name in batch.ALIASES.items():
        assert batch._operation(alias).name == name


def _extra_arguments(name, V, F):
    """Arguments a test run gives each operation that needs more than the mesh (a new function that needs
    some fails test_every_operation_runs until it is added here)."""
    nE = geotex.edges(V, F).shape[0]
    return {
        "deform": dict(handles=[0, 1], targets=V[[0, 1]] + 0.01),
        "phong_project": dict(P=V[:5] * 1.1),
        "one_form_fit": dict(T=np.cross(geotex.vertex_normals(V, F), [0.0, 0.0, 1.0])),
        "one_form_to_vertices": dict(c=np.zeros(nE)),
        "compare": dict(V_truth=(V, F)),
        "texture_edit": dict(op="scale-height", factor=2.0),
        "texture_transfer": dict(target=(V, F), source_radius=0.3, target_radius=0.8),
        "texture_atlas": dict(target=(V, F), source_radius=0.3, target_radius=0.8),
        "texture_synthesize": dict(target=(V, F), refine_ratio=0),
        "resize": dict(scale=[1.5, 1, 1]),
        "parametrize": {},
        "parametrization_quality": dict(uv=V[:, :2]),
    }.get(name, {})


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    d = tmp_path_factory.mktemp("small")
    V, F = geotex.generate("sphere", level=0)
    geotex.write_mesh(str(d / "sphere.ply"), V, F)
    Vp, Fp = geotex.generate("plane", level=0)
    geotex.write_mesh(str(d / "plane.ply"), Vp, Fp)
    (Vt, Ft), (Vb, _) = geotex.generate("bumpy-plate", level=0, with_base=True)
    geotex.write_texture(str(d / "bumps.ply"), geotex.texture_extract(Vt, Ft, Vb))
    return d


def test_every_operation_runs(small, tmp_path):
    V, F = geotex.read_mesh(str(small / "sphere.ply"))
    Vp, Fp = geotex.read_mesh(str(small / "plane.ply"))
    for name, op in sorted(batch.operations().items()):
        disk = name in ("parametrize", "one_form_fit")  # a disk, not a sphere
        src = small / ("plane.ply" if disk else "sphere.ply")
        if op.input == "texture":
            src = small / "bumps.ply"  # a texture file
        args = _extra_arguments(name, *((Vp, Fp) if disk else (V, F)))
        missing = [a for a in op.required if a not in args]
        assert not missing, f"{name} needs {missing}: add them to _extra_arguments"
        out = tmp_path / name
        result = batch.run(name, [src], output_dir=out, workers=1, progress=False, **args)
        row = result.rows[0]
        assert row["status"] == "ok", (name, row["error"])
        written = sorted(p.name for p in out.iterdir())
        assert written or "result" in row, f"{name}: neither a file nor a result"
        assert all(not w.startswith(".") for w in written), (name, written)  # no temporaries left


def test_needs_lists_every_argument_a_function_cannot_run_without(small):
    """batch.NEEDS is what makes options incomplete before any file is read: each listed argument really
    is needed (TypeError without it), and no other function stops for want of an argument."""
    V, F = geotex.read_mesh(str(small / "sphere.ply"))
    for name, op in batch.operations().items():
        for needed in batch.NEEDS.get(name, ()):
            args = {k: v for k, v in _extra_arguments(name, V, F).items() if k != needed}
            with pytest.raises(TypeError):
                op.function(V, F, **args)
            with pytest.raises(batch.BatchOptionError, match=needed):
                batch.check_options(name, args)


# ---------------------------------------------------------------------------------------------
# Options checked up front


@pytest.mark.parametrize("operation, options, words", [
    ("smooth", {"steps": -3}, ["steps"]),
    ("smooth", {"laplacian": "bilaplace"}, ["laplacian", "bilaplace"]),
    ("smooth", {"stepz": 2}, ["stepz", "not an option"]),
    ("smooth", {"lambda_": "big"}, ["lambda"]),
    ("denoise_mrf", {"preset": "fastest"}, ["fastest"]),
    ("denoise", {"method": "mrf", "phi0": -5}, ["phi0"]),
    ("denoise", {"method": "mrf", "beta": 3}, ["beta"]),
    ("resize", {"scale": "wide"}, ["scale"]),
])
def test_bad_option_is_refused_before_any_file_is_read(operation, options, words, tmp_path):
    with pytest.raises(batch.BatchOptionError) as e:
        batch.run(operation, tmp_path / "does-not-exist", output_dir=tmp_path / "out", progress=False, **options)
    for w in words:
        assert w in str(e.value)
    assert not (tmp_path / "out").exists()


def test_every_problem_is_listed_once(tmp_path):
    with pytest.raises(batch.BatchOptionError) as e:
        batch.check_options("deform", {"stepz": 1, "method": "wobble"})
    text = str(e.value)
    for w in ("stepz", "wobble", "handles", "targets"):
        assert text.count(w) >= 1, w
    assert text.count("stepz") == 1


def test_cli_reports_a_bad_set_once_with_exit_2(folder, tmp_path):
    out = tmp_path / "cli-out"
    proc = subprocess.run([sys.executable, "-m", "geotex.batch", "smooth", str(folder), "-o", str(out),
                           "--set", "steps=-1", "--set", "stepz=2", "--workers", "1"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("error:") == 1
    assert "steps" in proc.stderr and "stepz" in proc.stderr
    assert "stepz: not an option of smooth (did you mean steps?)" in proc.stderr
    assert "[1/" not in proc.stderr and not out.exists()  # no file was touched
    proc = subprocess.run([sys.executable, "-m", "geotex.batch", "teleport", str(folder)], capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 2 and "unknown operation" in proc.stderr


def test_an_unreachable_scheduler_is_one_line_within_seconds(folder, tmp_path):
    pytest.importorskip("distributed")
    import socket

    with socket.socket() as s:  # a port nobody listens on: bound, never listening
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
        proc = subprocess.run([sys.executable, "-m", "geotex.batch", "smooth", str(folder), "-o", str(tmp_path / "o"),
                               "--scheduler", f"tcp://127.0.0.1:{port}"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "cannot reach the Dask scheduler" in lines[0], proc.stderr
    assert f"within {batch.SCHEDULER_TIMEOUT:g} s" in lines[0]
    assert not (tmp_path / "o").exists()


# ---------------------------------------------------------------------------------------------
# Where it runs: one process, a process pool, a loopback cluster


def _loopback_worker(address, authkey):
    """A worker of LoopbackExecutor: runs the calls it is sent over its socket until told to stop."""
    with multiprocessing.connection.Client(address, authkey=authkey) as conn:
        while True:
            job = conn.recv()
            if job is None:
                return
            key, fn, args, kwargs = job
            try:
                conn.send((key, True, fn(*args, **kwargs)))
            except Exception as e:  # noqa: BLE001 - sent back to the caller's future
                conn.send((key, False, e))


class LoopbackExecutor(cf.Executor):
    """A two-worker cluster over 127.0.0.1: worker processes connect to this process's TCP listener and
    receive pickled calls, as the workers of a distributed scheduler do. Jobs go to the workers in
    turn, so both take part."""

    def __init__(self, workers=2):
        self._listener = multiprocessing.connection.Listener(("127.0.0.1", 0), authkey=b"geotex-test")
        ctx = multiprocessing.get_context("spawn")
        self._procs = [ctx.Process(target=_loopback_worker, args=(self._listener.address, b"geotex-test"))
                       for _ in range(workers)]
        for p in self._procs:
            p.start()
        self._conns = [self._listener.accept() for _ in self._procs]
        self._futures, self._lock, self._next = {}, threading.Lock(), 0
        self._readers = [threading.Thread(target=self._read, args=(c,), daemon=True) for c in self._conns]
        for t in self._readers:
            t.start()

    def _read(self, conn):
        while True:
            try:
                key, ok, value = conn.recv()
            except (EOFError, OSError):
                return
            fut = self._futures.pop(key)
            fut.set_result(value) if ok else fut.set_exception(value)

    def submit(self, fn, *args, **kwargs):
        fut = cf.Future()
        with self._lock:
            key, self._next = self._next, self._next + 1
            self._futures[key] = fut
            self._conns[key % len(self._conns)].send((key, fn, args, kwargs))
        return fut

    def shutdown(self, wait=True, **_):
        for c in self._conns:
            c.send(None)
        for p in self._procs:
            p.join(timeout=30)
        self._listener.close()


def _outputs(d: Path):
    return {p.name: _digest(p) for p in sorted(d.iterdir())}


def _comparable(rows):
    drop = {"seconds", "worker_pid", "output", "arrays"}
    def result(v):  # a result's own timings (seconds, seconds_per_iteration, ...) differ from run to run
        return {k: x for k, x in v.items() if not k.startswith("seconds")} if isinstance(v, dict) else v

    return [{k: result(v) if k == "result" else v for k, v in r.items() if k not in drop} for r in rows]


@pytest.mark.parametrize("operation, options", [
    ("denoise", {"method": "mrf", "iterations": 3}),
    ("smooth", {"steps": 2}),
    ("parametrize", {}),
])
def test_two_workers_over_loopback_give_what_one_process_gives(folder, tmp_path, operation, options):
    one = batch.run(operation, folder, output_dir=tmp_path / "one", workers=1, progress=False, **options)
    ex = LoopbackExecutor(2)
    try:
        two = batch.run(operation, folder, output_dir=tmp_path / "two", executor=ex, progress=False, **options)
    finally:
        ex.shutdown()
    assert _comparable(one.rows) == _comparable(two.rows)
    assert _outputs(tmp_path / "one") == _outputs(tmp_path / "two")
    assert len({r["worker_pid"] for r in two.rows}) == 2  # both workers took part
    assert len(one.rows) == 11


def test_process_pool_and_bad_files(folder, tmp_path):
    before = _outputs(folder)
    out = tmp_path / "out"
    with cf.ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as ex:
        result = batch.run("smooth", folder, output_dir=out, executor=ex, progress=False, steps=2, lambda_=0.2)
    assert len(result.rows) == 11 and len(result.ok) == 8
    assert {Path(r["file"]).name for r in result.failed} == {"corrupt-empty.obj", "corrupt-truncated.ply",
                                                             "corrupt-nan.obj"}
    assert all(r["error"] for r in result.failed)
    for r in result.ok:  # every good file has its output, readable, with its input's connectivity
        V, F = geotex.read_mesh(r["output"])
        V0, F0 = geotex.read_mesh(r["file"])
        assert (F == F0).all() and V.shape == V0.shape
    assert _outputs(folder) == before  # inputs untouched
    assert "8 ok, 3 failed, 11 files" in result.table()


def test_batch_cli_reports_ok_and_failed_files(folder, tmp_path):
    out = tmp_path / "cli-out"
    proc = subprocess.run(
        [sys.executable, "-m", "geotex.batch", "noise", str(folder), "-o", str(out), "--workers", "2",
         "--set", "sigma=0.1", "--set", "seed=4", "--json", str(tmp_path / "rows.json")],
        capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stderr  # three corrupt files
    assert "8 ok, 3 failed" in proc.stdout
    assert (tmp_path / "rows.json").exists() and len(list(out.iterdir())) == 8
