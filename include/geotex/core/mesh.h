#pragma once
//! \file mesh.h The one mesh type of geotex and its conversions to Eigen.
//!
//! `geotex::Mesh` is an OpenMesh triangle mesh with double-precision points and normals.
//! Numerics work on Eigen matrices: positions as #V by 3, faces as #F by 3 vertex indices
//! (OpenMesh's vertex/face indices, i.e. `vh.idx()` and `fh.idx()`).

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace geotex {

struct MeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  using TexCoord2D = OpenMesh::Vec2d;
};

//! Halfedge triangle mesh (double precision).
using Mesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

using Vec3 = Eigen::Vector3d;
using MatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3>;
using MatrixX3i = Eigen::Matrix<int, Eigen::Dynamic, 3>;
using MatrixX2d = Eigen::Matrix<double, Eigen::Dynamic, 2>;
using MatrixX2i = Eigen::Matrix<int, Eigen::Dynamic, 2>;

inline Vec3 to_eigen(const Mesh::Point& p) { return {p[0], p[1], p[2]}; }
inline Mesh::Point to_point(const Vec3& v) { return {v[0], v[1], v[2]}; }

//! \return #V by 3 vertex positions.
MatrixX3d positions(const Mesh& mesh);

//! \return #F by 3 vertex indices of each triangle, in the mesh's face order and orientation.
MatrixX3i faces(const Mesh& mesh);

//! \return #E by 2 vertex indices of each edge, in OpenMesh's edge order (from vertex of halfedge 0).
MatrixX2i edges(const Mesh& mesh);

//! Overwrite the vertex positions. \pre V has mesh.n_vertices() rows.
//! \throw InvalidInput on a size mismatch.
void set_positions(Mesh& mesh, const MatrixX3d& V);

//! What make_mesh() had to leave out or repair so that the result is a manifold OpenMesh mesh.
struct BuildReport {
  size_t degenerate_faces = 0;   //!< faces repeating a vertex index: dropped
  size_t duplicate_faces = 0;    //!< faces with the same vertex set as an earlier one: dropped
  size_t nonmanifold_faces = 0;  //!< faces OpenMesh refuses (complex edge/vertex): dropped
  size_t isolated_vertices = 0;  //!< vertices no kept face uses (kept, so indices stay valid)
  size_t flipped_faces = 0;      //!< BuildOptions::fix_orientation: faces turned round to match neighbours
  size_t split_vertices = 0;     //!< BuildOptions::split_nonmanifold_vertices: vertices split into one per fan
  size_t added_vertices = 0;     //!< copies made by the split, appended after the input's vertices
  size_t nonmanifold_vertices = 0;  //!< vertices left joining several fans (OpenMesh accepts some)
  size_t dropped() const { return degenerate_faces + duplicate_faces + nonmanifold_faces; }
  size_t repaired() const { return flipped_faces + split_vertices; }
};

//! Repairs make_mesh() may make instead of dropping faces. Off by default (callers that build meshes
//! from their own, already manifold, faces keep exact control); the file readers turn them on.
struct BuildOptions {
  //! Turn faces whose orientation disagrees with their neighbours' round (per connected component the
  //! orientation most faces have wins) instead of dropping them as non-manifold.
  bool fix_orientation = false;
  //! Give every extra fan at a non-manifold vertex its own copy of the vertex (appended after the
  //! input's vertices, so input indices stay valid) instead of dropping or keeping the pinch.
  bool split_nonmanifold_vertices = false;
};

//! Build a mesh from a polygon soup.
//! \param V #V by 3 positions (must be finite)
//! \param F #F by 3 vertex indices (each in [0, #V))
//! \param report if given, receives what had to be dropped or repaired
//! \param options repairs to make (see BuildOptions); faces on an edge beyond the second are always dropped
//! \return a mesh whose first #V vertices are V's rows (plus any copies made by the vertex split)
//! \throw InvalidInput on out-of-range indices or non-finite coordinates.
Mesh make_mesh(const MatrixX3d& V, const MatrixX3i& F, BuildReport* report = nullptr,
               const BuildOptions& options = {});

//! Largest coordinate magnitude, and smallest non-zero extent, that geotex computes with. Its methods
//! form areas, squared areas and inverse squared lengths (cotangent and mass matrices, 1-form fits):
//! fourth powers of lengths, which stay inside double precision (about 1e±308) for lengths within
//! 1e±75. A mesh outside is refused with the advice to rescale it, rather than left to overflow into
//! a solver failure or a non-finite result.
inline constexpr double kMaxCoordinate = 1e75;
inline constexpr double kMinExtent = 1e-75;

//! Throw InvalidInput if the mesh has no faces, a non-finite coordinate, or coordinates outside the
//! range above (|x| > kMaxCoordinate, or a bounding-box diagonal in (0, kMinExtent)). \p what names the mesh.
void require_valid(const Mesh& mesh, const char* what = "mesh");

//! Number of vertices that belong to at least one face (the others are isolated).
int vertices_in_faces(const Mesh& mesh);

}  // namespace geotex
