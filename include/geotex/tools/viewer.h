#pragma once
//! \file viewer.h Self-contained HTML viewer pages (three.js, bundled at build time from viewer/),
//! and the per-vertex fields and edge labels that pictures and pages show.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/tools/render.h"

namespace geotex {

//! What can be drawn over a mesh: per-vertex fields and labelled edges.
struct MeshLayers {
  std::map<std::string, Eigen::VectorXd> fields;  //!< name → #V values (e.g. "height", "feature", "error")
  MatrixX2i segments;                             //!< #S by 2 vertex indices of labelled edges
  Eigen::VectorXi labels;                         //!< #S labels (≥ 1) choosing the line colour
};

//! The per-vertex scalar properties of a PLY file (all but positions, normals, colours and texture
//! coordinates), and its labelled edges if it has an "edge" element with a "label" property.
//! Non-PLY files have none. \p n_vertices is the mesh's vertex count (fields of another size are
//! refused). \throw IoError on a malformed file.
MeshLayers read_mesh_layers(const std::filesystem::path& path, size_t n_vertices);

//! The edges whose \p property ("label") exceeds 0.5, from a PLY "edge" element, as segments and
//! labels (the value rounded). \throw IoError if absent; InvalidInput if a vertex index is ≥ \p n_vertices.
void read_edge_labels(const std::filesystem::path& path, size_t n_vertices, MeshLayers& layers,
                      const std::string& property = "label");

//! Values of a per-vertex field from a text file: #V numbers separated by white space or commas.
//! \throw IoError if unreadable or not a number; InvalidInput if the count is not \p n_vertices.
Eigen::VectorXd read_field_file(const std::filesystem::path& path, size_t n_vertices);

//! One mesh of a viewer page.
struct ViewerMesh {
  std::string name;  //!< caption
  Mesh mesh;
  MeshLayers layers;
};

struct ViewerOptions {
  std::string title = "geotex viewer";  //!< page title
  std::string initial_field;            //!< field shown when the page opens ("" = plain colour)
  bool flat = false;                    //!< start in flat shading
  bool wireframe = false;               //!< start with the wireframe shown
  UpAxis up = UpAxis::Auto;             //!< the models' up axis (auto: from the first mesh's box, see UpAxis)
  //! positions are quantised to this many bits per coordinate over each mesh's bounding box: the
  //! error is at most extent / 2^(bits+1) per axis (16 bits: 7.6e-6 of the box) plus float32 rounding
  int position_bits = 16;
  //! when set, the page loads the bundle from this (relative) URL instead of inlining it, so that
  //! many pages in one folder share one copy (the demo report); the page is then not self-contained
  std::string script_src;

  static const OptionTable<ViewerOptions>& table();
};

//! The viewer's JavaScript bundle (three.js + viewer/src/viewer.js). Looked up in order: the file
//! named by $GEOTEX_VIEWER_JS, the copy embedded at build time (viewer/CMakeLists.txt), and
//! viewer/dist/geotex-viewer.js in the source tree (written by `npm run build` in viewer/).
//! \throw IoError naming how to build it when none is available (e.g. no node/npm at build time).
std::string viewer_script();

//! A self-contained HTML page (no network needed, works from file://) showing the meshes side by
//! side with one shared camera (linked orbit controls, one scale for all, so sizes compare). Each
//! mesh is centred in its view on the box of its faces' vertices. The data is compact (see
//! viewer/src/viewer.js for the decoder): faces in a breadth-first order and vertices in order of
//! first use, indices as varints of (next new index − index), positions quantised (position_bits)
//! and delta-coded in byte planes, fields quantised to 16 bits; each array a zlib stream in base64.
//! \param script the bundle (viewer_script()); unused when options.script_src is set.
//! \throw InvalidInput for no meshes, bad layers or options.
std::string viewer_page(const std::vector<ViewerMesh>& meshes, const ViewerOptions& options,
                        const std::string& script);

}  // namespace geotex
