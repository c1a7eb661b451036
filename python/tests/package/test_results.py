"""Results are meshes and say what the CLI's report says (issues 28 and 29): a result that holds a mesh is
accepted wherever a mesh is; edge labels are accepted as labels; a denoising result has every key of
`geotex denoise|resize|texture ... --report` for the same call (both are written from the same C++ result
tables)."""

import json
import os
import subprocess
import warnings

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


# Every other command that writes --report: the report and the Python result of the same call are written
# from the same C++ result tables (resize/results.h, texture/results.h; core/results.h's RunTime).
CLI_OWN = {"input", "deformed", "feature_file"}  # the CLI's own: the names of the files it read


@pytest.fixture(scope="module")
def report_inputs(tmp_path_factory):
    """Small inputs, written as the CLI reads them (binary PLY: exact doubles): a bumpy plate over its base,
    its texture, and a coarse sphere to texture."""
    d = tmp_path_factory.mktemp("reports")
    (Vp, Fp), (Vpb, _) = geotex.generate("bumpy-plate", level=0, with_base=True)
    Vs, Fs = geotex.generate("sphere", level=1)
    tex = geotex.texture_extract(Vp, Fp, base=Vpb)
    geotex.write_mesh(d / "plate.ply", Vp, Fp)
    geotex.write_mesh(d / "plate_base.ply", Vpb, Fp)
    geotex.write_mesh(d / "sphere.ply", Vs, Fs)
    geotex.write_texture(d / "tex.ply", tex)
    return d, {"plate": (Vp, Fp), "plate_base": Vpb, "sphere": (Vs, Fs), "tex": tex}


# command: (the CLI's arguments, the input files as {placeholders}; the same call in Python)
REPORT_CASES = {
    "resize": (["resize", "{plate}", "--scale", "2,1,1"],
               lambda m: geotex.resize(m["plate"], scale=(2, 1, 1))),
    "texture extract": (["texture", "extract", "{plate}", "--base", "{plate_base}"],
                        lambda m: geotex.texture_extract(m["plate"], base=m["plate_base"])),
    "texture transfer": (["texture", "transfer", "{tex}", "{sphere}", "--source-near", "0,0,0", "--target-near",
                          "0,0,1", "--source-radius", "0.5", "--target-radius", "0.5", "--refine-ratio", "0"],
                         lambda m: geotex.texture_transfer(m["tex"], m["sphere"], source_near=(0, 0, 0),
                                                           target_near=(0, 0, 1), source_radius=0.5,
                                                           target_radius=0.5, refine_ratio=0)),
    "texture atlas": (["texture", "atlas", "{tex}", "{sphere}", "--source-near", "0,0,0", "--source-radius", "0.5",
                       "--target-radius", "0.7", "--refine-ratio", "0"],
                      lambda m: geotex.texture_atlas(m["tex"], m["sphere"], source_near=(0, 0, 0), source_radius=0.5,
                                                     target_radius=0.7, refine_ratio=0)),
    "texture synthesize": (["texture", "synthesize", "{tex}", "--target", "{sphere}", "--direction", "0,0,1",
                            "--refine-ratio", "0"],
                           lambda m: geotex.texture_synthesize(m["tex"], m["sphere"], direction=(0, 0, 1),
                                                               refine_ratio=0)),
}


