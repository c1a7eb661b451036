// Demo steps for the foundation: shapes, noise, smoothing, metrics.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/core/results.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/results.h"
#include "geotex/tools/shapes.h"
#include "geotex/toolkit/smoothing.h"

namespace geotex::cli {
namespace demo_foundation {  // named, not anonymous: a unity build compiles several commands in one unit

DemoRegistrar shapes{10, "shapes", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  for (const auto& name : shape_names()) {
    const TexturedShape s = make_shape(name, ctx.quick ? 0 : 1);
    const std::string file = (ctx.dir / (name + ".ply")).string();
    save_mesh(s.textured, file);
    const MeshSummary m = summarize(s.textured);
    r["files"].push_back(file);
    const std::string line =
        name + ": " + mesh_summary_results().figures(m, {"vertices", "faces", "genus", "boundary_loops"});
    r["summary"].push_back(line);
    add_figure(ctx, {.mesh = name + ".ply", .caption = "Generated test shape " + line});
  }
}};

DemoRegistrar smoothing{20, "noise and smoothing", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const Mesh clean = subdivided_cube(20);
  Mesh noisy = clean;
  NoiseOptions n;
  n.sigma = 0.3;
  set_positions(noisy, add_noise(clean, n));
  save_mesh(clean, (ctx.dir / "cube-clean.ply").string());
  save_mesh(noisy, (ctx.dir / "cube-noisy.ply").string());
  const Comparison c0 = compare_meshes(noisy, clean);
  // The figures as the report and Python name them (results.h: figures()).
  auto error = [](const Comparison& c) {
    return comparison_results().figures(c, {"mean_normal_error_deg", "ev_relative"});
  };
  r["summary"].push_back("cube, 2400 faces, noise sigma 0.3 mean edge: " + error(c0));
  add_figure(ctx, {.mesh = "cube-clean.ply", .caption = "Clean cube (2400 faces): the truth of this row.", .compare = "smooth"});
  add_figure(ctx, {.mesh = "cube-noisy.ply",
                   .caption = fmt::format("Noise, sigma 0.3 mean edge lengths: {}. Colour: distance to the clean "
                                          "cube (saturates).", error(c0)),
                   .compare = "smooth", .field = "error", .truth = "cube-clean.ply", .sets_range = false});
  for (auto lap : {LaplacianType::Umbrella, LaplacianType::Cotangent}) {
    SmoothingOptions o;
    o.laplacian = lap;
    o.lambda = lap == LaplacianType::Umbrella ? 1.0 : 0.5;
    o.steps = 3;
    Mesh out = noisy;
    set_positions(out, smooth(noisy, o));
    const std::string name = lap == LaplacianType::Umbrella ? "umbrella" : "cotan";
    save_mesh(out, (ctx.dir / ("cube-smoothed-" + name + ".ply")).string());
    const Comparison c = compare_meshes(out, clean);
    r["summary"].push_back(fmt::format("implicit {} smoothing, 3 steps of lambda {}: {}", name, o.lambda, error(c)));
    r[name] = comparison_results().report(c);
    add_figure(ctx, {.mesh = "cube-smoothed-" + name + ".ply",
                     .caption = fmt::format("Implicit {} smoothing (Eq. 5.14), 3 steps of lambda {}: {}; the edges "
                                            "and corners round off.", name, o.lambda, error(c)),
                     .compare = "smooth", .field = "error", .truth = "cube-clean.ply"});
  }
}};

}  // namespace demo_foundation
}  // namespace geotex::cli
