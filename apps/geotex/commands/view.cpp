// geotex view MESH… -o page.html: one self-contained HTML page showing the meshes side by side
// (three.js, linked orbit controls, flat/smooth shading, wireframe, edge labels, field colour maps).

#include <filesystem>

#include <fmt/format.h>

#include "cli.h"
#include "view_common.h"

namespace geotex::cli {
namespace {

struct Args {
  std::vector<std::string> inputs;
  std::string output, title, up = "z";
  bool flat = false, wireframe = false;
  LayerArgs layers;
};

void run(const Args& a) {
  if (std::filesystem::path(a.output).extension() != ".html")
    throw IoError(fmt::format("{}: the output must be an .html file", a.output));
  if (a.layers.edges.size() > a.inputs.size())
    throw InvalidInput(fmt::format("{} --edges files for {} meshes", a.layers.edges.size(), a.inputs.size()));
  const std::string script = viewer_script();  // fail early when the viewer was not built
  std::vector<ViewerMesh> meshes;
  ViewerOptions o;
  o.title = a.title.empty() ? "geotex: " + std::filesystem::path(a.inputs.front()).filename().string() +
                                  (a.inputs.size() > 1 ? fmt::format(" and {} more", a.inputs.size() - 1) : "")
                            : a.title;
  o.flat = a.flat;
  o.up = up_axis(a.up);
  o.wireframe = a.wireframe;
  for (size_t i = 0; i < a.inputs.size(); ++i) {
    ViewerMesh m;
    m.name = std::filesystem::path(a.inputs[i]).filename().string();
    m.mesh = load_mesh(a.inputs[i]);
    const std::string field =
        load_layers(a.inputs[i], m.mesh, a.layers, i < a.layers.edges.size() ? a.layers.edges[i] : "", m.layers);
    if (o.initial_field.empty()) o.initial_field = field;
    meshes.push_back(std::move(m));
  }
  write_text_atomic(a.output, viewer_page(meshes, o, script));
  info(fmt::format("wrote {} ({} mesh{})", a.output, meshes.size(), meshes.size() == 1 ? "" : "es"));
}

Registrar reg{920, "view", "Write a self-contained HTML page showing meshes side by side in 3D (three.js)",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("MESH", a->inputs, "meshes to show side by side")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "output page (.html)")->required();
  app.add_option("--title", a->title, "page title (default: the file names)");
  add_up_option(app, a->up);
  app.add_flag("--flat", a->flat, "start in flat shading");
  app.add_flag("--wireframe", a->wireframe, "start with the wireframe shown");
  add_layer_options(app, a->layers, true);
  app.callback([a] { run(*a); });
}};

}  // namespace
}  // namespace geotex::cli
