// geotex resize IN -o OUT [--scale 2,1,1] [--twist T] [--bend K] [--arc-radius R] | --deformed MESH
//   [--features auto|height|adf|none|FILE] [--preset thesis]: feature-aware resizing and deformation
// (thesis ch. 9). The options live in SpaceMapOptions, FeatureMapOptions and ResizeOptions (resize.h);
// the flags here translate to them.
//
// Feature files: a text file with one weight in [0, 1] per vertex and line; or a PLY with a vertex
// property "feature" (weights) or "height" (a texture height, e.g. from `geotex texture extract`;
// features where |height| > --height-threshold mean edge lengths).

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/resize/resize.h"
#include "geotex/core/user_files.h"

namespace geotex::cli {
namespace {

struct Args {
  std::string input, output, deformed, features = "auto", method = "sliding", preset;
  std::vector<double> scale;
  SpaceMapOptions map;
  FeatureMapOptions feature_map;
  double weight = 1.0, smoothness = 0.002, height_threshold = 0.5;
  int dilate = 2, refinements = 1;
  bool scale_features = false, ascii = false;
};

// Named maps go to feature_map() (the one definition of "auto"); anything else is a feature file.
Eigen::VectorXd read_features(const Args& a, const Mesh& mesh) {
  for (const auto& [name, method] : feature_map_names())
    if (a.features == name) {
      FeatureMapOptions o = a.feature_map;
      o.method = method;
      return feature_map(mesh, o).weights;
    }
  if (!std::filesystem::exists(a.features))
    throw IoError(fmt::format("{}: no such feature file (use auto, height, adf, none or a file)", a.features));
  return read_feature_file(a.features, mesh, {.height_threshold = a.height_threshold, .dilate = a.dilate});
}

void run(Args a) {
  check_output(a.input, a.output);
  if (!a.scale.empty()) {
    if (a.scale.size() != 3) throw InvalidInput("--scale needs three factors, e.g. 2,1,1");
    a.map.scale = Vec3(a.scale[0], a.scale[1], a.scale[2]);
  }
  if (a.map.identity() == a.deformed.empty())
    throw InvalidInput("give a deformation: --scale, --bend, --twist, --arc-radius (any together), or --deformed");
  Mesh mesh = load_mesh(a.input);
  MatrixX3d C;
  if (!a.deformed.empty()) {
    const Mesh d = load_mesh(a.deformed);
    if (d.n_vertices() != mesh.n_vertices() || d.n_faces() != mesh.n_faces())
      throw InvalidInput(fmt::format("{}: the deformed mesh must have the input's {} vertices and {} faces", a.deformed,
                                     mesh.n_vertices(), mesh.n_faces()));
    C = positions(d);
  } else {
    C = apply_space_map(space_map(a.map, bounding_box(mesh)), positions(mesh));
  }
  const Eigen::VectorXd f = read_features(a, mesh);
  const FeatureSummary summary = summarize_features(mesh, f);
  info(summary.describe());
  if (!summary.warning.empty()) info("geotex: warning: " + summary.warning);
  ResizeOptions o;
  if (!a.preset.empty()) ResizeOptions::table().apply_preset(o, a.preset);
  else o.method = parse_enum(resize_method_names(), a.method, "--method");
  o.position_weight = a.weight;
  o.background_smoothness = a.smoothness;
  if (a.preset.empty()) o.keep_feature_size = !a.scale_features;
  o.refinements = a.refinements;
  o.progress = progress_printer("resize");
  const auto t0 = std::chrono::steady_clock::now();
  set_positions(mesh, feature_aware_resize(mesh, C, f, o));
  info(fmt::format("resized {} vertices ({}) in {:.2f} s", mesh.n_vertices(), enum_name(resize_method_names(), o.method),
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
  save_mesh(mesh, a.output, !a.ascii);
}

Registrar reg{80, "resize", "Feature-aware resizing and deformation (ch. 9): features keep their shape and size",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "input mesh")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "output mesh")->required();
  app.add_option("--scale", a->scale, "anisotropic scale sx,sy,sz about the bounding-box centre")->delimiter(',');
  app.add_option("--bend", a->map.bend, "bend along x: z += K (x - x_centre)^2 / 2");
  app.add_option("--twist", a->map.twist, "twist about the x axis through the box centre, radians per unit length");
  app.add_option("--arc-radius", a->map.arc_radius, "bend the x axis into an arc of this radius (after --scale)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--deformed", a->deformed, "a deformed copy of IN (same connectivity), e.g. from geotex deform")
      ->check(ExistingMeshFile);
  app.add_option("--features", a->features,
                 "auto (adf, or height where the ADF finds no protrusion), height (over a smoothed base), adf (auto "
                 "diffusion function), none, or a file: text (one weight per line) or PLY with vertex 'feature' or 'height'")
      ->capture_default_str();
  app.add_option("--method", a->method, "sliding (background slides along the surface) or thesis (Eq. 9.2-9.3)")
      ->check(CLI::IsMember({"sliding", "thesis"}))->capture_default_str();
  app.add_option("--preset", a->preset, "thesis: the thesis' method as written (Eq. 9.2 with 9.3's squared weights, "
                 "T_i similarities); overrides --method")->check(CLI::IsMember({"thesis"}));
  app.add_option("--weight", a->weight, "w of Eq. (9.2): weight of the position terms")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--smoothness", a->smoothness, "sliding: weight of the background's Laplacian term")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--refinements", a->refinements, "sliding: extra re-projections onto the deformed surface")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--height-threshold", a->height_threshold, "feature PLY with 'height': |height| threshold in mean edge lengths")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--dilate", a->dilate, "feature PLY with 'height': grow thresholded features by this many vertex rings")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--adf-t", a->feature_map.adf_t, "adf/auto features: diffusion time in units of 1/lambda_1")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--significance", a->feature_map.significance,
                 "auto/height/adf features: a peak is a feature when it exceeds the median by this many robust deviations")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_flag("--scale-features", a->scale_features, "let features scale with the map (T_i similarities) instead of keeping their size");
  app.add_flag("--ascii", a->ascii, "ascii PLY/STL output");
  app.callback([a] { run(*a); });
}};

}  // namespace
}  // namespace geotex::cli
