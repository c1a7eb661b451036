"""Results are meshes and say what the CLI's report says (issues 28 and 29): a result that holds a mesh is
accepted wherever a mesh is; edge labels are accepted as labels; a denoising result has every key of
`geotex denoise --report` for the same call (both are written from the same C++ result tables)."""

import json
import os
import subprocess

import numpy as np
import pytest

import geotex

CLI = os.environ.get("GEOTEX_CLI")


@pytest.fixture(scope="module")
def noisy():
    V, F = geotex.generate("cube", level=1)
    return geotex.add_noise(V, F, sigma=0.2, seed=3), F


def test_a_denoising_result_is_written_as_its_mesh(tmp_path, noisy):
    r = geotex.denoise(*noisy, method="mrf", iterations=3)
    assert isinstance(r, geotex.MrfResult) and isinstance(r, geotex.MeshResult)
    path = tmp_path / "r.ply"
    geotex.write_mesh(path, r)  # binary PLY: exact doubles
    V, F = geotex.read_mesh(path)
    assert np.array_equal(V, r.V) and np.array_equal(F, r.F)


def test_a_result_is_a_mesh_for_every_entry_point(tmp_path, noisy):
    r = geotex.denoise(*noisy, method="mrf", iterations=3)
    assert np.array_equal(geotex.render(r, width=48, height=32), geotex.render(r.V, r.F, width=48, height=32))
    again = geotex.denoise(r, method="mrf", iterations=2)  # a result denoised again
    assert again.V.shape == r.V.shape
    assert geotex.info(r)["faces"] == len(r.F)
    page = geotex.view([r, {"mesh": again, "edges": again.edge_labels}], tmp_path / "v.html", script_src="viewer.js")
    assert os.path.getsize(page) > 0
    with pytest.raises(TypeError, match="without a mesh"):
        geotex.write_mesh(tmp_path / "x.ply", geotex.Result(weights=np.zeros(3)))


def test_edge_labels_draw_the_edges_labelled_above_one_half(noisy):
    r = geotex.denoise(*noisy, method="mrf", iterations=3)
    assert 0 < (r.edge_labels > 0.5).sum() < len(r.edge_labels)  # a picture that depends on the labels
    by_labels = geotex.render(r, edges=r.edge_labels, width=96, height=64)
    by_pairs = geotex.render(r, edges=r.edges[r.edge_labels > 0.5], width=96, height=64)
    assert np.array_equal(by_labels, by_pairs)
    assert not np.array_equal(by_labels, geotex.render(r, width=96, height=64))


def test_edge_labels_of_another_length_are_refused(noisy):
    r = geotex.denoise(*noisy, method="mrf", iterations=2)
    with pytest.raises(geotex.InvalidInput, match=f"{len(r.edges) - 1} labels given, but the mesh has {len(r.edges)} edges"):
        geotex.render(r, edges=r.edge_labels[:-1], width=16, height=16)


@pytest.mark.skipif(not CLI, reason="GEOTEX_CLI not set (ctest sets it)")
@pytest.mark.parametrize("method,options", [("auto", []), ("mrf", ["--iterations", "3"]), ("mrf-normal", ["--iterations", "2"]),
                                            ("surfel", [])])
def test_every_report_key_is_a_field_of_the_python_result(tmp_path, noisy, method, options):
    mesh = tmp_path / "noisy.ply"
    geotex.write_mesh(mesh, *noisy)
    report = tmp_path / "report.json"
    p = subprocess.run([CLI, "-q", "denoise", str(mesh), "--method", method, *options, "-o", str(tmp_path / "out.ply"),
                        "--report", str(report)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    keys = set(json.loads(report.read_text()))
    kwargs = {"iterations": int(options[1])} if options else {}
    r = geotex.denoise(*noisy, method=method, **kwargs)
    # 'input' is the CLI's own (the input file's name); every other key is one field of the result.
    assert keys - {"input"} <= set(r.keys()), keys - {"input"} - set(r.keys())
    assert r.method == method and r.seconds > 0
    tables = geotex._geotex._result_tables()
    name = {"auto": "AutoDenoiseResult", "surfel": "SurfelDenoiseResult"}.get(method, "MrfResult")
    declared = {f["name"] for f in tables[name] + tables["DenoiseRun"] if f["in_report"]}
    assert keys - {"input", "parameters"} == declared
