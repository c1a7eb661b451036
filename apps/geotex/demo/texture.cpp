// Demo step for the height-and-tilt texture (thesis ch. 8): extract from a spiky sphere, compare with a
// height field, edit (set tilt, wrap, wiggle), re-apply to a stretched base, transfer a patch to a sphere.

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/phong_projection.h"
#include "geotex/tools/shapes.h"
#include "geotex/texture/results.h"
#include "geotex/texture/texture.h"
#include "geotex/texture/transfer.h"

namespace geotex::cli {
namespace demo_texture {  // named, not anonymous: a unity build compiles several commands in one unit

// The vertex of \p mesh whose direction from the origin is nearest to \p dir.
int vertex_towards(const Mesh& mesh, const Vec3& dir) {
  const MatrixX3d V = positions(mesh);
  Eigen::Index best = 0;
  (V * dir.normalized()).maxCoeff(&best);
  return static_cast<int>(best);
}

// A summary line of the step's report.
void summary(const DemoContext& ctx, const std::string& s) { (*ctx.report)["summary"].push_back(s); }

// Writes \p base with positions \p X to the step's folder as \p name, listed in the report.
void save(const DemoContext& ctx, const Mesh& base, const MatrixX3d& X, const std::string& name) {
  Mesh m = base;
  set_positions(m, X);
  save_mesh(m, (ctx.dir / name).string());
  (*ctx.report)["files"].push_back((ctx.dir / name).string());
}

// The spiky sphere's texture re-applied, with its tilt and as a height field alone.
// \p e: the extraction over the given base, as `texture extract --base` reports it (the figures as it names them).
void round_trip(const DemoContext& ctx, const TexturedShape& s, TextureCodec& codec, const TextureExtraction& e) {
  nlohmann::json& r = *ctx.report;
  const MatrixX3d X = positions(s.textured);
  const Texture& tex = e.texture;
  write_texture(ctx.dir / "spiky-texture.ply", s.base, tex);
  save(ctx, s.base, X, "texture-original.ply");
  save(ctx, s.base, codec.apply(height_field_only(tex)), "texture-height-field-only.ply");
  const auto& table = texture_extraction_results();
  summary(ctx, fmt::format("texture round trip on spiky-sphere ({} vertices): {}", s.base.n_vertices(),
                           table.figures(e, {"max_error", "height_only_error", "fit_iterative", "fit_iterations"})));
  r["texture"] = table.report(e);
  add_figure(ctx, {.mesh = "texture-original.ply",
                   .caption = fmt::format("Spiky sphere ({} vertices), leaning spikes: extracted as height and tilt "
                                          "(Eq. 8.4&ndash;8.7) over its smooth base and re-applied: {}.",
                                          s.base.n_vertices(), table.figures(e, {"max_error"})),
                   .compare = "texture"});
  add_figure(ctx, {.mesh = "texture-height-field-only.ply",
                   .caption = fmt::format("The same texture as a height field alone (tilt dropped): the spikes stand "
                                          "upright; {}. A height field cannot lean.",
                                          table.figures(e, {"height_only_error"})),
                   .compare = "texture"});
}

// The edits of Sec. 8.4.1 applied to the spiky sphere's texture.
void edits(const DemoContext& ctx, const TexturedShape& s, TextureCodec& codec, const Texture& tex) {
  save(ctx, s.base, codec.apply(set_tilt(codec, tex, Vec3(0, 0, 1), 40)), "texture-set-tilt.ply");
  save(ctx, s.base, codec.apply(wrap(codec, set_tilt(codec, tex, Vec3(0, 0, 1), 0), Vec3(0, 0, 1), 70)), "texture-wrap.ply");
  save(ctx, s.base, codec.apply(wiggle(codec, tex, Vec3(1, 0, 0), 40, 0.7, 0.0)), "texture-wiggle.ply");
  summary(ctx, "texture edits written: set tilt (40 deg towards +z), wrap (70 deg), wiggle (40 deg, wavelength 0.7)");
  add_figure(ctx, {.mesh = "texture-set-tilt.ply", .caption = "Edit (Sec. 8.4.1): every spike tilted 40&deg; towards +z.",
                   .compare = "texture"});
  add_figure(ctx, {.mesh = "texture-wrap.ply", .caption = "Edit: spikes set upright, then wrapped 70&deg; about +z.",
                   .compare = "texture"});
  add_figure(ctx, {.mesh = "texture-wiggle.ply",
                   .caption = "Edit: wiggle, the lean turned by up to 40&deg; in a wave of wavelength 0.7 along x.",
                   .compare = "texture"});
}

// The texture re-applied to a stretched base (Sec. 8.4.2): the spikes keep their size; beside it the naive stretch.
void stretched_base(const DemoContext& ctx, const TexturedShape& s, const Texture& tex) {
  const MatrixX3d X = positions(s.textured);
  Mesh stretched = s.base;
  MatrixX3d B = positions(s.base);
  B.col(0) *= 1.6;
  set_positions(stretched, B);
  save(ctx, stretched, apply_texture(stretched, tex), "texture-on-stretched-base.ply");
  MatrixX3d naive = X;
  naive.col(0) *= 1.6;
  save(ctx, stretched, naive, "texture-stretched-naively.ply");
  summary(ctx, "texture re-applied to a base stretched 1.6x along x (spikes keep their size), beside the naive stretch");
  add_figure(ctx, {.mesh = "texture-on-stretched-base.ply",
                   .caption = "The texture re-applied to the base stretched 1.6&times; along x (Sec. 8.4.2): the spikes "
                              "keep their size and shape.",
                   .compare = "texture-stretch"});
  add_figure(ctx, {.mesh = "texture-stretched-naively.ply",
                   .caption = "The textured sphere stretched 1.6&times; naively: the spikes are stretched with it.",
                   .compare = "texture-stretch"});
}

// A patch of the tentacle plate transferred onto a sphere (Sec. 8.3.3). The target patch faces the
// picture's iso camera at 55° from its axis, so that the tentacles stand out against the background.
void transfer_to_sphere(const DemoContext& ctx) {
  const TexturedShape p = make_shape("tentacle-plane", 0);
  TextureCodec pc(p.base);
  const Texture ptex = pc.extract(positions(p.textured));
  const Mesh sphere = icosphere(ctx.quick ? 3 : 4, 1.0);
  const Vec3 iso = Vec3(1, -1, 1).normalized();
  const Vec3 tilt = (Vec3::UnitZ() - iso.z() * iso).normalized();
  const double a = 55 * M_PI / 180;
  TransferOptions o;
  {  // the plate's centre
    const MatrixX3d P = positions(p.base);
    Eigen::Index c = 0;
    P.rowwise().norm().minCoeff(&c);
    o.source_center = static_cast<int>(c);
  }
  o.source_radius = 1.5;
  o.target_center = vertex_towards(sphere, std::cos(a) * iso + std::sin(a) * tilt);
  o.target_radius = 0.9;
  const TransferResult tr = transfer_texture(p.base, ptex, sphere, o);
  save(ctx, tr.target, apply_texture(tr.target, tr.texture), "texture-transferred-to-sphere.ply");
  save(ctx, p.base, positions(p.textured), "texture-tentacle-plate.ply");
  // The figures as `texture transfer --report` and Python name them (results.h: figures()).
  const std::string figures = transfer_results().figures(
      tr, {"source_vertices", "target_vertices", "added_vertices", "excess_folded", "excess_self_intersecting"});
  const std::string transfer_line = fmt::format(
      "texture patch of the tentacle plate (radius {}) transferred to a sphere patch (radius {}) via conformal maps: {}",
      o.source_radius, o.target_radius, figures);
  summary(ctx, transfer_line);
  add_figure(ctx, {.mesh = "texture-tentacle-plate.ply",
                   .caption = "Source of the transfers: the tentacle plate, 3&times;3 curved tentacles leaning to +x "
                              "(no height field holds them)."});
  add_figure(ctx, {.mesh = "texture-transferred-to-sphere.ply",
                   .caption = fmt::format("Transfer (Sec. 8.3.3): a geodesic disk of radius {} of the plate onto a disk "
                                          "of radius {} of a sphere, through conformal maps; {}.",
                                          o.source_radius, o.target_radius, figures)});
}

// The whole sphere covered with copies of one disk of the spiky plate (an atlas of disks pasted along minimum cuts).
void atlas_sphere(const DemoContext& ctx) {
  const TexturedShape sp = make_shape("spiky-plane", ctx.quick ? 0 : 1);
  TextureCodec sc(sp.base);
  const Texture stex = sc.extract(positions(sp.textured));
  AtlasOptions ao;
  {  // the plate's centre
    const MatrixX3d P = positions(sp.base);
    Eigen::Index c = 0;
    P.rowwise().norm().minCoeff(&c);
    ao.source_center = static_cast<int>(c);
  }
  ao.source_radius = 0.3;
  ao.target_radius = 0.6;
  const Mesh ball = icosphere(ctx.quick ? 3 : 4, 1.0);
  const AtlasResult at = cover_with_texture(sp.base, stex, ball, ao);
  Mesh covered = at.target;
  set_positions(covered, apply_texture(at.target, at.texture));
  PlyExtras ax;
  Eigen::VectorXd owner = at.owner.cast<double>();
  ax.vertex_scalars["disk"] = std::vector<double>(owner.data(), owner.data() + owner.size());
  write_ply(covered, ctx.dir / "texture-atlas-sphere.ply", ax);
  const std::string figures = atlas_results().figures(
      at, {"disks", "vertices", "added_vertices", "excess_folded", "excess_self_intersecting"});
  summary(ctx, fmt::format("atlas: the whole sphere covered by disks of radius {} holding copies of a spiky-plate "
                           "disk (radius {}): {}", ao.target_radius, ao.source_radius, figures));
  add_figure(ctx, {.mesh = "texture-atlas-sphere.ply",
                   .caption = fmt::format("Atlas: the whole sphere covered by overlapping geodesic disks, each a copy "
                                          "of one disk of the spiky plate, pasted along minimum cuts where they overlap "
                                          "(the 3D page colours each vertex by its disk): {}.", figures)});
}

DemoRegistrar texture_step{80, "height-and-tilt texture", [](const DemoContext& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  const TexturedShape s = make_shape("spiky-sphere", ctx.quick ? 0 : 1);
  TextureCodec codec(s.base);
  const TextureExtraction e = texture_extraction(s.textured, &s.base);
  const Texture& tex = e.texture;
  round_trip(ctx, s, codec, e);
  edits(ctx, s, codec, tex);
  stretched_base(ctx, s, tex);
  transfer_to_sphere(ctx);
  atlas_sphere(ctx);
  summary(ctx, fmt::format("{:.1f} s for the whole step",
                           std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
}};

}  // namespace demo_texture
}  // namespace geotex::cli
