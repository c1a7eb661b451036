// geotex view MESH… -o page.html: one self-contained HTML page showing the meshes side by side
// (three.js, one shared camera and scale, flat/smooth shading, wireframe, edge labels, field colour maps).

#include <filesystem>

#include <fmt/format.h>

#include "cli.h"
#include "option_flags.h"
#include "view_common.h"

namespace geotex::cli {
namespace cmd_view {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::vector<std::string> inputs;
  std::string output;
  LayerArgs layers;
};

void run(Args a, ViewerOptions o, bool title_given) {
  if (std::filesystem::path(a.output).extension() != ".html")
    throw IoError(fmt::format("{}: the output must be an .html file", a.output));
  a.layers.field = o.initial_field;  // --field: the table's name for it is initial_field
  o.initial_field.clear();
  const std::vector<std::string> edges = bind_to_meshes(a.layers.edges, a.inputs, "--edges");
  const std::vector<std::string> field_files = bind_to_meshes(a.layers.field_files, a.inputs, "--field-file");
  Outputs out({a.layers.reference}, {{a.output, "-o"}});
  for (const auto& files : {a.inputs, edges, field_files})
    for (const auto& f : files) out.input(f);
  const std::string script = viewer_script();  // fail early when the viewer was not built
  if (!title_given)
    o.title = "geotex: " + std::filesystem::path(a.inputs.front()).filename().string() +
              (a.inputs.size() > 1 ? fmt::format(" and {} more", a.inputs.size() - 1) : "");
  std::vector<ViewerMesh> meshes;
  bool field_found = false;
  for (size_t i = 0; i < a.inputs.size(); ++i) {
    ViewerMesh m;
    m.name = std::filesystem::path(a.inputs[i]).filename().string();
    m.mesh = load_mesh(a.inputs[i]);
    // --field NAME: meshes without it are shown plain, but at least one must have it.
    const std::string field = load_layers(a.inputs[i], m.mesh, a.layers, edges[i], field_files[i], false, m.layers);
    if (o.initial_field.empty()) o.initial_field = field;
    field_found = field_found || m.layers.fields.count(field);
    meshes.push_back(std::move(m));
  }
  if (!a.layers.field.empty() && !field_found)
    throw InvalidInput(fmt::format("--field {}: no mesh has a per-vertex property of that name", a.layers.field));
  write_text_atomic(a.output, viewer_page(meshes, o, script));
  out.commit();
  info(fmt::format("wrote {} ({} mesh{})", a.output, meshes.size(), meshes.size() == 1 ? "" : "es"));
}

Registrar reg{920, "view", "Write a self-contained HTML page showing meshes side by side in 3D (three.js)",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("MESH", a->inputs, "meshes to show side by side")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "output page (.html)")->required();
  auto flags = std::make_shared<FlagSet>(app);
  flags->add("view", ViewerOptions::table());
  add_layer_options(app, a->layers, true, false);
  app.callback([a, flags] { run(*a, flags->resolve<ViewerOptions>("view"), flags->given("title")); });
}};

}  // namespace cmd_view
}  // namespace geotex::cli
