// `geotex denoise --method mrf|mrf-normal`: MRF denoising with explicit sharp-edge labelling (thesis ch. 6).
// Both methods share one set of flags (added once, by the first registration).

#include <memory>
#include <optional>

#include <fmt/format.h>

#include "cli.h"
#include "denoise_methods.h"
#include "geotex/denoise/mrf.h"

namespace geotex::cli {
namespace {

struct MrfArgs {
  std::optional<std::string> optimizer;
  std::string edge_optimizer = "metropolis", potential = "quadratic", ridges = "all";
  double phi0 = 40.0, phi0_start = 0.0, support = 0.5, te = 0.2, te_cooling = 0.95, tv = 0.0, tv_cooling = 0.5, step = 0.1;
  double tolerance = 1e-6;
  double final_phi0 = 60;
  int sweeps = 0, final_sweeps = 100, edge_sweeps = 1, normal_sweeps = 2, vertex_iterations = 20, rounds = 1;
  bool no_initial_labels = false;
};

MrfArgs& args() {
  static MrfArgs a;
  return a;
}

void add_options(CLI::App& app) {
  MrfArgs& a = args();
  const std::string g = "MRF (mrf, mrf-normal)";
  app.add_option("--phi0", a.phi0, "ridge sharpness threshold phi0, degrees (Eq. 6.9)")
      ->check(CLI::Range(0.0, 180.0))->capture_default_str()->group(g);
  app.add_option("--phi0-start", a.phi0_start,
                 "anneal the threshold from this angle (degrees) down to phi0 over the first half of the iterations; "
                 "0 = off (thesis)")
      ->check(CLI::Range(0.0, 180.0))->capture_default_str()->group(g);
  app.add_option("--support", a.support, "weight of the edge neighbourhood support (Eq. 6.11)")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--te", a.te, "edge-process start temperature T_E")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--te-cooling", a.te_cooling, "T_E factor per outer iteration (annealing schedule)")
      ->check(CLI::Range(1e-9, 1.0))->capture_default_str()->group(g);
  app.add_option("--tv", a.tv, "vertex-process (mrf-normal: normal-process) start temperature T_v, Metropolis only")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--tv-cooling", a.tv_cooling, "T_v factor per outer iteration")
      ->check(CLI::Range(1e-9, 1.0))->capture_default_str()->group(g);
  app.add_option("--optimizer", a.optimizer,
                 "mrf vertex process: metropolis|icm|cg|lbfgs (default lbfgs); mrf-normal normal process: "
                 "icm|metropolis (default icm)")
      ->check(CLI::IsMember({"metropolis", "icm", "cg", "lbfgs"}))->group(g);
  app.add_option("--edge-optimizer", a.edge_optimizer, "edge process: metropolis (annealed, thesis) or icm")
      ->check(CLI::IsMember({"metropolis", "icm"}))->capture_default_str()->group(g);
  app.add_option("--potential", a.potential, "smoothness potential rho: quadratic (Eq. 6.7) or sqrt (rho(y) = y)")
      ->check(CLI::IsMember({"quadratic", "sqrt"}))->capture_default_str()->group(g);
  app.add_option("--ridges", a.ridges, "edges that may be labelled: all, convex or concave (curvature clamping)")
      ->check(CLI::IsMember({"all", "convex", "concave"}))->capture_default_str()->group(g);
  app.add_option("--step", a.step, "Metropolis proposal std. dev. (mean edge lengths; radians for normals), adapted")
      ->check(CLI::PositiveNumber)->capture_default_str()->group(g);
  app.add_option("--sweeps", a.sweeps,
                 "mrf: vertex sweeps (metropolis, icm) or line searches (cg, lbfgs) per outer iteration; "
                 "0 = 5, 2, 5, 5")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--final-sweeps", a.final_sweeps,
                 "mrf: vertex sweeps or line searches after the last alternation, for the final labels")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--final-phi0", a.final_phi0,
                 "mrf: label the sharp edges once more on the denoised geometry with this threshold (degrees); "
                 "the geometry is not changed; 0 = off (thesis)")
      ->check(CLI::Range(0.0, 180.0))->capture_default_str()->group(g);
  app.add_option("--edge-sweeps", a.edge_sweeps, "edge-process sweeps per outer iteration")
      ->check(CLI::PositiveNumber)->capture_default_str()->group(g);
  app.add_option("--normal-sweeps", a.normal_sweeps, "mrf-normal: normal-process sweeps per outer iteration")
      ->check(CLI::PositiveNumber)->capture_default_str()->group(g);
  app.add_option("--vertex-iterations", a.vertex_iterations, "mrf-normal: iterations fitting vertices to the normals")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_option("--rounds", a.rounds, "mrf-normal: rounds of (normal MRF, vertex fit)")
      ->check(CLI::PositiveNumber)->capture_default_str()->group(g);
  app.add_option("--tolerance", a.tolerance, "stop when labels are stable and the energy fell by less than this fraction")
      ->check(CLI::NonNegativeNumber)->capture_default_str()->group(g);
  app.add_flag("--no-initial-labels", a.no_initial_labels,
               "start the edge process from no labels (default: edges with a dihedral angle above phi0)")
      ->group(g);
}

