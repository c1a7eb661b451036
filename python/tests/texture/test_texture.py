"""Height-and-tilt texture from Python (thesis ch. 8): the texture_* functions, texture files, and the
same results as `geotex texture …`."""

import inspect
import os
import subprocess
import warnings

import numpy as np
import pytest

import geotex


@pytest.fixture(scope="module")
def spiky():
    """A spiky sphere (leaning spikes no height field holds), its base and its texture."""
    (Vt, F), (Vb, _) = geotex.generate("spiky-sphere", level=1, with_base=True)
    tex = geotex.texture_extract(Vt, F, base=Vb)
    return Vt, F, Vb, tex, geotex.mean_edge_length(Vb, F)


def test_extract_then_apply_reproduces_the_mesh(spiky):
    Vt, F, Vb, tex, h = spiky
    assert tex.base_source == "given" and tex.max_error < 1e-3
    assert tex.height.shape == (len(Vb),) and tex.tilt.shape == (len(tex.edges),) and tex.lean.shape == (len(Vb),)
    assert np.array_equal(tex.V_base, Vb) and np.array_equal(tex.F, F)
    r = geotex.texture_apply(tex)
    assert np.abs(r.V - Vt).max() < 1e-3 * h and np.array_equal(r.F, F)
    # A height field alone (tilt dropped) cannot hold leaning spikes.
    assert np.abs(geotex.texture_apply(tex, height_only=True).V - Vt).max() > 1.0 * h
    # A rigid motion of the base moves the textured surface rigidly.
    R = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
    assert np.abs(geotex.texture_apply(tex, base=Vb @ R.T).V - r.V @ R.T).max() < 1e-3 * h
    assert np.abs(geotex.texture_apply(tex, base=(Vb @ R.T, F)).V - r.V @ R.T).max() < 1e-3 * h
    # height_scale scales the displacements of a height field.
    d1 = geotex.texture_apply(tex, height_only=True).V - Vb
    d2 = geotex.texture_apply(tex, height_only=True, height_scale=2.0).V - Vb
    assert np.abs(d2 - 2 * d1).max() < 1e-9
    with pytest.raises(geotex.InvalidInput, match="connectivity"):
        geotex.texture_apply(tex, base=(Vb, F[:, ::-1]))
    # On a stretched base the lean's direction turns with the base's rotation only (default); the
    # push-forward turns it with the stretch as well.
    S = Vb * [2.0, 1.0, 1.0]
    kept, pushed = (geotex.texture_apply(tex, base=S, tilt_encoding=e).V for e in ("lean", "lean-pushforward"))
    assert np.abs(kept - geotex.texture_apply(tex, base=S).V).max() == 0
    assert np.abs(kept - pushed).max() > 0.1 * h
    assert np.allclose(np.linalg.norm(kept - S, axis=1), np.linalg.norm(Vt - Vb, axis=1), atol=1e-6 * h)


def test_every_tilt_fit_and_the_automatic_base_round_trip(spiky):
    Vt, F, Vb, _, h = spiky
    for options in ({"tilt_solver": "direct"}, {"tangential_fit": False}):
        tex = geotex.texture_extract(Vt, F, base=Vb, **options)
        assert np.abs(geotex.texture_apply(tex).V - Vt).max() < 1e-3 * h, options
    # The thesis' encoding: no lean stored; its bound on the tilt costs accuracy on these spikes, as
    # the reported error says.
    thesis = geotex.texture_extract(Vt, F, base=Vb, preset="thesis")
    assert thesis.lean.size == 0 and thesis.parameters["tilt_encoding"] == "one-form"
    err = np.linalg.norm(geotex.texture_apply(thesis).V - Vt, axis=1).max() / h
    assert err == pytest.approx(thesis.max_error, rel=1e-6) and err > 1
    seen = []
    auto = geotex.texture_extract(Vt, F, steps=3, progress=lambda f, stage: seen.append(f))
    assert auto.base_source == "automatic" and auto.base_passes == 3 and seen
    assert np.abs(geotex.texture_apply(auto).V - Vt).max() < 1e-3 * h
    robust = geotex.texture_extract((Vt, F), robust_passes=1, threads=1)
    assert robust.base_source == "automatic" and robust.parameters["base_method"] == "robust"
    # A base of another connectivity is projected onto.
    Vs, Fs = geotex.generate("sphere", level=3)
    proj = geotex.texture_extract(Vt, F, base=(Vs, Fs))
    assert proj.base_source == "projected" and proj.V_base.shape == Vt.shape
    # Options of the automatic base do not apply with a base, and projection needs one.
    with pytest.raises(geotex.InvalidInput, match="automatic base"):
        geotex.texture_extract(Vt, F, base=Vb, lambda_=2.0)
    with pytest.raises(geotex.InvalidInput, match="needs base"):
        geotex.texture_extract(Vt, F, project_onto_base=True)
    with pytest.raises(geotex.InvalidInput, match="tilt_solver"):
        geotex.texture_extract(Vt, F, base=Vb, tilt_solver="cholesky")
    with pytest.raises(TypeError):
        geotex.texture_extract(Vt, F, base=Vb, tilt_fit="tangential")  # the old name: not an option


