// Demo step for denoising (thesis ch. 6–7): the default pipeline (auto_denoise) beside each method as the
// thesis runs it (preset "thesis": MRF vertex process, MRF face normals, surfels), on a noisy cube and on
// one real noisy/clean pair of the shared data (Fandisk0.3) when it is present. Error maps of one input
// share their colour range; the default's sharp-edge labels are drawn as red lines.

#include <chrono>
#include <filesystem>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/surfel.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/results.h"
#include "geotex/tools/shapes.h"

namespace geotex::cli {
namespace demo_denoise {  // named, not anonymous: a unity build compiles several commands in one unit

// Edges of `mesh` labelled above ½, scored against the edges of `truth` (same connectivity) whose
// dihedral angle exceeds 30°.
LabelScore score(const Mesh& mesh, const Mesh& truth, const Eigen::VectorXd& labels) {
  const MatrixX2i E = edges(mesh);
  const Eigen::VectorXd D = dihedral_angles(truth);
  std::vector<int> lab, tru;
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    if (labels[e] > 0.5) lab.push_back(static_cast<int>(e));
    if (std::abs(D[e]) > 30.0 * M_PI / 180.0) tru.push_back(static_cast<int>(e));
  }
  auto rows = [&](const std::vector<int>& idx) {
    MatrixX2i S(idx.size(), 2);
    for (size_t k = 0; k < idx.size(); ++k) S.row(k) = E.row(idx[k]);
    return S;
  };
  return score_edge_labels(rows(lab), rows(tru));
}

// One row of the page: the noisy input, the default, the three methods' thesis presets, the truth.
void compare_denoisers(const DemoContext& ctx, const std::string& name, const std::string& what, const Mesh& noisy,
                       const Mesh& clean, const std::string& up = "z") {
  nlohmann::json& r = *ctx.report;
  const std::string clean_file = name + "-clean.ply";
  save_mesh(clean, (ctx.dir / clean_file).string());
  save_mesh(noisy, (ctx.dir / (name + "-noisy.ply")).string());
  const Comparison c0 = compare_meshes(noisy, clean);
  const std::string error0 = comparison_results().figures(c0, {"mean_normal_error_deg", "ev_relative"});
  r["summary"].push_back(fmt::format("{} ({} faces): noisy input, {}", what, noisy.n_faces(), error0));
  add_figure(ctx, {.mesh = name + "-noisy.ply",
                   .caption = fmt::format("{}, noisy input ({} faces): {}. Colour: distance to the clean mesh "
                                          "(saturates here).", what, noisy.n_faces(), error0),
                   .compare = name, .field = "error", .truth = clean_file, .sets_range = false, .up = up});

  // A result: its mesh, optional edge labels (same connectivity), the time it took.
  auto show = [&](const std::string& method, const std::string& label, const Mesh& out, const Eigen::VectorXd* labels,
                  double sec) {
    const std::string file = fmt::format("{}-{}.ply", name, method);
    save_mesh(out, (ctx.dir / file).string());
    const Comparison c = compare_meshes(out, clean);
    const RunTime time{sec};
    nlohmann::json& row = r[name][method] = comparison_results().report(c);
    row.update(run_time_results().report(time));
    std::string edges_file, labels_text;
    if (labels && out.n_vertices() == clean.n_vertices()) {
      edges_file = fmt::format("{}-{}-edges.ply", name, method);
      write_edge_values(out, *labels, "label", ctx.dir / edges_file);
      const LabelScore s = score(out, clean, *labels);
      labels_text = "; sharp edges (red) " + label_score_results().figures(s, {"precision", "recall"});
      row.update(label_score_results().report(s));
    }
    // The figures are said as the report and Python name them (results.h: figures()).
    const std::string figures = comparison_results().figures(c, {"mean_normal_error_deg", "ev_relative"}) +
                                labels_text + "; " + run_time_results().figures(time, {"seconds"});
    r["summary"].push_back(fmt::format("{}, {}: {}", what, label, figures));
    add_figure(ctx, {.mesh = file, .caption = fmt::format("<b>{}</b>: {}.", label, figures), .compare = name,
                     .field = "error", .truth = clean_file, .edges = edges_file, .up = up});
  };
  using clock = std::chrono::steady_clock;
  auto since = [](clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); };

  auto t = clock::now();
  const AutoDenoiseResult a = auto_denoise(noisy);
  const double ta = since(t);
  Mesh out = noisy;
  set_positions(out, a.positions);
  show("default", "default (auto_denoise)", out, &a.edge_labels, ta);

  MrfOptions mo;
  MrfOptions::table().apply_preset(mo, "thesis");
  t = clock::now();
  const MrfResult m = mrf_denoise(noisy, mo);
  const double tm = since(t);
  set_positions(out, m.positions);
  show("mrf-thesis", "MRF vertex process, preset thesis (ch. 6)", out, &m.edge_labels, tm);

  MrfNormalOptions no;
  MrfNormalOptions::table().apply_preset(no, "thesis");
  t = clock::now();
  const MrfResult n = mrf_normal_denoise(noisy, no);
  const double tn = since(t);
  set_positions(out, n.positions);
  show("mrf-normal-thesis", "MRF face normals, preset thesis (Sec. 6.5)", out, &n.edge_labels, tn);

  SurfelDenoiseOptions so;
  SurfelDenoiseOptions::table().apply_preset(so, "thesis");
  t = clock::now();
  const SurfelDenoiseResult s = surfel_denoise(noisy, so);
  show("surfel-thesis", "surfels, preset thesis (ch. 7; dual mesh)", s.mesh, nullptr, since(t));

  add_figure(ctx, {.mesh = clean_file, .caption = what + ": the clean mesh (the truth the row is scored against).",
                   .compare = name, .up = up});
}

DemoRegistrar step{40, "denoising", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const Mesh clean = subdivided_cube(ctx.quick ? 8 : 16);
  Mesh noisy = clean;
  NoiseOptions n;
  n.sigma = 0.3;
  n.seed = 3;
  set_positions(noisy, add_noise(clean, n));
  compare_denoisers(ctx, "denoise-cube", "Generated cube, noise 0.3 mean edges", noisy, clean);

  // One real model, when the shared data is there.
  const std::filesystem::path pair = ctx.data / "denoise" / "Fandisk0.3";
  if (!ctx.data.empty() && std::filesystem::exists(pair / "Noisy.obj") && std::filesystem::exists(pair / "Original.obj")) {
    compare_denoisers(ctx, "denoise-fandisk", "Fandisk0.3 (shared data: Zhang et al. 2015)",
                      read_mesh(pair / "Noisy.obj"), read_mesh(pair / "Original.obj"), "auto");
  } else if (const auto spot = demo_model(ctx, "spot.obj"); !spot.empty()) {
    // Without the shared pairs: the shipped real model with seeded noise of 0.3 mean edges.
    const Mesh clean_spot = read_mesh(spot);
    Mesh noisy_spot = clean_spot;
    set_positions(noisy_spot, add_noise(clean_spot, n));
    compare_denoisers(ctx, "denoise-spot", "spot (shipped, CC0), noise 0.3 mean edges", noisy_spot, clean_spot,
                      "auto");
    r["summary"].push_back("Fandisk0.3 of the shared data is not here: the shipped spot with noise instead");
  } else {
    const std::string note = "real model skipped (--quick)";
    r["summary"].push_back(note);
    r["notes"].push_back(note);
  }
}};

}  // namespace demo_denoise
}  // namespace geotex::cli
