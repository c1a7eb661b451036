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
          {"shear, x += 0.5 z", [](const Vec3& x) { return Vec3(x.x() + 0.5 * x.z(), x.y(), x.z()); }},
          {"twist, 90 deg over the length", twist_map(M_PI / 12)}};
}

// Worst changes of the tentacles re-applied on the deformed base, against the generator's measurements.
struct Worst {
  double length = 0;   // max |length / length0 − 1|
  double lean = 0;     // max |lean − lean0|, degrees
  double azimuth = 0;  // max angle between the lean's direction and R l, R the rotation part of J (polar)
  double pushed = 0;   // max angle between the lean's direction and the push-forward J l of the original one
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
    const Eigen::Matrix3d J = space_map_jacobian(map, x);
    Vec3 jl = J * before[k].direction;
    jl = (jl - jl.dot(n) * n).normalized();
    const Vec3 rl = polar_rotated(J, before[k].normal, n, before[k].direction);
    auto angle = [&](const Vec3& v) { return std::acos(std::clamp(now[k].direction.dot(v), -1.0, 1.0)) * 180 / M_PI; };
    w.azimuth = std::max(w.azimuth, angle(rl));
    w.pushed = std::max(w.pushed, angle(jl));
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
  TextureOptions lean, pushforward, thesis;
  pushforward.encoding = TiltEncoding::LeanPushforward;  // issue 17's lean encoding
  thesis.encoding = TiltEncoding::OneForm;               // the thesis' encoding, all else equal
  const Texture a = TextureCodec(s.base, lean).extract(positions(s.textured));
  const Texture b = TextureCodec(s.base, thesis).extract(positions(s.textured));
  EXPECT_EQ(a.lean.size(), a.height.size());
  EXPECT_EQ(a.rest.rows(), a.height.size());
  EXPECT_EQ(b.lean.size(), 0);
  std::cout << "[ tentacle stick, level 0: worst of 9 tentacles; length |tip - foot|, lean = angle of tip - foot from "
               "the deformed base's normal at the foot, azimuth against R l (R the rotation of the map's tangent "
               "Jacobian), push = against J l, shape = RMS distance from the tentacle carried rigidly / length ]\n";
  for (const Deformation& d : deformations()) {
    SCOPED_TRACE(d.name);
    const Worst wa = measure(s, info, a, d.map, lean), wp = measure(s, info, a, d.map, pushforward),
                wb = measure(s, info, b, d.map, thesis);
    std::cout << fmt::format("  {:30} lean: length {:.2f}%, lean {:.2f}, azimuth {:.2f} deg, shape {:.3f} | "
                             "lean-pushforward: lean {:.2f}, azimuth {:.2f}, push {:.2f} deg | thesis: length {:.2f}%, "
                             "lean {:.2f}, push {:.2f} deg\n",
                             d.name, 100 * wa.length, wa.lean, wa.azimuth, wa.shape, wp.lean, wp.azimuth, wp.pushed,
                             100 * wb.length, wb.lean, wb.pushed);
    EXPECT_LT(wa.length, 0.03);
    EXPECT_LT(wa.lean, 3.0);
    EXPECT_LT(wa.azimuth, 3.0);  // the direction turns with the base's rotation only
    EXPECT_LT(wp.lean, 3.0);
    EXPECT_LT(wp.pushed, 3.0);   // the 1-form pushes the lean's direction forward (J d / det J)
    EXPECT_LT(wb.length, 0.03);  // heights are kept by both
    EXPECT_LT(wb.pushed, 3.0);
  }
  // The push-forward turns the lean's direction with a stretch or a shear; the default does not.
  for (const Deformation& d : {deformations()[2], deformations()[6]}) {
    SCOPED_TRACE(d.name);
    EXPECT_GT(measure(s, info, a, d.map, pushforward).azimuth, 8.0);
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

TEST(TextureDeform, TheRestPoseTravelsWithTheTextureThroughFilesAndTheApplyOptions) {
  std::vector<Tentacle> info;
  const TexturedShape s = tentacle_stick(0, &info);
  const Texture tex = extract_texture(s.base, positions(s.textured));
  Mesh stretched = s.base;
  set_positions(stretched, apply_space_map(scale_map(Vec3(2, 1, 1)), positions(s.base)));
  const MatrixX3d Y = apply_texture(stretched, tex);
  // Written over the stretched base, the texture keeps its rest pose (vertex rest_x, rest_y, rest_z).
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "geotex-rest-pose-test.ply";
  write_texture(path, stretched, tex);
  const TextureFile f = read_texture(path);
  std::filesystem::remove(path);
  ASSERT_EQ(f.texture.rest.rows(), tex.rest.rows());
  EXPECT_LT((f.texture.rest - tex.rest).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((apply_texture(f.base, f.texture) - Y).rowwise().norm().maxCoeff(), 1e-5);
  // The apply options choose the decoding: the push-forward turns the tentacles, so the surfaces differ.
  TextureApplyOptions pushed;
  pushed.encoding = TiltEncoding::LeanPushforward;
  EXPECT_GT((apply_texture(stretched, tex, pushed) - Y).rowwise().norm().maxCoeff(), 0.1);
  EXPECT_LT((apply_texture(stretched, tex, TextureApplyOptions()) - Y).rowwise().norm().maxCoeff(), 1e-12);
}
