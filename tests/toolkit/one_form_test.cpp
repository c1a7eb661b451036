// Discrete 1-forms (thesis Sec. 5.3): Whitney basis, interpolation, vertex reconstruction, LS fit.

#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/one_form.h"
#include "geotex/core/random.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

namespace {

// Line integral of a face-local vector function along the segment a→b (5-point Gauss–Legendre).
template <class Fn>
double integrate(const Vec3& ba, const Vec3& bb, const Vec3& a, const Vec3& b, Fn fn) {
  static const double x[5] = {0.0469100770306680, 0.2307653449471585, 0.5, 0.7692346550528415, 0.9530899229693320};
  static const double w[5] = {0.1184634425280945, 0.2393143352496832, 0.2844444444444444, 0.2393143352496832,
                              0.1184634425280945};
  double s = 0;
  for (int k = 0; k < 5; ++k) s += w[k] * fn(ba + x[k] * (bb - ba)).dot(b - a);
  return s;
}

double max_row_error(const MatrixX3d& A, const MatrixX3d& B) { return (A - B).rowwise().norm().maxCoeff(); }

// The rotational field z × x, tangent to a sphere about the origin.
MatrixX3d rotation_field(const MatrixX3d& V) {
  MatrixX3d T(V.rows(), 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) T.row(i) = Vec3(0, 0, 1).cross(Vec3(V.row(i).transpose())).transpose();
  return T;
}

}  // namespace

TEST(OneForm, WhitneyBasisIntegratesToOneOnItsEdgeAndZeroOnOthers) {
  const Mesh m = make_shape("sphere", 0).base;
  const MatrixX3d V = positions(m);
  const MatrixX3i F = faces(m);
  for (int f = 0; f < 20; ++f) {
    Vec3 corner[3], unit[3] = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    for (int k = 0; k < 3; ++k) corner[k] = V.row(F(f, k));
    for (int l = 0; l < 3; ++l) {
      for (int k = 0; k < 3; ++k) {
        const int a = k, b = (k + 1) % 3;
        const double s = integrate(unit[a], unit[b], corner[a], corner[b],
                                   [&](const Vec3& bary) { return whitney_basis(m, f, l, bary); });
        EXPECT_NEAR(s, l == k ? 1.0 : 0.0, 1e-12) << "face " << f << " basis " << l << " edge " << k;  // Eq. (5.74)–(5.76)
      }
    }
  }
}

TEST(OneForm, WhitneyInterpolationReproducesAConstantFieldOnAFlatMesh) {
  const Mesh m = plane(6, 2.0);
  const Vec3 t(0.3, -0.7, 0);
  const Eigen::VectorXd c = one_form_from_function(m, [&](const Vec3&) { return t; });
  Rng rng(2);
  for (int f = 0; f < static_cast<int>(m.n_faces()); f += 7) {
    double u = rng.uniform(), v = rng.uniform();
    if (u + v > 1) { u = 1 - u; v = 1 - v; }
    EXPECT_LT((whitney_interpolate(m, c, f, Vec3(u, v, 1 - u - v)) - t).norm(), 1e-13);
  }
  // And the vertex reconstruction (Eq. 5.79) gives it back too.
  const MatrixX3d T = one_form_to_vertices(m, c);
  for (Eigen::Index i = 0; i < T.rows(); ++i) EXPECT_LT((T.row(i).transpose() - t).norm(), 1e-13);
}

TEST(OneForm, WhitneyInterpolationAtACornerIsTheFaceContribution) {
  // Eq. (5.77) at α = (1, 0, 0) equals Eq. (5.78); so the average over faces is P·c (Eq. 5.79).
  const Mesh m = icosphere(2);
  Rng rng(4);
  Eigen::VectorXd c(m.n_edges());
  for (Eigen::Index e = 0; e < c.size(); ++e) c[e] = rng.normal();
  const MatrixX3d T = one_form_to_vertices(m, c);
  const MatrixX3i F = faces(m);
  MatrixX3d acc = MatrixX3d::Zero(m.n_vertices(), 3);
  Eigen::VectorXd cnt = Eigen::VectorXd::Zero(m.n_vertices());
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      Vec3 al = Vec3::Zero();
      al[k] = 1;
      acc.row(F(f, k)) += whitney_interpolate(m, c, f, al).transpose();
      cnt[F(f, k)] += 1;
    }
  for (Eigen::Index i = 0; i < T.rows(); ++i) EXPECT_LT((acc.row(i) / cnt[i] - T.row(i)).norm(), 1e-12);
}

TEST(OneForm, ConstantTangentFieldSurvivesLeastSquaresRoundTripOnFlatMesh) {
  const Mesh m = plane(12, 1.0);
  MatrixX3d T(m.n_vertices(), 3);
  T.rowwise() = Eigen::RowVector3d(0.4, 0.25, 0);
  for (bool tangential : {false, true}) {
    OneFormFitOptions o;
    o.tangential = tangential;
    const Eigen::VectorXd c = fit_one_form(m, T, o);
    EXPECT_LT(max_row_error(one_form_to_vertices(m, c), T), 1e-13) << "tangential " << tangential;
  }
}

