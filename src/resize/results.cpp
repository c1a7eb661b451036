// The resizing results as the front ends show them (resize/results.h). The report keys are those the CLI
// wrote by hand before the tables; the per-vertex arrays are Python only (the CLI writes them as files).

#include "geotex/resize/results.h"

namespace geotex {

const ResultTable<FeatureSummary>& feature_summary_results() {
  using R = FeatureSummary;
  static const auto t = ResultTable<R>()
      .add("marked_fraction", [](const R& r) { return r.marked_fraction; },
           "area share of the vertices marked (f > 1/2)")
      .add("marked_vertices", [](const R& r) { return r.marked_vertices; }, "vertices marked (f > 1/2; resize: of the mesh welded for the solve)")
      .add("regions", [](const R& r) { return r.regions; }, "connected regions of marked vertices")
      .add("warning", [](const R& r) { return r.warning; },
           "empty, or why the map is implausible (more than half or less than 0.5% marked)");
  return t;
}

const ResultTable<ResizeResult>& resize_results() {
  using R = ResizeResult;
  static const auto t = ResultTable<R>()
      .add("method", [](const R& r) { return std::string(enum_name(resize_method_names(), r.method)); },
           "the resize method run (for auto, the one chosen: axis-similarity for a box scale, else similarity)")
      .add("detector", [](const R& r) { return std::string(enum_name(feature_map_names(), r.detector)); },
           "the detector that made the map (for auto, the one chosen; none: weights given or no features)")
      .part(feature_summary_results(), [](const R& r) -> const FeatureSummary& { return r.summary; })
      .add("self_intersecting", [](const R& r) { return r.untangle.after; },
           "faces of the result crossed by an edge of a non-adjacent face (self_intersecting_faces())")
      .add("base_self_intersecting", [](const R& r) { return r.untangle.base; },
           "faces of the input so crossed (its own; counted only when the result has any)")
      .add("excess_self_intersecting", [](const R& r) { return r.untangle.excess_after(); },
           "self_intersecting beyond the input's own")
      .add("untangle_excess_before", [](const R& r) { return r.untangle.excess_before(); },
           "faces crossed beyond the input's own before the untangle blend")
      .add("untangle_blended_vertices", [](const R& r) { return r.untangle.blended; },
           "vertices the untangle blend moved towards the axis warp or the plain map")
      .add("welded_vertices", [](const R& r) { return r.welded_vertices; },
           "input vertices welded onto a coincident one for the map and the solve (unwelded patches' seams)")
      .add("weld_refused_groups", [](const R& r) { return r.weld_refused_groups; },
           "coincident groups left apart (welding them would make a face degenerate or an edge non-manifold) or "
           "welded per fan (their faces would join at a point)")
      .array("features", [](const R& r) { return r.features; }, "#V feature weights used, in [0, 1]", "",
             kPythonOnly)
      .array("mapped", [](const R& r) { return r.mapped; }, "#V by 3 positions under the plain deformation", "",
             kPythonOnly);
  return t;
}

const ResultTable<FeatureMap>& feature_map_results() {
  using R = FeatureMap;
  static const auto t = ResultTable<R>()
      .add("detector", [](const R& r) { return std::string(enum_name(feature_map_names(), r.method)); },
           "the detector used (for auto, the one chosen)")
      .part(feature_summary_results(), [](const R& r) -> const FeatureSummary& { return r.summary; })
      .array("weights", [](const R& r) { return r.weights; },
             "#V weights in [0, 1] (importance), in {0, 1} for the binary maps", "", kPythonOnly)
      .array("field", [](const R& r) { return r.field; },
             "#V values of the field the map was grown on (the raw importance, the height or the ADF)", "",
             kPythonOnly);
  return t;
}

}  // namespace geotex
