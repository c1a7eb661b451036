// The texture results as the front ends show them (texture/results.h). The report keys are those the CLI
// wrote by hand before the tables, where the CLI and Python spelled a thing differently the Python name
// (target_vertices, unfolded_vertices); per-vertex arrays and vertex lists are Python only.

#include "geotex/texture/results.h"

namespace geotex {

const ResultTable<TextureExtraction>& texture_extraction_results() {
  using R = TextureExtraction;
  static const auto t = ResultTable<R>()
      .add("base_source", [](const R& r) {
             static const char* names[] = {"given", "projected", "automatic"};
             return std::string(names[static_cast<int>(r.source)]);
           }, "where the base came from: given (same connectivity), projected (onto a given base), automatic")
      .add("median_off_normal_deg", [](const R& r) { return r.median_off_normal_deg; },
           "median angle of the displacements from the base normals", "deg")
      .add("projection_missed", [](const R& r) { return r.missed; },
           "projected: textured vertices without an inside solution (the closest point taken)")
      .add("base_passes", [](const R& r) { return r.shape.passes; },
           "automatic base: smoothing steps taken, or robust fits solved (else 0)")
      .add("base_stopped", [](const R& r) { return r.shape.stopped; },
           "automatic base: smoothing stopped by the tolerance (false: the step cap ran out)")
      .array("base_weight", [](const R& r) { return r.shape.weight; },
             "automatic base: #V robust weights of the last fit (1 follows the surface, 0 a protrusion; else empty)",
             "", kPythonOnly)
      .add("fit_iterative", [](const R& r) { return r.fit.iterative; },
           "the iterative tilt fit met its tolerance (false: the direct solve was used)")
      .add("fit_iterations", [](const R& r) { return r.fit.iterations; }, "CGLS iterations run")
      .add("max_error", [](const R& r) { return r.max_error; },
           "largest distance of a reconstructed vertex from its textured one", "mean edge lengths")
      .add("height_only_error", [](const R& r) { return r.height_only_error; },
           "the same for the height field alone (what the tilt adds)", "mean edge lengths")
      .add("base_area_ratio", [](const R& r) { return r.base_area_ratio; },
           "the base's area over the textured surface's (an automatic base below 0.85 is warned about)")
      .add("warnings", [](const R& r) { return r.warnings; }, "one line each (an automatic base that removed much of the surface)");
  return t;
}

const ResultTable<TextureDamage>& texture_damage_results() {
  using R = TextureDamage;
  static const auto t = ResultTable<R>()
      .add("folded", [](const R& r) { return r.folded; }, "folded faces of the textured target")
      .add("base_folded", [](const R& r) { return r.base_folded; }, "folded faces of the bare target")
      .add("excess_folded", [](const R& r) { return r.excess_folded(); }, "folded beyond the bare target's")
      .add("self_intersecting", [](const R& r) { return r.self_intersecting; },
           "self-intersecting faces of the textured target")
      .add("base_self_intersecting", [](const R& r) { return r.base_self_intersecting; },
           "self-intersecting faces of the bare target")
      .add("excess_self_intersecting", [](const R& r) { return r.excess_self_intersecting(); },
           "self-intersecting beyond the bare target's");
  return t;
}

const ResultTable<TransferResult>& transfer_results() {
  using R = TransferResult;
  static const auto t = ResultTable<R>()
      .add("source_center", [](const R& r) { return r.source_center; }, "the source patch's centre vertex")
      .add("target_center", [](const R& r) { return r.target_center; }, "the target patch's centre vertex")
      .add("source_vertices", [](const R& r) { return r.source_patch.vertices.size(); },
           "vertices of the source patch")
      .add("target_vertices", [](const R& r) { return r.target_vertices; },
           "target vertices that received a height (the target patch's)")
      .add("source_patch", [](const R& r) { return r.source_patch.vertices; },
           "the source patch's vertices (source base vertices)", "", kPythonOnly)
      .add("target_patch", [](const R& r) { return r.target_patch.vertices; },
           "the target patch's vertices (target vertices)", "", kPythonOnly)
      .add("vertices", [](const R& r) { return r.target.n_vertices(); }, "vertices of the target used (refined)")
      .add("added_vertices", [](const R& r) { return r.added_vertices; }, "vertices the refinement added")
      .add("height_factor", [](const R& r) { return r.height_factor; },
           "what the source heights were multiplied by (height rule x height_scale)")
      .array("falloff", [](const R& r) { return r.falloff; },
             "#V rim weight (1 inside the patch, 0 at its rim and outside)", "", kPythonOnly)
      .part(texture_damage_results(), [](const R& r) -> const TextureDamage& { return r.damage; })
      .add("warnings", [](const R& r) { return r.warnings; }, "one line each (refined target, damage, ...)");
  return t;
}

const ResultTable<AtlasResult>& atlas_results() {
  using R = AtlasResult;
  static const auto t = ResultTable<R>()
      .add("source_center", [](const R& r) { return r.source_center; }, "the source disk's centre vertex")
      .add("disks", [](const R& r) { return r.centers.size(); }, "disks placed")
      .add("centers", [](const R& r) { return r.centers; }, "the disks' centres (target vertices)", "", kPythonOnly)
      .add("vertices", [](const R& r) { return r.target.n_vertices(); }, "vertices of the target used (refined)")
      .add("added_vertices", [](const R& r) { return r.added_vertices; }, "vertices the refinement added")
      .add("uncovered", [](const R& r) { return int((r.coverage.array() <= 0).count()); },
           "target vertices no disk covers")
      .array("coverage", [](const R& r) { return r.coverage; },
             "#V largest disk weight (1 - |z|^2)^2 at each vertex (0: uncovered)", "", kPythonOnly)
      .array("owner", [](const R& r) { return r.owner; }, "#V the disk of largest weight (-1: none)", "",
             kPythonOnly)
      .add("height_factor", [](const R& r) { return r.height_factor; },
           "what the source heights were multiplied by (height rule x height_scale)")
      .add("unfolded_vertices", [](const R& r) { return r.unfolded_vertices; },
           "vertices whose displacement the unfolding lowered (faces it folded or made cross)")
      .add("unfold_rounds", [](const R& r) { return r.unfold_rounds; }, "unfolding rounds that found damage")
      .part(texture_damage_results(), [](const R& r) -> const TextureDamage& { return r.damage; })
      .add("warnings", [](const R& r) { return r.warnings; }, "one line each (refined target, damage, ...)");
  return t;
}

const ResultTable<SynthesisResult>& synthesis_results() {
  using R = SynthesisResult;
  static const auto t = ResultTable<R>()
      .add("vertices", [](const R& r) { return r.target.n_vertices(); }, "vertices of the target used (refined)")
      .add("added_vertices", [](const R& r) { return r.added_vertices; }, "vertices the refinement added")
      .add("patches", [](const R& r) { return r.centers.size(); }, "patches placed")
      .add("centers", [](const R& r) { return r.centers; }, "the patches' centres (target vertices)", "", kPythonOnly)
      .array("owner", [](const R& r) { return r.owner; }, "#V the patch of largest blend weight (-1: none)", "",
             kPythonOnly)
      .array("field", [](const R& r) { return r.field; }, "#V by 3 unit tangent directions the lean follows", "",
             kPythonOnly)
      .add("scale", [](const R& r) { return r.scale; }, "target length per exemplar length")
      .add("patch_radius", [](const R& r) { return r.patch_radius; }, "patch radius on the target (target units)")
      .add("exemplar_center", [](const R& r) { return r.exemplar_center; }, "the exemplar disk's centre vertex")
      .add("exemplar_radius", [](const R& r) { return r.exemplar_radius; },
           "the exemplar disk's geodesic radius (exemplar units)")
      .add("self_intersecting", [](const R& r) { return r.self_intersecting; },
           "faces of the textured target crossed by a non-adjacent face's edge")
      .add("base_self_intersecting", [](const R& r) { return r.base_self_intersecting; },
           "the same on the refined bare target")
      .add("excess_self_intersecting", [](const R& r) { return r.excess_self_intersecting; },
           "self-intersecting beyond the bare target's")
      .add("unfolded_vertices", [](const R& r) { return r.unfolded_vertices; },
           "vertices whose displacement the unfolding shrank")
      .add("shrunk_share", [](const R& r) { return r.shrunk_share; }, "unfolded_vertices / #V")
      .add("retried_placements", [](const R& r) { return r.retried_placements; },
           "patches whose first placement folded or crossed faces and a later one did not")
      .add("dropped_patches", [](const R& r) { return r.dropped_patches; },
           "patches whose colliding features were dropped (zeroed)")
      .add("dropped_vertices", [](const R& r) { return r.dropped_vertices; }, "vertices zeroed by dropping")
      .add("repaired_vertices", [](const R& r) { return r.repaired_vertices; },
           "vertices zeroed after encoding, where the textured surface still crossed itself")
      .add("filled_patches", [](const R& r) { return r.filled_patches; },
           "patches placed where a whole feature had room after the front (fill_holes)")
      .add("fragments_removed", [](const R& r) { return r.fragments_removed; },
           "broken features (lower than half the exemplar's lowest whole feature, or under 3/4 of its smallest "
           "footprint) zeroed after unfolding")
      .add("fragment_vertices", [](const R& r) { return r.fragment_vertices; },
           "vertices zeroed with the broken features")
      .add("bare_share", [](const R& r) { return r.bare_share; },
           "area share of the growth region where a whole feature would fit between the displaced vertices")
      .add("inward_share", [](const R& r) { return r.inward_share; },
           "area share of the relief's faces (a corner displaced by over 5 % of the largest) whose normal points "
           "against the base's")
      .add("exemplar_inward_share", [](const R& r) { return r.exemplar_inward_share; },
           "the same on the exemplar as it is read (its raster within the placements' reach)")
      .add("refined_share", [](const R& r) { return r.refined_share; }, "added_vertices / #V")
      .array("weight", [](const R& r) { return r.weight; },
             "#V the growth weight used (the user's times the automatic keep-out)", "", kPythonOnly)
      .add("kept_out_share", [](const R& r) { return r.kept_out_share; },
           "area share of the target kept out automatically (weight below 0.5)")
      .add("kept_out_creases", [](const R& r) { return r.kept_out_creases; }, "the same, near sharp creases")
      .add("kept_out_thin", [](const R& r) { return r.kept_out_thin; }, "the same, on parts smaller than the features")
      .add("kept_out_pits", [](const R& r) { return r.kept_out_pits; }, "the same, in closed pits smaller than the span")
      .add("kept_out_domes", [](const R& r) { return r.kept_out_domes; },
           "the same, on domes smaller than the span (an eyeball)")
      .add("exemplar_share", [](const R& r) { return r.estimate.exemplar_share; },
           "the exemplar share used (given, or automatic)")
      .add("estimated_vertices", [](const R& r) { return r.estimate.vertices; },
           "output vertices estimated before the work")
      .add("estimated_seconds", [](const R& r) { return r.estimate.seconds; },
           "CPU time estimated before the work (one core)", "s")
      .add("stage_seconds", [](const R& r) {
             nlohmann::json j = nlohmann::json::object();
             for (const auto& [stage, sec] : r.stage_seconds) j[stage] = sec;
             return j;
           }, "wall time of each stage", "s")
      .add("warnings", [](const R& r) { return r.warnings; }, "one line each");
  return t;
}

const ResultTable<SynthesisQuality>& synthesis_quality_results() {
  using R = SynthesisQuality;
  static const auto t = ResultTable<R>()
      .add("histogram_tv", [](const R& r) { return r.histogram_tv; },
           "total variation distance of the height histograms (exemplar x height_factor, target), in [0, 1]")
      .add("histogram_w1", [](const R& r) { return r.histogram_w1; },
           "Wasserstein-1 distance of the height histograms", "exemplar mean |h|")
      .add("exemplar_rms", [](const R& r) { return r.exemplar_rms; }, "area-weighted rms height of the exemplar "
           "(x height_factor)")
      .add("target_rms", [](const R& r) { return r.target_rms; }, "area-weighted rms height of the target")
      .add("exemplar_features", [](const R& r) { return r.exemplar_features; }, "height features of the exemplar")
      .add("target_features", [](const R& r) { return r.target_features; }, "height features of the target")
      .add("exemplar_spacing", [](const R& r) { return r.exemplar_spacing; },
           "mean nearest-neighbour distance of the exemplar's features", "target units")
      .add("target_spacing", [](const R& r) { return r.target_spacing; },
           "mean nearest-neighbour distance of the target's features", "target units")
      .add("spacing_change", [](const R& r) { return r.spacing_change; }, "target_spacing / exemplar_spacing - 1")
      .add("lean_angle_error_deg", [](const R& r) { return r.lean_angle_error_deg; },
           "mean angle between the lean's direction and the exemplar's", "deg")
      .add("seam_step99", [](const R& r) { return r.seam_step99; },
           "99th percentile of height steps across patch seams", "largest exemplar |h|")
      .add("seam_step_max", [](const R& r) { return r.seam_step_max; }, "largest height step across patch seams",
           "largest exemplar |h|")
      .add("within_step99", [](const R& r) { return r.within_step99; },
           "99th percentile of height steps within patches", "largest exemplar |h|")
      .add("within_step_max", [](const R& r) { return r.within_step_max; }, "largest height step within patches",
           "largest exemplar |h|")
      .add("coverage", [](const R& r) { return r.coverage; }, "area share of the target that received a displacement")
      .add("folded", [](const R& r) { return r.folded; }, "folded faces of the textured target beyond the base's");
  return t;
}

}  // namespace geotex
