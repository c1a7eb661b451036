// geotex texture extract|apply|edit|animate|transfer|atlas: height-and-tilt geometric texture (thesis ch. 8).
//
// Every option is a flag made from the library's option tables (TextureExtractOptions, TextureApplyOptions,
// TextureEditOptions, AnimationOptions, TransferOptions, AtlasOptions); only the files and the points that
// stand for vertices are written here. The files of a run are declared before any work (an output that
// names an input is refused) and put in place together at the end.

#include <sys/resource.h>

#include <chrono>
#include <future>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/texture/results.h"
#include "geotex/texture/texture.h"
#include "geotex/texture/transfer.h"
#include "option_flags.h"

namespace geotex::cli {

void add_texture_synthesize(CLI::App& texture);  // texture_synthesize.cpp

namespace cmd_texture {  // named, not anonymous: a unity build compiles several commands in one unit

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TextureFile load_texture(const std::string& path) {
  TextureFile f = read_texture(path);
  info(fmt::format("read texture {}: {} vertices, {} edges", path, f.base.n_vertices(), f.base.n_edges()));
  return f;
}

Mesh with_positions(Mesh mesh, const MatrixX3d& X) {
  set_positions(mesh, X);
  return mesh;
}

void warn(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) std::cerr << "geotex: warning: " << w << "\n";  // shown even when quiet
}

// Point flags (--source-near X,Y,Z) stand for the nearest vertex; they exclude the vertex flag.
void add_near(CLI::App& s, std::string& value, const std::string& which, const std::string& what) {
  s.add_option("--" + which + "-near", value, fmt::format("or: the {} vertex nearest to this point", what))
      ->type_name("X,Y,Z")
      ->excludes(s.get_option("--" + which + "-center"));
}

// The point of a --*-near flag (parsed before any work), or none.
std::optional<Vec3> near_point(const std::string& text, const std::string& which) {
  if (text.empty()) return std::nullopt;
  OptionInfo point;
  point.name = which + "_near";
  point.kind = OptionKind::Vec3;
  return std::get<Vec3>(parse_option_value(point, text));
}

int center_of(const Mesh& mesh, int center, const std::optional<Vec3>& near, const std::string& which) {
  if (!near) return center;
  const int v = nearest_vertex(mesh, *near);
  info(fmt::format("{} centre: vertex {}, the nearest to ({:g}, {:g}, {:g})", which, v, (*near)[0], (*near)[1], (*near)[2]));
  return v;
}

// ------------------------------------------------------------------------------------------------
struct ExtractFiles {
  std::string input, output, base, reconstructed, report;
};

void run_extract(const ExtractFiles& a, const FlagSet& flags) {
  TextureExtractOptions o = flags.resolve<TextureExtractOptions>("extract");
  // The automatic base's options mean nothing with a given base, and projection onto it nothing without.
  for (const auto& f : BaseShapeOptions::table().fields())
    if (!a.base.empty() && flags.given(f.info.name))
      throw InvalidOption(fmt::format("{} sets the automatic base; it does not apply with --base", f.info.cli_flag()));
  if (a.base.empty() && flags.given("project_onto_base"))
    throw InvalidOption("--project-onto-base needs --base");
  Outputs out({a.input, a.base}, {{a.output, "-o"}, {a.reconstructed, "--reconstructed"}, {a.report, "--report"}});
  const Mesh textured = load_mesh(a.input);
  Mesh base;
  if (!a.base.empty()) base = load_mesh(a.base);
  o.base.progress = progress_printer("base shape");
  const auto t0 = std::chrono::steady_clock::now();
  const TextureExtraction r = texture_extraction(textured, a.base.empty() ? nullptr : &base, o);
  const double seconds = seconds_since(t0);
  switch (r.source) {
    case BaseSource::Given: info("base: given, same connectivity (vertex correspondence)"); break;
    case BaseSource::Projected:
      info(fmt::format("base: textured vertices projected onto the given base along its Phong normals ({} of {} "
                       "without an inside solution took the closest point)",
                       r.missed, textured.n_vertices()));
      break;
    case BaseSource::Automatic:
      if (o.base.method == BaseMethod::Smoothing || o.base.steps > 0)
        info(fmt::format("base: implicit {} smoothing, {} step(s) of lambda {}{}",
                         enum_name(laplacian_names(), o.base.laplacian), r.shape.passes, o.base.lambda,
                         r.shape.stopped ? "" : " (stopped at the step cap)"));
      else
        info(fmt::format("base: robust fit ({} fits), {:.0f} of {} vertices projected along the base normals",
                         r.shape.passes, r.shape.projected.sum(), textured.n_vertices()));
      break;
  }
  info(fmt::format("base: displacements are a median {:.2f} deg off the base normal", r.median_off_normal_deg));
  if (r.fit.iterative)
    info(fmt::format("tilt fit: iterative, {} CGLS iterations", r.fit.iterations));
  else
    info(fmt::format("tilt fit: direct (sparse Cholesky{}){}",
                     o.texture.tangential_fit && !o.texture.bound_tilt ? ", vertex form" : "",
                     r.fit.iterations ? fmt::format("; the iterative fit stopped at {:.3g} mean edges after {} iterations",
                                                    r.fit.error, r.fit.iterations)
                                      : ""));
  info(fmt::format("extracted in {:.2f} s; reconstruction max error {:.3g} mean edges (height field alone: {:.3g}); "
                   "the base keeps {:.1f}% of the surface's area",
                   seconds, r.max_error, r.height_only_error, 100 * r.base_area_ratio));
  warn(r.warnings);
  write_texture(a.output, r.base, r.texture);
  info("wrote " + a.output);
  if (!a.reconstructed.empty()) save_mesh(with_positions(r.base, apply_texture(r.base, r.texture, o.texture)), a.reconstructed);
  if (!a.report.empty()) write_report(a.report, texture_extraction_results().report(r), seconds, options_json(o));
  out.commit();
}

// ------------------------------------------------------------------------------------------------
struct ApplyFiles {
  std::string input, output, base;
  bool ascii = false;
};

void run_apply(const ApplyFiles& a, const FlagSet& flags) {
  const TextureApplyOptions o = flags.resolve<TextureApplyOptions>("apply");
  Outputs out({a.input, a.base}, {{a.output, "-o"}});
  const TextureFile f = load_texture(a.input);
  Mesh base = f.base;
  if (!a.base.empty()) {
    base = load_mesh(a.base);
    if (base.n_vertices() != f.base.n_vertices() || faces(base) != faces(f.base))
      throw InvalidInput(fmt::format("{}: the new base must have the texture's connectivity ({} vertices, {} faces)",
                                     a.base, f.base.n_vertices(), f.base.n_faces()));
  }
  save_mesh(with_positions(base, apply_texture(base, f.texture, o)), a.output, !a.ascii);
  out.commit();
}

// ------------------------------------------------------------------------------------------------
struct EditFiles {
  std::string input, output, mesh;
};

void run_edit(const EditFiles& a, const FlagSet& flags) {
  const TextureEditOptions o = flags.resolve<TextureEditOptions>("edit");
  Outputs out({a.input}, {{a.output, "-o"}, {a.mesh, "--mesh"}});
  const TextureFile f = load_texture(a.input);
  const auto t0 = std::chrono::steady_clock::now();
  const Texture edited = edit_texture(f.base, f.texture, o);
  info(fmt::format("{} in {:.2f} s", enum_name(texture_edit_names(), o.op), seconds_since(t0)));
  write_texture(a.output, f.base, edited);
  info("wrote " + a.output);
  if (!a.mesh.empty()) save_mesh(with_positions(f.base, apply_texture(f.base, edited, o.texture)), a.mesh);
  out.commit();
}

// ------------------------------------------------------------------------------------------------
struct AnimateFiles {
  std::string input, prefix, format = "ply";
};

// Every frame's temporary stays open until the frames are put in place together (two descriptors each:
// the file and its folder): raise the soft limit on open files when the frames need more.
void allow_open_files(size_t needed) {
  rlimit lim{};
  if (::getrlimit(RLIMIT_NOFILE, &lim) != 0 || lim.rlim_cur == RLIM_INFINITY || lim.rlim_cur >= needed) return;
  const rlim_t want = lim.rlim_max == RLIM_INFINITY ? needed : std::min<rlim_t>(lim.rlim_max, needed);
  lim.rlim_cur = want;
  if (::setrlimit(RLIMIT_NOFILE, &lim) != 0 || want < needed)
    throw InvalidOption(fmt::format("--frames: {} frames need about {} open files; the limit here is {} (ulimit -n)",
                                    (needed - 64) / 2, needed, want));
}

void run_animate(const AnimateFiles& a, const FlagSet& flags) {
  const AnimationOptions o = flags.resolve<AnimationOptions>("animate");
  std::vector<std::string> paths;
  for (int k = 0; k < o.frames; ++k) paths.push_back(fmt::format("{}_{:04d}.{}", a.prefix, k, a.format));
  allow_open_files(2 * paths.size() + 64);
  Outputs out({a.input}, {});
  for (int k = 0; k < o.frames; ++k) out.output(paths[k], fmt::format("-o (frame {})", k));
  const TextureFile f = load_texture(a.input);
  const auto t0 = std::chrono::steady_clock::now();
  TextureAnimator animator(f.base, f.texture, o);
  const double t_setup = seconds_since(t0);
  const ProgressFn progress = progress_printer("animate");
  // Frame k + 1 is computed while frame k is written; writing stays on this thread, whose
  // transaction holds the outputs.
  std::future<MatrixX3d> next = std::async(std::launch::async, [&] { return animator.positions(0); });
  for (int k = 0; k < o.frames; ++k) {
    const MatrixX3d X = next.get();
    if (k + 1 < o.frames) next = std::async(std::launch::async, [&animator, k] { return animator.positions(k + 1); });
    write_mesh(with_positions(f.base, X), paths[k]);
    report(progress, double(k + 1) / o.frames, "frames");
  }
  info(fmt::format("{} frames in {:.2f} s (set-up {:.2f} s), {} .. {}", o.frames, seconds_since(t0), t_setup,
                   paths.front(), paths.back()));
  out.commit();
}

// ------------------------------------------------------------------------------------------------
struct TransferFiles {
  std::string source, target, output, texture_out, source_near, target_near, report;
};

std::string damage_line(const TextureDamage& d) {
  return fmt::format("damage: {} folded, {} self-intersecting faces (the bare target's own: {}, {})", d.folded,
                     d.self_intersecting, d.base_folded, d.base_self_intersecting);
}

void run_transfer(const TransferFiles& a, const FlagSet& flags) {
  TransferOptions o = flags.resolve<TransferOptions>("transfer");
  const auto source_near = near_point(a.source_near, "source"), target_near = near_point(a.target_near, "target");
  Outputs out({a.source, a.target}, {{a.output, "-o"}, {a.texture_out, "--texture-out"}, {a.report, "--report"}});
  const TextureFile src = load_texture(a.source);
  const Mesh target = load_mesh(a.target);
  o.source_center = center_of(src.base, o.source_center, source_near, "source");
  o.target_center = center_of(target, o.target_center, target_near, "target");
  o.progress = progress_printer("transfer");
  const auto t0 = std::chrono::steady_clock::now();
  const TransferResult r = transfer_texture(src.base, src.texture, target, o);
  const double seconds = seconds_since(t0);
  warn(r.warnings);
  info(fmt::format("transferred a {}-vertex source patch onto a {}-vertex target patch in {:.2f} s (heights x {:.4g})",
                   r.source_patch.vertices.size(), r.target_patch.vertices.size(), seconds,
                   r.height_factor));
  info(damage_line(r.damage));
  save_mesh(with_positions(r.target, apply_texture(r.target, r.texture, o.texture)), a.output);
  if (!a.texture_out.empty()) {
    write_texture(a.texture_out, r.target, r.texture);
    info("wrote " + a.texture_out);
  }
  if (!a.report.empty()) write_report(a.report, transfer_results().report(r), seconds, options_json(o));
  out.commit();
}

// ------------------------------------------------------------------------------------------------
struct AtlasFiles {
  std::string source, target, output, texture_out, source_near, report;
};

void run_atlas(const AtlasFiles& a, const FlagSet& flags) {
  AtlasOptions o = flags.resolve<AtlasOptions>("atlas");
  const auto source_near = near_point(a.source_near, "source");
  Outputs out({a.source, a.target}, {{a.output, "-o"}, {a.texture_out, "--texture-out"}, {a.report, "--report"}});
  const TextureFile src = load_texture(a.source);
  const Mesh target = load_mesh(a.target);
  o.source_center = center_of(src.base, o.source_center, source_near, "source");
  o.progress = progress_printer("atlas");
  const auto t0 = std::chrono::steady_clock::now();
  const AtlasResult r = cover_with_texture(src.base, src.texture, target, o);
  const double seconds = seconds_since(t0);
  warn(r.warnings);
  const nlohmann::json report = atlas_results().report(r);  // the counts, as --report and Python have them
  info(fmt::format("covered a {}-vertex target with {} disks in {:.2f} s (heights x {:.4g}; {} vertices uncovered)",
                   r.target.n_vertices(), r.centers.size(), seconds, r.height_factor, report["uncovered"].get<int>()));
  info(damage_line(r.damage));
  save_mesh(with_positions(r.target, apply_texture(r.target, r.texture, o.texture)), a.output);
  if (!a.texture_out.empty()) {
    write_texture(a.texture_out, r.target, r.texture);
    info("wrote " + a.texture_out);
  }
  if (!a.report.empty()) write_report(a.report, report, seconds, options_json(o));
  out.commit();
}

// The subcommand's options from \p table, owned by \p owner; \p required flags must be given.
template <class O>
std::shared_ptr<FlagSet> table_flags(CLI::App& s, const std::string& owner, std::initializer_list<const char*> required = {}) {
  auto flags = std::make_shared<FlagSet>(s);
  flags->add(owner, O::table());
  for (const char* name : required) s.get_option(name)->required();
  return flags;
}

Registrar reg{70, "texture", "height-and-tilt geometric texture (ch. 8)", [](CLI::App& app) {
  app.require_subcommand(1);
  {
    auto a = std::make_shared<ExtractFiles>();
    CLI::App* s = app.add_subcommand(
        "extract", "extract a texture (pseudo-height per vertex, tilt per edge) from a textured mesh (Sec. 8.3)");
    s->footer("Without --base the base is found automatically (the base-* options, --laplacian, --lambda, --steps, "
              "--max-steps, --stop, --outlier, --robust-passes, --project, --size-share, --hold-boundary; --steps N > 0 "
              "asks for the thesis' "
              "smoothing). --preset thesis: the thesis' base and encoding.");
    s->add_option("IN", a->input, "textured mesh")->required()->check(ExistingMeshFile);
    s->add_option("-o,--output", a->output, "texture file (PLY: base mesh, vertex 'height' and 'lean', edge 'tilt')")
        ->required()
        ->check(TextureOutputFile);
    s->add_option("--base", a->base, "base mesh: same connectivity (used vertex for vertex) or any (textured vertices "
                                      "are projected onto it along its Phong normals)")
        ->check(ExistingMeshFile);
    s->add_option("--reconstructed", a->reconstructed, "also write the surface rebuilt from the texture")
        ->check(MeshOutputFile);
    s->add_option("--report", a->report, "write how the base was found and how well the texture rebuilds the "
                                         "surface as JSON");
    auto flags = table_flags<TextureExtractOptions>(*s, "extract");
    s->callback([a, flags] { run_extract(*a, *flags); });
  }
  {
    auto a = std::make_shared<ApplyFiles>();
    CLI::App* s = app.add_subcommand(
        "apply", "apply a texture to its base, or to a deformed/rescaled base of the same connectivity (Sec. 8.4.2)");
    s->add_option("TEXTURE", a->input, "texture file")->required()->check(ExistingFile);
    s->add_option("-o,--output", a->output, "textured mesh")->required()->check(MeshOutputFile);
    s->add_option("--base", a->base, "new base with the texture's connectivity (default: the stored base)")
        ->check(ExistingMeshFile);
    s->add_flag("--ascii", a->ascii, "ascii PLY/STL output");
    auto flags = table_flags<TextureApplyOptions>(*s, "apply");
    s->callback([a, flags] { run_apply(*a, *flags); });
  }
  {
    auto a = std::make_shared<EditFiles>();
    CLI::App* s = app.add_subcommand("edit", "edit a texture: set-tilt, wrap, wiggle, scale-height (Sec. 8.4.1)");
    s->add_option("TEXTURE", a->input, "texture file")->required()->check(ExistingFile);
    s->add_option("-o,--output", a->output, "edited texture file")->required()->check(TextureOutputFile);
    s->add_option("--mesh", a->mesh, "also write the textured surface")->check(MeshOutputFile);
    auto flags = table_flags<TextureEditOptions>(*s, "edit");
    s->callback([a, flags] { run_edit(*a, *flags); });
  }
  {
    auto a = std::make_shared<AnimateFiles>();
    CLI::App* s = app.add_subcommand("animate", "write a numbered frame sequence of an edit in motion (Fig. 8.7)");
    s->add_option("TEXTURE", a->input, "texture file")->required()->check(ExistingFile);
    s->add_option("-o,--output", a->prefix, "frame path prefix: frames are PREFIX_0000.EXT, PREFIX_0001.EXT, ...")
        ->required();
    s->add_option("--format", a->format, "frame file format")
        ->check(CLI::IsMember({"ply", "obj", "off", "stl"}))
        ->capture_default_str();
    auto flags = table_flags<AnimationOptions>(*s, "animate");
    s->callback([a, flags] { run_animate(*a, *flags); });
  }
  {
    auto a = std::make_shared<TransferFiles>();
    CLI::App* s = app.add_subcommand(
        "transfer", "transfer a disk patch of a texture onto a disk patch of another base (Sec. 8.3.3)");
    s->add_option("TEXTURE", a->source, "source texture file")->required()->check(ExistingFile);
    s->add_option("TARGET", a->target, "target base mesh")->required()->check(ExistingMeshFile);
    s->add_option("-o,--output", a->output, "textured target mesh")->required()->check(MeshOutputFile);
    s->add_option("--texture-out", a->texture_out, "also write the target's texture file")->check(TextureOutputFile);
    s->add_option("--report", a->report, "write the transfer's counts (patches, refinement, damage) as JSON");
    auto flags = table_flags<TransferOptions>(*s, "transfer", {"--source-radius", "--target-radius"});
    add_near(*s, a->source_near, "source", "source base");
    add_near(*s, a->target_near, "target", "target");
    s->callback([a, flags] { run_transfer(*a, *flags); });
  }
  {
    auto a = std::make_shared<AtlasFiles>();
    CLI::App* s = app.add_subcommand(
        "atlas", "cover a whole surface with copies of one texture disk, cut (or blended) where they overlap");
    s->add_option("TEXTURE", a->source, "source texture file")->required()->check(ExistingFile);
    s->add_option("TARGET", a->target, "target base mesh")->required()->check(ExistingMeshFile);
    s->add_option("-o,--output", a->output, "textured target mesh")->required()->check(MeshOutputFile);
    s->add_option("--texture-out", a->texture_out, "also write the target's texture file")->check(TextureOutputFile);
    s->add_option("--report", a->report, "write the atlas' counts (disks, refinement, damage) as JSON");
    auto flags = table_flags<AtlasOptions>(*s, "atlas", {"--source-radius"});
    add_near(*s, a->source_near, "source", "source base");
    s->callback([a, flags] { run_atlas(*a, *flags); });
  }
  add_texture_synthesize(app);  // texture_synthesize.cpp
  // The subcommands named in the description (`geotex --help`, `geotex texture --help`) are the ones added.
  std::string names;
  for (const CLI::App* s : app.get_subcommands([](CLI::App*) { return true; }))
    names += (names.empty() ? ": " : ", ") + s->get_name();
  app.description(app.get_description() + names);
}};

}  // namespace cmd_texture
}  // namespace geotex::cli
