#pragma once
//! \file geometry.h Per-element geometry and topology of a mesh: normals, areas, dihedral angles,
//! edge lengths, bounding box, boundary loops, connected components, Euler characteristic.

#include <string>
#include <vector>

#include "geotex/core/mesh.h"

namespace geotex {

//! \return #F by 3 unit face normals (right-hand rule on the face's vertex order; zero for a
//!         zero-area face).
MatrixX3d face_normals(const Mesh& mesh);

//! \return #F face areas.
Eigen::VectorXd face_areas(const Mesh& mesh);

enum class NormalWeighting {
  Area,   //!< sum of area-weighted face normals (Eq. 5.10's 1-ring; used by the thesis for surfels)
  Angle,  //!< weights by the face's angle at the vertex (Thürmer & Wüthrich 1998)
  Uniform //!< plain average of incident face normals
};

//! \return #V by 3 unit vertex normals (zero for an isolated vertex).
MatrixX3d vertex_normals(const Mesh& mesh, NormalWeighting weighting = NormalWeighting::Area);

//! Signed dihedral angle at each edge: the angle between the two face normals, in radians,
//! in [0, π], positive for convex (ridge) and negative for concave (valley) edges; 0 on boundary edges.
//! \return #E angles in OpenMesh edge order.
Eigen::VectorXd dihedral_angles(const Mesh& mesh);

//! \return #E edge lengths.
Eigen::VectorXd edge_lengths(const Mesh& mesh);

//! Mean edge length; the unit of noise, smoothing steps and texture scales throughout geotex.
double mean_edge_length(const Mesh& mesh);

struct BoundingBox {
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();
  Vec3 size() const { return max - min; }
  Vec3 center() const { return 0.5 * (min + max); }
  double diagonal() const { return size().norm(); }
};

//! Box of the vertices (isolated ones included).
BoundingBox bounding_box(const Mesh& mesh);

//! Each boundary loop as the vertex indices in order around the hole.
std::vector<std::vector<int>> boundary_loops(const Mesh& mesh);

//! \return one component id per vertex (0..k-1, by face connectivity; isolated vertices get their
//!         own ids), and k through \p n_components.
Eigen::VectorXi connected_components(const Mesh& mesh, int* n_components = nullptr);

//! The first connected component (of connected_components; isolated vertices are not components here)
//! that holds none of the vertices \p pinned, described for an error line: "component 2 of 3 (12
//! vertices, e.g. vertex 40)"; empty when every component holds one. Solvers call it on their input
//! before factoring, so that an under-constrained system is refused the same way on every machine.
std::string component_without(const Mesh& mesh, const std::vector<int>& pinned);

//! V − E + F.
int euler_characteristic(const Mesh& mesh);

//! Total surface area.
double surface_area(const Mesh& mesh);

//! Signed enclosed volume (divergence theorem; meaningful for closed, consistently oriented meshes).
double signed_volume(const Mesh& mesh);

//! Area-weighted centroid of the surface.
Vec3 surface_centroid(const Mesh& mesh);

//! Summary used by `geotex info`.
struct MeshSummary {
  size_t vertices = 0, edges = 0, faces = 0, isolated_vertices = 0;
  int boundary_loops = 0, components = 0, euler = 0;
  int genus = -1;  //!< for a single closed or bounded component: (2 − χ − b)/2; −1 otherwise
  bool closed = false;
  double mean_edge = 0, area = 0, volume = 0, min_face_area = 0;
  size_t zero_area_faces = 0;
  BoundingBox box;
};
MeshSummary summarize(const Mesh& mesh);

}  // namespace geotex
