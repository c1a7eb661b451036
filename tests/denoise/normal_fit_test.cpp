// Vertex positions from target face normals (Sun et al. 2007).

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/normal_fit.h"
#include "geotex/core/random.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

TEST(NormalFit, BumpyPlaneBecomesFlatWithoutMovingSideways) {
  // Heights perturbed, target normals all +z: the update pulls every vertex to its faces' mean height
  // (the plane flattens) and, without relaxation, moves nothing in x or y.
  const Mesh m = plane(12, 1.0);
  MatrixX3d X = positions(m);
  Rng rng(2);
  for (Eigen::Index i = 0; i < X.rows(); ++i) X(i, 2) = 0.05 * rng.normal();
  const MatrixX3i F = faces(m);
  const MatrixX3d N = MatrixX3d::Zero(F.rows(), 3).rowwise() + Eigen::RowVector3d(0, 0, 1);
  const MatrixX3d Y = fit_vertices_to_normals(F, X, N, 200);
  const double spread = Y.col(2).maxCoeff() - Y.col(2).minCoeff();
  EXPECT_LT(spread, 0.05 * (X.col(2).maxCoeff() - X.col(2).minCoeff()));
  EXPECT_LT((Y.leftCols(2) - X.leftCols(2)).cwiseAbs().maxCoeff(), 1e-15);
  // Relaxation moves vertices only in the plane the normals leave free: heights as without it.
  const MatrixX3d R = fit_vertices_to_normals(F, X, N, 200, 0.5);
  EXPECT_LT(R.col(2).maxCoeff() - R.col(2).minCoeff(), 0.05 * (X.col(2).maxCoeff() - X.col(2).minCoeff()));
  EXPECT_GT((R.leftCols(2) - X.leftCols(2)).cwiseAbs().maxCoeff(), 0.0);
}

TEST(NormalFit, RelaxationKeepsVerticesOnTheirEdgeLineAndCornersInPlace) {
  // A noiseless cube with its own face normals is a fixed point, with or without relaxation: edge
  // vertices may only slide along their edge, corners not at all, and a regular grid is balanced.
  const Mesh cube = subdivided_cube(6);
  const MatrixX3d X = positions(cube);
  const MatrixX3d Y = fit_vertices_to_normals(faces(cube), X, face_normals(cube), 30, 0.5);
  EXPECT_LT((Y.cwiseAbs().rowwise().maxCoeff().array() - 0.5).abs().maxCoeff(), 1e-12);  // still on the cube
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if ((X.row(i).cwiseAbs().array() > 0.5 - 1e-12).count() == 3) EXPECT_LT((Y.row(i) - X.row(i)).norm(), 1e-12);
}

TEST(NormalFit, WrongSizedOrOutOfRangeArgumentsThrow) {
  const Mesh m = plane(3, 1.0);
  const MatrixX3i F = faces(m);
  const MatrixX3d X = positions(m), N = face_normals(m);
  EXPECT_THROW(fit_vertices_to_normals(F, X, N.topRows(2), 1), InvalidInput);
  EXPECT_THROW(fit_vertices_to_normals(F, X, N, -1), InvalidInput);
  EXPECT_THROW(fit_vertices_to_normals(F, X, N, 1, 1.5), InvalidInput);
  EXPECT_THROW(fit_vertices_to_normals(F, X.topRows(3), N, 1), InvalidInput);
}
