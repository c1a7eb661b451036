#pragma once
// Options shared by `geotex view` and `geotex render`: which field colours the mesh and which
// labelled edges are drawn.

#include <string>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/tools/render.h"
#include "geotex/tools/viewer.h"

namespace geotex::cli {

struct LayerArgs {
  std::string field;       // a per-vertex PLY property of the mesh file
  std::string field_file;  // or a text file of #V numbers
  std::string reference;   // or the distance to this mesh's surface ("error")
  std::vector<std::string> edges;  // PLY files with an "edge" element carrying "label"
};

inline void add_layer_options(CLI::App& app, LayerArgs& a, bool several_meshes) {
  auto* f = app.add_option("--field", a.field, "colour by this per-vertex PLY property (e.g. height, feature)");
  auto* ff = app.add_option("--field-file", a.field_file, "colour by the values in this text file (#V numbers)")
                 ->check(CLI::ExistingFile);
  auto* r = app.add_option("--reference", a.reference,
                           "colour by the error against this mesh: each vertex's distance to its surface")
                ->check(ExistingMeshFile);
  ff->excludes(f);
  r->excludes(f)->excludes(ff);
  app.add_option("--edges", a.edges,
                 several_meshes ? "labelled edges (PLY 'edge' element with 'label'), one file per mesh in order"
                                : "labelled edges (PLY 'edge' element with 'label') drawn as coloured lines")
      ->check(CLI::ExistingFile)
      ->expected(1, several_meshes ? -1 : 1);
}

// --up: the model's up axis.
inline Vec3 up_axis(const std::string& name) {
  if (name == "x") return Vec3::UnitX();
  if (name == "y") return Vec3::UnitY();
  if (name == "z") return Vec3::UnitZ();
  if (name == "-x") return -Vec3::UnitX();
  if (name == "-y") return -Vec3::UnitY();
  if (name == "-z") return -Vec3::UnitZ();
  throw InvalidInput(fmt::format("--up {}: expected x, y, z, -x, -y or -z", name));
}

inline void add_up_option(CLI::App& app, std::string& up) {
  app.add_option("--up", up, "the model's up axis: z (geotex shapes) or y (most scans); x, -x, -y, -z also work")
      ->check(CLI::IsMember({"x", "y", "z", "-x", "-y", "-z"}))
      ->capture_default_str();
}

// The layers of one mesh: the file's own fields and edge labels, the --edges file, and the field
// chosen by --field-file or --reference (named after the file or "error"). Returns the name of the
// field to show ("" for none).
inline std::string load_layers(const std::string& path, const Mesh& mesh, const LayerArgs& a,
                               const std::string& edges, MeshLayers& layers) {
  layers = read_mesh_layers(path, mesh.n_vertices());
  if (!edges.empty()) {
    layers.segments.resize(0, 2);
    layers.labels.resize(0);
    read_edge_labels(edges, mesh.n_vertices(), layers);
  }
  if (!a.field_file.empty()) {
    layers.fields["file"] = read_field_file(a.field_file, mesh.n_vertices());
    return "file";
  }
  if (!a.reference.empty()) {
    layers.fields["error"] = distance_to_surface(mesh, load_mesh(a.reference));
    return "error";
  }
  if (!a.field.empty() && !layers.fields.count(a.field)) {
    std::string have;
    for (const auto& [name, v] : layers.fields) have += (have.empty() ? "" : ", ") + name;
    throw InvalidInput(fmt::format("{}: no per-vertex property '{}' (it has: {})", path, a.field,
                                   have.empty() ? "none" : have));
  }
  return a.field;
}

}  // namespace geotex::cli
