// geotex render MESH -o out.png: a picture from a fixed camera (software rasterizer, no GPU),
// optionally coloured by a per-vertex field and with labelled edges drawn as lines.

#include <fmt/format.h>

#include "cli.h"
#include "option_flags.h"
#include "view_common.h"

namespace geotex::cli {
namespace cmd_render {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::string input, output, size;
  double lo = 0, hi = 0;
  LayerArgs layers;
};

void parse_size(const std::string& s, int& w, int& h) {
  const size_t x = s.find('x');
  char* e1 = nullptr;
  char* e2 = nullptr;
  const std::string width = s.substr(0, x == std::string::npos ? 0 : x);  // e1 points into it: keep it alive
  if (x != std::string::npos) {
    w = static_cast<int>(std::strtol(width.c_str(), &e1, 10));
    h = static_cast<int>(std::strtol(s.c_str() + x + 1, &e2, 10));
  }
  if (x == std::string::npos || *e1 != '\0' || *e2 != '\0' || x == 0 || x + 1 == s.size() || w < 1 || h < 1 ||
      w > 16384 || h > 16384)
    throw InvalidInput(fmt::format("--size {}: expected WIDTHxHEIGHT, e.g. 800x600 (1 to 16384 each)", s));
}

void run(const Args& a, RenderOptions o) {
  if (!a.size.empty()) parse_size(a.size, o.width, o.height);
  if (std::filesystem::path(a.output).extension() != ".png")
    throw IoError(fmt::format("{}: the output must be a .png file", a.output));
  const std::vector<std::string> inputs{a.input};
  const std::string edges = bind_to_meshes(a.layers.edges, inputs, "--edges").front();
  const std::string field_file = bind_to_meshes(a.layers.field_files, inputs, "--field-file").front();
  Outputs out({a.input, edges, field_file, a.layers.reference}, {{a.output, "-o"}});
  const Mesh mesh = load_mesh(a.input);
  MeshLayers layers;
  const std::string field = load_layers(a.input, mesh, a.layers, edges, field_file, true, layers);
  RenderLayers rl;
  if (!field.empty()) rl.field = layers.fields.at(field);
  rl.field_lo = a.lo;
  rl.field_hi = a.hi;
  rl.segments = layers.segments;
  rl.segment_labels = layers.labels;
  const Rendering r = render_mesh(mesh, o, rl);
  write_png(r.image, a.output);
  out.commit();
  info(fmt::format("wrote {} ({}x{}, {} view{}{})", a.output, o.width, o.height, enum_name(view_direction_names(), o.view),
                   field.empty() ? "" : fmt::format(", {} from {:.4g} to {:.4g}", field, r.field_lo, r.field_hi),
                   rl.segments.rows() ? fmt::format(", {} labelled edges", rl.segments.rows()) : ""));
}

Registrar reg{910, "render", "Render a mesh to a PNG picture (fixed camera, shading, field colours, edge labels)",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("MESH", a->input, "mesh to render")->required()->check(ExistingMeshFile);
  app.add_option("-o,--output", a->output, "output picture (.png)")->required();
  auto flags = std::make_shared<FlagSet>(app);
  flags->add("render", RenderOptions::table());
  app.add_option("--size", a->size, "picture size WIDTHxHEIGHT in pixels (the same as --width and --height)")
      ->excludes("--width")->excludes("--height");
  app.add_option("--range-lo", a->lo, "colour-map minimum (with --range-hi; default: the field's own range)")
      ->check(FiniteNumber)->capture_default_str();
  app.add_option("--range-hi", a->hi, "colour-map maximum")->check(FiniteNumber)->capture_default_str();
  add_layer_options(app, a->layers, false);
  app.callback([a, flags] { run(*a, flags->resolve<RenderOptions>("render")); });
}};

}  // namespace cmd_render
}  // namespace geotex::cli
