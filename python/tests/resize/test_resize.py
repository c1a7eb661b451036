"""geotex.resize and geotex.feature_map: the options of `geotex resize`, the same library calls."""

import inspect
import os
import subprocess
import warnings

import numpy as np
import pytest

import geotex
from geotex import _options


@pytest.fixture(scope="module")
def plate():
    return geotex.generate("bumpy-plate", level=0)


def test_signature_comes_from_the_tables():
    params = inspect.signature(geotex.resize).parameters
    for f in _options.table("ResizeRunOptions")["fields"]:
        p = params[_options.python_name(f["name"])]
        assert p.kind == inspect.Parameter.KEYWORD_ONLY and p.default == f["default"], f["name"]
    # The space map, the feature map, the feature file and the solver are all reachable.
    for name in ("scale", "twist", "arc_radius", "features", "adf_t", "significance", "height_threshold",
                 "height_dilate", "method", "position_weight", "transition", "preset", "progress", "threads"):
        assert name in params, name
    assert params["scale"].default == (1.0, 1.0, 1.0) and params["features"].default == "importance"
    assert "features" in inspect.signature(geotex.feature_map).parameters


def test_auto_is_the_feature_map_of_the_library(plate):
    V, F = plate
    fm = geotex.feature_map(V, F)  # features="importance"
    assert fm.detector == "importance" and fm.weights.shape == (len(V),)
    assert 0.005 < fm.marked_fraction < 0.5 and fm.warning == ""
    assert fm.parameters["features"] == "importance"
    assert fm.weights.min() >= 0 and fm.weights.max() <= 1
    assert ((fm.weights > 0.05) & (fm.weights < 0.95)).any()  # continuous, not yes/no
    assert geotex.feature_map(V, F, features="auto").detector in ("adf", "height")  # the binary map by name
    # resize(features="importance") uses exactly that map: giving its weights gives the same result.
    a = geotex.resize(V, F, scale=(2, 1, 1)).V
    b = geotex.resize(V, F, scale=(2, 1, 1), features=fm.weights).V
    assert np.array_equal(a, b)
    # And a different map gives a different result.
    c = geotex.resize(V, F, scale=(2, 1, 1), features="none").V
    assert np.abs(a - c).max() > 1e-3


def test_the_result_is_the_resized_mesh_with_the_map_it_used(plate):
    V, F = plate
    fm = geotex.feature_map(V, F)
    r = geotex.resize(V, F, scale=(2, 1, 1))
    assert isinstance(r, geotex.ResizeResult) and isinstance(r, geotex.MeshResult)
    assert np.array_equal(r.F, F) and r.V.shape == V.shape
    assert np.array_equal(r.features, fm.weights) and r.detector == fm.detector  # the same map as feature_map()
    assert (r.marked_fraction, r.marked_vertices, r.regions) == (fm.marked_fraction, fm.marked_vertices, fm.regions)
    given = geotex.resize(V, F, scale=(2, 1, 1), features=fm.weights)
    assert given.detector == "none" and np.array_equal(given.features, fm.weights)  # weights given: no detector
    assert geotex.info(r)["faces"] == len(F)  # a result is a mesh


def test_user_weights_and_feature_files(plate, tmp_path):
    V, F = plate
    f = geotex.feature_map(V, F, features="height").weights
    a = geotex.resize(V, F, scale=(2, 1, 1), features=f).V
    path = tmp_path / "f.txt"
    path.write_text("".join(f"{x}\n" for x in f))
    assert np.array_equal(geotex.resize(V, F, scale=(2, 1, 1), features=path).V, a)
    assert np.array_equal(geotex.resize(V, F, scale=(2, 1, 1), features=str(path)).V, a)
    with pytest.raises(geotex.InvalidInput):
        geotex.resize(V, F, scale=(2, 1, 1), features=f[:-1]).V  # one weight short
    with pytest.raises(geotex.InvalidInput):
        geotex.resize(V, F, scale=(2, 1, 1), features=np.full(len(V), 2.0)).V  # outside [0, 1]
    with pytest.raises(geotex.IoError):
        geotex.resize(V, F, scale=(2, 1, 1), features=tmp_path / "missing.txt").V


