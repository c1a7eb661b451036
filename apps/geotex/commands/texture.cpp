// geotex texture extract|apply|edit|animate|transfer: height-and-tilt geometric texture (thesis ch. 8).

#include <chrono>
#include <cmath>
#include <future>
#include <memory>
#include <iostream>
#include <sstream>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/texture/texture.h"

namespace geotex::cli {

void add_texture_synthesize(CLI::App& texture);  // texture_synthesize.cpp

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Vec3 parse_vec3(const std::string& s, const char* what) {
  std::stringstream ss(s);
  Vec3 v;
  char c1 = 0, c2 = 0;
  if (!(ss >> v[0] >> c1 >> v[1] >> c2 >> v[2]) || c1 != ',' || c2 != ',' || !v.allFinite())
    throw InvalidInput(fmt::format("{}: expected three numbers like 1,0,0, got '{}'", what, s));
  std::string rest;
  if (ss >> rest) throw InvalidInput(fmt::format("{}: expected three numbers like 1,0,0, got '{}'", what, s));
  return v;
}

bool same_connectivity(const Mesh& a, const Mesh& b) {
  if (a.n_vertices() != b.n_vertices() || a.n_faces() != b.n_faces()) return false;
  return faces(a) == faces(b);
}

TextureFile load_texture(const std::string& path) {
  TextureFile f = read_texture(path);
  info(fmt::format("read texture {}: {} vertices, {} edges", path, f.base.n_vertices(), f.base.n_edges()));
  return f;
}

// ------------------------------------------------------------------------------------------------
struct ExtractArgs {
  std::string input, output, base, reconstructed, laplacian = "umbrella", solver = "iterative",
      fit = "tangential";
  bool project = false, bound = false;
  double fit_tolerance = TextureOptions().fit_tolerance;
  BaseShapeOptions base_opt;
};

void run_extract(const ExtractArgs& a) {
  check_output(a.input, a.output);
  const Mesh textured = load_mesh(a.input);
  const auto t0 = std::chrono::steady_clock::now();
  Mesh base;
  if (!a.base.empty()) {
    const Mesh given = load_mesh(a.base);
    if (!a.project && same_connectivity(given, textured)) {
      base = given;
      info("base: given, same connectivity (vertex correspondence)");
    } else {
      size_t missed = 0;
      base = project_onto_base(textured, given, &missed);
      info(fmt::format("base: textured vertices projected onto the given base along its Phong normals ({} of {} "
                       "without an inside solution took the closest point)",
                       missed, textured.n_vertices()));
    }
  } else {
    BaseShapeOptions o = a.base_opt;
    o.laplacian = a.laplacian == "cotan" ? LaplacianType::Cotangent : LaplacianType::Umbrella;
    o.progress = progress_printer("base shape");
    if (o.steps > 0) o.method = BaseMethod::Smoothing;  // a step count asks for the thesis' smoothing
    base = textured;
    const BaseShape b = base_shape(textured, o);
    set_positions(base, b.positions);
    if (o.method == BaseMethod::Smoothing)
      info(fmt::format("base: implicit {} smoothing, {} step(s) of lambda {}{}", a.laplacian, b.passes, o.lambda,
                       b.stopped ? "" : " (stopped at the step cap)"));
    else
      info(fmt::format("base: robust fit ({} fits), {:.0f} of {} vertices projected along the base normals",
                       b.passes, b.projected.sum(), textured.n_vertices()));
    info(fmt::format("base: displacements are a median {:.2f} deg off the base normal", b.median_off_normal_deg));
  }
  TextureOptions to;
  to.bound_tilt = a.bound;
  to.solver = a.solver == "direct" ? TiltSolver::Direct : TiltSolver::Iterative;
  to.fit_tolerance = a.fit_tolerance;
  to.tangential_fit = a.fit == "tangential";
  TextureCodec codec(base, to);
  const MatrixX3d X = positions(textured);
  const Texture tex = codec.extract(X);
  const TiltFitReport& fit = codec.last_fit();
  if (fit.iterative)
    info(fmt::format("tilt fit: iterative, {} CGLS iterations", fit.iterations));
  else
    info(fmt::format("tilt fit: direct (sparse Cholesky{}){}", to.tangential_fit && !to.bound_tilt ? ", vertex form" : "",
                     fit.iterations ? fmt::format("; the iterative fit stopped at {:.3g} mean edges after {} iterations",
                                                  fit.error, fit.iterations)
                                    : ""));
  const MatrixX3d Y = codec.apply(tex);
  const double h = mean_edge_length(base);
  info(fmt::format("extracted in {:.2f} s; reconstruction max error {:.3g} mean edges (height field alone: {:.3g})",
                   seconds_since(t0), (Y - X).rowwise().norm().maxCoeff() / h,
                   (codec.apply(height_field_only(tex)) - X).rowwise().norm().maxCoeff() / h));
  write_texture(a.output, base, tex);
  info("wrote " + a.output);
  if (!a.reconstructed.empty()) {
    Mesh out = base;
    set_positions(out, Y);
    save_mesh(out, a.reconstructed);
  }
}

// ------------------------------------------------------------------------------------------------
struct ApplyArgs {
  std::string input, output, base;
  bool height_only = false;
  double height_scale = 1.0;
};

void run_apply(const ApplyArgs& a) {
  check_output(a.input, a.output);
  TextureFile f = load_texture(a.input);
  Mesh base = f.base;
  if (!a.base.empty()) {
    base = load_mesh(a.base);
    if (!same_connectivity(base, f.base))
      throw InvalidInput(fmt::format("{}: the new base must have the texture's connectivity ({} vertices, {} faces)",
                                     a.base, f.base.n_vertices(), f.base.n_faces()));
  }
  Texture tex = scale_height(f.texture, a.height_scale);
  if (a.height_only) tex = height_field_only(tex);
  Mesh out = base;
  set_positions(out, apply_texture(base, tex));
  save_mesh(out, a.output);
}

// ------------------------------------------------------------------------------------------------
struct EditArgs {
  std::string input, output, op = "set-tilt", direction = "1,0,0", mesh;
  double angle = 30, wavelength = 0, phase = 0, factor = 1;
};

Texture edit_once(TextureCodec& codec, const Texture& tex, const std::string& op, const Vec3& dir, double angle,
                  double wavelength, double phase, double factor) {
  if (op == "set-tilt") return set_tilt(codec, tex, dir, angle);
  if (op == "wrap") return wrap(codec, tex, dir, angle);
  if (op == "wiggle") return wiggle(codec, tex, dir, angle, wavelength, phase);
  return scale_height(tex, factor);
}

double default_wavelength(const Mesh& base) { return 0.25 * bounding_box(base).diagonal(); }

void run_edit(const EditArgs& a) {
  check_output(a.input, a.output);
  TextureFile f = load_texture(a.input);
  TextureCodec codec(f.base);
  const Vec3 dir = parse_vec3(a.direction, "--direction");
  const double wl = a.wavelength > 0 ? a.wavelength : default_wavelength(f.base);
  const Texture out = edit_once(codec, f.texture, a.op, dir, a.angle, wl, a.phase, a.factor);
  write_texture(a.output, f.base, out);
  info("wrote " + a.output);
  if (!a.mesh.empty()) {
    Mesh m = f.base;
    set_positions(m, codec.apply(out));
    save_mesh(m, a.mesh);
  }
}

// ------------------------------------------------------------------------------------------------
struct AnimateArgs {
  std::string input, output, op = "wiggle", direction = "1,0,0", format = "ply";
  double angle = 30, wavelength = 0;
  int frames = 24;
};

void run_animate(const AnimateArgs& a) {
  TextureFile f = load_texture(a.input);
  AnimationOptions o;
  o.kind = parse_enum(animation_kind_names(), a.op, "--op");
  o.frames = a.frames;
  o.direction = parse_vec3(a.direction, "--direction");
  o.angle_deg = a.angle;
  o.wavelength = a.wavelength;
  const auto t0 = std::chrono::steady_clock::now();
  TextureAnimator animator(f.base, f.texture, o);
  // Frame k + 1 is computed while frame k is written.
  std::future<void> writing;
  for (int k = 0; k < a.frames; ++k) {
    auto m = std::make_shared<Mesh>(f.base);
    set_positions(*m, animator.positions(k));
    if (writing.valid()) writing.get();
    writing = std::async(std::launch::async, [m, path = fmt::format("{}_{:04d}.{}", a.output, k, a.format)] {
      save_mesh(*m, path);
    });
  }
  if (writing.valid()) writing.get();
  info(fmt::format("{} frames in {:.2f} s", a.frames, seconds_since(t0)));
}

// ------------------------------------------------------------------------------------------------
struct TransferArgs {
  std::string source, target, output, texture_out, source_near, target_near;
  TransferOptions opt;
};

int nearest_vertex(const Mesh& m, const Vec3& p) {
  int best = 0;
  double d = 1e300;
  for (auto v : m.vertices()) {
    const double e = (to_eigen(m.point(v)) - p).squaredNorm();
    if (e < d) { d = e; best = v.idx(); }
  }
  return best;
}

void run_transfer(const TransferArgs& a) {
  check_output(a.source, a.output);
  check_output(a.target, a.output);
  TextureFile src = load_texture(a.source);
  const Mesh target = load_mesh(a.target);
  TransferOptions opt = a.opt;
  if (!a.source_near.empty()) opt.source_center = nearest_vertex(src.base, parse_vec3(a.source_near, "--source-near"));
  if (!a.target_near.empty()) opt.target_center = nearest_vertex(target, parse_vec3(a.target_near, "--target-near"));
  if (opt.source_center < 0 || opt.target_center < 0)
    throw InvalidInput("transfer: give --source-center or --source-near, and --target-center or --target-near");
  const auto t0 = std::chrono::steady_clock::now();
  const TransferResult r = transfer_texture(src.base, src.texture, target, opt);
  for (const std::string& w : r.warnings) std::cerr << "geotex: warning: " << w << "\n";  // shown even when quiet
  info(fmt::format("transferred a {}-vertex source patch onto a {}-vertex target patch in {:.2f} s (heights x {:.4g})",
                   r.source_patch.vertices.size(), r.target_patch.vertices.size(), seconds_since(t0),
                   r.height_factor));
  Mesh out = r.target;
  set_positions(out, apply_texture(r.target, r.texture, opt.texture));
  save_mesh(out, a.output);
  if (!a.texture_out.empty()) {
    write_texture(a.texture_out, r.target, r.texture);
    info("wrote " + a.texture_out);
  }
}

Registrar reg{70, "texture", "height-and-tilt geometric texture: extract, apply, edit, animate, transfer (ch. 8)",
              [](CLI::App& app) {
  app.require_subcommand(1);

  {
    auto a = std::make_shared<ExtractArgs>();
    CLI::App* s = app.add_subcommand("extract", "extract a texture (pseudo-height per vertex, tilt per edge) from a textured mesh");
    s->add_option("IN", a->input, "textured mesh")->required()->check(ExistingMeshFile);
    s->add_option("-o,--output", a->output, "texture file (PLY: base mesh, vertex 'height', edge 'tilt')")->required();
    s->add_option("--base", a->base, "base mesh: same connectivity (used directly) or any (textured vertices are "
                                      "projected onto it along the Phong normal field)")->check(ExistingMeshFile);
    s->add_flag("--project", a->project, "project onto --base even when it has the same connectivity");
    s->add_option("--laplacian", a->laplacian, "no --base: smoothing Laplacian for the base shape (umbrella or cotan)")
        ->check(CLI::IsMember({"umbrella", "cotan"}))->capture_default_str();
    s->add_option("--lambda", a->base_opt.lambda, "no --base: implicit smoothing step size")
        ->check(CLI::PositiveNumber)->capture_default_str();
    s->add_option("--steps", a->base_opt.steps, "no --base: use the thesis' implicit smoothing for the base, with this many steps (0: the robust fit)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    s->add_option("--max-steps", a->base_opt.max_steps, "no --base, automatic: at most this many steps")
        ->check(CLI::PositiveNumber)->capture_default_str();
    s->add_option("--stop", a->base_opt.stop_tolerance,
                  "no --base, automatic: stop when a step moves no vertex more than this many mean edges")
        ->check(CLI::PositiveNumber)->capture_default_str();
    s->add_flag("--bound-tilt", a->bound, "keep |c_ij| <= |e_ij| in the tilt fit (Sec. 8.5; usually worse)");
    s->add_option("--tilt-solver", a->solver,
                  "tilt 1-form fit: iterative (CGLS to --fit-tolerance, falls back to direct) or direct (exact "
                  "sparse Cholesky; slower)")
        ->check(CLI::IsMember({"iterative", "direct"}))->capture_default_str();
    s->add_option("--tilt-fit", a->fit,
                  "what the tilt 1-form fits at each vertex: tangential (the tilt's tangent components, all that "
                  "decoding reads) or full (Eq. 5.81 as in the thesis: all three components of P c)")
        ->check(CLI::IsMember({"tangential", "full"}))->capture_default_str();
    s->add_option("--fit-tolerance", a->fit_tolerance,
                  "iterative: stop when every reconstructed vertex is within this many mean edge lengths")
        ->check(CLI::PositiveNumber)->capture_default_str();
    s->add_option("--reconstructed", a->reconstructed, "also write the surface rebuilt from the texture");
    s->callback([a] { run_extract(*a); });
  }
  {
    auto a = std::make_shared<ApplyArgs>();
    CLI::App* s = app.add_subcommand("apply", "apply a texture to its base, or to a deformed/rescaled base of the same connectivity");
    s->add_option("TEXTURE", a->input, "texture file")->required()->check(CLI::ExistingFile);
    s->add_option("-o,--output", a->output, "textured mesh")->required();
    s->add_option("--base", a->base, "new base with the texture's connectivity (default: the stored base)")
        ->check(ExistingMeshFile);
    s->add_option("--height-scale", a->height_scale, "multiply every height by this")->capture_default_str();
    s->add_flag("--height-only", a->height_only, "drop the tilt: a plain height field along the normals");
    s->callback([a] { run_apply(*a); });
  }
  {
    auto a = std::make_shared<EditArgs>();
    CLI::App* s = app.add_subcommand("edit", "edit a texture: set-tilt, wrap, wiggle, scale-height (Sec. 8.4.1)");
    s->add_option("TEXTURE", a->input, "texture file")->required()->check(CLI::ExistingFile);
    s->add_option("-o,--output", a->output, "edited texture file")->required();
    s->add_option("--op", a->op, "set-tilt | wrap | wiggle | scale-height")
        ->check(CLI::IsMember({"set-tilt", "wrap", "wiggle", "scale-height"}))->capture_default_str();
    s->add_option("--direction", a->direction, "lean direction x,y,z (projected onto each tangent plane)")
        ->capture_default_str();
    s->add_option("--angle", a->angle, "degrees: set-tilt lean, wrap bend at the highest point, wiggle amplitude")
        ->capture_default_str();
    s->add_option("--wavelength", a->wavelength, "wiggle: wavelength along the direction (0 = a quarter of the box diagonal)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    s->add_option("--phase", a->phase, "wiggle: phase in wavelengths")->capture_default_str();
    s->add_option("--factor", a->factor, "scale-height: factor")->capture_default_str();
    s->add_option("--mesh", a->mesh, "also write the textured surface");
    s->callback([a] { run_edit(*a); });
  }
  {
    auto a = std::make_shared<AnimateArgs>();
    CLI::App* s = app.add_subcommand("animate", "write a numbered frame sequence of an edit in motion (Fig. 8.7)");
    s->add_option("TEXTURE", a->input, "texture file")->required()->check(CLI::ExistingFile);
    s->add_option("-o,--output", a->output, "frame path prefix: frames are PREFIX_0000.EXT, PREFIX_0001.EXT, ...")->required();
    s->add_option("--op", a->op, "wiggle (travelling wave) | wrap (sway) | grow (heights 0 -> 1 -> 0)")
        ->check(CLI::IsMember({"wiggle", "wrap", "grow"}))->capture_default_str();
    s->add_option("--frames", a->frames, "number of frames")->check(CLI::Range(1, 100000))->capture_default_str();
    s->add_option("--direction", a->direction, "direction x,y,z")->capture_default_str();
    s->add_option("--angle", a->angle, "degrees: wave amplitude or sway angle")->capture_default_str();
    s->add_option("--wavelength", a->wavelength, "wiggle wavelength (0 = a quarter of the box diagonal)")
        ->check(CLI::NonNegativeNumber)->capture_default_str();
    s->add_option("--format", a->format, "frame file format")->check(CLI::IsMember({"ply", "obj", "off", "stl"}))
        ->capture_default_str();
    s->callback([a] { run_animate(*a); });
  }
  {
    auto a = std::make_shared<TransferArgs>();
    CLI::App* s = app.add_subcommand("transfer", "transfer a disk patch of a texture onto a disk patch of another base (Sec. 8.3.3)");
    s->add_option("TEXTURE", a->source, "source texture file")->required()->check(CLI::ExistingFile);
    s->add_option("TARGET", a->target, "target base mesh")->required()->check(ExistingMeshFile);
    s->add_option("-o,--output", a->output, "textured target mesh")->required();
    a->opt.source_center = a->opt.target_center = -1;
    auto sc = s->add_option("--source-center", a->opt.source_center, "source base vertex at the patch centre")
        ->check(CLI::NonNegativeNumber);
    s->add_option("--source-near", a->source_near, "or: the source vertex nearest to x,y,z")->excludes(sc);
    s->add_option("--source-radius", a->opt.source_radius, "geodesic radius of the source patch")->required()
        ->check(CLI::PositiveNumber);
    auto tc = s->add_option("--target-center", a->opt.target_center, "target vertex at the patch centre")
        ->check(CLI::NonNegativeNumber);
    s->add_option("--target-near", a->target_near, "or: the target vertex nearest to x,y,z")->excludes(tc);
    s->add_option("--height-scale", a->opt.height_scale, "multiply the transferred heights, on top of the ratio of the radii")
        ->capture_default_str();
    s->add_option("--target-radius", a->opt.target_radius, "geodesic radius of the target patch")->required()
        ->check(CLI::PositiveNumber);
    s->add_option("--rotation", a->opt.rotation_deg, "rotate the source disk by this many degrees")->capture_default_str();
    s->add_option("--texture-out", a->texture_out, "also write the target's texture file");
    s->callback([a] { run_transfer(*a); });
  }
  add_texture_synthesize(app);  // texture_synthesize.cpp
}};

}  // namespace
}  // namespace geotex::cli