EdgeProcessOptions edge_options(const MrfArgs& a) {
  EdgeProcessOptions e;
  e.phi0_deg = a.phi0;
  e.phi0_start_deg = a.phi0_start;
  e.support_weight = a.support;
  e.ridges = parse_ridges(a.ridges);
  e.optimizer = parse_optimizer(a.edge_optimizer);
  e.temperature = a.te;
  e.cooling = a.te_cooling;
  e.sweeps = a.edge_sweeps;
  return e;
}

DenoiseResult to_result(const Mesh& input, const MrfResult& r, nlohmann::json params) {
  DenoiseResult out;
  out.mesh = input;
  set_positions(out.mesh, r.positions);
  out.edge_labels = r.edge_labels;
  nlohmann::json& j = out.report;
  j["parameters"] = std::move(params);
  j["iterations"] = r.iterations;
  j["converged"] = r.converged;
  j["energy_per_iteration"] = {{"vertex_or_normal_process", r.vertex_energy}, {"edge_process", r.edge_energy}};
  j["labelled_per_iteration"] = r.labelled;
  j["seconds_per_iteration"] = r.seconds;
  j["seconds_optimizing"] = r.seconds.empty() ? 0.0 : r.seconds.back();
  int labelled = 0;
  for (Eigen::Index e = 0; e < r.edge_labels.size(); ++e) labelled += r.edge_labels[e] > 0.5;
  j["labelled_edges"] = labelled;
  info(fmt::format("{} outer iterations{}, {} edges labelled sharp", r.iterations,
                   r.converged ? " (converged)" : "", labelled));
  return out;
}

nlohmann::json edge_params(const EdgeProcessOptions& e) {
  return {{"phi0_deg", e.phi0_deg}, {"phi0_start_deg", e.phi0_start_deg}, {"support_weight", e.support_weight}, {"ridges", to_string(e.ridges)},
          {"edge_optimizer", to_string(e.optimizer)}, {"te", e.temperature}, {"te_cooling", e.cooling},
          {"edge_sweeps", e.sweeps}};
}

DenoiseResult run_mrf(const Mesh& mesh, const DenoiseCommon& c) {
  const MrfArgs& a = args();
  MrfOptions o;
  if (c.alpha) o.alpha = *c.alpha;
  if (c.iterations) o.iterations = *c.iterations;
  o.seed = c.seed;
  o.progress = c.progress;
  o.optimizer = parse_optimizer(a.optimizer.value_or("lbfgs"));
  o.potential = parse_potential(a.potential);
  o.temperature = a.tv;
  o.cooling = a.tv_cooling;
  o.step = a.step;
  o.vertex_sweeps = a.sweeps;
  o.final_sweeps = a.final_sweeps;
  o.final_phi0_deg = a.final_phi0;
  o.tolerance = a.tolerance;
  o.initial_labels_from_angles = !a.no_initial_labels;
  o.edges = edge_options(a);
  nlohmann::json p = edge_params(o.edges);
  p.update({{"alpha", o.alpha}, {"optimizer", to_string(o.optimizer)}, {"potential", to_string(o.potential)},
            {"tv", o.temperature}, {"tv_cooling", o.cooling}, {"step", o.step}, {"sweeps", o.vertex_sweeps}, {"final_sweeps", o.final_sweeps}, {"final_phi0", o.final_phi0_deg},
            {"iterations", o.iterations}, {"seed", o.seed}, {"tolerance", o.tolerance}});
  return to_result(mesh, mrf_denoise(mesh, o), p);
}

DenoiseResult run_mrf_normal(const Mesh& mesh, const DenoiseCommon& c) {
  const MrfArgs& a = args();
  MrfNormalOptions o;
  if (c.alpha) o.alpha = *c.alpha;
  if (c.iterations) o.iterations = *c.iterations;
  o.seed = c.seed;
  o.progress = c.progress;
  o.optimizer = parse_optimizer(a.optimizer.value_or("icm"));
  if (o.optimizer != MrfOptimizer::Icm && o.optimizer != MrfOptimizer::Metropolis)
    throw InvalidInput("--method mrf-normal takes --optimizer icm or metropolis");
  o.potential = parse_potential(a.potential);
  o.temperature = a.tv;
  o.cooling = a.tv_cooling;
  o.step = a.step;
  o.normal_sweeps = a.normal_sweeps;
  o.vertex_iterations = a.vertex_iterations;
  o.rounds = a.rounds;
  o.tolerance = a.tolerance;
  o.initial_labels_from_angles = !a.no_initial_labels;
  o.edges = edge_options(a);
  nlohmann::json p = edge_params(o.edges);
  p.update({{"alpha", o.alpha}, {"optimizer", to_string(o.optimizer)}, {"potential", to_string(o.potential)},
            {"tv", o.temperature}, {"tv_cooling", o.cooling}, {"step", o.step}, {"normal_sweeps", o.normal_sweeps},
            {"vertex_iterations", o.vertex_iterations}, {"rounds", o.rounds}, {"iterations", o.iterations},
            {"seed", o.seed}, {"tolerance", o.tolerance}});
  return to_result(mesh, mrf_normal_denoise(mesh, o), p);
}

DenoiseRegistrar mrf{"mrf",
                     "MRF vertex process + edge labelling (thesis ch. 6); thesis run: --te 0.05 --te-cooling 0.9 --iterations 20",
                     add_options, run_mrf};
DenoiseRegistrar mrf_normal{"mrf-normal",
                            "MRF on face normals + edge labelling, then vertices fitted to the normals (Sec. 6.5)",
                            nullptr, run_mrf_normal};

}  // namespace
}  // namespace geotex::cli
