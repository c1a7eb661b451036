// geotex compare RESULT TRUTH: mean normal error (degrees), Ev, Hausdorff distance.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/results.h"

namespace geotex::cli {
namespace cmd_compare {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::string result, truth, labels;
  double truth_angle = 30.0, label_threshold = 0.5;
  bool json = false;
};

void run(const Args& a) {
  const Mesh result = load_mesh(a.result);
  const Mesh truth = load_mesh(a.truth);
  const Comparison c = compare_meshes(result, truth);
  // Edge labels against the truth's sharp edges (dihedral angle above --truth-angle).
  nlohmann::json jl;
  if (!a.labels.empty()) {
    const EdgeValues ev = read_edge_values(a.labels, "label");
    std::vector<int> keep;
    for (Eigen::Index i = 0; i < ev.values.size(); ++i)
      if (ev.values[i] > a.label_threshold) keep.push_back(static_cast<int>(i));
    MatrixX2i L(keep.size(), 2);
    for (size_t k = 0; k < keep.size(); ++k) L.row(k) = ev.edges.row(keep[k]);
    const Eigen::VectorXd D = dihedral_angles(truth);
    const MatrixX2i E = edges(truth);
    std::vector<int> sharp;
    for (Eigen::Index i = 0; i < D.size(); ++i)
      if (std::abs(D[i]) > a.truth_angle * M_PI / 180.0) sharp.push_back(static_cast<int>(i));
    MatrixX2i T(sharp.size(), 2);
    for (size_t k = 0; k < sharp.size(); ++k) T.row(k) = E.row(sharp[k]);
    const LabelScore s = score_edge_labels(L, T);
    jl = label_score_results().report(s);  // what Python's score_edge_labels() returns too
    jl["truth_angle_deg"] = a.truth_angle;
  }
  if (a.json) {
    nlohmann::json j = comparison_results().report(c);  // what Python's compare() returns too
    j["result"] = a.result;
    j["truth"] = a.truth;
    if (!jl.is_null()) j["edge_labels"] = jl;
    fmt::print("{}\n", j.dump(2));
    return;
  }
  fmt::print("mean normal error  {:.3f} deg (max {:.2f} deg; faces matched by {})\n", c.mean_normal_error_deg,
             c.max_normal_error_deg, c.faces_by_index ? "index" : "closest face");
  fmt::print("Ev                 {:.4e} of the bbox diagonal ({:.6g} absolute)\n", c.ev_relative, c.ev);
  fmt::print("Hausdorff          {:.4e} of the bbox diagonal ({:.6g} absolute)\n", c.hausdorff_relative, c.hausdorff);
  if (!jl.is_null())
    fmt::print("edge labels        precision {:.3f}, recall {:.3f}, F1 {:.3f} ({} labelled, {} true sharp edges above {} deg)\n",
               jl["precision"].get<double>(), jl["recall"].get<double>(), jl["f1"].get<double>(),
               jl["labelled"].get<size_t>(), jl["truth_sharp_edges"].get<size_t>(), a.truth_angle);
}

Registrar reg{90, "compare", "Compare a result with the ground truth: mean normal error, Ev, Hausdorff", [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("RESULT", a->result, "result mesh")->required()->check(ExistingMeshFile);
  app.add_option("TRUTH", a->truth, "ground-truth mesh")->required()->check(ExistingMeshFile);
  app.add_flag("--json", a->json, "print JSON");
  app.add_option("--labels", a->labels, "edge labels (PLY edge element with 'label') to score against TRUTH's sharp edges");
  app.add_option("--truth-angle", a->truth_angle, "dihedral angle (degrees) above which a TRUTH edge is sharp")
      ->check(FiniteNumber)->capture_default_str();
  app.add_option("--label-threshold", a->label_threshold, "label above which an edge counts as labelled")
      ->check(FiniteNumber)->capture_default_str();
  app.callback([a] { run(*a); });
}};

}  // namespace cmd_compare
}  // namespace geotex::cli