TEST(OneForm, LeastSquaresLosesLessThanAveragingOnCurvedMesh) {
  const Mesh m = icosphere(3);
  const MatrixX3d T = rotation_field(positions(m));
  const double scale = T.rowwise().norm().maxCoeff();
  const double err_avg = max_row_error(one_form_to_vertices(m, one_form_average(m, T)), T) / scale;
  OneFormFitOptions o;
  const double err_ls = max_row_error(one_form_to_vertices(m, fit_one_form(m, T, o)), T) / scale;
  o.tangential = true;
  const MatrixX3d N = vertex_normals(m);
  // The tangential fit matches the tangent parts Π T (the field is tangent to the sphere, not exactly
  // to the discrete vertex normals: |T − Π T| is of the order of the averaging error).
  MatrixX3d R = one_form_to_vertices(m, fit_one_form(m, T, o)), PT = T;
  for (Eigen::Index i = 0; i < R.rows(); ++i) {
    R.row(i) -= R.row(i).dot(N.row(i)) * N.row(i);
    PT.row(i) -= PT.row(i).dot(N.row(i)) * N.row(i);
  }
  const double err_tan = max_row_error(R, PT) / scale;
  std::cout << "[ rotation field on icosphere(3), max relative vertex error ] averaging (5.80): " << err_avg
            << ", least squares (5.81): " << err_ls << ", tangential least squares (against the tangent parts): "
            << err_tan << " (the tangent parts differ from the field by " << max_row_error(PT, T) / scale << ")\n";
  RecordProperty("error_average", std::to_string(err_avg));
  RecordProperty("error_least_squares", std::to_string(err_ls));
  EXPECT_LT(err_ls, 0.01 * err_avg);
  EXPECT_LT(err_ls, 1e-5);
  EXPECT_LT(err_tan, 1e-5);
}

TEST(OneForm, TangentialDirectFitIsTheMinimiserOfItsNormalEquations) {
  // The vertex-form solve (2#V unknowns) against the #E × #E normal equations of the same objective,
  // ‖W^½ Π (P c − t)‖² + ε ‖c − c_avg‖² (Eq. 5.81, 5.80), solved densely.
  const Mesh m = icosphere(2);
  const Eigen::Index n = m.n_vertices(), ne = m.n_edges();
  const MatrixX3d N = vertex_normals(m);
  MatrixX3d T = rotation_field(positions(m));
  Rng rng(11);
  Eigen::VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    T.row(i) += 0.3 * Eigen::RowVector3d(rng.normal(), rng.normal(), rng.normal());  // not exactly representable
    T.row(i) -= T.row(i).dot(N.row(i)) * N.row(i);
    w[i] = 0.1 + rng.uniform();
  }
  OneFormFitOptions o;
  o.tangential = true;
  o.regularization = 1e-3;  // large enough to matter, so that ε is checked too
  OneFormFitter fitter(m, o, N);
  const Eigen::VectorXd c = fitter.fit(T, w);

  const Eigen::MatrixXd P = Eigen::MatrixXd(one_form_reconstruction_matrix(m));
  Eigen::MatrixXd Pi = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  Eigen::VectorXd t(3 * n), w3(3 * n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      t[a * n + i] = T(i, a);
      w3[a * n + i] = w[i];
      for (int b = 0; b < 3; ++b) Pi(a * n + i, b * n + i) = (a == b) - N(i, a) * N(i, b);
    }
  const Eigen::MatrixXd A = Pi * P;
  Eigen::MatrixXd M = A.transpose() * w3.asDiagonal() * A;
  const double eps = o.regularization * M.trace() / ne;
  M.diagonal().array() += eps;
  const Eigen::VectorXd ref =
      M.ldlt().solve(A.transpose() * w3.asDiagonal() * (Pi * t) + eps * one_form_average(m, T));
  EXPECT_LT((c - ref).cwiseAbs().maxCoeff(), 1e-9 * ref.cwiseAbs().maxCoeff());
  // A second field reuses the factorization and is still exact.
  const Eigen::VectorXd c2 = fitter.fit(2.0 * T, w);
  EXPECT_LT((c2 - 2.0 * c).cwiseAbs().maxCoeff(), 1e-9 * ref.cwiseAbs().maxCoeff());
}

