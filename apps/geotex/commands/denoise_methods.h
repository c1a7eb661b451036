#pragma once
// The `geotex denoise` subcommand dispatches to methods that register themselves from their own
// files (denoise_mrf.cpp, denoise_surfel.cpp, …):
//
//   DenoiseRegistrar r{"mrf", "help line", add_options, run};
//
// add_options adds the method's own flags to the shared subcommand (names must not collide with
// the shared ones below or with another method's); run denoises and returns the result.

#include <functional>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "geotex/core/mesh.h"
#include "geotex/core/progress.h"

namespace geotex::cli {

// Flags shared by every method (parsed by cmd_denoise.cpp).
struct DenoiseCommon {
  std::optional<double> alpha;     // --alpha: data weight (each method has its thesis default)
  std::optional<int> iterations;   // --iterations
  uint64_t seed = 1;               // --seed
  ProgressFn progress;             // progress lines on stderr
};

struct DenoiseResult {
  Mesh mesh;                       // the denoised mesh (any connectivity)
  Eigen::VectorXd edge_labels;     // per edge of `mesh` in [0, 1] (empty when the method has none)
  nlohmann::json report;           // energies per iteration, parameters, timings…
};

struct DenoiseMethod {
  std::string name, help;
  std::function<void(CLI::App&)> add_options;
  std::function<DenoiseResult(const Mesh&, const DenoiseCommon&)> run;
};
std::vector<DenoiseMethod>& denoise_methods();
struct DenoiseRegistrar {
  DenoiseRegistrar(std::string name, std::string help, std::function<void(CLI::App&)> add_options,
                   std::function<DenoiseResult(const Mesh&, const DenoiseCommon&)> run) {
    denoise_methods().push_back({std::move(name), std::move(help), std::move(add_options), std::move(run)});
  }
};

}  // namespace geotex::cli
