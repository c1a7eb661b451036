// geotex smooth IN -o OUT: explicit or implicit Laplacian smoothing (thesis Sec. 5.1.3).

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/toolkit/smoothing.h"

namespace geotex::cli {
namespace {

struct Args {
  std::string input, output;
  std::string laplacian = "cotan", mass = "voronoi";
  bool explicit_steps = false, no_fix_boundary = false, freeze = false, ascii = false;
  SmoothingOptions opt;
};

void run(Args a) {
  check_output(a.input, a.output);
  Mesh mesh = load_mesh(a.input);
  a.opt.laplacian = a.laplacian == "umbrella" ? LaplacianType::Umbrella : LaplacianType::Cotangent;
  a.opt.mass = a.mass == "thesis" ? MassType::Thesis : a.mass == "barycentric" ? MassType::Barycentric : MassType::Voronoi;
  a.opt.implicit = !a.explicit_steps;
  a.opt.fix_boundary = !a.no_fix_boundary;
  a.opt.update_weights = !a.freeze;
  a.opt.progress = progress_printer("smooth");
  const auto t0 = std::chrono::steady_clock::now();
  set_positions(mesh, smooth(mesh, a.opt));
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  info(fmt::format("smoothed {} vertices: {} {} step(s) of lambda {} in {:.2f} s ({})", mesh.n_vertices(), a.opt.steps,
                   a.opt.implicit ? "implicit" : "explicit", a.opt.lambda, sec, SpdSolver::backend()));
  save_mesh(mesh, a.output, !a.ascii);
}

Registrar reg{40, "smooth", "Laplacian smoothing: explicit (Eq. 5.12) or implicit (Eq. 5.14), umbrella or cotangent", [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "input mesh")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "output mesh")->required();
  app.add_option("--laplacian", a->laplacian, "umbrella (Eq. 5.8) or cotan (Eq. 5.11)")
      ->check(CLI::IsMember({"umbrella", "cotan"}))->capture_default_str();
  app.add_flag("--implicit,!--explicit", a->opt.implicit, "backward Euler (default) or forward Euler steps");
  app.add_option("--lambda", a->opt.lambda,
                 "step size: dimensionless for umbrella; in squared mean edge lengths for cotan")
      ->check(CLI::PositiveNumber)->capture_default_str();
  app.add_option("--steps", a->opt.steps, "number of steps")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--mass", a->mass, "cotan mass matrix: voronoi, barycentric, or thesis (Eq. 5.11 verbatim)")
      ->check(CLI::IsMember({"voronoi", "barycentric", "thesis"}))->capture_default_str();
  app.add_flag("--rescale", a->opt.rescale, "restore volume (closed) or area (open) and centroid after each step");
  app.add_flag("--move-boundary", a->no_fix_boundary, "let boundary vertices move too (default: fixed)");
  app.add_flag("--freeze-weights", a->freeze, "cotan: factor the first step's matrix once and reuse it");
  app.add_flag("--ascii", a->ascii, "ascii PLY/STL output");
  app.callback([a] {
    Args copy = *a;
    copy.explicit_steps = !a->opt.implicit;
    run(copy);
  });
}};

}  // namespace
}  // namespace geotex::cli
