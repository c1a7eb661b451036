// Demo step for feature-aware resizing (thesis ch. 9): a plate with round bumps and a ridge, scaled by
// (2, 1, 1), bent and twisted, and the tentacle stick scaled ×2 along its axis and bent into an arc;
// automatic features (feature_map(), "auto"); plain map, the thesis' method (preset "thesis") and the
// default (similarity) method; and spot.obj (shipped, CC0) ×2 along x.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/resize/measure.h"
#include "geotex/resize/resize.h"
#include "geotex/tools/shapes.h"

namespace geotex::cli {
namespace demo_resize {  // named, not anonymous: a unity build compiles several commands in one unit

void save_with_features(const Mesh& mesh, const MatrixX3d& Y, const Eigen::VectorXd& f, const std::filesystem::path& path) {
  Mesh out = mesh;
  set_positions(out, Y);
  PlyExtras fx;
  fx.vertex_scalars["feature"] = std::vector<double>(f.data(), f.data() + f.size());
  write_ply(out, path, fx);
}

// The three results of one deformation: plain space map, thesis preset, the default (similarity).
std::vector<std::pair<std::string, MatrixX3d>> results(const Mesh& mesh, const MatrixX3d& C, const Eigen::VectorXd& f) {
  ResizeOptions thesis;
  ResizeOptions::table().apply_preset(thesis, "thesis");
  return {{"plain", C}, {"thesis", feature_aware_resize(mesh, C, f, thesis)}, {"default", feature_aware_resize(mesh, C, f)}};
}

const char* method_label(const std::string& name) {
  return name == "plain" ? "plain space map" : name == "thesis" ? "preset thesis (Eq. 9.2&ndash;9.3)" : "default (similarity)";
}

DemoRegistrar step{85, "feature-aware resizing", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const BumpyPlate b = ridge_plate(ctx.quick ? 40 : 80);
  const MatrixX3d X = positions(b.mesh);
  const FeatureMap fm = feature_map(b.mesh);
  r["ridge_plate_features"] = fm.summary.describe();
  r["summary"].push_back("ridge plate, automatic " + fm.summary.describe());
  save_with_features(b.mesh, X, fm.weights, ctx.dir / "ridge-plate-features.ply");
  add_figure(ctx, {.mesh = "ridge-plate-features.ply",
                   .caption = "Ridge plate: round bumps and a ridge. Colour: the automatic importance map (1: kept "
                              "similar; 0: stretchable), " + fm.summary.describe() + ".",
                   .compare = "ridge-plate", .field = "feature"});
  const std::pair<SpaceMap, const char*> maps[] = {
      {scale_map({2, 1, 1}), "scale-2-1-1"}, {bend_map(1.5), "bend-1.5"}, {twist_map(1.0), "twist-1"}};
  for (const auto& [map, label] : maps) {
    if (ctx.quick && std::string(label) != "scale-2-1-1") continue;  // --quick: the scaling only
    for (const auto& [name, Y] : results(b.mesh, apply_space_map(map, X), fm.weights)) {
      save_with_features(b.mesh, Y, fm.weights, ctx.dir / fmt::format("ridge-plate-{}-{}.ply", label, name));
      double aspect = 0, height = 0, tilt = 0;
      for (const Vec3& c : b.centres) {
        const BumpShape s0 = measure_bump(X, X, c, b.radius), s = measure_bump(X, Y, c, b.radius);
        aspect = std::max(aspect, std::abs(s.aspect / s0.aspect - 1));
        height = std::max(height, std::abs(s.height / s0.height - 1));
        tilt = std::max(tilt, s.tilt_deg);
      }
      const auto e0 = region_extents(b.mesh, X, b.ridge), e1 = region_extents(b.mesh, Y, b.ridge);
      const double ridge = e0.empty() ? 0.0 : aspect_change(e0[0].extents, e1[0].extents);
      const double crease = rim_crease_deg(b.mesh, Y, fm.weights), crease0 = rim_crease_deg(b.mesh, X, fm.weights);
      r[label][name] = {{"worst_bump_aspect_change", aspect}, {"worst_bump_height_change", height},
                        {"worst_bump_tilt_deg", tilt}, {"ridge_aspect_change", ridge},
                        {"rim_crease_deg", crease}, {"input_rim_crease_deg", crease0}};
      r["summary"].push_back(fmt::format("ridge plate, {}, {}: bumps' aspect change {:.1f}%, height change {:.1f}%, tilt "
                                         "{:.1f} deg; ridge's aspect change {:.1f}%; largest crease at feature rims "
                                         "{:.1f} deg (input {:.1f})",
                                         label, name, 100 * aspect, 100 * height, tilt, 100 * ridge, crease, crease0));
      if (name != "plain" || std::string(label) == "scale-2-1-1")
        add_figure(ctx, {.mesh = fmt::format("ridge-plate-{}-{}.ply", label, name),
                         .caption = fmt::format("Ridge plate {}, <b>{}</b>: bumps' aspect change {:.1f}%, height {:.1f}%, "
                                                "tilt {:.1f}&deg;; ridge's aspect {:.1f}%; crease at feature rims "
                                                "{:.1f}&deg; (input {:.1f}&deg;).",
                                                label, method_label(name), 100 * aspect, 100 * height, tilt, 100 * ridge,
                                                crease, crease0),
                         .compare = "ridge-plate", .field = "feature"});
    }
  }
  // The tentacle stick (coarse level, to keep the demo quick), ×2 along its axis and bent into an arc.
  std::vector<Tentacle> info;
  const TexturedShape stick = tentacle_stick(0, &info);
  const Mesh& m = stick.textured;
  const MatrixX3d S = positions(m);
  const FeatureMap sf = feature_map(m);
  const Eigen::VectorXd truth = tentacle_truth(stick.base, info, TentacleOptions{}.radius);
  double inter = 0, uni = 0;
  for (Eigen::Index i = 0; i < truth.size(); ++i) {
    inter += std::min(truth[i], sf.weights[i]);
    uni += std::max(truth[i], sf.weights[i]);
  }
  r["summary"].push_back(fmt::format("tentacle stick, automatic {}; IoU with the true tentacles {:.3f}",
                                     sf.summary.describe(), inter / uni));
  save_with_features(m, S, sf.weights, ctx.dir / "tentacle-stick-features.ply");
  add_figure(ctx, {.mesh = "tentacle-stick-features.ply",
                   .caption = fmt::format("Tentacle stick: nine curved tentacles on a capsule. Colour: the automatic "
                                          "feature map; IoU with the true tentacles {:.2f}.", inter / uni),
                   .compare = "stick", .field = "feature"});
  SpaceMapOptions so;
  so.scale = Vec3(2, 1, 1);
  so.arc_radius = 6;
  for (const auto& [name, Y] : results(m, apply_space_map(space_map(so, bounding_box(m)), S), sf.weights)) {
    save_with_features(m, Y, sf.weights, ctx.dir / fmt::format("tentacle-stick-arc-{}.ply", name));
    double length = 0, angle = 0;
    for (const Tentacle& t : info) {
      const Eigen::VectorXd foot = tentacle_truth(stick.base, {t}, TentacleOptions{}.radius);
      const ProtrusionPose a = measure_protrusion(m, S, t.foot, foot), c = measure_protrusion(m, Y, t.foot, foot);
      length = std::max(length, std::abs(c.length / a.length - 1));
      angle = std::max(angle, std::abs(c.angle_deg - a.angle_deg));
    }
    r["tentacle-stick-arc"][name] = {{"worst_length_change", length}, {"worst_angle_change_deg", angle}};
    r["summary"].push_back(fmt::format("tentacle stick x2 and arc, {}: worst tentacle length change {:.1f}%, worst "
                                       "change of its angle to the local base {:.1f} deg",
                                       name, 100 * length, angle));
    add_figure(ctx, {.mesh = fmt::format("tentacle-stick-arc-{}.ply", name),
                     .caption = fmt::format("Stick &times;2 along its axis and bent into an arc (radius 6), <b>{}</b>: "
                                            "worst tentacle length change {:.1f}%, worst change of its angle to the "
                                            "base {:.1f}&deg;.",
                                            method_label(name), 100 * length, angle),
                     .compare = "stick", .field = "feature"});
  }
  // A real model (shared data, not with --quick): spot ×2 along x, automatic features; the aspect of
  // each feature region (principal extents of its vertices) before and after.
  if (const auto spot_file = demo_model(ctx, "spot.obj"); !spot_file.empty()) {
    const Mesh spot = read_mesh(spot_file);
    const MatrixX3d P = positions(spot);
    const FeatureMap pf = feature_map(spot);
    save_with_features(spot, P, pf.weights, ctx.dir / "spot-features.ply");
    add_figure(ctx, {.mesh = "spot-features.ply",
                     .caption = fmt::format("spot.obj (K. Crane, CC0): the automatic feature map, {}.", pf.summary.describe()),
                     .compare = "spot", .field = "feature", .up = "auto"});
    SpaceMapOptions sx;
    sx.scale = Vec3(2, 1, 1);
    const auto before = region_extents(spot, P, pf.weights);
    for (const auto& [name, Y] : results(spot, apply_space_map(space_map(sx, bounding_box(spot)), P), pf.weights)) {
      if (name == "thesis") continue;  // the plain map and the default tell the story; bench/resize.md has all
      save_with_features(spot, Y, pf.weights, ctx.dir / fmt::format("spot-x2-{}.ply", name));
      const auto after = region_extents(spot, Y, pf.weights);
      double worst = 0;
      for (size_t k = 0; k < before.size(); ++k)
        if (before[k].vertices.size() >= 20) worst = std::max(worst, aspect_change(before[k].extents, after[k].extents));
      r["spot-x2"][name] = {{"worst_aspect_change", worst}};
      r["summary"].push_back(fmt::format("spot x2 along x, {}: worst feature aspect change {:.1f}%", name, 100 * worst));
      add_figure(ctx, {.mesh = fmt::format("spot-x2-{}.ply", name),
                       .caption = fmt::format("spot &times;2 along x, <b>{}</b>: worst change of a feature's aspect "
                                              "(horns, ears, legs, tail) {:.1f}%.",
                                              method_label(name), 100 * worst),
                       .compare = "spot", .field = "feature", .up = "auto"});
    }
  }
}};

}  // namespace demo_resize
}  // namespace geotex::cli