def test_read_write_round_trip(spiky, tmp_path):
    _, F, Vb, tex, _ = spiky
    geotex.write_texture(tmp_path / "t.ply", tex)
    back = geotex.read_texture(tmp_path / "t.ply")
    for name in ("V_base", "F", "height", "tilt", "lean", "edges"):
        assert np.array_equal(getattr(back, name), getattr(tex, name)), name
    geotex.write_texture(str(tmp_path / "a.ply"), {"V_base": Vb, "F": F, "height": tex.height, "tilt": tex.tilt},
                         binary=False)
    plain = geotex.read_texture(tmp_path / "a.ply")
    assert plain.lean.size == 0 and np.allclose(plain.height, tex.height)
    with pytest.raises(geotex.IoError):
        geotex.read_texture(tmp_path / "missing.ply")
    with pytest.raises(TypeError, match="tilt"):
        geotex.write_texture(tmp_path / "b.ply", {"V_base": Vb, "F": F, "height": tex.height})


def test_edits_change_what_they_name_and_refuse_unknown_ops(spiky):
    _, F, Vb, tex, h = spiky
    doubled = geotex.texture_edit(tex, op="scale-height", factor=2.0)
    assert np.allclose(doubled.height, 2 * tex.height) and np.array_equal(doubled.tilt, tex.tilt)
    upright = geotex.texture_edit(tex, op="set-tilt", angle=0.0, direction=(0, 0, 1))
    assert np.abs(upright.lean).max() < 1e-9
    leaning = geotex.texture_edit(tex, op="set-tilt", angle=40.0)
    spikes = np.abs(tex.height) > 0.5 * np.abs(tex.height).max()
    assert np.allclose(leaning.lean[spikes], np.radians(40.0))
    waved = geotex.texture_edit(tex, op="wiggle", wavelength=0.5, phase=0.25)
    assert waved.parameters["wavelength"] == 0.5 and waved.parameters["op"] == "wiggle"
    with pytest.raises(geotex.InvalidInput, match="op"):
        geotex.texture_edit(tex, op="twist")
    with pytest.raises(TypeError):
        geotex.texture_edit(tex, direction=(1, 0))


def test_animation_runs_from_the_base_to_the_texture(spiky):
    _, F, Vb, tex, h = spiky
    seen = []
    r = geotex.texture_animate(tex, op="grow", frames=4, progress=lambda f, stage: seen.append(f))
    assert r.frames.shape == (4, len(Vb), 3) and np.array_equal(r.F, F)
    assert np.abs(r.frames[0] - Vb).max() < 1e-9  # heights × 0
    assert np.abs(r.frames[2] - geotex.texture_apply(tex).V).max() < 1e-3 * h  # heights × 1
    assert seen == [0.25, 0.5, 0.75, 1.0]
    w = geotex.texture_animate(tex, frames=3, refit=False)
    assert w.frames.shape == (3, len(Vb), 3) and np.isfinite(w.frames).all()


