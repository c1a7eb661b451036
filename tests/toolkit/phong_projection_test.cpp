// Phong-normal projection (thesis Sec. 5.2): analytic cubic vs Newton, derivatives, mesh projection.

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/toolkit/phong_projection.h"
#include "geotex/core/random.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

namespace {

Vec3 random_unit(Rng& rng) { return Vec3(rng.normal(), rng.normal(), rng.normal()).normalized(); }

// A random triangle near the xy-plane with normals around +z, tilted by up to \p spread, and a point
// above it.
PhongTriangle random_config(Rng& rng, double spread, Vec3* p) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.3, 0.9, 0);
  auto n = [&] { return (Vec3(0, 0, 1) + spread * random_unit(rng)).normalized(); };
  *p = Vec3(rng.uniform() * 1.2 - 0.1, rng.uniform() * 1.1 - 0.1, (rng.uniform() - 0.3) * 1.5);
  return PhongTriangle(a, b, c, n(), n(), n());
}

double residual(const Vec3& p, const PhongCandidate& c) { return (p - c.point).cross(c.normal).norm(); }

}  // namespace

TEST(PhongProjection, CubicCoefficientsVanishAtEveryCandidate) {
  Rng rng(3);
  int total = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Vec3 p;
    const PhongTriangle t = random_config(rng, 0.8, &p);
    for (const PhongCandidate& c : phong_project_analytic(p, t)) {
      ++total;
      // p = q + d n_q, hence the residual (p − q) × n_q of Eq. (5.27) vanishes and p − q = d n_q.
      // Relative to the size of the terms: far-outside candidates have huge barycentric coordinates.
      const double scale = (1 + (p - c.point).norm()) * std::max(1.0, c.normal.norm());
      EXPECT_LT(residual(p, c), 1e-10 * scale) << "trial " << trial;
      EXPECT_LT((p - c.point - c.d * c.normal).norm(), 1e-10 * scale);
      EXPECT_NEAR(c.bary.sum(), 1.0, 1e-12);
    }
  }
  EXPECT_GT(total, 2000);
}

TEST(PhongProjection, FlatTriangleWithEqualNormalsIsOrthogonalProjection) {
  const Vec3 n(0, 0, 1);
  const PhongTriangle t(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), n, n, n);
  const Vec3 p(0.5, 0.25, 0.7);
  const auto cands = phong_project_analytic(p, t);
  ASSERT_EQ(cands.size(), 1u);
  EXPECT_NEAR(cands[0].d, 0.7, 1e-14);
  EXPECT_TRUE(cands[0].inside);
  EXPECT_NEAR((cands[0].point - Vec3(0.5, 0.25, 0)).norm(), 0, 1e-14);
  EXPECT_NEAR(cands[0].bary[1], 0.25, 1e-14);
  EXPECT_NEAR(cands[0].bary[2], 0.125, 1e-14);
}

TEST(PhongProjection, DerivativesMatchFiniteDifferences) {
  Rng rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    Vec3 p;
    const PhongTriangle t = random_config(rng, 0.7, &p);
    const PhongQuadratic q(p, t);
    const double u = rng.uniform(), v = rng.uniform(), h = 1e-6;
    // F itself against its definition, Eq. (5.28) with the corrected bracket.
    const Vec3 qp = u * t.a + v * t.b + (1 - u - v) * t.c;
    const Vec3 nq = u * t.na + v * t.nb + (1 - u - v) * t.nc;
    EXPECT_LT((q.F(u, v) - (p - qp).cross(nq)).norm(), 1e-13);
    EXPECT_LT((q.Fu(u, v) - (q.F(u + h, v) - q.F(u - h, v)) / (2 * h)).norm(), 1e-8);
    EXPECT_LT((q.Fv(u, v) - (q.F(u, v + h) - q.F(u, v - h)) / (2 * h)).norm(), 1e-8);
    const Eigen::Vector2d g = q.gradient(u, v);
    EXPECT_NEAR(g[0], (q.f(u + h, v) - q.f(u - h, v)) / (2 * h), 1e-7);
    EXPECT_NEAR(g[1], (q.f(u, v + h) - q.f(u, v - h)) / (2 * h), 1e-7);
    const Eigen::Matrix2d H = q.hessian(u, v);
    const Eigen::Vector2d gu = (q.gradient(u + h, v) - q.gradient(u - h, v)) / (2 * h);
    const Eigen::Vector2d gv = (q.gradient(u, v + h) - q.gradient(u, v - h)) / (2 * h);
    EXPECT_LT((H.col(0) - gu).norm(), 1e-6);
    EXPECT_LT((H.col(1) - gv).norm(), 1e-6);
  }
}

TEST(PhongProjection, NewtonAgreesWithAnalyticWhereItConverges) {
  Rng rng(7);
  int converged = 0, matched = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Vec3 p;
    const PhongTriangle t = random_config(rng, 0.3, &p);
    const PhongNewtonResult nr = phong_project_newton(p, t);
    if (!nr.converged) continue;
    ++converged;
    double best = 1e300;
    for (const PhongCandidate& c : phong_project_analytic(p, t))
      best = std::min(best, (c.bary - nr.candidate.bary).norm());
    EXPECT_LT(best, 1e-7) << "trial " << trial;
    matched += best < 1e-7;
  }
  EXPECT_GT(converged, 1000);
  EXPECT_EQ(matched, converged);
}

