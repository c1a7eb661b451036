// Demo step for the height-and-tilt texture (thesis ch. 8): extract from a spiky sphere, compare with a
// height field, edit (set tilt, wrap, wiggle), re-apply to a stretched base, transfer a patch to a sphere.

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/phong_projection.h"
#include "geotex/tools/shapes.h"
#include "geotex/texture/texture.h"

namespace geotex::cli {
namespace {

DemoRegistrar texture_step{80, "height-and-tilt texture", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  auto summary = [&](const std::string& s) { r["summary"].push_back(s); };
  auto save = [&](const Mesh& base, const MatrixX3d& X, const std::string& name) {
    Mesh m = base;
    set_positions(m, X);
    save_mesh(m, (ctx.dir / name).string());
    r["files"].push_back((ctx.dir / name).string());
  };
  const auto t0 = std::chrono::steady_clock::now();
  const TexturedShape s = make_shape("spiky-sphere", 1);
  const double h = mean_edge_length(s.base);
  TextureCodec codec(s.base);
  const MatrixX3d X = positions(s.textured);
  const Texture tex = codec.extract(X);
  const double err = (codec.apply(tex) - X).rowwise().norm().maxCoeff() / h;
  const double err_h = (codec.apply(height_field_only(tex)) - X).rowwise().norm().maxCoeff() / h;
  write_texture(ctx.dir / "spiky-texture.ply", s.base, tex);
  save(s.base, X, "texture-original.ply");
  save(s.base, codec.apply(height_field_only(tex)), "texture-height-field-only.ply");
  const TiltFitReport fit = codec.last_fit();
  summary(fmt::format("texture round trip on spiky-sphere ({} vertices): max error {:.2e} mean edges with tilt, {:.2f} "
                      "as a height field alone (tilt fit: {})",
                      s.base.n_vertices(), err, err_h,
                      fit.iterative ? fmt::format("iterative, {} CGLS iterations", fit.iterations) : "direct"));
  r["texture"] = {{"round_trip_error_edges", err}, {"height_only_error_edges", err_h}};

  save(s.base, codec.apply(set_tilt(codec, tex, Vec3(0, 0, 1), 40)), "texture-set-tilt.ply");
  save(s.base, codec.apply(wrap(codec, set_tilt(codec, tex, Vec3(0, 0, 1), 0), Vec3(0, 0, 1), 70)), "texture-wrap.ply");
  save(s.base, codec.apply(wiggle(codec, tex, Vec3(1, 0, 0), 40, 0.7, 0.0)), "texture-wiggle.ply");
  summary("texture edits written: set tilt (40 deg towards +z), wrap (70 deg), wiggle (40 deg, wavelength 0.7)");

  // Re-apply to a stretched base: spikes keep their size (Sec. 8.4.2).
  Mesh stretched = s.base;
  MatrixX3d B = positions(s.base);
  B.col(0) *= 1.6;
  set_positions(stretched, B);
  save(stretched, apply_texture(stretched, tex), "texture-on-stretched-base.ply");
  MatrixX3d naive = X;
  naive.col(0) *= 1.6;
  save(stretched, naive, "texture-stretched-naively.ply");
  summary("texture re-applied to a base stretched 1.6x along x (spikes keep their size), beside the naive stretch");

  // Transfer a patch of the spiky plane onto a sphere.
  const TexturedShape p = make_shape("spiky-plane", 1);
  TextureCodec pc(p.base);
  const Texture ptex = pc.extract(positions(p.textured));
  const Mesh sphere = icosphere(5, 1.0);
  TransferOptions o;
  o.source_center = 0;
  double best = 1e9;
  for (auto v : p.base.vertices())
    if (p.base.point(v).norm() < best) { best = p.base.point(v).norm(); o.source_center = v.idx(); }
  o.source_radius = 0.45;
  o.target_center = 0;
  o.target_radius = 0.9;
  const TransferResult tr = transfer_texture(p.base, ptex, sphere, o);
  save(tr.target, apply_texture(tr.target, tr.texture), "texture-transferred-to-sphere.ply");
  summary(fmt::format("texture patch of spiky-plane ({} vertices) transferred to a sphere patch ({} vertices) via "
                      "conformal maps; {:.1f} s for the whole step",
                      tr.source_patch.vertices.size(), tr.target_patch.vertices.size(),
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
}};

}  // namespace
}  // namespace geotex::cli
