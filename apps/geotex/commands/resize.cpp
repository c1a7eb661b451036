// geotex resize IN -o OUT [--scale 2,1,1] [--twist T] [--bend K] [--arc-radius R] | --deformed MESH
//   [--features importance|auto|height|adf|none|FILE] [--save-features PLY] [--report JSON] [--preset thesis]:
// feature-aware resizing and deformation (thesis ch. 9). One flag per field of ResizeRunOptions
// (resize.h: the space map, the feature map, the feature file, the solver), made from its table; the
// run itself is the library's resize_mesh(), as in Python's geotex.resize().
//
// Feature files (--features FILE): a text file with one weight in [0, 1] per vertex and line (binary or
// continuous, e.g. painted in a DCC tool; --save-features writes the continuous importance map); or a PLY
// with a vertex property "feature" (weights) or "height" (a texture height, e.g. from `geotex texture
// extract`; features where |height| > --height-threshold mean edge lengths, grown by --height-dilate).

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/user_files.h"
#include "geotex/resize/resize.h"
#include "geotex/resize/results.h"
#include "option_flags.h"

namespace geotex::cli {
namespace cmd_resize {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::string deformed, feature_file, save_features, report;
};

// --features names a map (a choice of the table) or a feature file. A file is taken off the flag here,
// so that the table sees only map names.
std::string take_feature_file(CLI::App& app) {
  CLI::Option* opt = app.get_option("--features");
  if (opt->count() == 0) return {};
  const std::string value = opt->as<std::string>();
  for (const auto& [name, method] : feature_map_names())
    if (value == name) return {};
  std::error_code ec;
  if (!std::filesystem::exists(value, ec)) {
    std::string names;
    for (const auto& [name, method] : feature_map_names()) names += (names.empty() ? "" : ", ") + std::string(name);
    throw InvalidOption(fmt::format("--features: '{}' is neither a map ({}) nor a feature file", value, names));
  }
  opt->clear();
  return value;
}

// The weights as --features reads them back: a PLY of the input with vertex property "feature", or text.
void write_features(const Mesh& input, const Eigen::VectorXd& f, const std::string& path, bool binary) {
  if (std::filesystem::path(path).extension() == ".ply") {
    PlyExtras extras;
    extras.vertex_scalars["feature"] = std::vector<double>(f.data(), f.data() + f.size());
    write_ply(input, path, extras, binary);
  } else {
    std::string text;
    for (Eigen::Index i = 0; i < f.size(); ++i) text += fmt::format("{}\n", f[i]);
    write_text_atomic(path, text);
  }
  info(fmt::format("wrote {} (feature weights of {} vertices)", path, f.size()));
}

void run(const MeshIo& io, const Args& a, ResizeRunOptions o) {
  Outputs out({io.input, a.deformed, a.feature_file},
              {{io.output, "-o"}, {a.save_features, "--save-features"}, {a.report, "--report"}});
  Mesh mesh = load_mesh(io.input);
  MatrixX3d deformed;
  if (!a.deformed.empty()) {
    const Mesh d = load_mesh(a.deformed);
    if (d.n_vertices() != mesh.n_vertices() || d.n_faces() != mesh.n_faces())
      throw InvalidInput(fmt::format("{}: the deformed mesh must have the input's {} vertices and {} faces", a.deformed,
                                     mesh.n_vertices(), mesh.n_faces()));
    deformed = positions(d);
  }
  Eigen::VectorXd given;
  if (!a.feature_file.empty()) given = read_feature_file(a.feature_file, mesh, o.feature_file);
  o.progress = progress_printer("resize");
  const auto t0 = std::chrono::steady_clock::now();
  const ResizeResult r =
      resize_mesh(mesh, o, a.deformed.empty() ? nullptr : &deformed, a.feature_file.empty() ? nullptr : &given);
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string source = a.feature_file.empty() ? enum_name(feature_map_names(), r.detector) : a.feature_file;
  info(fmt::format("{} (from {})", r.summary.describe(), source));
  if (!r.summary.warning.empty()) info("geotex: warning: " + r.summary.warning);
  const std::string method(enum_name(resize_method_names(), r.method));  // for auto, the one chosen
  info(fmt::format("resized {} vertices ({}{}) in {:.2f} s", mesh.n_vertices(), method,
                   o.resize.method == ResizeMethod::Auto ? ", auto" : "", sec));
  info("self-intersections: " + r.untangle.describe());
  if (r.welded_vertices > 0 || r.weld_refused_groups > 0)
    info(fmt::format("welded {} coincident vertices for the solve ({} groups left apart or welded per fan); written "
                     "unwelded, as read",
                     r.welded_vertices, r.weld_refused_groups));
  if (!a.save_features.empty()) write_features(mesh, r.features, a.save_features, !io.ascii);
  set_positions(mesh, r.V);
  save_mesh(mesh, io.output, !io.ascii);
  if (!a.report.empty()) {
    nlohmann::json j = resize_results().report(r);
    j.update({{"input", io.input}, {"deformed", a.deformed}, {"feature_file", a.feature_file}});  // the CLI's own
    write_report(a.report, std::move(j), sec, options_json(o));
  }
  out.commit();
}

Registrar reg{80, "resize", "Feature-aware resizing and deformation (ch. 9): features keep their shape and size",
              [](CLI::App& app) {
  auto io = std::make_shared<MeshIo>(app);
  auto a = std::make_shared<Args>();
  app.add_option("--deformed", a->deformed, "a deformed copy of IN (same connectivity), e.g. from geotex deform, "
                 "instead of a space map")->check(ExistingMeshFile);
  app.add_option("--save-features", a->save_features,
                 "write the feature weights used: PLY (the input with vertex property 'feature') or text (one "
                 "weight per line); --features reads either back");
  app.add_option("--report", a->report, "write a JSON report (method, marked fraction, detector, parameters, time)");
  auto flags = std::make_shared<FlagSet>(app);
  flags->add("resize", ResizeRunOptions::table());
  app.get_option("--features")->description(app.get_option("--features")->get_description() +
                                            "; or a feature file: text (one weight per line) or PLY with vertex "
                                            "'feature' or 'height'");
  app.callback([&app, io, a, flags] {
    a->feature_file = take_feature_file(app);
    const ResizeRunOptions o = flags->resolve<ResizeRunOptions>("resize");  // refused before any work
    run(*io, *a, o);
  });
}};

}  // namespace cmd_resize
}  // namespace geotex::cli
