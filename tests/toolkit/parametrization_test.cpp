#include <cmath>
#include <complex>
#include <map>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::TempDir;

namespace {

// Flat round disk of radius 1: a centre vertex and rings k = 1..n of 6k vertices evenly spaced.
Mesh flat_disk(int n) {
  std::vector<Vec3> V{Vec3::Zero()};
  std::vector<int> start{0};
  for (int k = 1; k <= n; ++k) {
    start.push_back(static_cast<int>(V.size()));
    for (int j = 0; j < 6 * k; ++j) {
      const double t = 2 * M_PI * j / (6.0 * k);
      V.emplace_back(k * std::cos(t) / n, k * std::sin(t) / n, 0.0);
    }
  }
  auto ring = [&](int k, int j) { return k == 0 ? 0 : start[k] + ((j % (6 * k)) + 6 * k) % (6 * k); };
  std::vector<Eigen::Vector3i> F;
  for (int k = 1; k <= n; ++k) {
    // Sextant s of ring k has k+1 vertices (k·s .. k·s+k), of ring k−1 has k (shared corners).
    for (int s = 0; s < 6; ++s)
      for (int j = 0; j < k; ++j) {
        const int a = ring(k, k * s + j), b = ring(k, k * s + j + 1);
        const int c = ring(k - 1, (k - 1) * s + j);
        F.emplace_back(a, b, c);
        if (j + 1 < k) F.emplace_back(b, ring(k - 1, (k - 1) * s + j + 1), c);
      }
  }
  MatrixX3d VM(V.size(), 3);
  for (size_t i = 0; i < V.size(); ++i) VM.row(i) = V[i];
  MatrixX3i FM(F.size(), 3);
  for (size_t f = 0; f < F.size(); ++f) FM.row(f) = F[f];
  return make_mesh(VM, FM);
}

// The faces of \p mesh that \p keep selects, as a new mesh (unused vertices removed).
Mesh extract(const Mesh& mesh, const std::function<bool(int)>& keep) {
  const MatrixX3d V = positions(mesh);
  const MatrixX3i F = faces(mesh);
  std::map<int, int> id;
  std::vector<Eigen::Vector3i> out;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (!keep(static_cast<int>(f))) continue;
    Eigen::Vector3i t;
    for (int c = 0; c < 3; ++c) {
      auto [it, fresh] = id.try_emplace(F(f, c), static_cast<int>(id.size()));
      t[c] = it->second;
    }
    out.push_back(t);
  }
  MatrixX3d VO(id.size(), 3);
  for (auto [o, n] : id) VO.row(n) = V.row(o);
  MatrixX3i FO(out.size(), 3);
  for (size_t f = 0; f < out.size(); ++f) FO.row(f) = out[f];
  return make_mesh(VO, FO);
}

// Largest deviation of uv from the best similarity (complex a·z + b) of the mesh's xy coordinates,
// relative to the size of the uv map.
double similarity_residual(const Mesh& mesh, const MatrixX2d& uv) {
  const MatrixX3d X = positions(mesh);
  const Eigen::Index n = X.rows();
  Eigen::MatrixXcd A(n, 2);
  Eigen::VectorXcd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    A(i, 0) = {X(i, 0), X(i, 1)};
    A(i, 1) = 1.0;
    b[i] = {uv(i, 0), uv(i, 1)};
  }
  const Eigen::VectorXcd s = A.colPivHouseholderQr().solve(b);
  return (A * s - b).cwiseAbs().maxCoeff() / uv.rowwise().norm().maxCoeff();
}

const ParamMethod kAll[] = {ParamMethod::Conformal, ParamMethod::Authalic, ParamMethod::Combined,
                            ParamMethod::NaturalConformal};

}  // namespace

TEST(Parametrization, ConformalMapOfFlatRoundDiskIsASimilarity) {
  const Mesh disk = flat_disk(8);
  const MatrixX2d uv = parametrize(disk, {ParamMethod::Conformal});
  EXPECT_LT(similarity_residual(disk, uv), 1e-12);
  // Every method reproduces a flat round disk with evenly spaced boundary (linear functions are
  // harmonic under both weightings on a flat mesh).
  for (auto m : kAll) EXPECT_LT(similarity_residual(disk, parametrize(disk, {m})), 1e-9) << int(m);
}

