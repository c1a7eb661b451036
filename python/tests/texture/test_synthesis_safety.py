"""Issue 27: texture synthesis safe with its defaults — the estimate before the work, a refusal beyond the
cap, and the damage counts — the same through Python and the CLI."""

import json
import os
import subprocess

import numpy as np
import pytest

import geotex

CLI = os.environ.get("GEOTEX_CLI")


@pytest.fixture(scope="module")
def tentacles():
    (Vt, F), (Vb, _) = geotex.generate("tentacle-plane", level=0, with_base=True)
    return geotex.texture_extract(Vt, F, Vb)


def test_the_damage_counts_and_the_estimate_are_returned(tentacles):
    Vs, Fs = geotex.generate("sphere", level=1)
    r = geotex.texture_synthesize(tentacles, Vs, Fs, direction=(0, 0, 1), vertex_budget=20000)
    assert r.exemplar_share > 0.05                  # automatic: raised to keep within the budget
    n = len(r.V)
    assert r.added_vertices > 0                     # a coarse sphere needs refinement, and gets it
    assert r.refined_share == pytest.approx(r.added_vertices / n)
    assert r.shrunk_share == pytest.approx(r.unfolded_vertices / n)
    assert r.excess_self_intersecting == max(0, r.self_intersecting - r.base_self_intersecting)
    assert r.excess_self_intersecting == 0          # placement avoids crossings (drops what it cannot avoid)
    assert 0 <= r.dropped_vertices + r.repaired_vertices < n and r.retried_placements >= 0
    assert n / 1.5 < r.estimated_vertices < 1.5 * n
    assert set(r.stage_seconds) >= {"exemplar", "refine", "patches", "unfold"}
    # Faces turned against the base (the inward faces): recounted here on the result's meshes, and
    # no more than 0.1 % of the relief beyond the exemplar's own (its leaning tentacles' undersides).
    V, B, F = np.asarray(r.V), np.asarray(r.V_base), np.asarray(r.F)
    d = np.linalg.norm(V - B, axis=1)
    relief = (d[F] > 0.05 * d.max()).any(axis=1)
    nv = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    nb = np.cross(B[F[:, 1]] - B[F[:, 0]], B[F[:, 2]] - B[F[:, 0]])
    area = np.linalg.norm(nv, axis=1)
    against = relief & ((nv * nb).sum(axis=1) < 0)
    assert r.inward_share == pytest.approx(area[against].sum() / area[relief].sum(), abs=0.01)
    assert r.exemplar_inward_share > 0.05
    assert r.inward_share <= r.exemplar_inward_share + 0.001
    assert r.kept_out_pits == 0                     # a sphere has no pit
    assert r.kept_out_domes == 0                    # nor a dome


def test_the_estimate_is_given_before_the_work(tentacles):
    # Issue 27: the estimate is stated before the work (the CLI's first line; here on_estimate), after the
    # exemplar is read and before any refinement or patch.
    Vs, Fs = geotex.generate("sphere", level=1)
    events = []
    r = geotex.texture_synthesize(tentacles, Vs, Fs, direction=(0, 0, 1), vertex_budget=20000,
                                  progress=lambda f, s: events.append(s) if not events or events[-1] != s else None,
                                  on_estimate=lambda e: events.append(e))
    first = [i for i, e in enumerate(events) if isinstance(e, dict)]
    assert len(first) == 1, events
    assert events[:first[0]] == ["exemplar"], events
    assert "refine" in events[first[0]:] and "patches" in events[first[0]:], events
    est = events[first[0]]
    assert est["refine"] and est["seconds"] > 0 and 0 < est["exemplar_share"] <= 1 and est["scale"] > 0
    assert est["vertices"] == r.estimated_vertices
    assert len(r.V) / 1.5 < est["vertices"] < 1.5 * len(r.V)
    with pytest.raises(TypeError, match="on_estimate"):
        geotex.texture_synthesize(tentacles, Vs, Fs, on_estimate=3)


def test_an_estimate_beyond_the_cap_is_refused_before_the_work(tentacles):
    Vs, Fs = geotex.generate("sphere", level=1)
    with pytest.raises(ValueError, match=r"output vertices estimated .* beyond max_vertices 20000"):
        geotex.texture_synthesize(tentacles, Vs, Fs, exemplar_share=0.001, max_vertices=20000)


@pytest.mark.skipif(not CLI, reason="GEOTEX_CLI not set (ctest sets it)")
@pytest.mark.skipif(bool(os.environ.get("GEOTEX_SANITIZE")),
                    reason="two full syntheses: too slow under AddressSanitizer (the C++ test covers the same code there)")
def test_cli_prints_the_estimate_first_refuses_beyond_the_cap_and_reports_the_counts(tmp_path, tentacles):
    run = lambda *a: subprocess.run([CLI, *map(str, a)], capture_output=True, text=True, timeout=300)
    assert run("generate", "tentacle-plane", "--level", 0, "-o", tmp_path / "tp.ply",
               "--base-output", tmp_path / "tpb.ply").returncode == 0
    assert run("texture", "extract", tmp_path / "tp.ply", "--base", tmp_path / "tpb.ply",
               "-o", tmp_path / "tex.ply").returncode == 0
    assert run("generate", "sphere", "--level", 1, "-o", tmp_path / "s.ply").returncode == 0
    p = run("texture", "synthesize", tmp_path / "tex.ply", "--target", tmp_path / "s.ply", "-o", tmp_path / "o.ply",
            "--exemplar-share", 0.001, "--max-vertices", 20000)
    assert p.returncode == 1
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and "output vertices estimated" in lines[0] and "max_vertices 20000" in lines[0], p.stderr
    assert not (tmp_path / "o.ply").exists()
    p = run("texture", "synthesize", tmp_path / "tex.ply", "--target", tmp_path / "s.ply", "-o", tmp_path / "o.ply",
            "--direction", "0,0,1", "--vertex-budget", 20000, "--report", tmp_path / "r.json")
    assert p.returncode == 0, p.stderr
    first = p.stderr.splitlines()[0]
    assert first.startswith("synthesize: estimate ") and "vertices" in first, p.stderr
    rep = json.loads((tmp_path / "r.json").read_text())
    py = geotex.texture_synthesize(tentacles, *geotex.read_mesh(str(tmp_path / "s.ply")), direction=(0, 0, 1),
                                  vertex_budget=20000)
    for key in ("self_intersecting", "base_self_intersecting", "excess_self_intersecting", "shrunk_share",
                "refined_share", "estimated_vertices", "exemplar_share", "retried_placements", "dropped_patches",
                "dropped_vertices", "repaired_vertices", "inward_share", "exemplar_inward_share", "kept_out_pits",
                "kept_out_domes"):
        assert rep[key] == pytest.approx(getattr(py, key)), key
    V, _ = geotex.read_mesh(str(tmp_path / "o.ply"))
    assert np.allclose(V, py.V)
