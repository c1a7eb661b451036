// `geotex denoise --method mrf|mrf-normal`: MRF denoising with explicit sharp-edge labelling (thesis ch. 6).

#include <fmt/format.h>

#include "cli.h"
#include "denoise_methods.h"
#include "geotex/denoise/mrf.h"

namespace geotex::cli {
namespace cmd_denoise_mrf {  // named, not anonymous: a unity build compiles several commands in one unit

template <class O>
DenoiseOutput to_output(const Mesh& input, const MrfResult& r, const O& o) {
  DenoiseOutput out;
  out.mesh = input;
  set_positions(out.mesh, r.positions);
  out.edge_labels = r.edge_labels;
  nlohmann::json& j = out.report;
  j["parameters"] = options_json(o);
  j["iterations"] = r.iterations;
  j["converged"] = r.converged;
  j["energy_per_iteration"] = {{"vertex_or_normal_process", r.vertex_energy}, {"edge_process", r.edge_energy}};
  j["labelled_per_iteration"] = r.labelled;
  j["seconds_per_iteration"] = r.seconds;
  j["seconds_optimizing"] = r.seconds.empty() ? 0.0 : r.seconds.back();
  int labelled = 0;
  for (Eigen::Index e = 0; e < r.edge_labels.size(); ++e) labelled += r.edge_labels[e] > 0.5;
  j["labelled_edges"] = labelled;
  info(fmt::format("{} outer iterations{}, {} edges labelled sharp", r.iterations, r.converged ? " (converged)" : "",
                   labelled));
  return out;
}

DenoiseRegistrar mrf{"mrf", "MRF vertex process + edge labelling (thesis ch. 6)",
                     [](FlagSet& f) { f.add("mrf", MrfOptions::table(), "mrf, mrf-normal"); },
                     [](const FlagSet& f) -> DenoiseRun {
                       const MrfOptions o = f.resolve<MrfOptions>("mrf");
                       return [o](const Mesh& mesh, const ProgressFn& progress) {
                         MrfOptions run = o;
                         run.progress = progress;
                         return to_output(mesh, mrf_denoise(mesh, run), o);
                       };
                     }};

DenoiseRegistrar mrf_normal{
    "mrf-normal", "MRF on face normals + edge labelling, then vertices fitted to the normals (Sec. 6.5)",
    [](FlagSet& f) { f.add("mrf-normal", MrfNormalOptions::table(), "mrf, mrf-normal"); },
    [](const FlagSet& f) -> DenoiseRun {
      const MrfNormalOptions o = f.resolve<MrfNormalOptions>("mrf-normal");
      return [o](const Mesh& mesh, const ProgressFn& progress) {
        MrfNormalOptions run = o;
        run.progress = progress;
        return to_output(mesh, mrf_normal_denoise(mesh, run), o);
      };
    }};

}  // namespace cmd_denoise_mrf
}  // namespace geotex::cli