TEST(Parametrization, NaturalConformalMapOfFlatSquareIsASimilarity) {
  const Mesh p = plane(12);
  const MatrixX2d uv = parametrize(p, {ParamMethod::NaturalConformal});
  EXPECT_LT(similarity_residual(p, uv), 1e-9);
  EXPECT_NEAR(uv.rowwise().norm().maxCoeff(), 1.0, 1e-12);  // normalised to the unit disk
  EXPECT_EQ(parametrization_quality(p, uv).flipped, 0u);
  EXPECT_LT(parametrization_quality(p, uv).max_angle_error_deg, 1e-6);
  // With the boundary pinned to the circle, the square's corners go to the circle: not a similarity.
  EXPECT_GT(similarity_residual(p, parametrize(p)), 1e-2);
}

TEST(Parametrization, BoundaryLiesOnUnitCircleByArcLength) {
  const Mesh p = plane(10);
  const MatrixX2d uv = parametrize(p);
  const auto loop = boundary_loops(p).front();
  const MatrixX3d X = positions(p);
  double L = 0;
  for (size_t k = 0; k < loop.size(); ++k) L += (X.row(loop[(k + 1) % loop.size()]) - X.row(loop[k])).norm();
  for (size_t k = 0; k < loop.size(); ++k) {
    const int a = loop[k], b = loop[(k + 1) % loop.size()];
    EXPECT_NEAR(uv.row(a).norm(), 1.0, 1e-12);
    // the angle between consecutive boundary UVs is 2π × (edge length / perimeter)
    const double ang = std::acos(std::clamp(uv.row(a).dot(uv.row(b)), -1.0, 1.0));
    EXPECT_NEAR(ang, 2 * M_PI * (X.row(b) - X.row(a)).norm() / L, 1e-9);
  }
}

TEST(Parametrization, SphericalCapHasNoFlipsUnderEveryMethod) {
  const Mesh s = icosphere(4);
  const MatrixX3d V = positions(s);
  const MatrixX3i F = faces(s);
  const Mesh cap = extract(s, [&](int f) { return (V(F(f, 0), 2) + V(F(f, 1), 2) + V(F(f, 2), 2)) / 3 > -0.2; });
  ASSERT_EQ(disk_topology_problem(cap), "");
  for (auto m : kAll) {
    const MatrixX2d uv = parametrize(cap, {m});
    const ParamQuality q = parametrization_quality(cap, uv);
    EXPECT_EQ(q.flipped, 0u) << int(m);
    EXPECT_TRUE(uv.allFinite());
    EXPECT_LE(uv.rowwise().norm().maxCoeff(), 1.0 + 1e-12);
  }
  // A free boundary removes angle distortion that the circle imposes. (On this nearly uniform cap the
  // conformal and authalic maps differ by less than 1% in either measure, so they are not ranked.)
  const ParamQuality c = parametrization_quality(cap, parametrize(cap, {ParamMethod::Conformal}));
  const ParamQuality n = parametrization_quality(cap, parametrize(cap, {ParamMethod::NaturalConformal}));
  EXPECT_LT(n.mean_angle_error_deg, 0.5 * c.mean_angle_error_deg);
}