def test_transfer_textures_the_target_patch_and_atlas_covers_the_target():
    (Vp, Fp), (Vpb, _) = geotex.generate("bumpy-plate", level=0, with_base=True)
    tex = geotex.texture_extract(Vp, Fp, base=Vpb)
    Vs, Fs = geotex.generate("sphere", level=1)
    stages = []
    r = geotex.texture_transfer(tex, Vs, Fs, source_near=(0, 0, 0), target_near=(0, 0, 1), source_radius=0.5,
                                target_radius=0.5, refine_ratio=0, progress=lambda f, stage: stages.append(stage))
    assert stages[-1] == "encoding"
    assert r.V.shape == Vs.shape and np.array_equal(r.F, Fs) and r.added_vertices == 0
    assert r.texture.height.shape == (len(Vs),) and np.all(r.texture.height[Vs[:, 2] < 0] == 0)
    assert r.target_center == int(np.argmin(np.linalg.norm(Vs - [0, 0, 1], axis=1)))
    assert r.parameters["falloff"] == 0.4 and r.height_factor == pytest.approx(1.0)
    # The damage against the bare target's own: none for these low bumps.
    assert r.base_folded == 0 and r.base_self_intersecting == 0
    assert r.excess_folded == r.folded == 0 and r.excess_self_intersecting == r.self_intersecting == 0
    # A coarse target is refined, with a warning.
    with pytest.warns(UserWarning, match="refined"):
        fine = geotex.texture_transfer(tex, (Vs, Fs), source_near=(0, 0, 0), target_near=(0, 0, 1),
                                       source_radius=0.5, target_radius=0.5)
    assert fine.added_vertices > 0 and len(fine.V) == len(Vs) + fine.added_vertices
    with pytest.raises(geotex.InvalidInput, match="not both"):
        geotex.texture_transfer(tex, Vs, Fs, source_center=0, source_near=(0, 0, 0), source_radius=0.5,
                                target_radius=0.5)
    with pytest.raises(geotex.InvalidInput, match="falloff"):
        geotex.texture_transfer(tex, Vs, Fs, source_radius=0.5, target_radius=0.5, falloff=2.0)
    seen = []
    a = geotex.texture_atlas(tex, (Vs, Fs), source_near=(0, 0, 0), source_radius=0.5, target_radius=0.7,
                             refine_ratio=0, progress=lambda f, stage: seen.append(f))
    assert a.coverage.min() > 0 and a.owner.min() >= 0 and len(a.centers) > 4
    assert seen and seen[-1] == 1.0
    assert a.texture.height.shape == (len(Vs),)
    assert a.excess_folded == 0 and a.excess_self_intersecting == 0 and a.base_self_intersecting == 0
    # Tentacles three times as tall on a small patch cross each other: counted, with a warning.
    (Vq, Fq), (Vqb, _) = geotex.generate("tentacle-plane", level=0, with_base=True)
    tentacles = geotex.texture_extract(Vq, Fq, base=Vqb)
    V2, F2 = geotex.generate("sphere", level=2)
    with pytest.warns(UserWarning, match="self-intersecting"):
        tall = geotex.texture_transfer(tentacles, V2, F2, source_near=(0, 0, 0), target_near=(0, 0, 1),
                                       source_radius=1, target_radius=0.6, refine_ratio=0, height_scale=3)
    assert tall.excess_folded > 0 and tall.excess_self_intersecting > 0 and tall.base_folded == 0


def test_signatures_come_from_the_tables():
    sig = inspect.signature(geotex.texture_transfer)
    assert sig.parameters["falloff"].default == 0.4
    assert sig.parameters["falloff"].kind == inspect.Parameter.KEYWORD_ONLY
    assert sig.parameters["height_rule"].default == "patch-radius"
    assert inspect.signature(geotex.texture_extract).parameters["lambda_"].default == 1.0
    assert inspect.signature(geotex.texture_edit).parameters["op"].default == "set-tilt"
    assert "preset" not in inspect.signature(geotex.texture_apply).parameters
    assert "falloff" in geotex.texture_transfer.__doc__


