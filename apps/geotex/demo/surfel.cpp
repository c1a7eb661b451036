// Demo step for surfel-based reconstruction (thesis ch. 7): a noisy cube, its surfels optimised, the dual
// and primal retrievals, scored against the clean cube.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "geotex/denoise/surfel.h"

namespace geotex::cli {
namespace {

DemoRegistrar step{70, "surfel reconstruction", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const Mesh clean = subdivided_cube(20);
  Mesh noisy = clean;
  NoiseOptions no;
  no.sigma = 0.2;
  set_positions(noisy, add_noise(clean, no));
  const MatrixX3d X = positions(noisy);
  SurfelOptions o;
  o.unit_length = mean_edge_length(noisy);
  const SurfelResult res = optimize_surfels(X, one_ring_neighborhoods(noisy), initial_surfels(noisy), o);
  const PolygonMesh poly = surfel_dual_polygons(noisy, X, res.surfels);
  const Mesh dual = triangulate_polygons(poly);
  const Mesh primal = surfel_primal_mesh(noisy, X, res.surfels);
  save_mesh(noisy, (ctx.dir / "surfel-cube-noisy.ply").string());
  save_mesh(dual, (ctx.dir / "surfel-cube-dual.ply").string());
  save_mesh(primal, (ctx.dir / "surfel-cube-primal.ply").string());
  write_polygon_obj(poly, (ctx.dir / "surfel-cube-dual-polygons.obj").string());
  const Comparison c0 = compare_meshes(noisy, clean), cd = compare_meshes(dual, clean), cp = compare_meshes(primal, clean);
  r["summary"].push_back(fmt::format(
      "surfels (alpha {}, beta {}, t {}->{} deg, {} sweeps) on the cube with noise 0.2: normal error {:.2f} -> "
      "{:.2f} deg (dual mesh), {:.2f} deg (primal); Ev {:.2e} -> {:.2e} (dual)",
      o.alpha, o.beta, o.t_start_deg, o.t_end_deg, res.energy.size(), c0.mean_normal_error_deg,
      cd.mean_normal_error_deg, cp.mean_normal_error_deg, c0.ev_relative, cd.ev_relative));
  r["surfel"] = {{"noisy_normal_error_deg", c0.mean_normal_error_deg},
                 {"dual_normal_error_deg", cd.mean_normal_error_deg},
                 {"primal_normal_error_deg", cp.mean_normal_error_deg},
                 {"energy", res.energy}};
}};

}  // namespace
}  // namespace geotex::cli
