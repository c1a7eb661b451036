#pragma once
// Options shared by `geotex view` and `geotex render`: which field colours the mesh, which labelled
// edges are drawn (bound to their mesh: MESH:FILE), the up axis.

#include <algorithm>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/options.h"
#include "geotex/tools/render.h"
#include "geotex/tools/viewer.h"

namespace geotex::cli {

struct LayerArgs {
  std::string field;                     // a per-vertex PLY property of the mesh files
  std::vector<std::string> field_files;  // [MESH:]FILE, text files of #V numbers
  std::string reference;                 // or the distance to this mesh's surface ("error")
  std::vector<std::string> edges;        // [MESH:]FILE, PLY files with an "edge" element carrying "label"
};

// --field (unless the options table has it), --field-file, --reference, --edges.
inline void add_layer_options(CLI::App& app, LayerArgs& a, bool several_meshes, bool field_flag = true) {
  const std::string bound = several_meshes ? " With several meshes, say which: MESH:FILE, MESH being the mesh's "
                                             "file name or its position (1, 2, ...); repeat for other meshes."
                                           : "";
  CLI::Option* f = field_flag ? app.add_option("--field", a.field, "colour by this per-vertex PLY property (e.g. height, feature)")
                              : nullptr;
  auto* ff = app.add_option("--field-file", a.field_files,
                            "colour by the values in this text file (#V numbers)." + bound)
                 ->expected(1, several_meshes ? -1 : 1);
  auto* r = app.add_option("--reference", a.reference,
                           "colour by the error against this mesh: each vertex's distance to its surface")
                ->check(ExistingMeshFile);
  if (f) ff->excludes(f), r->excludes(f);
  r->excludes(ff);
  app.add_option("--edges", a.edges, "labelled edges (PLY 'edge' element with 'label') drawn as coloured lines." + bound)
      ->expected(1, several_meshes ? -1 : 1);
}

// The file given to each of \p meshes by the values of \p flag ("[MESH:]FILE"; MESH is a mesh's path
// as given, its file name, or its 1-based position). An unbound FILE is the one mesh's; with several
// meshes it is an error, as are a name that fits several meshes and two files for one mesh.
inline std::vector<std::string> bind_to_meshes(const std::vector<std::string>& values,
                                               const std::vector<std::string>& meshes, const std::string& flag) {
  std::vector<std::string> bound(meshes.size());
  const std::string how = fmt::format("say which mesh: {} MESH:FILE, MESH a file name or a position 1..{}", flag,
                                      meshes.size());
  for (const std::string& value : values) {
    int mesh = -1;
    std::string file = value;
    if (const size_t colon = value.find(':'); colon != std::string::npos && colon > 0) {
      const std::string key = value.substr(0, colon);
      std::vector<int> hits;
      if (std::all_of(key.begin(), key.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        const long k = key.size() > 6 ? 0 : std::stol(key);
        if (k < 1 || k > static_cast<long>(meshes.size()))
          throw InvalidInput(fmt::format("{} {}: there is no mesh {} ({} mesh{})", flag, value, key, meshes.size(),
                                         meshes.size() == 1 ? "" : "es"));
        hits.push_back(static_cast<int>(k - 1));
      } else {
        for (size_t i = 0; i < meshes.size(); ++i)
          if (key == meshes[i] || key == std::filesystem::path(meshes[i]).filename().string())
            hits.push_back(static_cast<int>(i));
      }
      if (hits.size() > 1)
        throw InvalidInput(fmt::format("{} {}: '{}' names meshes {} and {}; use its position instead, e.g. {}:{}", flag,
                                       value, key, hits[0] + 1, hits[1] + 1, hits[0] + 1, value.substr(colon + 1)));
      if (hits.size() == 1) mesh = hits[0], file = value.substr(colon + 1);
    }
    if (mesh < 0) {
      if (meshes.size() > 1) throw InvalidInput(fmt::format("{} {}: {} meshes are shown; {}", flag, value, meshes.size(), how));
      mesh = 0;
    }
    if (file.empty()) throw InvalidInput(fmt::format("{} {}: no file after the mesh", flag, value));
    if (!bound[mesh].empty())
      throw InvalidInput(fmt::format("{}: mesh {} ({}) is given two files, {} and {}", flag, mesh + 1, meshes[mesh],
                                     bound[mesh], file));
    require_input_file(file, flag);  // missing, a loop of links, a directory, a FIFO or a device, said as such
    bound[mesh] = file;
  }
  return bound;
}

// The layers of one mesh: the file's own fields and edge labels, its --edges file, and the field
// chosen by --field-file or --reference (named "file" or "error"). Returns the name of the field to
// show ("" for none). A --field the mesh lacks is an error when \p need_field, else it is shown plain.
inline std::string load_layers(const std::string& path, const Mesh& mesh, const LayerArgs& a, const std::string& edges,
                               const std::string& field_file, bool need_field, MeshLayers& layers) {
  layers = read_mesh_layers(path, mesh.n_vertices());
  if (!edges.empty()) {
    layers.segments.resize(0, 2);
    layers.labels.resize(0);
    read_edge_labels(edges, mesh.n_vertices(), layers);
  }
  if (!field_file.empty()) {
    layers.fields["file"] = read_field_file(field_file, mesh.n_vertices());
    return "file";
  }
  if (!a.field_files.empty()) return "file";  // another mesh's file: the same field name, this one plain
  if (!a.reference.empty()) {
    layers.fields["error"] = distance_to_surface(mesh, load_mesh(a.reference));
    return "error";
  }
  if (!a.field.empty() && need_field && !layers.fields.count(a.field)) {
    std::string have;
    for (const auto& [name, v] : layers.fields) have += (have.empty() ? "" : ", ") + name;
    throw InvalidInput(fmt::format("{}: no per-vertex property '{}' (it has: {})", path, a.field,
                                   have.empty() ? "none" : have));
  }
  return a.field;
}

}  // namespace geotex::cli