TEST(OneForm, TangentialFitToleratesAnIsolatedVertex) {
  Mesh m = plane(6, 1.0);
  m.add_vertex(Mesh::Point(5, 5, 5));  // no faces, hence no normal (scans have such points)
  MatrixX3d T(m.n_vertices(), 3);
  T.rowwise() = Eigen::RowVector3d(0.4, 0.25, 0);
  OneFormFitOptions o;
  o.tangential = true;
  const Eigen::VectorXd c = fit_one_form(m, T, o);
  ASSERT_TRUE(c.allFinite());
  const MatrixX3d R = one_form_to_vertices(m, c);
  for (Eigen::Index i = 0; i + 1 < R.rows(); ++i) EXPECT_LT((R.row(i) - T.row(i)).norm(), 1e-12);
}

TEST(OneForm, RigidMotionLeavesCoefficientsUnchanged) {
  Mesh m = icosphere(2);
  const MatrixX3d V = positions(m);
  const MatrixX3d T = rotation_field(V);
  const Eigen::VectorXd c = fit_one_form(m, T);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::RowVector3d shift(3, -1, 2);
  set_positions(m, (V * R.transpose()).rowwise() + shift);
  const Eigen::VectorXd c2 = fit_one_form(m, T * R.transpose());
  EXPECT_LT((c - c2).cwiseAbs().maxCoeff(), 1e-6 * c.cwiseAbs().maxCoeff());
}

TEST(OneForm, BoundKeepsCoefficientsWithinEdgeLengths) {
  const Mesh m = icosphere(2);
  MatrixX3d T = 3.0 * rotation_field(positions(m));  // magnitude up to 3: many |c| > |e|
  OneFormFitOptions o;
  const Eigen::VectorXd free = fit_one_form(m, T, o);
  const Eigen::VectorXd len = edge_lengths(m);
  EXPECT_GT((free.cwiseAbs() - len).maxCoeff(), 0.0);
  o.bound_by_edge_length = true;
  const Eigen::VectorXd c = fit_one_form(m, T, o);
  EXPECT_LE((c.cwiseAbs() - len).maxCoeff(), 1e-15);
  // Within bounds the fit stays a fit: the field's direction survives.
  const MatrixX3d R = one_form_to_vertices(m, c);
  for (Eigen::Index i = 0; i < R.rows(); ++i)
    if (T.row(i).norm() > 0.5) EXPECT_GT(R.row(i).dot(T.row(i)), 0.0);
}

TEST(OneForm, SizeMismatchThrows) {
  const Mesh m = icosphere(1);
  EXPECT_THROW(one_form_to_vertices(m, Eigen::VectorXd::Zero(3)), InvalidInput);
  EXPECT_THROW(fit_one_form(m, MatrixX3d::Zero(2, 3)), InvalidInput);
}

TEST(OneForm, IterativeFitReachesTheDirectResidualAndReportsItsIterations) {
  const Mesh m = icosphere(3);
  const MatrixX3d T = rotation_field(positions(m));
  const double scale = T.rowwise().norm().maxCoeff();
  const Eigen::Index n = T.rows();
  OneFormFitter fitter(m);
  const double err_direct = max_row_error(one_form_to_vertices(m, fitter.fit(T)), T) / scale;
  // Monitor: stop once the vertex field P c (3#V, x then y then z) is within 1e-5 of T everywhere.
  int calls = 0;
  double monitored = 0;
  auto monitor = [&](const Eigen::VectorXd& c, const Eigen::VectorXd& Pc) {
    ++calls;
    EXPECT_EQ(c.size(), static_cast<Eigen::Index>(m.n_edges()));
    double e = 0;
    for (Eigen::Index i = 0; i < n; ++i) e = std::max(e, (Vec3(Pc[i], Pc[n + i], Pc[2 * n + i]) - Vec3(T.row(i).transpose())).norm());
    monitored = e / scale;
    return monitored < 1e-5;
  };
  IterativeFitOptions io;
  io.max_iterations = 20000;
  const IterativeFitResult r = fitter.fit_iterative(T, Eigen::VectorXd(), monitor, io);
  const double err_iter = max_row_error(one_form_to_vertices(m, r.c), T) / scale;
  std::cout << "[ rotation field on icosphere(3) ] iterative: " << r.iterations << " CGLS iterations, max relative error "
            << err_iter << " (direct " << err_direct << ")\n";
  EXPECT_TRUE(r.converged);
  EXPECT_LT(err_iter, 1e-5);
  EXPECT_NEAR(err_iter, monitored, 1e-12);          // the monitor saw P c of the returned coefficients
  EXPECT_EQ(calls, 1 + (r.iterations + io.check_every - 1) / io.check_every);  // start + every check_every
  // Start = the averaging estimate (Eq. 5.80): with a monitor that accepts at once, nothing iterates.
  const IterativeFitResult r0 = fitter.fit_iterative(T, Eigen::VectorXd(), [](auto&, auto&) { return true; });
  EXPECT_EQ(r0.iterations, 0);
  EXPECT_LT((r0.c - one_form_average(m, T)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_THROW(fitter.fit_iterative(T, Eigen::VectorXd::Zero(n), monitor), InvalidInput);
}
