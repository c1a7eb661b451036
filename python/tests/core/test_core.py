"""The foundation through Python: numpy in and out, same defaults as the CLI, typed errors."""

import math
import warnings

import numpy as np
import pytest

import geotex


def test_generate_shapes_and_info():
    for name in geotex.shape_names():
        V, F = geotex.generate(name, level=0)
        assert V.dtype == np.float64 and V.shape[1] == 3
        assert F.shape[1] == 3 and F.min() >= 0 and F.max() < len(V)
    V, F = geotex.generate("torus", level=0)
    info = geotex.info(V, F)
    assert info["genus"] == 1 and info["euler_characteristic"] == 0 and info["closed"]
    (Vt, Ft), (Vb, Fb) = geotex.generate("spiky-sphere", level=0, with_base=True)
    assert np.array_equal(Ft, Fb) and not np.allclose(Vt, Vb)


def test_io_round_trip_is_exact(tmp_path):
    V, F = geotex.generate("sphere", level=0)
    V = V * math.pi / 3
    for ext in ("obj", "ply", "off"):
        p = str(tmp_path / f"s.{ext}")
        geotex.write_mesh(p, V, F)
        V2, F2 = geotex.read_mesh(p)
        assert np.array_equal(V, V2) and np.array_equal(F, F2)


def test_errors_are_typed(tmp_path):
    with pytest.raises(geotex.IoError):
        geotex.read_mesh(str(tmp_path / "missing.obj"))
    assert issubclass(geotex.IoError, OSError)
    bad = tmp_path / "nan.obj"
    bad.write_text("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n")
    with pytest.raises(geotex.InvalidInput):
        geotex.read_mesh(str(bad))
    assert issubclass(geotex.InvalidInput, ValueError)
    V, F = geotex.generate("cube", level=0)
    with pytest.raises(geotex.InvalidInput):
        geotex.smooth(V, F, laplacian="fancy")
    with pytest.raises(geotex.InvalidInput):
        geotex.smooth(V, F, lambda_=-1.0)
    with pytest.raises(geotex.InvalidInput):
        geotex.info(V, F + 10 ** 6)  # out-of-range indices


def test_dropped_faces_warn():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1.0]])
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])  # third face is non-manifold
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        info = geotex.info(V, F)
    assert info["faces"] == 2
    assert any("non-manifold" in str(x.message) for x in w)


def test_laplacians_are_scipy_sparse_with_zero_row_sums():
    V, F = geotex.generate("sphere", level=0)
    for L in (geotex.umbrella_laplacian(V, F), geotex.cotan_laplacian(V, F)):
        assert L.shape == (len(V), len(V))
        assert np.abs(L @ np.ones(len(V))).max() < 1e-9
    C = geotex.cotan_matrix(V, F)
    assert abs(C - C.T).max() < 1e-12
    M = geotex.mass_matrix(V, F)
    assert M.diagonal().sum() == pytest.approx(geotex.info(V, F)["area"], rel=1e-12)


def test_smoothing_matches_mean_curvature_flow_and_cli_defaults():
    V, F = geotex.generate("sphere", level=2)
    h = geotex.mean_edge_length(V, F)
    t = 0.05
    Vs = geotex.smooth(V, F, lambda_=t / h ** 2)
    r = np.linalg.norm(Vs, axis=1).mean()
    assert r == pytest.approx(1 / (1 + 2 * t), abs=2e-3)  # linearized backward Euler on a unit sphere


def test_noise_is_seeded_and_smoothing_lowers_the_normal_error():
    V, F = geotex.generate("cube", level=1)
    Vn = geotex.add_noise(V, F, sigma=0.3, seed=4)
    assert np.array_equal(Vn, geotex.add_noise(V, F, sigma=0.3, seed=4))
    before = geotex.compare(Vn, F, V, F)
    after = geotex.compare(geotex.smooth(Vn, F, lambda_=0.2), F, V, F)
    assert after["mean_normal_error_deg"] < before["mean_normal_error_deg"]
    assert before["faces_matched_by"] == "index"
    same = geotex.compare(V, F, V, F)
    assert same["ev"] == 0 and same["hausdorff"] == 0


def test_geometry_helpers_give_the_cube_angles_and_sphere_curvature():
    V, F = geotex.generate("cube", level=0)
    D = geotex.dihedral_angles(V, F)
    E = geotex.edges(V, F)
    assert len(D) == len(E)
    sharp = np.abs(D) > 1e-9
    assert np.allclose(D[sharp], math.pi / 2)
    N = geotex.face_normals(V, F)
    assert np.allclose(np.linalg.norm(N, axis=1), 1)
    H = geotex.mean_curvature_normals(*geotex.generate("sphere", level=1))
    assert np.linalg.norm(H, axis=1).mean() == pytest.approx(1.0, rel=0.03)


def test_shared_data_reads(data_dir):
    V, F = geotex.read_mesh(str(data_dir / "igea.ply"))  # triangle strips
    assert len(V) == 134345 and len(F) > 260000


def test_gltf_round_trip_is_exact_and_gzip_is_read(tmp_path):
    import gzip
    V, F = geotex.generate("sphere", level=0)
    V = V.astype(np.float32).astype(np.float64)  # glTF stores float32
    for ext in ("glb", "gltf"):
        p = str(tmp_path / f"s.{ext}")
        geotex.write_mesh(p, V, F)
        V2, F2 = geotex.read_mesh(p)
        assert np.array_equal(V, V2) and np.array_equal(F, F2)
    geotex.write_mesh(str(tmp_path / "s.ply"), V, F)
    (tmp_path / "s.ply.gz").write_bytes(gzip.compress((tmp_path / "s.ply").read_bytes()))
    V3, F3 = geotex.read_mesh(str(tmp_path / "s.ply.gz"))
    assert np.array_equal(V, V3) and np.array_equal(F, F3)
    (tmp_path / "bad.gltf").write_text('{"asset": {"version": "2.0"}, "meshes": [')
    with pytest.raises(geotex.IoError, match="glTF"):
        geotex.read_mesh(str(tmp_path / "bad.gltf"))
    (tmp_path / "cut.ply.gz").write_bytes((tmp_path / "s.ply.gz").read_bytes()[:200])
    with pytest.raises(geotex.IoError, match="truncated gzip"):
        geotex.read_mesh(str(tmp_path / "cut.ply.gz"))
