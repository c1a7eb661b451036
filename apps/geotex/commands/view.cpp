// geotex view MESH… -o page.html: one self-contained HTML page showing the meshes side by side
// (three.js, one shared camera and scale, flat/smooth shading, wireframe, edge labels, field colour maps).

#include <filesystem>

#include <fmt/format.h>

#include "cli.h"
#include "view_common.h"

namespace geotex::cli {
namespace {

struct Args {
  std::vector<std::string> inputs;
  std::string output, title, up, position_bits;
  bool flat = false, wireframe = false;
  LayerArgs layers;
};

void run(const Args& a) {
  if (std::filesystem::path(a.output).extension() != ".html")
    throw IoError(fmt::format("{}: the output must be an .html file", a.output));
  ViewerOptions o;
  set_from_text(o, "up", a.up);
  set_from_text(o, "position_bits", a.position_bits);
  const std::vector<std::string> edges = bind_to_meshes(a.layers.edges, a.inputs, "--edges");
  const std::vector<std::string> field_files = bind_to_meshes(a.layers.field_files, a.inputs, "--field-file");
  const std::string script = viewer_script();  // fail early when the viewer was not built
  o.title = a.title.empty() ? "geotex: " + std::filesystem::path(a.inputs.front()).filename().string() +
                                  (a.inputs.size() > 1 ? fmt::format(" and {} more", a.inputs.size() - 1) : "")
                            : a.title;
  o.flat = a.flat;
  o.wireframe = a.wireframe;
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
  info(fmt::format("wrote {} ({} mesh{})", a.output, meshes.size(), meshes.size() == 1 ? "" : "es"));
}

Registrar reg{920, "view", "Write a self-contained HTML page showing meshes side by side in 3D (three.js)",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("MESH", a->inputs, "meshes to show side by side")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "output page (.html)")->required();
  app.add_option("--title", a->title, "page title (default: the file names)");
  add_table_option<ViewerOptions>(app, "--up", "up", a->up);
  add_table_option<ViewerOptions>(app, "--position-bits", "position_bits", a->position_bits);
  app.add_flag("--flat", a->flat, "start in flat shading");
  app.add_flag("--wireframe", a->wireframe, "start with the wireframe shown");
  add_layer_options(app, a->layers, true);
  app.callback([a] { run(*a); });
}};

}  // namespace
}  // namespace geotex::cli
