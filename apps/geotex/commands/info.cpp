// geotex info MESH: counts, bounds, boundary loops, genus, manifoldness, what the reader dropped.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/core/results.h"

namespace geotex::cli {
namespace cmd_info {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::string input;
  bool json = false;
  bool strict = false;
};

void run(const Args& a) {
  ReadReport rep;
  const Mesh mesh = load_mesh(a.input, &rep, a.strict);
  const MeshSummary s = summarize(mesh);
  nlohmann::json j = mesh_summary_results().report(s);  // what Python's info() says too
  // About the file as read: the CLI's own.
  j["file"] = a.input;
  j["format"] = rep.format;
  j["read"] = read_report_results().report(rep);
  // About the file: the mesh as read is manifold once faces are dropped or vertices split.
  const bool manifold = rep.build.nonmanifold_faces == 0 && rep.build.split_vertices == 0 &&
                        rep.build.nonmanifold_vertices == 0;
  j["manifold"] = manifold;
  j["consistently_oriented"] = rep.build.flipped_faces == 0;
  if (a.json) {
    fmt::print("{}\n", j.dump(2));
    return;
  }
  fmt::print("file           {} ({})\n", a.input, rep.format);
  fmt::print("vertices       {}{}\n", s.vertices, s.isolated_vertices ? fmt::format(" ({} isolated)", s.isolated_vertices) : "");
  fmt::print("edges          {}\n", s.edges);
  fmt::print("faces          {}\n", s.faces);
  fmt::print("components     {}\n", s.components);
  fmt::print("boundary loops {}{}\n", s.boundary_loops, s.closed ? " (closed)" : "");
  fmt::print("euler char.    {}\n", s.euler);
  fmt::print("genus          {}\n", s.genus >= 0 ? std::to_string(s.genus) : std::string("n/a (several components)"));
  std::vector<std::string> fixes;
  if (rep.build.nonmanifold_faces) fixes.push_back(fmt::format("{} face(s) dropped", rep.build.nonmanifold_faces));
  if (rep.build.split_vertices) fixes.push_back(fmt::format("{} vertex(es) split", rep.build.split_vertices));
  if (rep.build.nonmanifold_vertices) fixes.push_back(fmt::format("{} pinched vertex(es) kept", rep.build.nonmanifold_vertices));
  fmt::print("manifold       {}\n", manifold ? "yes" : fmt::format("no: {}", fmt::join(fixes, ", ")));
  if (rep.build.flipped_faces) fmt::print("orientation    {} face(s) turned round to agree with their neighbours\n", rep.build.flipped_faces);
  fmt::print("bbox           [{:.6g}, {:.6g}, {:.6g}] .. [{:.6g}, {:.6g}, {:.6g}] (diagonal {:.6g})\n",
             s.box.min[0], s.box.min[1], s.box.min[2], s.box.max[0], s.box.max[1], s.box.max[2], s.box.diagonal());
  fmt::print("mean edge      {:.6g}\n", s.mean_edge);
  fmt::print("area           {:.6g}\n", s.area);
  if (s.closed) fmt::print("volume         {:.6g}\n", s.volume);
  if (s.zero_area_faces) fmt::print("zero-area      {} face(s)\n", s.zero_area_faces);
}

Registrar reg{10, "info", "Print counts, bounds, boundary loops, genus and manifoldness of a mesh",
              [](CLI::App& app) {
                auto a = std::make_shared<Args>();
                app.add_option("MESH", a->input, "mesh file (.obj .ply .off .stl .glb .gltf, or gzipped: .ply.gz …; - reads standard input)")->required()->check(ExistingMeshFile);
                app.add_flag("--json", a->json, "print JSON");
                app.add_flag("--strict", a->strict, "fail instead of dropping bad faces");
                app.callback([a] { run(*a); });
              }};

}  // namespace cmd_info
}  // namespace geotex::cli
