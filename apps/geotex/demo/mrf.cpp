// Demo step for MRF denoising with explicit edge labelling (thesis ch. 6): a noisy cube, denoised by
// the vertex process (L-BFGS) and by the face-normal variant, with its sharp edges found.

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/metrics.h"
#include "geotex/denoise/mrf.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"

namespace geotex::cli {
namespace {

// Edges of `mesh` whose label is above ½, and edges of `truth` with a dihedral angle above 30°.
LabelScore score(const Mesh& mesh, const Eigen::VectorXd& labels) {
  const MatrixX2i E = edges(mesh);
  const Eigen::VectorXd D = dihedral_angles(mesh);
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

DemoRegistrar step{60, "mrf denoising", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const Mesh clean = subdivided_cube(16);
  Mesh noisy = clean;
  NoiseOptions n;
  n.sigma = 0.3;
  n.seed = 3;
  set_positions(noisy, add_noise(clean, n));
  save_mesh(noisy, (ctx.dir / "mrf-cube-noisy.ply").string());
  const Comparison c0 = compare_meshes(noisy, clean);
  r["summary"].push_back(fmt::format("mrf: cube with {} faces, noise 0.3 mean edge: normal error {:.2f} deg",
                                     noisy.n_faces(), c0.mean_normal_error_deg));
  auto report_run = [&](const std::string& name, const MrfResult& m, double sec) {
    Mesh out = noisy;
    set_positions(out, m.positions);
    save_mesh(out, (ctx.dir / ("mrf-cube-" + name + ".ply")).string());
    write_edge_values(out, m.edge_labels, "label", (ctx.dir / ("mrf-cube-" + name + "-edges.ply")).string());
    const Comparison c = compare_meshes(out, clean);
    const LabelScore s = score(clean, m.edge_labels);
    r["summary"].push_back(fmt::format(
        "mrf ({}): normal error {:.2f} deg, Ev {:.2e}; sharp edges precision {:.3f}, recall {:.3f}; {:.2f} s", name,
        c.mean_normal_error_deg, c.ev_relative, s.precision, s.recall, sec));
    r["mrf_" + name] = {{"mean_normal_error_deg", c.mean_normal_error_deg}, {"ev_relative", c.ev_relative},
                        {"precision", s.precision}, {"recall", s.recall}, {"seconds", sec}};
  };
  auto t0 = std::chrono::steady_clock::now();
  const MrfResult v = mrf_denoise(noisy, {});
  report_run("vertex-lbfgs", v, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  t0 = std::chrono::steady_clock::now();
  const MrfResult f = mrf_normal_denoise(noisy, {});
  report_run("normal", f, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}};

}  // namespace
}  // namespace geotex::cli
