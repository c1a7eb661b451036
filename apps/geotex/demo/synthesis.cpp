// Demo step for texture synthesis (texture/synthesis.h): the tentacle plate's texture grown over a whole
// sphere (and spot and the cow when the shared data is there and --quick is not given).

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/texture/results.h"
#include "geotex/texture/synthesis.h"
#include "geotex/tools/shapes.h"

namespace geotex::cli {
namespace demo_synthesis {  // named, not anonymous: a unity build compiles several commands in one unit

DemoRegistrar step{82, "texture synthesis", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  auto summary = [&](const std::string& s) { r["summary"].push_back(s); };
  const auto t0 = std::chrono::steady_clock::now();
  const TexturedShape p = make_shape("tentacle-plane", 0);
  const Texture tex = extract_texture(p.base, positions(p.textured));
  {
    Mesh m = p.base;
    set_positions(m, positions(p.textured));
    save_mesh(m, (ctx.dir / "synthesis-exemplar.ply").string());
    r["files"].push_back((ctx.dir / "synthesis-exemplar.ply").string());
  }
  add_figure(ctx, {.mesh = "synthesis-exemplar.ply",
                   .caption = "Exemplar of the synthesis: the tentacle plate (3&times;3 tentacles leaning to +x)."});

  auto grow = [&](const std::string& name, const std::string& what, const Mesh& target, const SynthesisOptions& o) {
    const SynthesisResult s = synthesize_texture(p.base, tex, target, o);
    const SynthesisQuality q = synthesis_quality(p.base, tex, s, o);
    Mesh out = s.target;
    set_positions(out, s.textured);
    const std::string file = "synthesis-" + name + ".ply";
    save_mesh(out, (ctx.dir / file).string());
    r["files"].push_back((ctx.dir / file).string());
    r["synthesis"][name] = synthesis_results().report(s);  // as `texture synthesize --report` has them
    r["synthesis"][name].update(synthesis_quality_results().report(q));
    // The figures as `texture synthesize --report` and Python name them (results.h: figures()).
    const std::string line = fmt::format(
        "{}: {}, {}", what, synthesis_results().figures(s, {"vertices", "patches", "excess_self_intersecting"}),
        synthesis_quality_results().figures(q, {"spacing_change", "histogram_tv", "lean_angle_error_deg",
                                                "seam_step99", "within_step99", "folded"}));
    summary("synthesis: " + line);
    add_figure(ctx, {.mesh = file,
                     .caption = fmt::format("Synthesis (patches pasted along minimum-cut seams, lean along a "
                                            "direction field towards +{}): the tentacle texture grown over {}.",
                                            o.direction.z() > 0 ? "z" : "y", line),
                     .up = o.direction.z() > 0 ? "z" : "auto"});
  };

  SynthesisOptions o;
  o.direction = Vec3::UnitZ();
  o.scale = ctx.quick ? 0.6 : 0.4;  // quick: fewer, larger tentacles (fewer vertices after refinement)
  grow("sphere", "a sphere", icosphere(ctx.quick ? 4 : 5, 1.0), o);

  SynthesisOptions m;
  m.direction = Vec3::UnitY();
  m.exemplar_share = 0.15;  // ~85 000 vertices after refinement: drawn, and ~25 s each
  if (const auto spot = demo_model(ctx, "spot.obj"); !spot.empty()) grow("spot", "spot", read_mesh(spot), m);
  if (const auto cow = demo_model(ctx, "cow.obj"); !cow.empty())
    grow("cow", "the cow", read_mesh(cow), m);
  else if (!ctx.quick)
    summary("the cow of the shared data is not here: synthesis on the shipped spot only");
  if (ctx.quick) {
    const std::string note = "synthesis on real models skipped (--quick)";
    summary(note);
    r["notes"].push_back(note);
  }
  summary(fmt::format("{:.1f} s for the whole step",
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
}};

}  // namespace demo_synthesis
}  // namespace geotex::cli