TEST(Parametrization, CombinedInterpolatesBetweenConformalAndAuthalic) {
  const Mesh s = icosphere(3);
  const MatrixX3d V = positions(s);
  const MatrixX3i F = faces(s);
  const Mesh cap = extract(s, [&](int f) { return V(F(f, 0), 2) > 0.1 && V(F(f, 1), 2) > 0.1 && V(F(f, 2), 2) > 0.1; });
  const MatrixX2d c = parametrize(cap, {ParamMethod::Conformal});
  const MatrixX2d a = parametrize(cap, {ParamMethod::Authalic});
  EXPECT_LT((parametrize(cap, {ParamMethod::Combined, 1.0}) - c).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((parametrize(cap, {ParamMethod::Combined, 0.0}) - a).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_GT((c - a).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_THROW(parametrize(cap, {ParamMethod::Combined, 1.5}), InvalidInput);
}

TEST(Parametrization, PatchOfARealMeshHasNoFlips) {
  GEOTEX_REQUIRE_DATA();
  const Mesh bunny = read_mesh(geotex::test::data_dir() / "stanford-bunny.obj");
  const MatrixX3d V = positions(bunny);
  const MatrixX3i F = faces(bunny);
  // A ball around a vertex on the back; grow the radius until the patch is a disk of a useful size.
  const Vec3 c = V.row(1000);
  const double h = mean_edge_length(bunny);
  bool tested = false;
  for (double r = 15 * h; r < 40 * h && !tested; r += 2 * h) {
    const Mesh patch = extract(bunny, [&](int f) {
      for (int k = 0; k < 3; ++k)
        if ((Vec3(V.row(F(f, k))) - c).norm() > r) return false;
      return true;
    });
    if (!disk_topology_problem(patch).empty() || patch.n_faces() < 300) continue;
    tested = true;
    for (auto m : {ParamMethod::Conformal, ParamMethod::NaturalConformal}) {
      const ParamQuality q = parametrization_quality(patch, parametrize(patch, {m}));
      EXPECT_EQ(q.flipped, 0u) << int(m) << " on a patch of " << patch.n_faces() << " faces";
    }
  }
  EXPECT_TRUE(tested) << "no disk-shaped patch found";
}

TEST(Parametrization, RejectsMeshesThatAreNotDisks) {
  EXPECT_THROW(parametrize(icosphere(2)), InvalidInput);  // closed
  const Mesh p = plane(10);
  const MatrixX3d V = positions(p);
  const MatrixX3i F = faces(p);
  const Mesh annulus = extract(p, [&](int f) {
    const Vec3 c = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3;
    return c.head<2>().norm() > 0.2;
  });
  EXPECT_NE(disk_topology_problem(annulus), "");
  EXPECT_THROW(parametrize(annulus), InvalidInput);
  const Mesh halves = extract(p, [&](int f) {
    const Vec3 c = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3;
    return std::abs(c.x()) > 0.1;
  });
  EXPECT_THROW(parametrize(halves), InvalidInput);
  try {
    parametrize(torus(1, 0.3, 16, 8));
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("disk"), std::string::npos);
  }
}

TEST(Parametrization, NaturalMapRefusesABoundaryCollapsedToOnePointBeforeFactoring) {
  // The two pins of the natural map would coincide: the map's similarity is free and the system
  // singular. The refusal is decided on the input, whatever the solver would have made of it.
  Mesh p = plane(6);
  const auto loops = boundary_loops(p);
  for (int v : loops.front()) p.set_point(p.vertex_handle(v), to_point(Vec3::Zero()));
  ParametrizationOptions o;
  o.method = ParamMethod::NaturalConformal;
  try {
    parametrize(p, o);
    FAIL() << "a collapsed boundary was parametrized";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("boundary vertex"), std::string::npos) << e.what();
  }
  o.method = ParamMethod::Conformal;  // the circle boundary needs no pins: still a map
  EXPECT_TRUE(parametrize(p, o).allFinite());
}

TEST(Parametrization, ObjWithUvHasOneUvPerVertex) {
  TempDir tmp;
  const Mesh p = plane(5);
  const MatrixX2d uv = parametrize(p);
  write_obj_with_uv(p, uv, tmp / "p.obj");
  const Mesh r = read_mesh(tmp / "p.obj");
  EXPECT_EQ(r.n_vertices(), p.n_vertices());
  EXPECT_EQ(r.n_faces(), p.n_faces());
  const std::string text = geotex::test::read_file(tmp / "p.obj");
  size_t vt = 0;
  for (size_t pos = text.find("\nvt "); pos != std::string::npos; pos = text.find("\nvt ", pos + 1)) ++vt;
  EXPECT_EQ(vt, p.n_vertices());
}

TEST(ParamCli, WritesUvsAndRejectsClosedMeshes) {
  TempDir tmp;
  write_mesh(plane(6), tmp / "p.ply");
  auto ok = geotex::test::run_cli("param " + tmp / "p.ply" + " -o " + tmp / "p.obj" + " --method natural");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(geotex::test::read_file(tmp / "p.obj").find("vt "), std::string::npos);
  write_mesh(icosphere(1), tmp / "s.ply");
  auto bad = geotex::test::run_cli("param " + tmp / "s.ply" + " -o " + tmp / "s.obj");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("disk"), std::string::npos) << bad.err;
  auto flag = geotex::test::run_cli("param " + tmp / "p.ply" + " -o " + tmp / "q.obj" + " --method nope");
  EXPECT_NE(flag.exit_code, 0);
  EXPECT_EQ(geotex::test::run_cli("param --help").exit_code, 0);
}
