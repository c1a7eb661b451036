#pragma once
//! \file user_files.h Readers of the small user files the CLI takes besides meshes: deformation handles
//! (JSON, `geotex deform --handles`), per-vertex feature weights (`geotex resize --features FILE`) and
//! point clouds (`geotex surfels`). Each parses from memory too, so that it can be fuzzed
//! (fuzz/fuzz_files.cpp, scripts/fuzz.sh) and unit tested; the file versions only read the bytes.
//! Every malformed input throws IoError (unreadable, not JSON, not a number) or InvalidInput
//! (well-formed but unusable: ids out of range, counts that do not match the mesh, non-finite values).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "geotex/core/io.h"
#include "geotex/core/mesh.h"
#include "geotex/core/options.h"

namespace geotex {

// ---------------------------------------------------------------------------------------------
// Deformation handles (Laplacian editing, thesis Sec. 5.1.4)

//! Handle constraints of Eq. (5.19): vertex ids, their weights w_i and target positions.
struct HandleSet {
  std::vector<int> ids;         //!< handle vertex ids (in file order; each vertex at most once)
  std::vector<double> weights;  //!< w_i of Eq. (5.19), one per id, finite and > 0
  MatrixX3d targets;            //!< #ids by 3 target positions
};

//! Parse a handles document:
//!   {"handles": [ HANDLE, ... ]}
//! HANDLE selects vertices by exactly one of
//!   "vertices": [i, j, ...]                          vertex ids (integers in [0, #V))
//!   "sphere": {"center": [x,y,z], "radius": r}       every vertex within r of the centre
//!   "box": {"min": [x,y,z], "max": [x,y,z]}          every vertex inside the axis-aligned box
//! and gives their targets by either
//!   "targets": [[x,y,z], ...]                        one per id (only with "vertices")
//! or a transform x ↦ R(s (x − c)) + c + t (a handle without one stays put):
//!   "scale": s, "rotate": {"axis": [x,y,z], "angle_deg": a, "center": [x,y,z]}, "translate": [x,y,z],
//!   "center": [x,y,z]   (c for scale and rotation; default: the centroid of the selected vertices;
//!                         "rotate.center" overrides it for the rotation)
//! Optional "weight": w_i of Eq. (5.19) for the handle's vertices (default \p default_weight).
//! \p X is the #V by 3 rest positions. \p name prefixes error messages.
//! \throw IoError if the text is not JSON; InvalidInput for a document that cannot be used.
HandleSet parse_handles(std::string_view json_text, const MatrixX3d& X, double default_weight,
                        const std::string& name = "<memory>");

//! Read and parse a handles file (see parse_handles()). \throw IoError if it cannot be read.
HandleSet read_handles(const std::filesystem::path& path, const MatrixX3d& X, double default_weight);

// ---------------------------------------------------------------------------------------------
// Feature weights (feature-aware resizing, thesis ch. 9)

//! Feature weights from text: one number in [0, 1] per vertex and line; blank lines and lines starting
//! with '#' are skipped. Returns #V weights. \throw IoError for a non-number, InvalidInput for a count
//! other than \p n_vertices or a value outside [0, 1].
Eigen::VectorXd parse_feature_weights(std::string_view text, size_t n_vertices, const std::string& name = "<memory>");

//! \throw InvalidInput naming \p name unless every weight is in [0, 1].
void require_unit_weights(const Eigen::VectorXd& weights, const std::string& name);

// ---------------------------------------------------------------------------------------------
// Point clouds (surfel reconstruction, thesis ch. 7)

//! Points from text. \p obj: OBJ `v x y z` lines (other lines ignored); otherwise XYZ/PTS/TXT: three
//! numbers per line (extra columns ignored, blank lines and '#' comments skipped).
//! Returns #P by 3. \throw IoError for a malformed line, InvalidInput for no points or a non-finite one.
MatrixX3d parse_point_text(std::string_view text, bool obj, const std::string& name = "<memory>");

//! Points of a PLY's vertex element (x, y, z). \throw IoError without them, InvalidInput as above.
MatrixX3d points_from_ply(const PlyData& ply, const std::string& name = "<memory>");

//! True for the extensions read_point_file() reads: .ply .obj .xyz .pts .txt (any case).
bool is_point_file(const std::filesystem::path& path);

//! Points of a .ply/.obj/.xyz/.pts/.txt file (see is_point_file()). \throw IoError for other extensions.
MatrixX3d read_point_file(const std::filesystem::path& path);

}  // namespace geotex
