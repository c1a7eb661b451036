// Demo step for feature-aware resizing (thesis ch. 9): a plate with round bumps and a ridge, scaled by
// (2, 1, 1), bent and twisted, and the tentacle stick scaled ×2 along its axis and bent into an arc;
// automatic features (feature_map(), "auto"); plain map, the thesis' method (preset "thesis") and the
// default (auto) method; and spot.obj (shipped, CC0) ×2 along x.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/results.h"
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

// What the demo measures of a resize, declared once (core/results.h) for its report and its captions.
struct Measures {
  double bump_aspect = 0, bump_height = 0, bump_tilt = 0, ridge_aspect = 0, crease = 0, input_crease = 0;  // plate
  double length = 0, angle = 0;  // tentacle stick: the worst tentacle's
  double aspect = 0;             // spot: the worst feature region's
};

const ResultTable<Measures>& measures() {
  using R = Measures;
  static const auto t = ResultTable<R>()
      .add("worst_bump_aspect_change", [](const R& r) { return 100 * r.bump_aspect; }, "of a bump's aspect", "%")
      .add("worst_bump_height_change", [](const R& r) { return 100 * r.bump_height; }, "of a bump's height", "%")
      .add("worst_bump_tilt_deg", [](const R& r) { return r.bump_tilt; }, "a bump's tilt", "deg")
      .add("ridge_aspect_change", [](const R& r) { return 100 * r.ridge_aspect; }, "of the ridge's aspect", "%")
      .add("rim_crease_deg", [](const R& r) { return r.crease; }, "largest crease at feature rims", "deg")
      .add("input_rim_crease_deg", [](const R& r) { return r.input_crease; }, "the same in the input", "deg")
      .add("worst_length_change", [](const R& r) { return 100 * r.length; }, "of a tentacle's length", "%")
      .add("worst_angle_change_deg", [](const R& r) { return r.angle; }, "of a tentacle's angle to the base", "deg")
      .add("worst_aspect_change", [](const R& r) { return 100 * r.aspect; }, "of a feature region's aspect", "%");
  return t;
}

// The report's record of \p names of \p m (the same names as the captions').
nlohmann::json record(const Measures& m, std::initializer_list<std::string_view> names) {
  const nlohmann::json all = measures().report(m);
  nlohmann::json j = nlohmann::json::object();
  for (std::string_view n : names) j[std::string(n)] = all.at(std::string(n));
  return j;
}

// The three results of one deformation: plain space map, thesis preset, the default (auto: axis-similarity
// for a box scale, similarity otherwise).
std::vector<std::pair<std::string, MatrixX3d>> results(const Mesh& mesh, const MatrixX3d& C, const Eigen::VectorXd& f) {
  ResizeOptions thesis;
  ResizeOptions::table().apply_preset(thesis, "thesis");
  return {{"plain", C}, {"thesis", feature_aware_resize(mesh, C, f, thesis)}, {"default", feature_aware_resize(mesh, C, f)}};
}

const char* method_label(const std::string& name) {
  return name == "plain"    ? "plain space map"
         : name == "thesis" ? "preset thesis (Eq. 9.2&ndash;9.3)"
                            : "default (auto: axis-similarity on a box scale, else similarity)";
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
      Measures q;
      for (const Vec3& c : b.centres) {
        const BumpShape s0 = measure_bump(X, X, c, b.radius), s = measure_bump(X, Y, c, b.radius);
        q.bump_aspect = std::max(q.bump_aspect, std::abs(s.aspect / s0.aspect - 1));
        q.bump_height = std::max(q.bump_height, std::abs(s.height / s0.height - 1));
        q.bump_tilt = std::max(q.bump_tilt, s.tilt_deg);
      }
      const auto e0 = region_extents(b.mesh, X, b.ridge), e1 = region_extents(b.mesh, Y, b.ridge);
      q.ridge_aspect = e0.empty() ? 0.0 : aspect_change(e0[0].extents, e1[0].extents);
      q.crease = rim_crease_deg(b.mesh, Y, fm.weights);
      q.input_crease = rim_crease_deg(b.mesh, X, fm.weights);
      const std::initializer_list<std::string_view> names = {
          "worst_bump_aspect_change", "worst_bump_height_change", "worst_bump_tilt_deg", "ridge_aspect_change",
          "rim_crease_deg", "input_rim_crease_deg"};
      r[label][name] = record(q, names);
      const std::string figures = measures().figures(q, names);
      r["summary"].push_back(fmt::format("ridge plate, {}, {}: {}", label, name, figures));
      if (name != "plain" || std::string(label) == "scale-2-1-1")
        add_figure(ctx, {.mesh = fmt::format("ridge-plate-{}-{}.ply", label, name),
                         .caption = fmt::format("Ridge plate {}, <b>{}</b>: {}.", label, method_label(name), figures),
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
    Measures q;
    for (const Tentacle& t : info) {
      const Eigen::VectorXd foot = tentacle_truth(stick.base, {t}, TentacleOptions{}.radius);
      const ProtrusionPose a = measure_protrusion(m, S, t.foot, foot), c = measure_protrusion(m, Y, t.foot, foot);
      q.length = std::max(q.length, std::abs(c.length / a.length - 1));
      q.angle = std::max(q.angle, std::abs(c.angle_deg - a.angle_deg));
    }
    const std::initializer_list<std::string_view> names = {"worst_length_change", "worst_angle_change_deg"};
    r["tentacle-stick-arc"][name] = record(q, names);
    const std::string figures = measures().figures(q, names);
    r["summary"].push_back(fmt::format("tentacle stick x2 and arc, {}: {}", name, figures));
    add_figure(ctx, {.mesh = fmt::format("tentacle-stick-arc-{}.ply", name),
                     .caption = fmt::format("Stick &times;2 along its axis and bent into an arc (radius 6), <b>{}</b>: "
                                            "{}.", method_label(name), figures),
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
      Measures q;
      for (size_t k = 0; k < before.size(); ++k)
        if (before[k].vertices.size() >= 20) q.aspect = std::max(q.aspect, aspect_change(before[k].extents, after[k].extents));
      r["spot-x2"][name] = record(q, {"worst_aspect_change"});
      const std::string figures = measures().figures(q, {"worst_aspect_change"});
      r["summary"].push_back(fmt::format("spot x2 along x, {}: {}", name, figures));
      add_figure(ctx, {.mesh = fmt::format("spot-x2-{}.ply", name),
                       .caption = fmt::format("spot &times;2 along x, <b>{}</b>: {} (horns, ears, legs, tail).",
                                              method_label(name), figures),
                       .compare = "spot", .field = "feature", .up = "auto"});
    }
  }
}};

}  // namespace demo_resize
}  // namespace geotex::cli