// Figure 5.8: three candidates close to the triangle; Newton from the barycentre may end at an outside
// one (or between them) while an inside solution exists, which the analytic method finds.
TEST(PhongProjection, Figure58NewtonLandsOutsideWhileAnalyticFindsInside) {
  Rng rng(11);
  int cases = 0;
  for (int trial = 0; trial < 20000 && cases < 3; ++trial) {
    Vec3 p;
    const PhongTriangle t = random_config(rng, 1.2, &p);
    const auto cands = phong_project_analytic(p, t);
    const PhongCandidate* inside = nullptr;
    for (const auto& c : cands)
      if (c.inside) { inside = &c; break; }
    if (!inside || cands.size() < 3) continue;
    const PhongNewtonResult nr = phong_project_newton(p, t);
    if (nr.candidate.inside && nr.converged) continue;
    ++cases;
    EXPECT_LT(residual(p, *inside), 1e-9);
    EXPECT_GE(inside->bary.minCoeff(), -1e-9);
    if (nr.converged) EXPECT_LT(nr.candidate.bary.minCoeff(), 0.0);
  }
  EXPECT_GE(cases, 1) << "no configuration of Figure 5.8's kind found";
}

TEST(PhongProjection, MeshProjectionOfOffsetSphereRecoversRadialFeet) {
  // On a sphere the vertex normals are radial; a point pushed out along the Phong normal of a surface
  // point projects back to that point.
  const Mesh s = icosphere(3, 1.0);
  const MatrixX3d V = positions(s);
  const MatrixX3i F = faces(s);
  MatrixX3d N(V.rows(), 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) N.row(i) = V.row(i).normalized();
  const PhongProjector proj(s, N);
  Rng rng(13);
  for (int trial = 0; trial < 200; ++trial) {
    const int f = static_cast<int>(rng.uniform() * F.rows());
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1) { u = 1 - u; v = 1 - v; }
    const Vec3 bary(u, v, 1 - u - v);
    Vec3 q = Vec3::Zero(), n = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      q += bary[k] * V.row(F(f, k)).transpose();
      n += bary[k] * N.row(F(f, k)).transpose();
    }
    const double d = (rng.uniform() - 0.5) * 0.3;
    const Vec3 p = q + d * n;
    const PhongHit hit = proj.project(p);
    ASSERT_TRUE(hit.found);
    EXPECT_LT((hit.point - q).norm(), 1e-9) << "trial " << trial;
    EXPECT_NEAR(hit.d, d, 1e-9);
  }
}

TEST(PhongProjection, MeshProjectionBatchMatchesSingle) {
  const TexturedShape s = make_shape("spiky-sphere", 0);
  const PhongProjector proj(s.base);
  const MatrixX3d P = positions(s.textured);
  const auto hits = proj.project(P);
  int found = 0;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const PhongHit h = proj.project(Vec3(P.row(i).transpose()));
    EXPECT_EQ(h.face, hits[i].face);
    found += hits[i].found;
    if (hits[i].found) EXPECT_LT((P.row(i).transpose() - hits[i].point).cross(hits[i].normal).norm(), 1e-8);
  }
  EXPECT_GT(found, P.rows() * 9 / 10);
}

// PhongProjector::project by its definition, over every face: the faces whose box lies within the
// search radius, the inside solution of smallest |d|; the radius doubled up to 4 times; else the
// closest point.
PhongHit project_by_brute_force(const MatrixX3d& V, const MatrixX3i& F, double h, const PhongProjector& proj,
                                const Vec3& p, const PhongProjectionOptions& o = {}) {
  // The closest point by brute force too.
  TriangleTree::Hit closest;
  closest.sq_distance = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 q = closest_point_on_triangle(p, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
    if ((q - p).squaredNorm() < closest.sq_distance) closest = {static_cast<int>(f), q, Vec3::Zero(), (q - p).squaredNorm()};
  }
  double radius = o.search_factor * std::sqrt(closest.sq_distance) + o.search_margin * h;
  PhongHit best;
  for (int attempt = 0; attempt < 5 && !best.found; ++attempt, radius *= 2)
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      Eigen::AlignedBox3d box;
      for (int k = 0; k < 3; ++k) box.extend(Vec3(V.row(F(f, k)).transpose()));
      if (box.exteriorDistance(p) > radius) continue;
      for (const PhongCandidate& c : phong_project_analytic(p, proj.triangle(static_cast<int>(f)), o.inside_tol)) {
        // A projection: p − q parallel to n_q (a root where the shifted triangle degenerates is none).
        const bool parallel = (p - c.point).cross(c.normal.normalized()).norm() <= 1e-6 * ((p - c.point).norm() + h);
        if (c.inside && parallel && (!best.found || std::abs(c.d) < std::abs(best.d))) {
          best.found = true;
          best.face = static_cast<int>(f);
          best.point = c.point;
          best.d = c.d;
        }
      }
    }
  if (!best.found) best.point = closest.point;
  return best;
}

