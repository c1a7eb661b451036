// geotex deform IN --handles H.json -o OUT: Laplacian surface editing (thesis Sec. 5.1.4).
//
// The handles file is described in the command's help (kHandlesHelp), parsed by geotex::parse_handles()
// in user_files.h.

#include <chrono>

#include <fmt/format.h>

#include "cli.h"
#include "option_flags.h"
#include "geotex/toolkit/editing.h"
#include "geotex/core/user_files.h"

namespace geotex::cli {
namespace cmd_deform {  // named, not anonymous: a unity build compiles several commands in one unit

constexpr const char* kHandlesHelp = R"(Handles file (--handles, JSON):
  {"handles": [HANDLE, ...]}
A HANDLE selects vertices by exactly one of
  "vertices": [i, j, ...]                          vertex ids
  "sphere": {"center": [x,y,z], "radius": r}       every vertex within r of the centre
  "box": {"min": [x,y,z], "max": [x,y,z]}          every vertex inside the axis-aligned box
and gives their targets by either
  "targets": [[x,y,z], ...]                        one per id (only with "vertices")
or a transform x -> R(s (x - c)) + c + t, applied in that order (a handle without one stays put):
  "scale": s, "rotate": {"axis": [x,y,z], "angle_deg": a, "center": [x,y,z]}, "translate": [x,y,z],
  "center": [x,y,z]   (c for scale and rotation; default: the centroid of the selected vertices;
                       "rotate.center" overrides it for the rotation)
Optional "weight": w_i of Eq. (5.19) for the handle's vertices (default --handle-weight).
Every connected component needs a handle.)";

void run(const MeshIo& io, const std::string& handles, const EditOptions& o) {
  Outputs out({io.input, handles}, {{io.output, "-o"}});
  Mesh mesh = load_mesh(io.input);
  const HandleSet h = read_handles(handles, positions(mesh), o.handle_weight);
  const auto t0 = std::chrono::steady_clock::now();
  const LaplacianEditor editor(mesh, h.ids, h.weights, o);
  const auto t1 = std::chrono::steady_clock::now();
  const MatrixX3d Y = editor.solve(h.targets);
  const auto t2 = std::chrono::steady_clock::now();
  double worst = 0;
  for (size_t k = 0; k < h.ids.size(); ++k) worst = std::max(worst, (Y.row(h.ids[k]) - h.targets.row(k)).norm());
  info(fmt::format("deformed {} vertices with {} handle vertices ({}, {} Laplacian): factor {:.2f} s, solve {:.2f} s; "
                   "largest handle miss {:.3g}",
                   Y.rows(), h.ids.size(), enum_name(edit_method_names(), o.method), enum_name(laplacian_names(), o.laplacian),
                   std::chrono::duration<double>(t1 - t0).count(), std::chrono::duration<double>(t2 - t1).count(), worst));
  set_positions(mesh, Y);
  save_mesh(mesh, io.output, !io.ascii);
  out.commit();
}

Registrar reg{70, "deform", "Laplacian surface editing with handles (Sec. 5.1.4): plain, membrane-fit or linear", [](CLI::App& app) {
  auto io = std::make_shared<MeshIo>(app);
  auto handles = std::make_shared<std::string>();
  app.add_option("--handles", *handles,
                 "JSON handles file: {\"handles\": [{\"vertices\"|\"sphere\"|\"box\": ..., \"targets\"|\"translate\"|"
                 "\"rotate\"|\"scale\": ..., \"weight\": w}]} (see below)")
      ->required()->check(ExistingFile);
  app.footer(kHandlesHelp);
  auto flags = std::make_shared<FlagSet>(app);
  flags->add("deform", EditOptions::table());
  app.callback([io, handles, flags] { run(*io, *handles, flags->resolve<EditOptions>("deform")); });
}};

}  // namespace cmd_deform
}  // namespace geotex::cli
