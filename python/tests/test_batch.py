"""Batch runs on a two-worker local Dask cluster over loopback: every good file done, every bad one
reported, nothing lost."""

import hashlib
from pathlib import Path

import pytest

import geotex
from geotex import batch

pytest.importorskip("distributed")


def _digest(p: Path) -> str:
    return hashlib.sha256(p.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("batch-in")
    names = geotex.shape_names()
    for i in range(20):
        V, F = geotex.generate(names[i % len(names)], level=0, seed=i + 1)
        V = geotex.add_noise(V, F, sigma=0.2, seed=i)
        geotex.write_mesh(str(d / f"mesh{i:02d}.{['ply', 'obj', 'off'][i % 3]}"), V, F)
    (d / "corrupt-empty.obj").write_text("")
    (d / "corrupt-truncated.ply").write_bytes(
        b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        b"property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" + b"\0" * 10)
    (d / "corrupt-nan.obj").write_text("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
    (d / "notes.txt").write_text("not a mesh; ignored because of its extension")
    return d


def test_batch_smooth_on_local_cluster(folder, tmp_path):
    before = {p.name: _digest(p) for p in folder.iterdir()}
    out = tmp_path / "out"
    result = batch.run("smooth", folder, output_dir=out, n_workers=2, progress=False, steps=2, lambda_=0.2)
    assert len(result.rows) == 23
    assert len(result.ok) == 20
    bad = {Path(r["file"]).name for r in result.failed}
    assert bad == {"corrupt-empty.obj", "corrupt-truncated.ply", "corrupt-nan.obj"}
    assert all(r["error"] for r in result.failed)
    # every good file has its output, readable, with its input's connectivity
    for r in result.ok:
        V, F = geotex.read_mesh(r["output"])
        V0, F0 = geotex.read_mesh(r["file"])
        assert (F == F0).all() and V.shape == V0.shape
    # both workers took part, the inputs are untouched, and the table lists every file
    assert len({r["worker_pid"] for r in result.rows}) == 2
    assert {p.name: _digest(p) for p in folder.iterdir()} == before
    table = result.table()
    assert "20 ok, 3 failed, 23 files" in table


def test_batch_cli(folder, tmp_path):
    import subprocess
    import sys

    out = tmp_path / "cli-out"
    proc = subprocess.run(
        [sys.executable, "-m", "geotex.batch", "info", str(folder), "-o", str(out), "--workers", "2",
         "--json", str(tmp_path / "rows.json")],
        capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stderr  # three corrupt files
    assert "20 ok, 3 failed" in proc.stdout
    assert (tmp_path / "rows.json").exists()


def test_unknown_operation_is_rejected(folder):
    with pytest.raises(ValueError):
        batch.run("teleport", folder)
