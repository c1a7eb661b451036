// geotex texture synthesize EXEMPLAR --target MESH -o OUT: grow a texture like the exemplar over a whole
// surface (texture/synthesis.h). Registered from texture.cpp by add_texture_synthesize().

#include <chrono>
#include <iostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/core/user_files.h"
#include "geotex/resize/feature_file.h"
#include "geotex/texture/synthesis.h"
#include "option_flags.h"

namespace geotex::cli {
namespace {

struct SynthesizeArgs {
  std::string exemplar, exemplar_base, target, output, texture_out, weight_file, report;
};

nlohmann::json stage_seconds(const SynthesisResult& r) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, sec] : r.stage_seconds) j[name] = sec;
  return j;
}

void run_synthesize(const SynthesizeArgs& a, SynthesisOptions o) {
  Outputs out({a.exemplar, a.exemplar_base, a.target, a.weight_file},
              {{a.output, "-o"}, {a.texture_out, "--texture-out"}, {a.report, "--report"}});
  TextureFile ex;
  if (a.exemplar_base.empty()) {
    ex = read_texture(a.exemplar);
  } else {  // a textured mesh over its base
    ex.base = load_mesh(a.exemplar_base);
    const Mesh textured = load_mesh(a.exemplar);
    if (textured.n_vertices() != ex.base.n_vertices() || faces(textured) != faces(ex.base))
      throw InvalidInput("synthesize: the exemplar and --exemplar-base must have the same connectivity");
    ex.texture = extract_texture(ex.base, positions(textured), o.texture);
  }
  const Mesh target = load_mesh(a.target);
  SynthesisGuides guides;
  // The feature-file reader: regular files only, size-capped, one number in [0, 1] per line (or a PLY).
  if (!a.weight_file.empty()) guides.weight = read_feature_file(a.weight_file, target);
  o.progress = progress_printer("synthesize");
  o.on_estimate = [&](const SynthesisEstimate& e) {  // before the work: what it will cost
    info(fmt::format("synthesize: estimate {} vertices{}, about {:.0f} s of CPU (exemplar share {:.3g}, scale {:.4g})",
                     e.vertices, e.refine ? " after refinement" : "", e.seconds, e.exemplar_share, e.scale));
  };
  const auto t0 = std::chrono::steady_clock::now();
  const SynthesisResult r = synthesize_texture(ex.base, ex.texture, target, o, guides);
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (const std::string& w : r.warnings) std::cerr << "geotex: warning: " << w << "\n";  // shown even when quiet
  info(fmt::format("synthesized {} patches of radius {:.4g} on {} vertices in {:.2f} s (scale {:.4g}, exemplar disk "
                   "at vertex {} of radius {:.4g})",
                   r.centers.size(), r.patch_radius, r.target.n_vertices(), sec, r.scale, r.exemplar_center,
                   r.exemplar_radius));
  Mesh textured = r.target;
  set_positions(textured, r.textured);
  save_mesh(textured, a.output);
  if (!a.texture_out.empty()) write_texture(a.texture_out, r.target, r.texture);
  if (!a.report.empty()) {
    const SynthesisQuality q = synthesis_quality(ex.base, ex.texture, r, o);
    const nlohmann::json j = {
        {"seconds", sec}, {"vertices", r.target.n_vertices()}, {"added_vertices", r.added_vertices},
        {"patches", r.centers.size()}, {"scale", r.scale}, {"patch_radius", r.patch_radius},
        {"exemplar_center", r.exemplar_center}, {"exemplar_radius", r.exemplar_radius},
        {"histogram_tv", q.histogram_tv}, {"histogram_w1", q.histogram_w1}, {"exemplar_rms", q.exemplar_rms},
        {"target_rms", q.target_rms}, {"exemplar_features", q.exemplar_features},
        {"target_features", q.target_features}, {"exemplar_spacing", q.exemplar_spacing},
        {"target_spacing", q.target_spacing}, {"spacing_change", q.spacing_change},
        {"lean_angle_error_deg", q.lean_angle_error_deg}, {"seam_step99", q.seam_step99},
        {"seam_step_max", q.seam_step_max}, {"within_step99", q.within_step99},
        {"within_step_max", q.within_step_max}, {"coverage", q.coverage}, {"folded", q.folded},
        {"self_intersecting", r.self_intersecting}, {"base_self_intersecting", r.base_self_intersecting},
        {"excess_self_intersecting", r.excess_self_intersecting}, {"shrunk_vertices", r.unfolded_vertices},
        {"shrunk_share", r.shrunk_share}, {"refined_share", r.refined_share},
        {"exemplar_share", r.estimate.exemplar_share}, {"estimated_vertices", r.estimate.vertices},
        {"estimated_seconds", r.estimate.seconds}, {"stage_seconds", stage_seconds(r)},
        {"warnings", r.warnings}};
    write_text_atomic(a.report, j.dump(1) + "\n");
  }
  out.commit();
}

}  // namespace

void add_texture_synthesize(CLI::App& texture) {
  auto a = std::make_shared<SynthesizeArgs>();
  CLI::App* s = texture.add_subcommand(
      "synthesize", "grow a texture like an exemplar over a whole surface (patch-based, oriented by a direction field)");
  s->add_option("EXEMPLAR", a->exemplar, "exemplar texture file (texture extract), or a textured mesh with --exemplar-base")
      ->required()
      ->check(ExistingFile);
  s->add_option("--exemplar-base", a->exemplar_base, "the exemplar's base, when EXEMPLAR is a textured mesh")
      ->check(ExistingMeshFile);
  s->add_option("--target", a->target, "target base mesh")->required()->check(ExistingMeshFile);
  s->add_option("-o,--output", a->output, "textured target mesh")->required()->check(MeshOutputFile);
  s->add_option("--texture-out", a->texture_out, "also write the target's texture file (over the refined target)")
      ->check(TextureOutputFile);
  s->add_option("--report", a->report, "write the synthesis measures (bench/synthesis.md) as JSON");
  s->add_option("--weight", a->weight_file,
                "per-vertex growth weights in [0, 1] of the target: text, one per line, or PLY with vertex 'feature'")
      ->check(ExistingFile);
  auto flags = std::make_shared<FlagSet>(*s);
  flags->add("synthesize", SynthesisOptions::table());
  s->callback([a, flags] { run_synthesize(*a, flags->resolve<SynthesisOptions>("synthesize")); });
}

}  // namespace geotex::cli
