// geotex deform IN --handles H.json -o OUT: Laplacian surface editing (thesis Sec. 5.1.4).
//
// Handles file (JSON; parsed by geotex::parse_handles() in user_files.h):
//   {"handles": [ HANDLE, ... ]}
// HANDLE selects vertices by exactly one of
//   "vertices": [i, j, ...]                          vertex ids
//   "sphere": {"center": [x,y,z], "radius": r}       every vertex within r of the centre
//   "box": {"min": [x,y,z], "max": [x,y,z]}          every vertex inside the axis-aligned box
// and gives their targets by either
//   "targets": [[x,y,z], ...]                        one per id (only with "vertices")
// or a transform x ↦ R(s (x − c)) + c + t, applied in that order (a handle without one stays put):
//   "scale": s, "rotate": {"axis": [x,y,z], "angle_deg": a, "center": [x,y,z]}, "translate": [x,y,z],
//   "center": [x,y,z]   (c for scale and rotation; default: the centroid of the selected vertices;
//                         "rotate.center" overrides it for the rotation)
// Optional "weight": w_i of Eq. (5.19) for the handle's vertices (default --weight).

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/toolkit/editing.h"
#include "geotex/core/user_files.h"

namespace geotex::cli {
namespace {

struct Args {
  std::string input, output, handles;
  std::string method = "linear", laplacian = "umbrella";
  double weight = 1.0;
  bool no_scale = false, literal = false, ascii = false;
};

void run(const Args& a) {
  check_output(a.input, a.output);
  Mesh mesh = load_mesh(a.input);
  const HandleSet h = read_handles(a.handles, positions(mesh), a.weight);
  EditOptions o;
  o.method = a.method == "plain" ? EditMethod::Plain : a.method == "membrane-fit" ? EditMethod::MembraneFit : EditMethod::Linear;
  o.laplacian = a.laplacian == "cotan" ? LaplacianType::Cotangent : LaplacianType::Umbrella;
  o.handle_weight = a.weight;
  o.allow_scale = !a.no_scale;
  o.fit_to_rest_membrane = !a.literal;
  const auto t0 = std::chrono::steady_clock::now();
  const LaplacianEditor editor(mesh, h.ids, h.weights, o);
  const auto t1 = std::chrono::steady_clock::now();
  const MatrixX3d Y = editor.solve(h.targets);
  const auto t2 = std::chrono::steady_clock::now();
  const MatrixX3d X = positions(mesh);
  double worst = 0;
  for (size_t k = 0; k < h.ids.size(); ++k) worst = std::max(worst, (Y.row(h.ids[k]) - h.targets.row(k)).norm());
  info(fmt::format("deformed {} vertices with {} handle vertices ({}, {} Laplacian): factor {:.2f} s, solve {:.2f} s; "
                   "largest handle miss {:.3g}",
                   X.rows(), h.ids.size(), a.method, a.laplacian, std::chrono::duration<double>(t1 - t0).count(),
                   std::chrono::duration<double>(t2 - t1).count(), worst));
  set_positions(mesh, Y);
  save_mesh(mesh, a.output, !a.ascii);
}

Registrar reg{70, "deform", "Laplacian surface editing with handles (Sec. 5.1.4): plain, membrane-fit or linear", [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "input mesh")->required()->check(ExistingMeshFile);
  app.add_option("--handles", a->handles,
                 "JSON handles file: {\"handles\": [{\"vertices\"|\"sphere\"|\"box\": ..., \"targets\"|\"translate\"|"
                 "\"rotate\"|\"scale\": ..., \"weight\": w}]} (see cmd_deform.cpp)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("-o,--output", a->output, "output mesh")->required();
  app.add_option("--method", a->method,
                 "plain (Eq. 5.20), membrane-fit (T_i fitted to a membrane, Eq. 5.23-5.24) or linear (T_i linear in "
                 "the positions, Eq. 5.22, Sorkine et al. 2004)")
      ->check(CLI::IsMember({"plain", "membrane-fit", "linear"}))->capture_default_str();
  app.add_option("--laplacian", a->laplacian, "umbrella (Eq. 5.8) or cotan (row-normalised cotangent weights)")
      ->check(CLI::IsMember({"umbrella", "cotan"}))->capture_default_str();
  app.add_option("--weight", a->weight, "default handle weight w_i (Eq. 5.19)")->check(CLI::PositiveNumber)->capture_default_str();
  app.add_flag("--no-scale", a->no_scale, "fit rotations only (no isotropic scale) in membrane-fit");
  app.add_flag("--literal-fit", a->literal, "membrane-fit: fit the original 1-ring to the membrane, as Eq. (5.24) reads");
  app.add_flag("--ascii", a->ascii, "ascii PLY/STL output");
  app.callback([a] { run(*a); });
}};

}  // namespace
}  // namespace geotex::cli
