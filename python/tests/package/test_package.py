"""The package as users get it: signatures made from the option tables, stubs that match the module,
mesh objects, installation with pip."""

import inspect
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

import geotex
from geotex import _options


def test_every_option_is_a_keyword_with_the_tables_default():
    # For each function made from a table: one keyword-only argument per option, default and all.
    checked = 0
    for name in geotex.__all__:
        fn = getattr(geotex, name)
        table = getattr(fn, "options_table", None)
        if table is None:
            continue
        params = inspect.signature(fn).parameters
        for f in _options.table(table)["fields"]:
            p = params[_options.python_name(f["name"])]
            assert p.kind == inspect.Parameter.KEYWORD_ONLY, (name, f["name"])
            assert p.default == f["default"], (name, f["name"])
            checked += 1
        assert "progress" in params and "threads" in params
        assert ("preset" in params) == bool(_options.table(table)["presets"])
        assert f["help"] in fn.__doc__  # help() lists the options
    assert checked > 50


def test_options_are_checked_by_name_and_type():
    V, F = geotex.generate("cube", level=0)
    with pytest.raises(TypeError):
        geotex.smooth(V, F, lambda_=1.0, steps=2.5)  # a float for an integer
    with pytest.raises(TypeError):
        geotex.smooth(V, F, no_such_option=1)
    for bad in (float("nan"), float("inf"), -1.0):
        with pytest.raises(geotex.InvalidInput, match="lambda"):
            geotex.smooth(V, F, lambda_=bad)
    with pytest.raises(geotex.InvalidInput):
        geotex.denoise_mrf(V, F, preset="best")
    with pytest.raises(geotex.InvalidInput):
        geotex.smooth(V, F, threads=0)


def test_arrays_are_converted_without_silent_narrowing():
    V, F = geotex.generate("cube", level=0)
    with pytest.raises(geotex.InvalidInput, match="integers"):
        geotex.info(V, F.astype(float))
    with pytest.raises(geotex.InvalidInput, match="out of range"):
        geotex.info(V, np.array([[0, 1, 2 ** 32]], dtype=np.int64))
    with pytest.raises(geotex.InvalidInput, match="non-finite"):
        geotex.info(np.vstack([V, [[np.nan, 0, 0]]]), F)
    # Any integer dtype is fine.
    assert geotex.info(V, F.astype(np.uint16))["faces"] == len(F)


def test_dropped_face_warns_without_crashing_a_computation():
    # A warning raised while the GIL was released used to crash the interpreter (issue 14).
    V, F = geotex.generate("cube", level=0)
    F2 = np.vstack([F, F[:1]])
    with pytest.warns(UserWarning, match="duplicate"):
        Vs = geotex.smooth(V, F2, steps=1)
    assert np.isfinite(Vs).all()


def test_mesh_objects_are_accepted():
    V, F = geotex.generate("sphere", level=0)

    class Trimesh:  # the shape of trimesh.Trimesh
        def __init__(self, V, F):
            self.vertices, self.faces = V, F

    class TriangleMesh:  # the shape of open3d.geometry.TriangleMesh
        def __init__(self, V, F):
            self.vertices, self.triangles = V, F

    a = geotex.smooth(V, F, steps=2)
    assert np.array_equal(geotex.smooth(Trimesh(V, F), steps=2), a)
    assert np.array_equal(geotex.smooth(TriangleMesh(V, F), steps=2), a)
    assert np.array_equal(geotex.smooth((V, F), steps=2), a)
    with pytest.raises(TypeError):
        geotex.smooth("not a mesh")


def test_progress_and_results():
    V, F = geotex.generate("cube", level=0)
    seen = []
    r = geotex.denoise(geotex.add_noise(V, F, sigma=0.2), F, method="mrf", iterations=4,
                       progress=lambda f, stage: seen.append(f))
    assert seen and seen[-1] == pytest.approx(1.0) and seen == sorted(seen)
    assert r.V.shape == V.shape and r["V"] is r.V
    assert r.parameters["iterations"] == 4 and r.parameters["alpha"] == 0.1
    with pytest.raises(AttributeError):
        r.no_such_field

    def stop(fraction, stage):
        raise KeyError("stop")  # an exception in the callback ends the computation

    with pytest.raises(KeyError):
        geotex.denoise(V, F, method="mrf", progress=stop)


def test_stubs_match_the_module():
    mypy = pytest.importorskip("mypy")
    root = Path(geotex.__file__).parent
    assert (root / "__init__.pyi").exists() and (root / "py.typed").exists()
    allow = Path(__file__).with_name("stubtest_allowlist.txt")
    r = subprocess.run([sys.executable, "-m", "mypy.stubtest", "geotex", "--ignore-missing-stub", "--allowlist",
                        str(allow)], capture_output=True, text=True, cwd=root.parent,
                       env={**os.environ, "PYTHONPATH": str(root.parent), "MYPY_CACHE_DIR": tempfile.mkdtemp()})
    assert r.returncode == 0, r.stdout + r.stderr