def test_painted_weights_are_honoured(plate, tmp_path):
    V, F = plate
    # A painted map: 1 in a disc about the plate's centre, smoothly 0 at twice its radius.
    r = np.linalg.norm(V[:, :2] - (V.min(0) + V.max(0))[:2] / 2, axis=1)
    t = np.clip((0.5 - r) / 0.25, 0, 1)
    paint = t * t * (3 - 2 * t)
    path = tmp_path / "paint.txt"
    path.write_text("".join(f"{x!r}\n" for x in paint))
    a = geotex.resize(V, F, scale=(2, 1, 1), features=paint).V
    assert np.array_equal(geotex.resize(V, F, scale=(2, 1, 1), features=path).V, a)
    assert not np.array_equal(geotex.resize(V, F, scale=(2, 1, 1)).V, a)
    # Inside the painted core the stretch is gone: the core keeps its proportions (it may grow uniformly).
    core = r < 0.2
    aspect = lambda P: np.ptp(P[core, 0]) / np.ptp(P[core, 1])
    assert abs(aspect(a) / aspect(V) - 1) < 0.05, aspect(a) / aspect(V)
    ext = np.ptp(a, axis=0) / np.ptp(V, axis=0)
    assert ext[0] == pytest.approx(2, abs=1e-9) and ext[1] == pytest.approx(1, abs=1e-9)


def test_none_features_scale_the_box_exactly(plate):
    V, F = plate
    out = geotex.resize(V, F, scale=(2, 1, 1), features="none").V
    ext, ext0 = np.ptp(out, axis=0), np.ptp(V, axis=0)
    assert ext[0] == pytest.approx(2 * ext0[0], rel=1e-6) and ext[1] == pytest.approx(ext0[1], rel=1e-6)


def test_deformed_copy_instead_of_a_map(plate):
    V, F = plate
    f = geotex.feature_map(V, F).weights
    lo, hi = V.min(axis=0), V.max(axis=0)
    D = (lo + hi) / 2 + (V - (lo + hi) / 2) * np.array([2.0, 1.0, 1.0])  # scale=(2, 1, 1) about the box centre
    by_map = geotex.resize(V, F, scale=(2, 1, 1), features=f)
    assert np.allclose(geotex.resize(V, F, D, features=f).V, by_map.V, atol=1e-9)
    with pytest.raises(geotex.InvalidInput, match="not both"):
        geotex.resize(V, F, D, scale=(2, 1, 1)).V
    with pytest.raises(geotex.InvalidInput, match="deformation"):
        geotex.resize(V, F).V


def test_warning_when_everything_is_marked(plate):
    V, F = plate
    with pytest.warns(UserWarning, match="surface"):
        geotex.resize(V, F, scale=(2, 1, 1), features=np.ones(len(V))).V
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        geotex.resize(V, F, scale=(2, 1, 1)).V  # a plausible map: no warning


def test_options_are_checked(plate):
    V, F = plate
    with pytest.raises(geotex.InvalidInput, match="features"):
        geotex.feature_map(V, F, features="everything")
    with pytest.raises(geotex.InvalidInput, match="scale"):
        geotex.resize(V, F, scale=(2, -1, 1)).V
    with pytest.raises(geotex.InvalidInput, match="position_weight"):
        geotex.resize(V, F, scale=(2, 1, 1), position_weight=float("nan")).V
    with pytest.raises(TypeError):
        geotex.resize(V, F, scale=(2, 1, 1), no_such_option=1).V
    with pytest.raises(geotex.InvalidInput):
        geotex.resize(V, F, scale=(2, 1, 1), preset="best").V


