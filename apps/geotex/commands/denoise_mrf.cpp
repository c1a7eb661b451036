// `geotex denoise --method mrf|mrf-normal`: MRF denoising with explicit sharp-edge labelling (thesis ch. 6).

#include <fmt/format.h>

#include "cli.h"
#include "denoise_methods.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/results.h"

namespace geotex::cli {
namespace cmd_denoise_mrf {  // named, not anonymous: a unity build compiles several commands in one unit

template <class O>
DenoiseOutput to_output(const Mesh& input, const MrfResult& r, const O& o) {
  DenoiseOutput out;
  out.mesh = input;
  set_positions(out.mesh, r.positions);
  out.edge_labels = r.edge_labels;
  out.report = mrf_results().report(r);  // the fields Python's result has too
  out.report["parameters"] = options_json(o);
  info(fmt::format("{} outer iterations{}, {} edges labelled sharp", r.iterations, r.converged ? " (converged)" : "",
                   out.report["labelled_edges"].get<int>()));
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
