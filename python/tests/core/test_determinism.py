"""Issue 33: outcomes decided on the input, not by rounding in the machine's BLAS kernel.

Each under-constrained case is built exactly (two handles on a sphere, three collinear handles, a
component without a handle, harmonic extension over a component with no known vertex) and its outcome
asserted through Python and the CLI: a defined result or a clear error, the same on every machine."""

import json
import os
import subprocess

import numpy as np
import pytest

import geotex

CLI = os.environ.get("GEOTEX_CLI")


def two_spheres():
    V, F = geotex.generate("sphere", level=1)
    return np.r_[V, V + [3.0, 0, 0]], np.r_[F, F + len(V)], len(V)


def test_two_handles_on_a_sphere_move_it_rigidly():
    # The issue's call: the linear method leaves the rotation about the handles' axis free; the stated
    # rule fixes it at the handles' own motion, here a translation.
    V, F = geotex.generate("sphere", level=0)
    out = geotex.deform(V, F, handles=[0, 1], targets=V[[0, 1]] + 0.01)
    assert np.abs(out - (V + 0.01)).max() < 1e-6


def test_three_collinear_handles_move_a_plane_rigidly():
    V, F = geotex.generate("plane", level=0)
    row = np.flatnonzero(np.abs(V[:, 1] - V[0, 1]) < 1e-12)[:3]
    out = geotex.deform(V, F, handles=row.tolist(), targets=V[row] + [0, 0, 0.2])
    assert np.abs(out - (V + [0, 0, 0.2])).max() < 1e-6


@pytest.mark.parametrize("method", ["linear", "plain", "membrane-fit"])
def test_a_component_without_a_handle_is_named(method):
    V, F, n = two_spheres()
    with pytest.raises(geotex.InvalidInput, match="component 2 of 2"):
        geotex.deform(V, F, handles=[0, 1, 2], targets=V[:3] + 0.1, method=method)
    out = geotex.deform(V, F, handles=[0, n], targets=V[[0, n]] + 0.1, method=method)
    # One handle per component: a translation for every method (membrane-fit keeps the rest frame where
    # the membrane of the handles is a point).
    assert np.abs(out - (V + 0.1)).max() < 1e-6


@pytest.mark.skipif(not CLI, reason="GEOTEX_CLI not set (ctest sets it)")
def test_cli_two_handles_and_an_unpinned_component(tmp_path):
    V, F = geotex.generate("sphere", level=0)
    geotex.write_mesh(str(tmp_path / "s.ply"), V, F)
    spec = {"handles": [{"vertices": [0, 1], "targets": (V[[0, 1]] + 0.01).tolist()}]}
    (tmp_path / "h.json").write_text(json.dumps(spec))
    r = subprocess.run([CLI, "-q", "deform", str(tmp_path / "s.ply"), "--handles", str(tmp_path / "h.json"),
                        "-o", str(tmp_path / "d.ply")], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert np.abs(geotex.read_mesh(str(tmp_path / "d.ply"))[0] - (V + 0.01)).max() < 1e-6

    V2, F2, _ = two_spheres()
    geotex.write_mesh(str(tmp_path / "two.ply"), V2, F2)
    r = subprocess.run([CLI, "-q", "deform", str(tmp_path / "two.ply"), "--handles", str(tmp_path / "h.json"),
                        "-o", str(tmp_path / "d2.ply")], capture_output=True, text=True, timeout=120)
    assert r.returncode == 1 and "component 2 of 2" in r.stderr, r.stderr
    assert not (tmp_path / "d2.ply").exists()


def _first_array(out):
    """The positions (or the first float array) a call returns, whatever its result type."""
    for key in ("V", "height"):
        if hasattr(out, key):
            return np.asarray(getattr(out, key))
        if isinstance(out, dict) and key in out:
            return np.asarray(out[key])
    if isinstance(out, tuple):
        return np.asarray(out[0])
    if hasattr(out, "keys"):  # a Result without positions: its first float array
        for key in out.keys():
            a = np.asarray(out[key])
            if a.dtype.kind == "f" and a.size:
                return a
        return np.zeros(0)
    return np.asarray(out)


def thread_cases(V, F):
    """Every computing operation on one mesh, as (name, call taking a thread count)."""
    n = len(V)
    handles = [0, n // 3, (2 * n) // 3]
    texture = geotex.texture_extract(V, F)
    disk = len(geotex.boundary_loops(V, F)) == 1 and len(np.unique(geotex.connected_components(V, F))) == 1
    return [
        ("smooth", lambda t: geotex.smooth(V, F, steps=3, threads=t)),
        ("denoise", lambda t: geotex.denoise(V, F, threads=t)),
        ("denoise mrf", lambda t: geotex.denoise_mrf(V, F, threads=t)),
        ("denoise mrf-normal", lambda t: geotex.denoise_mrf_normal(V, F, threads=t)),
        ("denoise surfel", lambda t: geotex.denoise_surfel(V, F, threads=t)),
        ("deform", lambda t: geotex.deform(V, F, handles=handles, targets=V[handles] + 0.05, threads=t)),
        ("resize", lambda t: geotex.resize(V, F, scale=(2, 1, 1), threads=t)),
        ("texture extract", lambda t: geotex.texture_extract(V, F, threads=t)),
        ("feature map", lambda t: geotex.feature_map(V, F, threads=t)),
        ("surfels", lambda t: geotex.point_surfels(V, threads=t)),
        ("project", lambda t: geotex.phong_project(V, F, V + 0.01 * (V - V.mean(0)), threads=t)["point"]),
        ("texture apply", lambda t: geotex.texture_apply(texture, threads=t)),
    ] + ([("param", lambda t: geotex.parametrize(V, F, threads=t))] if disk else [])


def thread_differences(V, F):
    """{operation: largest |output(1 thread) - output(2 threads)| / bounding-box diagonal}."""
    diag = float(np.linalg.norm(V.max(0) - V.min(0)))
    out = {}
    for name, call in thread_cases(V, F):
        a, b = _first_array(call(1)), _first_array(call(2))
        out[name] = float(np.abs(a - b).max()) / diag if a.size else 0.0
    return out


def test_outputs_agree_across_thread_counts():
    # Measured 3e-14 of the diagonal for denoise, smooth and resize (issue 33): a parallel loop that made
    # the result depend on the thread count would show as a difference far above round-off.
    V, F = geotex.generate("cube", level=2)
    V = geotex.add_noise(V, F, sigma=0.2, seed=3)
    P, Q = geotex.generate("bumpy-plate", level=1)  # a disk: parametrize joins the list
    found = {**thread_differences(V, F), **{f"{k} (disk)": d for k, d in thread_differences(P, Q).items()}}
    assert "param (disk)" in found
    for name, d in found.items():
        assert d < 1e-9, f"{name}: 1 and 2 threads differ by {d:.2e} of the diagonal"
