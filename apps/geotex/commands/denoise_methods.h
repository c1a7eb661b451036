#pragma once
// The `geotex denoise` subcommand dispatches to methods that register themselves from their own
// files (denoise_mrf.cpp, denoise_surfel.cpp, …):
//
//   DenoiseRegistrar r{"mrf", "help line", add_flags, prepare};
//
// add_flags adds the method's option tables to the shared FlagSet under the method's name (a flag of
// another method is refused); prepare resolves the options from the flags — before the input is read,
// so that a bad flag costs nothing — and returns the run.

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "geotex/core/mesh.h"
#include "geotex/core/progress.h"
#include "option_flags.h"

namespace geotex::cli {

struct DenoiseOutput {
  Mesh mesh;                       // the denoised mesh (any connectivity)
  Eigen::VectorXd edge_labels;     // per edge of `mesh` in [0, 1] (empty when the method has none)
  nlohmann::json report;           // parameters used, energies per iteration, timings…
};

using DenoiseRun = std::function<DenoiseOutput(const Mesh&, const ProgressFn&)>;

struct DenoiseMethod {
  std::string name, help;
  std::function<void(FlagSet&)> add_flags;
  std::function<DenoiseRun(const FlagSet&)> prepare;
  //! Files the method itself writes, as (path, flag); declared with the command's outputs.
  std::function<std::vector<std::pair<std::string, std::string>>()> outputs;
};
std::vector<DenoiseMethod>& denoise_methods();
struct DenoiseRegistrar {
  DenoiseRegistrar(std::string name, std::string help, std::function<void(FlagSet&)> add_flags,
                   std::function<DenoiseRun(const FlagSet&)> prepare,
                   std::function<std::vector<std::pair<std::string, std::string>>()> outputs = nullptr) {
    denoise_methods().push_back(
        {std::move(name), std::move(help), std::move(add_flags), std::move(prepare), std::move(outputs)});
  }
};

}  // namespace geotex::cli
