// geotex param IN -o OUT.obj: parametrization of a disk-topology mesh (thesis Sec. 5.4).

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/toolkit/parametrization.h"

namespace geotex::cli {
namespace {

struct Args {
  std::string input, output;
  std::string method = "conformal";
  double lambda = 0.5;
  bool json = false;
};

void run(const Args& a) {
  check_output(a.input, a.output);
  const Mesh mesh = load_mesh(a.input);
  ParametrizationOptions opt;
  opt.method = a.method == "authalic"   ? ParamMethod::Authalic
               : a.method == "combined" ? ParamMethod::Combined
               : a.method == "natural"  ? ParamMethod::NaturalConformal
                                        : ParamMethod::Conformal;
  opt.conformal_weight = a.lambda;
  const auto t0 = std::chrono::steady_clock::now();
  const MatrixX2d uv = parametrize(mesh, opt);
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ParamQuality q = parametrization_quality(mesh, uv);
  info(fmt::format("{} parametrization of {} vertices in {:.2f} s: {} flipped face(s), mean angle error {:.2f} deg, "
                   "mean |log area ratio| {:.3f}",
                   a.method, mesh.n_vertices(), sec, q.flipped, q.mean_angle_error_deg, q.mean_log_area_ratio));
  if (a.json) {
    nlohmann::json j{{"method", a.method},         {"vertices", mesh.n_vertices()},
                     {"seconds", sec},             {"flipped", q.flipped},
                     {"mean_angle_error_deg", q.mean_angle_error_deg},
                     {"max_angle_error_deg", q.max_angle_error_deg},
                     {"mean_log_area_ratio", q.mean_log_area_ratio}};
    fmt::print("{}\n", j.dump(2));
  }
  write_obj_with_uv(mesh, uv, a.output);
  info("wrote " + a.output);
}

Registrar reg{60, "param", "Parametrize a disk-topology mesh (Sec. 5.4): writes an OBJ with one UV per vertex",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "input mesh (one connected disk: one boundary loop, genus 0)")
      ->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "output OBJ with vt coordinates")->required();
  app.add_option("--method", a->method,
                 "conformal (cotangent harmonic, Eq. 5.84-5.88), authalic, combined (Desbrun et al. 2002), or "
                 "natural (free-boundary conformal)")
      ->check(CLI::IsMember({"conformal", "authalic", "combined", "natural"}))->capture_default_str();
  app.add_option("--lambda", a->lambda, "combined: weight of the conformal energy in [0, 1]")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str();
  app.add_flag("--json", a->json, "print the distortion measures as JSON on stdout");
  app.callback([a] {
    if (a->output.size() < 4 || a->output.substr(a->output.size() - 4) != ".obj")
      throw InvalidInput("param writes UVs as OBJ: the output must end in .obj");
    run(*a);
  });
}};

}  // namespace
}  // namespace geotex::cli
