#include <cmath>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

TEST(Noise, SameSeedGivesSameNoise) {
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

// Scanner-like noise (issue 24): correlated over patches, banded, or along one viewing axis. Each keeps the
// asked standard deviation; the patterns are correlated between neighbours where white noise is not.
TEST(Noise, PatternsAreCorrelatedAndDepthNoiseIsAlongTheAxis) {
  const Mesh m = icosphere(4);
  const double h = mean_edge_length(m);
  const MatrixX3d N = vertex_normals(m);
  const auto neighbour_correlation = [&](const MatrixX3d& D) {
    std::vector<double> a, b;
    for (auto e : m.edges()) {
      const int i = e.v0().idx(), j = e.v1().idx();
      a.push_back(D.row(i).dot(N.row(i)));
      b.push_back(D.row(j).dot(N.row(j)));
    }
    const Eigen::Map<Eigen::VectorXd> x(a.data(), a.size()), y(b.data(), b.size());
    const Eigen::VectorXd xc = x.array() - x.mean(), yc = y.array() - y.mean();
    return xc.dot(yc) / (xc.norm() * yc.norm());
  };
  NoiseOptions o;
  o.sigma = 0.3;
  o.seed = 5;
  EXPECT_LT(std::abs(neighbour_correlation(add_noise(m, o) - positions(m))), 0.1) << "white";
  for (NoisePattern p : {NoisePattern::LowFrequency, NoisePattern::Striped}) {
    o.pattern = p;
    const MatrixX3d D = add_noise(m, o) - positions(m);
    EXPECT_GT(neighbour_correlation(D), 0.6) << enum_name(noise_pattern_names(), p);
    EXPECT_NEAR(std::sqrt(D.squaredNorm() / D.rows()) / h, 0.3, 0.03) << enum_name(noise_pattern_names(), p);
    EXPECT_TRUE(add_noise(m, o) == add_noise(m, o)) << "seeded";
  }
  o = {};
  o.direction = NoiseDirection::Depth;
  o.axis = Vec3(1, 2, 2);
  const MatrixX3d D = add_noise(m, o) - positions(m);
  const Vec3 a = o.axis.normalized();
  for (Eigen::Index i = 0; i < D.rows(); ++i) EXPECT_LT((D.row(i).transpose() - D.row(i).dot(a) * a).norm(), 1e-12 * h);
  o.axis = Vec3::Zero();
  EXPECT_THROW(add_noise(m, o), InvalidInput);
}

// An output no command could compute with (issue 30): coordinates beyond kMaxCoordinate are refused, not written.
TEST(Noise, ASigmaThatLeavesTheComputableRangeIsRefused) {
  const Mesh m = icosphere(2);
  NoiseOptions o;
  o.sigma = 1e100;
  try {
    add_noise(m, o);
    FAIL() << "noise of sigma 1e100 was returned";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("beyond"), std::string::npos) << e.what();
  }
  o.sigma = 1e60;  // large, but inside the range: returned
  EXPECT_TRUE(add_noise(m, o).allFinite());
}
