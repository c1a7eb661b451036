// A texture that follows its base (thesis Sec. 8.4.2, issue 17): tentacles re-applied after scaling,
// bending and twisting the base keep their length and their lean from the local base normal.

#include <cmath>
#include <iostream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/resize/resize.h"
#include "geotex/texture/measures.h"
#include "geotex/texture/texture.h"
#include "geotex/toolkit/space_maps.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

struct Deformation {
  const char* name;
  SpaceMap map;
};

std::vector<Deformation> deformations() {
  return {{"x0.5 along the axis", scale_map(Vec3(0.5, 1, 1))},
          {"x1.5 along the axis", scale_map(Vec3(1.5, 1, 1))},
          {"x2 along the axis", scale_map(Vec3(2, 1, 1))},
          {"x0.5 uniform", scale_map(Vec3(0.5, 0.5, 0.5))},
          {"arc bend, radius 4", arc_bend_map(4.0)},
          {"shear bend, kappa 0.15", bend_map(0.15)},
          {"twist, 90 deg over the length", twist_map(M_PI / 12)}};
}

// Worst changes of the tentacles re-applied on the deformed base, against the generator's measurements.
struct Worst {
  double length = 0;   // max |length / length0 − 1|
  double lean = 0;     // max |lean − lean0|, degrees
  double azimuth = 0;  // max angle between the lean's direction and the push-forward J l of the original one
  double shape = 0;    // max RMS distance of a tentacle's vertices from the tentacle carried rigidly by the
                       // foot's frame, over its length (how much the shaft itself deforms)
};

Worst measure(const TexturedShape& s, const std::vector<Tentacle>& info, const Texture& tex, const SpaceMap& map,
              const TextureOptions& o) {
  Mesh deformed = s.base;
  const MatrixX3d B0 = positions(s.base), X0 = positions(s.textured);
  set_positions(deformed, apply_space_map(map, B0));
  const MatrixX3d Y = apply_texture(deformed, tex, o);
  std::vector<int> feet;
  for (const auto& t : info) feet.push_back(t.foot);
  const std::vector<Protrusion> now = measure_protrusions(deformed, Y, feet);
  const std::vector<Protrusion> before = measure_protrusions(s.base, X0, feet);
  const Eigen::VectorXd inside = tentacle_truth(s.base, info, TentacleOptions().radius);
  Worst w;
  for (size_t k = 0; k < info.size(); ++k) {
    const Tentacle& t = info[k];
    w.length = std::max(w.length, std::abs(now[k].length / t.length - 1));
    w.lean = std::max(w.lean, std::abs(now[k].lean_deg - t.lean_deg));
    const Vec3 x = B0.row(t.foot).transpose(), n = now[k].normal;
    Vec3 jl = space_map_jacobian(map, x) * before[k].direction;
    jl = (jl - jl.dot(n) * n).normalized();
    w.azimuth = std::max(w.azimuth, std::acos(std::clamp(now[k].direction.dot(jl), -1.0, 1.0)) * 180 / M_PI);
    // The ideal: the original tentacle moved rigidly with the frame (n, l, n × l) at its foot.
    Eigen::Matrix3d F0, F1;
    F0 << before[k].normal, before[k].direction, before[k].normal.cross(before[k].direction);
    F1 << n, jl, n.cross(jl);
    const Eigen::Matrix3d R = F1 * F0.transpose();
    const Vec3 foot1 = map(x);
    double sum = 0;
    int count = 0;
    for (Eigen::Index i = 0; i < B0.rows(); ++i) {
      if (inside[i] == 0 || (B0.row(i) - B0.row(t.foot)).norm() >= TentacleOptions().radius) continue;
      const Vec3 ideal = foot1 + R * (X0.row(i).transpose() - x);
      sum += (Y.row(i).transpose() - ideal).squaredNorm();
      ++count;
    }
    w.shape = std::max(w.shape, std::sqrt(sum / count) / t.length);
  }
  return w;
}

}  // namespace

TEST(TextureDeform, TentaclesKeepLengthAndLeanUnderScalingBendingAndTwisting) {
  std::vector<Tentacle> info;
  const TexturedShape s = tentacle_stick(0, &info);
  ASSERT_EQ(info.size(), 9u);
  TextureOptions lean, thesis;
  thesis.encoding = TiltEncoding::OneForm;  // the thesis' encoding, all else equal
  const Texture a = TextureCodec(s.base, lean).extract(positions(s.textured));
  const Texture b = TextureCodec(s.base, thesis).extract(positions(s.textured));
  EXPECT_EQ(a.lean.size(), a.height.size());
  EXPECT_EQ(b.lean.size(), 0);
  std::cout << "[ tentacle stick, level 0: worst of 9 tentacles; length |tip - foot|, lean = angle of tip - foot from "
               "the deformed base's normal at the foot, azimuth against J l, shape = RMS distance from the tentacle "
               "carried rigidly / length ]\n";
  for (const Deformation& d : deformations()) {
    SCOPED_TRACE(d.name);
    const Worst wa = measure(s, info, a, d.map, lean), wb = measure(s, info, b, d.map, thesis);
    std::cout << fmt::format("  {:30} lean encoding: length {:.2f}%, lean {:.2f} deg, azimuth {:.2f} deg, shape {:.3f}"
                             " | thesis: length {:.2f}%, lean {:.2f} deg, azimuth {:.2f} deg, shape {:.3f}\n",
                             d.name, 100 * wa.length, wa.lean, wa.azimuth, wa.shape, 100 * wb.length, wb.lean,
                             wb.azimuth, wb.shape);
    EXPECT_LT(wa.length, 0.03);
    EXPECT_LT(wa.lean, 3.0);
    EXPECT_LT(wa.azimuth, 3.0);
    EXPECT_LT(wb.length, 0.03);  // heights are kept by both
    EXPECT_LT(wb.azimuth, 3.0);  // the 1-form pushes the lean's direction forward (J d / det J)
  }
  // The thesis' 1-form divides sin(lean) by the scale: halving the base lays the tentacles flat.
  EXPECT_GT(measure(s, info, b, scale_map(Vec3(0.5, 0.5, 0.5)), thesis).lean, 30.0);
}

TEST(TextureDeform, LeanEncodingRoundTripsAndKeepsRigidMotionInvariance) {
  const TexturedShape s = make_shape("spiky-sphere", 0);
  TextureCodec codec(s.base);
  const MatrixX3d X = positions(s.textured);
  const Texture tex = codec.extract(X);
  const double h = mean_edge_length(s.base);
  EXPECT_LT((codec.apply(tex) - X).rowwise().norm().maxCoeff() / h, 1e-3);
  for (Eigen::Index i = 0; i < tex.lean.size(); ++i) {
    EXPECT_GE(tex.lean[i], 0.0);
    EXPECT_LE(tex.lean[i], M_PI / 2 + 1e-12);
  }
  // A uniform scaling of the base keeps every displacement's length and its angle from the normal.
  Mesh big = s.base;
  set_positions(big, 3.0 * positions(s.base));
  const MatrixX3d Y = apply_texture(big, tex);
  const MatrixX3d N0 = codec.normals(), N1 = vertex_normals(big, NormalWeighting::Angle);
  const MatrixX3d D0 = X - positions(s.base), D1 = Y - positions(big);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    ASSERT_NEAR(D1.row(i).norm(), D0.row(i).norm(), 1e-9);
    if (D0.row(i).norm() < 1e-3 * h) continue;
    ASSERT_NEAR(D1.row(i).normalized().dot(N1.row(i)), D0.row(i).normalized().dot(N0.row(i)), 1e-6) << i;
  }
}
