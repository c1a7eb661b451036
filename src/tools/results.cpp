// The metrics' results as the front ends show them (tools/results.h); the names are those the CLI's
// `compare --json` and Python used before the tables.

#include "geotex/tools/results.h"

namespace geotex {

const ResultTable<Comparison>& comparison_results() {
  using R = Comparison;
  static const auto t = ResultTable<R>()
      .add("mean_normal_error_deg", [](const R& r) { return r.mean_normal_error_deg; },
           "mean angle between corresponding face normals", "deg")
      .add("max_normal_error_deg", [](const R& r) { return r.max_normal_error_deg; },
           "largest angle between corresponding face normals", "deg")
      .add("faces_matched_by", [](const R& r) { return std::string(r.faces_by_index ? "index" : "closest-face"); },
           "how faces correspond: index (same connectivity) or closest-face")
      .add("ev", [](const R& r) { return r.ev; }, "RMS distance of the result's vertices to the true surface")
      .add("ev_relative", [](const R& r) { return r.ev_relative; }, "ev over the truth's bounding-box diagonal")
      .add("hausdorff", [](const R& r) { return r.hausdorff; }, "symmetric Hausdorff distance")
      .add("hausdorff_relative", [](const R& r) { return r.hausdorff_relative; },
           "hausdorff over the truth's bounding-box diagonal")
      .add("mean_distance", [](const R& r) { return r.mean_distance; },
           "mean distance of the result's vertices to the true surface")
      .add("bbox_diagonal", [](const R& r) { return r.diagonal; }, "the truth's bounding-box diagonal");
  return t;
}

const ResultTable<LabelScore>& label_score_results() {
  using R = LabelScore;
  static const auto t = ResultTable<R>()
      .add("precision", [](const R& r) { return r.precision; }, "share of the labelled edges that are true")
      .add("recall", [](const R& r) { return r.recall; }, "share of the true edges labelled")
      .add("f1", [](const R& r) { return r.f1; }, "harmonic mean of precision and recall")
      .add("labelled", [](const R& r) { return r.labelled; }, "edges labelled")
      .add("truth_sharp_edges", [](const R& r) { return r.truth; }, "true (sharp) edges")
      .add("true_positive", [](const R& r) { return r.true_positive; }, "labelled edges that are true");
  return t;
}

}  // namespace geotex