@pytest.mark.skipif(not CLI, reason="GEOTEX_CLI not set (ctest sets it)")
@pytest.mark.parametrize("command", list(REPORT_CASES))
def test_every_report_key_of_every_command_is_a_field_of_the_python_result(report_inputs, command):
    d, inputs = report_inputs
    args, call = REPORT_CASES[command]
    files = {"plate": d / "plate.ply", "plate_base": d / "plate_base.ply", "sphere": d / "sphere.ply",
             "tex": d / "tex.ply"}
    out, report = d / f"{command.replace(' ', '_')}.ply", d / f"{command.replace(' ', '_')}.json"
    p = subprocess.run([CLI, "-q", *[a.format(**files) for a in args], "-o", str(out), "--report", str(report)],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    rep = json.loads(report.read_text())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a warning is also a field (warnings, warning), compared below
        r = call(inputs)
    keys = set(rep) - CLI_OWN
    assert keys <= set(r.keys()), keys - set(r.keys())
    _, tables = geotex._RESULT_CLASSES[type(r).__name__]
    all_tables = geotex._geotex._result_tables()
    declared = {f["name"] for t in tables for f in all_tables[t] if f["in_report"]}
    assert keys - {"parameters"} == declared
    # One name for one thing: the same value under the same name (times aside; the same call, same input).
    for key in keys - {"seconds", "stage_seconds", "parameters"}:
        got, want = rep[key], r[key]
        if isinstance(want, float):
            assert got == pytest.approx(want, rel=1e-9, abs=1e-12), key
        else:
            assert got == want, key
    assert r.seconds > 0 and rep["seconds"] > 0


@pytest.mark.skipif(not CLI, reason="GEOTEX_CLI not set (ctest sets it)")
@pytest.mark.parametrize("shape,level", [("torus", 1), ("bumpy-plate", 0)])  # closed (a volume, a genus), open
def test_info_says_what_the_cli_says_of_a_mesh(tmp_path, shape, level):
    V, F = geotex.generate(shape, level=level)
    geotex.write_mesh(tmp_path / "m.ply", V, F)
    p = subprocess.run([CLI, "info", "--json", str(tmp_path / "m.ply")], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    info = geotex.info(V, F)
    declared = {f["name"] for f in geotex._geotex._result_tables()["MeshSummary"]}
    # The file's own keys (its name, format, what the reader did) are the CLI's; the rest is the summary.
    assert set(j) - {"file", "format", "read", "manifold", "consistently_oriented"} == declared == set(info)
    for key in declared:
        want = info[key]
        assert j[key] == (pytest.approx(want, rel=1e-12) if isinstance(want, float) else want), key
    assert (info["volume"] is None) == (not info["closed"])


@pytest.mark.skipif(not CLI, reason="GEOTEX_CLI not set (ctest sets it)")
def test_compare_says_what_the_cli_says(tmp_path, noisy):
    V, F = geotex.generate("cube", level=1)
    r = geotex.denoise(*noisy, method="mrf", iterations=3)
    geotex.write_mesh(tmp_path / "r.ply", r)
    geotex.write_mesh(tmp_path / "t.ply", V, F)
    labels = tmp_path / "labels.ply"
    p = subprocess.run([CLI, "-q", "denoise", str(tmp_path / "r.ply"), "--method", "mrf", "--iterations", "1",
                        "-o", str(tmp_path / "o.ply"), "--edges", str(labels)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    p = subprocess.run([CLI, "compare", "--json", str(tmp_path / "r.ply"), str(tmp_path / "t.ply"), "--labels",
                        str(labels)], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    tables = geotex._geotex._result_tables()
    c = geotex.compare(r.V, r.F, V, F)
    assert set(j) - {"result", "truth", "edge_labels"} == {f["name"] for f in tables["Comparison"]} == set(c)
    for key, want in c.items():
        assert j[key] == (pytest.approx(want, rel=1e-12) if isinstance(want, float) else want), key
    # The labels' score: the CLI scores the edges labelled above 1/2 against the truth's above 30 degrees.
    E = geotex.edges(V, F)
    truth = E[np.abs(geotex.dihedral_angles(V, F)) > np.radians(j["edge_labels"]["truth_angle_deg"])]
    again = geotex.denoise(r, method="mrf", iterations=1)
    s = geotex.score_edge_labels(again.edges[again.edge_labels > 0.5], truth)
    assert set(j["edge_labels"]) - {"truth_angle_deg"} == {f["name"] for f in tables["LabelScore"]} == set(s)
    for key, want in s.items():
        assert j["edge_labels"][key] == pytest.approx(want, rel=1e-12), key
    assert s["labelled"] > 0 and s["truth_sharp_edges"] > 0  # a score of something


@pytest.mark.skipif(not CLI, reason="GEOTEX_CLI not set (ctest sets it)")
@pytest.mark.parametrize("method", ["conformal", "combined"])
def test_parametrization_quality_says_what_param_json_says(tmp_path, method):
    V, F = geotex.generate("bumpy-plate", level=0)
    geotex.write_mesh(tmp_path / "disk.ply", V, F)
    p = subprocess.run([CLI, "param", "--json", str(tmp_path / "disk.ply"), "-o", str(tmp_path / "uv.obj"),
                        "--method", method], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    uv = geotex.parametrize(V, F, method=method)
    assert isinstance(uv, np.ndarray) and uv.shape == (len(V), 2)  # parametrize() still returns the UVs
    q = geotex.parametrization_quality(V, F, uv)
    declared = {f["name"] for f in geotex._geotex._result_tables()["ParamQuality"]}
    # The method, the vertex count and the time are the CLI's own; the rest is the quality, by one name.
    assert set(j) - {"method", "vertices", "seconds"} == declared == set(q)
    for key, want in q.items():
        assert j[key] == (pytest.approx(want, rel=1e-9, abs=1e-12) if isinstance(want, float) else want), key
    assert j["method"] == method and j["vertices"] == len(V)
    # The measure can tell maps apart: UVs squashed along v distort angles more than the map itself.
    squashed = geotex.parametrization_quality(V, F, uv * [1.0, 0.2])
    assert squashed["mean_angle_error_deg"] > q["mean_angle_error_deg"]
    with pytest.raises(geotex.InvalidInput, match="uv"):
        geotex.parametrization_quality(V, F, uv[:-1])


def test_the_docs_results_tables_are_the_result_tables():
    # docs/results.md is generated from the same C++ tables as the report, the result classes and the
    # demo's captions: a field added to a table and not to the docs fails here.
    from geotex import _stubgen
    doc = os.path.join(os.path.dirname(__file__), "..", "..", "..", "docs", "results.md")
    if not os.path.exists(doc):
        pytest.skip("docs/results.md is not here (an installed package without the source tree)")
    with open(doc) as f:
        assert f.read() == _stubgen.results_markdown(), (
            "docs/results.md is out of date: PYTHONPATH=build/python /usr/bin/python3 -m geotex._stubgen "
            "--results-md docs/results.md")
