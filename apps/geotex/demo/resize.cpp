// Demo step for feature-aware resizing (thesis ch. 9): a plate with round bumps scaled by (2, 1, 1)
// and bent, with automatic features; plain map, the thesis' Eq. (9.2-9.3) and the sliding method.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/resize/resize.h"

namespace geotex::cli {
namespace {

DemoRegistrar step{85, "feature-aware resizing", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const BumpyPlate b = bumpy_plate();
  const MatrixX3d X = positions(b.mesh);
  const Eigen::VectorXd f = features_from_height(b.mesh);
  PlyExtras fx;
  fx.vertex_scalars["feature"] = std::vector<double>(f.data(), f.data() + f.size());
  write_ply(b.mesh, ctx.dir / "bumpy-plate-features.ply", fx);
  for (auto [map, label] : {std::pair{scale_map({2, 1, 1}), "scale-2-1-1"}, std::pair{bend_map(1.5), "bend-1.5"}}) {
    MatrixX3d C(X.rows(), 3);
    for (Eigen::Index i = 0; i < X.rows(); ++i) C.row(i) = map(X.row(i).transpose()).transpose();
    for (auto [method, name] : {std::pair{-1, "plain"}, std::pair{int(ResizeMethod::Thesis), "thesis"},
                                std::pair{int(ResizeMethod::Sliding), "sliding"}}) {
      MatrixX3d Y = C;
      if (method >= 0) {
        ResizeOptions o;
        o.method = ResizeMethod(method);
        Y = feature_aware_resize(b.mesh, C, f, o);
      }
      Mesh out = b.mesh;
      set_positions(out, Y);
      save_mesh(out, (ctx.dir / fmt::format("bumpy-plate-{}-{}.ply", label, name)).string());
      double aspect = 0, height = 0, tilt = 0;
      for (const Vec3& c : b.centres) {
        const BumpShape s0 = measure_bump(X, X, c, b.radius), s = measure_bump(X, Y, c, b.radius);
        aspect = std::max(aspect, s.aspect / s0.aspect);
        height = std::max(height, std::abs(s.height / s0.height - 1));
        tilt = std::max(tilt, s.tilt_deg);
      }
      r[label][name] = {{"worst_aspect", aspect}, {"worst_height_change", height}, {"worst_tilt_deg", tilt}};
      r["summary"].push_back(fmt::format("bumpy plate, {}, {}: worst bump aspect {:.3f}, worst height change {:.1f}%, "
                                         "worst tilt against the base {:.1f} deg", label, name, aspect, 100 * height, tilt));
    }
  }
}};

}  // namespace
}  // namespace geotex::cli
