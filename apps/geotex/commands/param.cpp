// geotex param IN -o OUT.obj: parametrization of a disk-topology mesh (thesis Sec. 5.4).

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "option_flags.h"
#include "geotex/core/results.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/toolkit/results.h"

namespace geotex::cli {
namespace cmd_param {  // named, not anonymous: a unity build compiles several commands in one unit

void run(const MeshIo& io, bool json, const ParametrizationOptions& o) {
  Outputs out({io.input}, {{io.output, "-o"}});
  const Mesh mesh = load_mesh(io.input);
  const std::string method = enum_name(param_method_names(), o.method);
  const auto t0 = std::chrono::steady_clock::now();
  const MatrixX2d uv = parametrize(mesh, o);
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ParamQuality q = parametrization_quality(mesh, uv);
  info(fmt::format("{} parametrization of {} vertices in {:.2f} s: {} flipped face(s), mean angle error {:.2f} deg, "
                   "mean |log area ratio| {:.3f}",
                   method, mesh.n_vertices(), sec, q.flipped, q.mean_angle_error_deg, q.mean_log_area_ratio));
  if (json) {
    // The quality's fields, as Python's parametrization_quality() has them; the method and size are the CLI's.
    nlohmann::json j = param_quality_results().report(q);
    j.update(run_time_results().report({sec}));
    j["method"] = method;
    j["vertices"] = mesh.n_vertices();
    fmt::print("{}\n", j.dump(2));
  }
  write_obj_with_uv(mesh, uv, io.output);
  out.commit();
  info("wrote " + io.output);
}

Registrar reg{60, "param", "Parametrize a disk-topology mesh (Sec. 5.4): writes an OBJ with one UV per vertex",
              [](CLI::App& app) {
  auto io = std::make_shared<MeshIo>(app, "output OBJ with vt coordinates (one connected disk in: one boundary loop, genus 0)");
  auto json = std::make_shared<bool>(false);
  app.add_flag("--json", *json, "print the distortion measures as JSON on stdout");
  auto flags = std::make_shared<FlagSet>(app);
  flags->add("param", ParametrizationOptions::table());
  app.callback([io, json, flags] {
    const ParametrizationOptions o = flags->resolve<ParametrizationOptions>("param");
    if (io->output.size() < 4 || io->output.substr(io->output.size() - 4) != ".obj")
      throw InvalidInput("param writes UVs as OBJ: the output must end in .obj");
    run(*io, *json, o);
  });
}};

}  // namespace cmd_param
}  // namespace geotex::cli
