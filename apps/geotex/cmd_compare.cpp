// geotex compare RESULT TRUTH: mean normal error (degrees), Ev, Hausdorff distance.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/metrics.h"

namespace geotex::cli {
namespace {

struct Args {
  std::string result, truth;
  bool json = false;
};

void run(const Args& a) {
  const Mesh result = load_mesh(a.result);
  const Mesh truth = load_mesh(a.truth);
  const Comparison c = compare_meshes(result, truth);
  if (a.json) {
    nlohmann::json j{{"result", a.result},
                     {"truth", a.truth},
                     {"mean_normal_error_deg", c.mean_normal_error_deg},
                     {"max_normal_error_deg", c.max_normal_error_deg},
                     {"faces_matched_by", c.faces_by_index ? "index" : "closest-face"},
                     {"ev", c.ev},
                     {"ev_relative", c.ev_relative},
                     {"hausdorff", c.hausdorff},
                     {"hausdorff_relative", c.hausdorff_relative},
                     {"mean_distance", c.mean_distance},
                     {"bbox_diagonal", c.diagonal}};
    fmt::print("{}\n", j.dump(2));
    return;
  }
  fmt::print("mean normal error  {:.3f} deg (max {:.2f} deg; faces matched by {})\n", c.mean_normal_error_deg,
             c.max_normal_error_deg, c.faces_by_index ? "index" : "closest face");
  fmt::print("Ev                 {:.4e} of the bbox diagonal ({:.6g} absolute)\n", c.ev_relative, c.ev);
  fmt::print("Hausdorff          {:.4e} of the bbox diagonal ({:.6g} absolute)\n", c.hausdorff_relative, c.hausdorff);
}

Registrar reg{90, "compare", "Compare a result with the ground truth: mean normal error, Ev, Hausdorff", [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("RESULT", a->result, "result mesh")->required()->check(ExistingMeshFile);
  app.add_option("TRUTH", a->truth, "ground-truth mesh")->required()->check(ExistingMeshFile);
  app.add_flag("--json", a->json, "print JSON");
  app.callback([a] { run(*a); });
}};

}  // namespace
}  // namespace geotex::cli