@pytest.mark.skipif(not os.environ.get("GEOTEX_SOURCE_DIR"), reason="GEOTEX_SOURCE_DIR not set (ctest sets it)")
def test_pip_install_into_a_virtual_environment(tmp_path):
    # The README's install: a venv over Debian's site packages (numpy), then pip without network.
    src = Path(os.environ["GEOTEX_SOURCE_DIR"])
    venv = tmp_path / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv)], check=True)
    # ctest passes its own build tree to reuse (GEOTEX_PIP_BUILD_DIR, GEOTEX_PIP_REUSE=1: the wheel from
    # the objects the tests ran); by hand, a build in build-pip/ as a user's pip install does.
    env = {**os.environ, "PIP_NO_INDEX": "1"}
    env.setdefault("GEOTEX_PIP_BUILD_DIR", str(src / "build-pip"))
    env.pop("PYTHONPATH", None)
    r = subprocess.run([str(venv / "bin" / "pip"), "install", "--no-build-isolation", "--no-deps", "-q", str(src)],
                       capture_output=True, text=True, env=env)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    code = ("import geotex, numpy as np; V, F = geotex.generate('cube', level=0); "
            "r = geotex.denoise(geotex.add_noise(V, F, sigma=0.2), F, method=\"mrf\", iterations=3); "
            "assert r.V.shape == V.shape and np.isfinite(r.V).all(); print(geotex.__file__)")
    r = subprocess.run([str(venv / "bin" / "python"), "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert str(venv) in r.stdout  # the installed copy, not the build tree
    # The command line comes with it: the `geotex` command and `python -m geotex`, the same CLI.
    r = subprocess.run([str(venv / "bin" / "geotex"), "--version"], capture_output=True, text=True, env=env)
    assert r.returncode == 0 and r.stdout.startswith("geotex "), r.stdout + r.stderr
    mesh, out = tmp_path / "cube.ply", tmp_path / "clean.ply"
    for args in (["generate", "cube", "--level", "1", "-o", str(mesh)], ["noise", str(mesh), "--sigma", "0.2", "-o", str(out)],
                 ["denoise", str(out), "-o", str(tmp_path / "d.ply")]):
        r = subprocess.run([str(venv / "bin" / "geotex"), "-q", *args], capture_output=True, text=True, env=env)
        assert r.returncode == 0, r.stderr
    r = subprocess.run([str(venv / "bin" / "python"), "-m", "geotex", "info", str(tmp_path / "d.ply")],
                       capture_output=True, text=True, env=env, cwd=tmp_path)
    assert r.returncode == 0 and "vertices" in r.stdout, r.stdout + r.stderr
    r = subprocess.run([str(venv / "bin" / "python"), "-m", "geotex", "info"], capture_output=True, text=True, env=env)
    assert r.returncode == 2 and "MESH is required" in r.stderr, r.stderr
    r = subprocess.run([str(venv / "bin" / "geotex"), "info", "--help"], capture_output=True, text=True, env=env)
    assert r.returncode == 0 and "Usage: geotex info" in r.stdout and str(venv) not in r.stdout, r.stdout


# Each command's options (and each method's, for denoise) and the Python function with the same ones.
CLI_TO_PYTHON = {
    ("smooth", "smooth"): "smooth",
    ("noise", "noise"): "add_noise",
    ("denoise", "auto"): "denoise_auto",
    ("denoise", "mrf"): "denoise_mrf",
    ("denoise", "mrf-normal"): "denoise_mrf_normal",
    ("denoise", "surfel"): "denoise_surfel",
    ("deform", "deform"): "deform",
    ("param", "param"): "parametrize",
    ("project", "project"): "phong_project",
    ("surfels", "surfels"): "point_surfels",
    ("render", "render"): "render",
    ("view", "view"): "view",
    ("texture extract", "extract"): "texture_extract",
    ("texture apply", "apply"): "texture_apply",
    ("texture edit", "edit"): "texture_edit",
    ("texture animate", "animate"): "texture_animate",
    ("texture transfer", "transfer"): "texture_transfer",
    ("texture atlas", "atlas"): "texture_atlas",
    ("resize", "resize"): "resize",
    ("texture synthesize", "synthesize"): "texture_synthesize",
}


def _parse_cli_default(kind, text, automatic):
    if automatic and text == "auto":
        return None
    if kind == "bool":
        return text == "true"
    if kind == "int":
        return int(text)
    if kind == "float":
        return float(text)
    if kind == "vec3":
        return tuple(float(x) for x in text.split(","))
    return text


@pytest.mark.skipif(not os.environ.get("GEOTEX_CLI"), reason="GEOTEX_CLI not set (ctest sets it)")
def test_cli_and_python_have_the_same_options():
    import json
    cli = json.loads(subprocess.run([os.environ["GEOTEX_CLI"], "options"], capture_output=True, text=True,
                                    check=True).stdout)
    pairs = {(c, o) for c, owners in cli.items() for o in owners}
    assert pairs == set(CLI_TO_PYTHON), "every command's options need a Python function (and back)"
    for (command, owner), fn_name in CLI_TO_PYTHON.items():
        fn = getattr(geotex, fn_name)
        params = inspect.signature(fn).parameters
        py_fields = {f["name"]: f for f in _options.table(fn.options_table)["fields"]}
        assert set(cli[command][owner]) == set(py_fields), (command, owner)
        for name, c in cli[command][owner].items():
            p = params[_options.python_name(name)]
            assert p.default == _parse_cli_default(c["kind"], c["default"], c["automatic"]), (command, owner, name)
            f = py_fields[name]
            unbounded = lambda v: None if v is None or abs(v) == float("inf") else v
            assert (unbounded(c["lo"]), unbounded(c["hi"])) == (unbounded(f["lo"]), unbounded(f["hi"])), (command, name)
            assert c["choices"] == f["choices"] and c["kind"] == f["kind"], (command, name)