def test_dropped_faces_warn_without_crashing(spiky):
    # Warnings are raised with the GIL held (issue 14): a duplicate face while extracting.
    Vt, F, Vb, _, _ = spiky
    F2 = np.vstack([F, F[:1]])
    with pytest.warns(UserWarning, match="duplicate"):
        tex = geotex.texture_extract(Vt, F2, steps=2)
    assert np.isfinite(tex.height).all()


@pytest.mark.skipif(not os.environ.get("GEOTEX_CLI"), reason="GEOTEX_CLI not set (ctest sets it)")
def test_python_and_cli_give_the_same_results(spiky, tmp_path):
    Vt, F, Vb, _, _ = spiky
    cli = os.environ["GEOTEX_CLI"]
    geotex.write_mesh(tmp_path / "s.ply", Vt, F)
    geotex.write_mesh(tmp_path / "b.ply", Vb, F)

    def run(*args):
        r = subprocess.run([cli, "-q", "texture", *map(str, args)], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr

    run("extract", tmp_path / "s.ply", "--base", tmp_path / "b.ply", "-o", tmp_path / "t.ply", "--tilt-solver", "direct")
    tex = geotex.texture_extract(Vt, F, base=Vb, tilt_solver="direct")
    cli_tex = geotex.read_texture(tmp_path / "t.ply")
    assert np.allclose(cli_tex.height, tex.height, atol=1e-12) and np.allclose(cli_tex.tilt, tex.tilt, atol=1e-9)
    run("edit", tmp_path / "t.ply", "-o", tmp_path / "e.ply", "--op", "wrap", "--angle", "25", "--direction", "0,1,0")
    edited = geotex.texture_edit(cli_tex, op="wrap", angle=25.0, direction=(0, 1, 0))
    assert np.allclose(geotex.read_texture(tmp_path / "e.ply").tilt, edited.tilt, atol=1e-9)
    run("apply", tmp_path / "e.ply", "-o", tmp_path / "a.ply", "--height-scale", "0.5")
    V_cli, _ = geotex.read_mesh(tmp_path / "a.ply")
    assert np.allclose(V_cli, geotex.texture_apply(edited, height_scale=0.5).V, atol=1e-9)
    run("animate", tmp_path / "t.ply", "-o", tmp_path / "fr", "--frames", "2", "--op", "wrap")
    frames = geotex.texture_animate(cli_tex, frames=2, op="wrap").frames
    assert np.allclose(geotex.read_mesh(tmp_path / "fr_0001.ply")[0], frames[1], atol=1e-9)


@pytest.mark.skipif(not os.environ.get("GEOTEX_CLI"), reason="GEOTEX_CLI not set (ctest sets it)")
def test_an_automatic_base_keeps_a_flat_outline_and_warns_when_it_removes_much_of_the_surface(tmp_path):
    # Issue 26: a flat open model is its own base (no texture, its outline kept); a base that keeps less
    # than 85% of the surface's area warns, in Python and on the command line, and says so in the report.
    Vp, Fp = geotex.generate("plane")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        flat = geotex.texture_extract(Vp, Fp)
    assert abs(flat.base_area_ratio - 1) < 1e-3 and flat.warnings == []
    assert np.abs(flat.V_base - Vp).max() < 1e-3 * geotex.mean_edge_length(Vp, Fp)
    (Vt, F), _ = geotex.generate("spiky-sphere", level=0, with_base=True)  # its base keeps about 77%
    with pytest.warns(UserWarning, match="the automatic base keeps"):
        hairy = geotex.texture_extract(Vt, F)
    assert hairy.base_area_ratio < 0.85 and len(hairy.warnings) == 1
    geotex.write_mesh(tmp_path / "spiky.ply", Vt, F)
    r = subprocess.run([os.environ["GEOTEX_CLI"], "-q", "texture", "extract", str(tmp_path / "spiky.ply"),
                        "-o", str(tmp_path / "t.ply"), "--report", str(tmp_path / "r.json")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "geotex: warning: the automatic base keeps" in r.stderr
    import json
    report = json.load(open(tmp_path / "r.json"))
    assert abs(report["base_area_ratio"] - hairy.base_area_ratio) < 1e-9 and report["warnings"] == hairy.warnings
