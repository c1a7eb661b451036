// `geotex denoise --method surfel`: surfel-based reconstruction of piecewise-smooth surfaces (thesis ch. 7).

#include <fmt/format.h>

#include "cli.h"
#include "denoise_methods.h"
#include "geotex/denoise/results.h"
#include "geotex/denoise/surfel.h"

namespace geotex::cli {
namespace cmd_denoise_surfel {  // named, not anonymous: a unity build compiles several commands in one unit

auto polygons_path = std::make_shared<std::string>();

DenoiseRegistrar reg{
    "surfel", "surfels (thesis ch. 7): ICM on planes per vertex, then the surface retrieved from the planes",
    [](FlagSet& f) {
      f.add("surfel", SurfelDenoiseOptions::table(), "surfel");
      f.app().add_option("--polygons", *polygons_path, "surfel, dual retrieval: also write the dual polygon mesh as OBJ")
          ->check(OutputWithExtension(".obj", "--polygons writes OBJ polygons: name it .obj"))
          ->group("surfel");
    },
    [](const FlagSet& f) -> DenoiseRun {
      const SurfelDenoiseOptions o = f.resolve<SurfelDenoiseOptions>("surfel");
      if (!polygons_path->empty() && o.retrieval != SurfelRetrieval::Dual)
        throw InvalidOption("--polygons needs --retrieval dual");
      return [o](const Mesh& mesh, const ProgressFn& progress) {
        SurfelDenoiseOptions run = o;
        run.progress = progress;
        const SurfelDenoiseResult r = surfel_denoise(mesh, run);
        info(fmt::format("surfel: median angle between neighbouring surfels {:.1f} deg: t from {:.1f} to {:.1f} deg",
                         r.median_angle_deg, r.t_start_deg, o.t_end_deg));
        if (!polygons_path->empty()) {
          write_polygon_obj(r.polygons, *polygons_path);
          info(fmt::format("wrote {} ({} polygons)", *polygons_path, r.polygons.faces.size()));
        }
        DenoiseOutput out;
        out.mesh = r.mesh;
        out.edge_labels = r.edge_labels;
        SurfelDenoiseOptions used = o;
        used.t_start_deg = r.t_start_deg;
        out.report = surfel_denoise_results().report(r);  // the fields Python's result has too
        out.report["parameters"] = options_json(used);
        return out;
      };
    },
    [] { return std::vector<std::pair<std::string, std::string>>{{*polygons_path, "--polygons"}}; }};

}  // namespace cmd_denoise_surfel
}  // namespace geotex::cli
