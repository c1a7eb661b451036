#include <cmath>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

TEST(Noise, SeededAndReproducible) {
  const Mesh m = icosphere(3);
  NoiseOptions a;
  a.seed = 7;
  EXPECT_TRUE(add_noise(m, a) == add_noise(m, a));
  NoiseOptions b = a;
  b.seed = 8;
  EXPECT_FALSE(add_noise(m, a) == add_noise(m, b));
  a.sigma = 0;
  EXPECT_TRUE(add_noise(m, a) == positions(m));
}

TEST(Noise, StandardDeviationInEdgeUnits) {
  const Mesh m = icosphere(5);  // 10242 vertices
  const double h = mean_edge_length(m);
  for (bool normal : {true, false}) {
    NoiseOptions o;
    o.sigma = 0.5;
    o.along_normal = normal;
    const MatrixX3d D = add_noise(m, o) - positions(m);
    const Eigen::VectorXd len = D.rowwise().norm();
    const double rms = std::sqrt(len.squaredNorm() / len.size());
    EXPECT_NEAR(rms / h, 0.5, 0.02);
    if (normal) {
      const MatrixX3d N = vertex_normals(m);
      for (Eigen::Index i = 0; i < D.rows(); i += 97)
        EXPECT_NEAR(std::abs(D.row(i).dot(N.row(i))), len[i], 1e-12);
    }
  }
}

TEST(Noise, ImpulsiveTouchesOnlyAFraction) {
  const Mesh m = icosphere(5);
  NoiseOptions o;
  o.impulsive_fraction = 0.1;
  const MatrixX3d D = add_noise(m, o) - positions(m);
  const double moved = (D.rowwise().norm().array() > 0).cast<double>().mean();
  EXPECT_NEAR(moved, 0.1, 0.015);
  o.impulsive_fraction = 2;
  EXPECT_THROW(add_noise(m, o), InvalidInput);
}
