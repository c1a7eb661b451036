// The denoising results as the front ends show them (denoise/results.h). The report keys are those the
// CLI wrote by hand before the tables; Python-only fields are the old Python spellings and per-surfel arrays.

#include "geotex/denoise/results.h"

namespace geotex {

const ResultTable<DenoiseRun>& denoise_run_results() {
  static const auto t = ResultTable<DenoiseRun>()
      .add("method", [](const DenoiseRun& r) { return r.method; }, "the denoising method run")
      .part(run_time_results(), [](const DenoiseRun& r) { return RunTime{r.seconds}; });
  return t;
}

const ResultTable<AutoDenoiseResult>& auto_denoise_results() {
  using R = AutoDenoiseResult;
  static const auto t = ResultTable<R>()
      .add("noise", [](const R& r) {
             const NoiseEstimate& n = r.noise;
             return nlohmann::json{{"sigma", n.sigma}, {"normal_sigma", n.normal_sigma},
                                   {"rms_normal_sigma", n.rms_normal_sigma}, {"outliers", n.outliers},
                                   {"mean_edge", n.mean_edge}, {"clean_edge", n.clean_edge}, {"samples", n.samples},
                                   {"misfit_growth", n.misfit_growth}, {"noise_share", n.noise_share}};
           }, "the noise estimate: sigma, normal_sigma, rms_normal_sigma (mean edge lengths), outliers (a fraction), "
              "mean_edge, clean_edge (absolute), samples, misfit_growth (the fit's residual from two rings to three: "
              "about 1 for noise, above for a coarse model's facets), noise_share (the residual's share read as noise)")
      .array("noise_map", [](const R& r) { return r.noise_map; },
             "#V: the normal noise of each vertex's region (mean edge lengths, as noise.normal_sigma: the estimate read "
             "over about three rings); the given level everywhere when sigma is given")
      .add("choices", [](const R& r) { return r.choices; }, "what was chosen and why, one short line each")
      .add("turned_over", [](const R& r) { return r.turned_over; }, "faces left turned over (normally 0)")
      .add("creased_share", [](const R& r) { return r.creased_share; }, "the share of the area read creased")
      .array("creased", [](const R& r) { return r.creased; },
             "#F: how each face was read, 1 creased, 0 smooth, between: a transition")
      .add("refused_share", [](const R& r) { return r.refused_share; },
           "the share of the area refused the creased reading: the sharp fit moved it beyond the noise")
      .array("refused", [](const R& r) { return r.refused; },
             "#F: the creased reading refused (the share of the face's vertices): the sharp fit moved them beyond the "
             "noise on an organic-looking part")
      .add("relief_share", [](const R& r) { return r.relief_share; },
           "the share of the light fit's relief kept, area-weighted over the faces read smooth")
      .array("relief", [](const R& r) { return r.relief; },
             "#F: the light fit's relief kept, 0 plain (the mild fit) to 1 (relief above the noise: the light fit)")
      .add("strong_share", [](const R& r) { return r.strong_share; },
           "the share of the sharp fit's stronger smoothing taken (step 5c), area-weighted over the faces read smooth")
      .array("strong", [](const R& r) { return r.strong; },
             "#F: the sharp fit's stronger smoothing taken in smooth regions, 0 (the mild fit) to 1 (plain, "
             "smoothly curved and noisy: the sharp fit)")
      .add("change_kept_share", [](const R& r) { return r.change_kept_share; },
           "the share of the change kept by step 6a (coherent change given back), area-weighted")
      .array("change_kept", [](const R& r) { return r.change_kept; },
             "#F: the change kept, 1 where it is white like noise, towards 0 where it is coherent beyond it "
             "(a coarse mesh's own facets)")
      .add("seconds_per_stage", [](const R& r) {
             nlohmann::json j = nlohmann::json::object();
             for (const auto& [stage, sec] : r.seconds) j[stage] = sec;
             return j;
           }, "wall time of each stage", "s")
      .add("noise_sigma", [](const R& r) { return r.noise.sigma; }, "noise.sigma (the older Python name)",
           "mean edge lengths", kPythonOnly)
      .add("noise_normal_sigma", [](const R& r) { return r.noise.normal_sigma; },
           "noise.normal_sigma (the older Python name)", "mean edge lengths", kPythonOnly);
  return t;
}

const ResultTable<MrfResult>& mrf_results() {
  using R = MrfResult;
  static const auto t = ResultTable<R>()
      .add("iterations", [](const R& r) { return r.iterations; }, "outer iterations run")
      .add("converged", [](const R& r) { return r.converged; }, "stopped by the tolerance")
      .add("energy_per_iteration", [](const R& r) {
             return nlohmann::json{{"vertex_or_normal_process", r.vertex_energy}, {"edge_process", r.edge_energy}};
           }, "U_V (or U_N) and U_E after each outer iteration, Eq. (6.12), (6.15)")
      .add("labelled_per_iteration", [](const R& r) { return r.labelled; }, "edges labelled (> 1/2) after each outer iteration")
      .add("seconds_per_iteration", [](const R& r) { return r.seconds; }, "wall time since the start after each outer iteration", "s")
      .add("seconds_optimizing", [](const R& r) { return r.seconds.empty() ? 0.0 : r.seconds.back(); },
           "wall time of the optimization", "s")
      .add("labelled_edges", [](const R& r) { return int((r.edge_labels.array() > 0.5).count()); },
           "edges labelled sharp (> 1/2) at the end")
      .add("vertex_energy", [](const R& r) { return r.vertex_energy; },
           "energy_per_iteration's vertex_or_normal_process (the older Python name)", "", kPythonOnly)
      .add("edge_energy", [](const R& r) { return r.edge_energy; },
           "energy_per_iteration's edge_process (the older Python name)", "", kPythonOnly);
  return t;
}

const ResultTable<SurfelDenoiseResult>& surfel_denoise_results() {
  using R = SurfelDenoiseResult;
  static const auto t = ResultTable<R>()
      .add("cluster_moves", [](const R& r) { return r.surfels.cluster_moves; }, "cluster moves made")
      .add("unit_length", [](const R& r) { return r.surfels.unit_length; }, "the unit length used (absolute)")
      .add("initial_energy", [](const R& r) { return r.surfels.initial_energy; },
           "sum of U_i of the initial surfels at the first threshold", "unit lengths")
      .add("energy", [](const R& r) { return r.surfels.energy; }, "sum of U_i after each ICM sweep", "unit lengths")
      .add("thresholds_deg", [](const R& r) { return r.surfels.thresholds_deg; }, "the threshold t of each sweep", "deg")
      .add("median_angle_deg", [](const R& r) { return r.median_angle_deg; },
           "median angle between neighbouring initial surfels (the noise measure)", "deg")
      .array("normals", [](const R& r) { return r.surfels.surfels.normals; }, "#V by 3 surfel normals", "",
             kPythonOnly)
      .array("offsets", [](const R& r) { return r.surfels.surfels.offsets; }, "#V surfel plane offsets", "",
             kPythonOnly);
  return t;
}

}  // namespace geotex
