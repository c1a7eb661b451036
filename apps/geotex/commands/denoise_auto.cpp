// `geotex denoise` (--method auto, the default): the pipeline of auto_denoise.h, its parameters derived
// from the input's noise level and from whether it is creased or smooth.

#include <fmt/format.h>

#include "cli.h"
#include "denoise_methods.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/results.h"

namespace geotex::cli {
namespace cmd_denoise_auto {  // named, not anonymous: a unity build compiles several commands in one unit

DenoiseRegistrar reg{
    "auto", "the default: estimates the noise, reads creased or smooth per region, then surfels + fitted positions + labels",
    [](FlagSet& f) { f.add("auto", AutoDenoiseOptions::table(), "auto"); },
    [](const FlagSet& f) -> DenoiseRun {
      const AutoDenoiseOptions o = f.resolve<AutoDenoiseOptions>("auto");
      return [o](const Mesh& mesh, const ProgressFn& progress) {
        AutoDenoiseOptions run = o;
        run.progress = progress;
        const AutoDenoiseResult r = auto_denoise(mesh, run);
        for (const std::string& line : r.choices) info("auto: " + line);
        if (r.turned_over > 0) info(fmt::format("auto: warning: {} faces are left turned over", r.turned_over));
        DenoiseOutput out;
        out.mesh = mesh;
        set_positions(out.mesh, r.positions);
        out.edge_labels = r.edge_labels;
        out.report = auto_denoise_results().report(r);  // the fields Python's result has too
        out.report["parameters"] = options_json(r.resolved);
        return out;
      };
    }};

}  // namespace cmd_denoise_auto
}  // namespace geotex::cli
