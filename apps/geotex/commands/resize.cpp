// geotex resize IN -o OUT --scale 2,1,1 | --bend K | --twist T | --deformed MESH [--features auto|adf|none|FILE]:
// feature-aware resizing and deformation (thesis ch. 9).
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
  std::string input, output, deformed, features = "auto", method = "sliding";
  std::vector<double> scale;
  double bend = 0, twist = 0;
  double weight = 1.0, smoothness = 0.002, height_threshold = 0.5, adf_t = 0.1, adf_threshold = 0.5;
  int dilate = 2, refinements = 1;
  bool scale_features = false, ascii = false;
};

Eigen::VectorXd read_features(const Args& a, const Mesh& mesh) {
  const size_t n = mesh.n_vertices();
  if (a.features == "auto") return features_from_height(mesh, {.height_threshold = a.height_threshold, .dilate = a.dilate});
  if (a.features == "adf") return features_from_adf(mesh, a.adf_t, 100, a.adf_threshold, a.dilate);
  if (a.features == "none") return Eigen::VectorXd::Zero(n);
  if (!std::filesystem::exists(a.features))
    throw IoError(fmt::format("{}: no such feature file (use auto, adf, none or a file)", a.features));
  return read_feature_file(a.features, mesh, {.height_threshold = a.height_threshold, .dilate = a.dilate});
}

void run(const Args& a) {
  check_output(a.input, a.output);
  const int maps = !a.scale.empty() + (a.bend != 0) + (a.twist != 0) + !a.deformed.empty();
  if (maps != 1) throw InvalidInput("give exactly one deformation: --scale, --bend, --twist or --deformed");
  Mesh mesh = load_mesh(a.input);
  const BoundingBox box = bounding_box(mesh);
  MatrixX3d C;
  if (!a.deformed.empty()) {
    const Mesh d = load_mesh(a.deformed);
    if (d.n_vertices() != mesh.n_vertices() || d.n_faces() != mesh.n_faces())
      throw InvalidInput(fmt::format("{}: the deformed mesh must have the input's {} vertices and {} faces", a.deformed,
                                     mesh.n_vertices(), mesh.n_faces()));
    C = positions(d);
  } else {
    SpaceMap map;
    if (!a.scale.empty()) {
      if (a.scale.size() != 3) throw InvalidInput("--scale needs three factors, e.g. 2,1,1");
      for (double s : a.scale)
        if (!(s > 0)) throw InvalidInput("--scale factors must be positive");
      map = scale_map({a.scale[0], a.scale[1], a.scale[2]}, box.center());
    } else if (a.bend != 0) {
      map = bend_map(a.bend, box.center().x());
    } else {
      map = twist_map(a.twist, box.center().x());
    }
    const MatrixX3d X = positions(mesh);
    C.resize(X.rows(), 3);
    for (Eigen::Index i = 0; i < X.rows(); ++i) C.row(i) = map(X.row(i).transpose()).transpose();
  }
  const Eigen::VectorXd f = read_features(a, mesh);
  info(fmt::format("features: {} of {} vertices (weight > 0.5)", (f.array() > 0.5).count(), f.size()));
  ResizeOptions o;
  o.method = a.method == "thesis" ? ResizeMethod::Thesis : ResizeMethod::Sliding;
  o.position_weight = a.weight;
  o.background_smoothness = a.smoothness;
  o.keep_feature_size = !a.scale_features;
  o.refinements = a.refinements;
  o.progress = progress_printer("resize");
  const auto t0 = std::chrono::steady_clock::now();
  set_positions(mesh, feature_aware_resize(mesh, C, f, o));
  info(fmt::format("resized {} vertices ({}) in {:.2f} s", mesh.n_vertices(), a.method,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
  save_mesh(mesh, a.output, !a.ascii);
}

Registrar reg{80, "resize", "Feature-aware resizing and deformation (ch. 9): features keep their shape and size",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "input mesh")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "output mesh")->required();
  app.add_option("--scale", a->scale, "anisotropic scale sx,sy,sz about the bounding-box centre")->delimiter(',');
  app.add_option("--bend", a->bend, "bend along x: z += K (x - x_centre)^2 / 2");
  app.add_option("--twist", a->twist, "twist about the x axis through the box centre, radians per unit length");
  app.add_option("--deformed", a->deformed, "a deformed copy of IN (same connectivity), e.g. from geotex deform")
      ->check(ExistingMeshFile);
  app.add_option("--features", a->features,
                 "auto (height over a smoothed base), adf (auto diffusion function threshold), none, or a file: "
                 "text (one weight per line) or PLY with vertex 'feature' or 'height'")
      ->capture_default_str();
  app.add_option("--method", a->method, "sliding (background slides along the surface) or thesis (Eq. 9.2-9.3)")
      ->check(CLI::IsMember({"sliding", "thesis"}))->capture_default_str();
  app.add_option("--weight", a->weight, "w of Eq. (9.2): weight of the position terms")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--smoothness", a->smoothness, "sliding: weight of the background's Laplacian term")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--refinements", a->refinements, "sliding: extra re-projections onto the deformed surface")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--height-threshold", a->height_threshold, "auto/height features: |height| threshold in mean edge lengths")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--adf-t", a->adf_t, "adf features: diffusion time in units of 1/lambda_1")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--adf-threshold", a->adf_threshold, "adf features: threshold on the ADF normalised to [0, 1]")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_option("--dilate", a->dilate, "grow thresholded features by this many vertex rings")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_flag("--scale-features", a->scale_features, "let features scale with the map (T_i similarities) instead of keeping their size");
  app.add_flag("--ascii", a->ascii, "ascii PLY/STL output");
  app.callback([a] { run(*a); });
}};

}  // namespace
}  // namespace geotex::cli
