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
#include "geotex/texture/results.h"
#include "geotex/texture/synthesis.h"
#include "option_flags.h"

namespace geotex::cli {
namespace {

struct SynthesizeArgs {
  std::string exemplar, exemplar_base, target, output, texture_out, weight_file, report;
};

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
  if (r.kept_out_share > 0)
    info(fmt::format("synthesize: kept out {:.1f}% of the target's area (near creases {:.1f}%, parts smaller than the "
                     "texture {:.1f}%, closed pits {:.1f}%, domes {:.1f}%; --keep-out-crease-angle 0, --no-keep-out-thin, "
                     "--keep-out-pit-depth 0 and --keep-out-dome-ridge 0 cover them)",
                     100 * r.kept_out_share, 100 * r.kept_out_creases, 100 * r.kept_out_thin, 100 * r.kept_out_pits,
                     100 * r.kept_out_domes));
  info(fmt::format("synthesize: {:.2f}% of the relief's faces turned against the base (the exemplar's own: {:.2f}%)",
                   100 * r.inward_share, 100 * r.exemplar_inward_share));
  Mesh textured = r.target;
  set_positions(textured, r.textured);
  save_mesh(textured, a.output);
  if (!a.texture_out.empty()) write_texture(a.texture_out, r.target, r.texture);
  if (!a.report.empty()) {
    nlohmann::json j = synthesis_results().report(r);  // the fields Python's result has too
    j.update(synthesis_quality_results().report(synthesis_quality(ex.base, ex.texture, r, o)));
    write_report(a.report, std::move(j), sec, options_json(o));
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