void expect_matches_brute_force(const Mesh& m, const MatrixX3d& P) {
  const PhongProjector proj(m);
  const std::vector<PhongHit> hits = proj.project(P);
  const MatrixX3d V = positions(m);
  const MatrixX3i F = faces(m);
  const double h = mean_edge_length(m);
  int found = 0;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    const Vec3 p = P.row(i).transpose();
    const PhongHit ref = project_by_brute_force(V, F, h, proj, p);
    const double scale = std::max(1.0, p.norm());
    ASSERT_EQ(hits[i].found, ref.found) << "point " << i << " at " << p.transpose();
    EXPECT_LT((hits[i].point - ref.point).norm(), 1e-9 * scale) << "point " << i << " at " << p.transpose();
    if (ref.found) EXPECT_NEAR(hits[i].d, ref.d, 1e-9 * scale) << "point " << i;
    found += ref.found;
  }
  EXPECT_GT(found, 0);
}

TEST(PhongProjection, FarAndMixedPointsMatchBruteForce) {
  // The normal-cone pruning (points 1e7 away cost log #F, not #F) leaves the result unchanged: points
  // at every distance from 1e-3 to 1e7 mean edges, in every direction, on a closed and an open surface
  // (where far points off its side find no inside solution and take the closest point).
  Rng rng(29);
  for (const Mesh& m : {icosphere(2, 1.0), make_shape("spiky-sphere", 0).textured, plane(6, 1.0)}) {
    const MatrixX3d V = positions(m);
    MatrixX3d P(200, 3);
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
      const Vec3 anchor = V.row(static_cast<Eigen::Index>(rng.uniform() * V.rows()) % V.rows()).transpose();
      const double distance = std::pow(10.0, -3 + 10 * rng.uniform());
      P.row(i) = (i % 4 == 0 ? Vec3(1e7 * random_unit(rng)) : Vec3(anchor + distance * random_unit(rng))).transpose();
    }
    expect_matches_brute_force(m, P);
  }
}

TEST(PhongProjection, NeedlesProjectOntoThemselves) {
  // Points on a soup of needles (aspect 100 to 10^4) are their own Phong projections (d = 0). The
  // barycentric coordinates of the shifted triangle once came from its Gram determinant, whose
  // cancellation put a needle's own vertex 1e-9 outside it: no projection found, and the search went
  // on over every face within the radius, doubled four times (issue 30: minutes on 10^5 needles).
  const int k = 2000;
  MatrixX3d V(3 * k, 3);
  MatrixX3i F(k, 3);
  Rng rng(5);
  for (int i = 0; i < k; ++i) {
    const Vec3 a(rng.uniform(), rng.uniform(), rng.uniform()), d = random_unit(rng);
    const Vec3 w = d.cross(random_unit(rng)).normalized();
    V.row(3 * i) = a.transpose();
    V.row(3 * i + 1) = (a + 0.5 * d).transpose();
    V.row(3 * i + 2) = (a + 0.25 * d + std::pow(10.0, rng.uniform(-4.3, -2.3)) * w).transpose();
    F.row(i) << 3 * i, 3 * i + 1, 3 * i + 2;
  }
  const Mesh m = make_mesh(V, F);
  const PhongProjector proj(m);
  MatrixX3d P(V.rows() + k, 3);
  P.topRows(V.rows()) = V;
  for (int i = 0; i < k; ++i) {  // a point inside each needle
    const double s = rng.uniform(), t = rng.uniform() * (1 - s);
    P.row(V.rows() + i) = (1 - s - t) * V.row(3 * i) + s * V.row(3 * i + 1) + t * V.row(3 * i + 2);
  }
  const std::vector<PhongHit> hits = proj.project(P);
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    ASSERT_TRUE(hits[i].found) << "point " << i;
    EXPECT_LT(std::abs(hits[i].d), 1e-12) << "point " << i;
    EXPECT_LT((hits[i].point - P.row(i).transpose()).norm(), 1e-12) << "point " << i;
  }
}

TEST(PhongProjectionCli, ProjectsOntoABaseAndRejectsBadInput) {
  geotex::test::TempDir dir;
  const TexturedShape s = make_shape("spiky-sphere", 0);
  write_mesh(s.textured, dir / "t.ply");
  write_mesh(s.base, dir / "b.ply");
  auto r = geotex::test::run_cli("project " + (dir / "t.ply") + " " + (dir / "b.ply") + " -o " + (dir / "p.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Mesh p = read_mesh(dir / "p.ply");
  EXPECT_EQ(p.n_vertices(), s.textured.n_vertices());
  r = geotex::test::run_cli("project " + (dir / "t.ply") + " " + (dir / "missing.ply") + " -o " + (dir / "p.ply"));
  EXPECT_NE(r.exit_code, 0);
  r = geotex::test::run_cli("project " + (dir / "t.ply") + " " + (dir / "b.ply") + " -o " + (dir / "p.ply") +
                            " --search-factor -1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(geotex::test::run_cli("project --help").exit_code, 0);
}