def test_preset_and_progress(plate):
    V, F = plate
    seen = []
    a = geotex.resize(V, F, scale=(2, 1, 1), features="height", preset="thesis",
                      progress=lambda f, stage: seen.append(f)).V
    b = geotex.resize(V, F, scale=(2, 1, 1), features="height", method="thesis", square_weights=True,
                      keep_feature_size=False).V
    assert np.array_equal(a, b)
    assert seen and seen == sorted(seen) and seen[-1] == pytest.approx(1.0)

    def stop(fraction, stage):
        raise KeyError("stop")

    with pytest.raises(KeyError):
        geotex.resize(V, F, scale=(2, 1, 1), features="none", progress=stop).V


@pytest.mark.skipif(not os.environ.get("GEOTEX_CLI"), reason="GEOTEX_CLI not set (ctest sets it)")
def test_cli_and_python_give_the_same_result(tmp_path):
    cli = os.environ["GEOTEX_CLI"]
    mesh, out = tmp_path / "plate.ply", tmp_path / "out.ply"
    subprocess.run([cli, "generate", "bumpy-plate", "--level", "0", "-o", str(mesh)], check=True, capture_output=True)
    r = subprocess.run([cli, "resize", str(mesh), "-o", str(out), "--scale", "2,1,1.5", "--features", "auto",
                        "--transition", "0.2", "--method", "sliding"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "marked fraction " in r.stderr  # the marked fraction is printed, as the report names it
    V, F = geotex.read_mesh(mesh)
    expected = geotex.resize(V, F, scale=(2, 1, 1.5), features="auto", transition=0.2, method="sliding").V
    got, _ = geotex.read_mesh(out)
    assert np.abs(got - expected).max() < 1e-9
    # And the default (importance map, method auto: axis-similarity for this box scale).
    r = subprocess.run([cli, "resize", str(mesh), "-o", str(out), "--scale", "2,1,1.5"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    expected = geotex.resize(V, F, scale=(2, 1, 1.5)).V
    got, _ = geotex.read_mesh(out)
    assert np.abs(got - expected).max() < 1e-9


def test_default_method_is_auto_and_the_result_says_which_it_ran(plate):
    V, F = plate
    params = inspect.signature(geotex.resize).parameters
    assert params["method"].default == "auto"
    # A box scale runs axis-similarity, a bend or a deformed copy similarity: the same vertices as asking for it.
    bent = geotex.resize(V, F, bend=0.5, features="none").mapped  # the plain bend, as a deformed copy
    for kw, runs, other in (({"scale": (2, 1, 1)}, "axis-similarity", "similarity"),
                            ({"bend": 0.5}, "similarity", "sliding"),
                            ({"deformed": bent}, "similarity", "sliding")):
        r = geotex.resize(V, F, **kw)
        assert r.method == runs and r.parameters["method"] == "auto", kw
        asked = geotex.resize(V, F, method=runs, **kw)
        assert asked.method == runs and np.array_equal(r.V, asked.V), kw
        assert not np.array_equal(r.V, geotex.resize(V, F, method=other, **kw).V), kw  # the methods differ here
    assert geotex.resize(V, F, scale=(2, 1, 1), preset="thesis").method == "thesis"  # the preset as it was


def test_axis_method_honours_a_painted_map_and_keeps_the_box(plate, tmp_path):
    V, F = plate
    r = np.linalg.norm(V[:, :2] - (V.min(0) + V.max(0))[:2] / 2, axis=1)
    t = np.clip((0.5 - r) / 0.25, 0, 1)
    paint = t * t * (3 - 2 * t)
    for scale in ((2, 1, 1), (1, 3, 1)):
        a = geotex.resize(V, F, scale=scale, features=paint, method="axis").V
        # The painted core keeps its proportions and its size (the stretch goes to unpainted slabs).
        core = r < 0.2
        for k in (0, 1):
            assert np.ptp(a[core, k]) / np.ptp(V[core, k]) == pytest.approx(1, abs=0.05), (scale, k)
        # The box exactly as asked, and no face turned over against the plain stretch.
        assert np.ptp(a, axis=0) == pytest.approx(np.ptp(V, axis=0) * scale, rel=1e-12)
        P = V * scale
        n1 = np.cross(a[F[:, 1]] - a[F[:, 0]], a[F[:, 2]] - a[F[:, 0]])
        n0 = np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])
        assert ((n1 * n0).sum(1) > 0).all()
    # Each coordinate goes through an increasing map of itself alone.
    for k in range(3):
        order = np.argsort(V[:, k], kind="stable")
        assert (np.diff(a[order, k]) >= -1e-12).all()
    with pytest.raises(geotex.InvalidInput, match="box scale"):
        geotex.resize(V, F, bend=0.5, features=paint, method="axis").V


@pytest.mark.skipif(not os.environ.get("GEOTEX_CLI"), reason="GEOTEX_CLI not set (ctest sets it)")
def test_axis_method_from_the_cli_with_a_painted_file(tmp_path):
    cli = os.environ["GEOTEX_CLI"]
    mesh, out, paint = tmp_path / "plate.ply", tmp_path / "out.ply", tmp_path / "paint.txt"
    subprocess.run([cli, "generate", "bumpy-plate", "--level", "0", "-o", str(mesh)], check=True, capture_output=True)
    V, F = geotex.read_mesh(mesh)
    f = np.clip(1.5 - 3 * np.abs(V[:, 0]), 0, 1)  # a painted vertical band
    paint.write_text("".join(f"{x!r}\n" for x in f))
    for method in ("axis", "axis-similarity"):
        r = subprocess.run([cli, "resize", str(mesh), "-o", str(out), "--scale", "2,1,1", "--features", str(paint),
                            "--method", method], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        got, _ = geotex.read_mesh(out)
        expected = geotex.resize(V, F, scale=(2, 1, 1), features=f, method=method).V
        assert np.abs(got - expected).max() < 1e-9
        band = f >= 1
        assert np.ptp(got[band, 0]) / np.ptp(V[band, 0]) == pytest.approx(1, abs=0.05)  # the band keeps its width
    r = subprocess.run([cli, "resize", str(mesh), "-o", str(out), "--twist", "0.5", "--method", "axis"],
                       capture_output=True, text=True)
    assert r.returncode != 0 and "box scale" in r.stderr


@pytest.mark.skipif(not os.environ.get("GEOTEX_CLI"), reason="GEOTEX_CLI not set (ctest sets it)")
def test_rigid_protrusions_are_the_default_and_can_be_turned_off(tmp_path):
    # The tentacle stick x2 across it: by default its tentacles are put back at their size (the body, mostly
    # unimportant, takes the room), so the box's y extent is no longer the tentacles' doubled reach; off gives the
    # method's own per-vertex similarities. The CLI's --no-rigid-protrusions is Python's rigid_protrusions=False.
    assert inspect.signature(geotex.resize).parameters["rigid_protrusions"].default is True
    cli = os.environ["GEOTEX_CLI"]
    mesh, out = tmp_path / "stick.ply", tmp_path / "out.ply"
    subprocess.run([cli, "generate", "tentacle-stick", "--level", "0", "-o", str(mesh)], check=True, capture_output=True)
    V, F = geotex.read_mesh(mesh)
    on = geotex.resize(V, F, scale=(1, 2, 1))
    off = geotex.resize(V, F, scale=(1, 2, 1), rigid_protrusions=False)
    assert on.parameters["rigid_protrusions"] is True and off.parameters["rigid_protrusions"] is False
    assert np.abs(on.V - off.V).max() > 0.1
    for flags, expected in (([], on.V), (["--no-rigid-protrusions"], off.V)):
        r = subprocess.run([cli, "resize", str(mesh), "-o", str(out), "--scale", "1,2,1", *flags],
                           capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        got, _ = geotex.read_mesh(out)
        assert np.abs(got - expected).max() < 1e-9
    for r in (on, off):  # the box as asked either way
        assert np.ptp(r.V, axis=0) == pytest.approx(np.ptp(V, axis=0) * (1, 2, 1), rel=1e-9)


def test_crossings_beyond_the_inputs_own_are_counted_and_untangled(data_dir):
    # Issue 25: cheburashka x2 along x, its ears run into its head after the similarity stage; the result counts
    # them, the default blends them back (none left beyond the input's own), untangle=False leaves them.
    V, F = geotex.read_mesh(str(data_dir / "cheburashka.obj"))
    on = geotex.resize(V, F, scale=(2, 1, 1))
    off = geotex.resize(V, F, scale=(2, 1, 1), untangle=False)
    assert off.excess_self_intersecting > 0 and off.untangle_blended_vertices == 0
    assert on.untangle_excess_before == off.excess_self_intersecting
    assert on.excess_self_intersecting == 0 and 0 < on.untangle_blended_vertices < len(V)
    assert on.self_intersecting <= on.base_self_intersecting
    span, asked = np.ptp(on.V, axis=0), np.ptp(on.mapped, axis=0)
    assert np.allclose(span, asked, rtol=1e-12, atol=0)


def _coincident_groups(V):
    """Rows of V that share their position with another row, as lists of indices."""
    _, inverse, counts = np.unique(V, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    return [np.flatnonzero(inverse == g) for g in np.flatnonzero(counts > 1)]


def test_unwelded_patches_keep_their_seams_closed(data_dir):
    # Issue 25: the teapot is stored as unwelded Bezier patches (its seams are boundary loops with a vertex on either
    # side). Resize welds them for the solve and writes the input's vertices in its order with its faces.
    V, F = geotex.read_mesh(str(data_dir / "teapot.obj"))
    groups = _coincident_groups(V)
    assert len(groups) > 300
    for scale in [(2, 1, 1), (1, 1, 2)]:
        r = geotex.resize(V, F, scale=scale)
        assert r.V.shape == V.shape and np.array_equal(r.F, F)
        assert r.welded_vertices > 300 and r.features.shape == (len(V),)
        # Every seam shut: coincident vertices stay exactly together, but for the groups the weld leaves apart or
        # welds per fan (the handle touching the body at one point), which the result counts.
        gaps = np.array([np.abs(r.V[g] - r.V[g[0]]).max() for g in groups])
        assert (gaps > 0).sum() <= r.weld_refused_groups < len(groups) / 100, (scale, gaps.max())
        assert r.excess_self_intersecting == 0
        assert np.allclose(np.ptp(r.V, axis=0), np.ptp(r.mapped, axis=0), rtol=1e-12, atol=0)


def test_weld_off_solves_the_patches_apart(data_dir):
    # Issue 25, fifteenth session: weld=False (--no-weld) solves the teapot as stored: nothing welded, and the seams
    # the weld keeps shut open; the default keeps them shut.
    V, F = geotex.read_mesh(str(data_dir / "teapot.obj"))
    groups = _coincident_groups(V)
    on = geotex.resize(V, F, scale=(2, 1, 1))
    off = geotex.resize(V, F, scale=(2, 1, 1), weld=False)
    assert off.welded_vertices == 0 and off.weld_refused_groups == 0 and on.welded_vertices > 300
    gap = lambda r: max(np.abs(r.V[g] - r.V[g[0]]).max() for g in groups)
    edge = np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1).mean()
    opened = sum(np.abs(off.V[g] - off.V[g[0]]).max() > 1e-3 * edge for g in groups)
    shut = sum(np.abs(on.V[g] - on.V[g[0]]).max() > 1e-3 * edge for g in groups)
    assert opened > 10 * max(shut, 1), (opened, shut, gap(off) / edge)
