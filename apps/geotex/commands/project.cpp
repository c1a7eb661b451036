// geotex project IN BASE -o OUT: project every vertex of IN onto BASE along BASE's Phong normal field
// (thesis Sec. 5.2, analytic solution Eq. 5.46-5.63).

#include <cmath>

#include <fmt/format.h>

#include "cli.h"
#include "option_flags.h"
#include "geotex/toolkit/phong_projection.h"

namespace geotex::cli {
namespace cmd_project {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::string input, base, output;
};

void run(const Args& a, const PhongProjectionOptions& opt) {
  Outputs out({a.input, a.base}, {{a.output, "-o"}});
  Mesh points = load_mesh(a.input);
  const Mesh base = load_mesh(a.base);
  const PhongProjector proj(base, MatrixX3d(), opt);
  const std::vector<PhongHit> hits = proj.project(positions(points));
  MatrixX3d Q(hits.size(), 3);
  size_t found = 0;
  double max_d = 0, sum_d = 0;
  for (size_t i = 0; i < hits.size(); ++i) {
    Q.row(i) = hits[i].point.transpose();
    found += hits[i].found;
    max_d = std::max(max_d, std::abs(hits[i].distance));
    sum_d += std::abs(hits[i].distance);
  }
  info(fmt::format("{} of {} points have an inside Phong projection (the rest took the closest point); "
                   "|distance| mean {:.4g}, max {:.4g}",
                   found, hits.size(), sum_d / std::max<size_t>(hits.size(), 1), max_d));
  set_positions(points, Q);
  save_mesh(points, a.output);
  out.commit();
}

Registrar reg{75, "project", "project a mesh's vertices onto a base along the base's Phong normal field (Sec. 5.2)",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "mesh whose vertices are projected")->required()->check(ExistingMeshFile);
  app.add_option("BASE", a->base, "base mesh (vertex normals: angle-weighted)")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "IN with its vertices moved to their projections")
      ->required()
      ->check(MeshOutputFile);
  auto flags = std::make_shared<FlagSet>(app);
  flags->add("project", PhongProjectionOptions::table());
  app.callback([a, flags] { run(*a, flags->resolve<PhongProjectionOptions>("project")); });
}};

}  // namespace cmd_project
}  // namespace geotex::cli
