#pragma once
//! \file weld.h Coincident vertices: found, and welded into one vertex for a computation. Many models are stored
//! as unwelded patches (the teapot's Bézier patches), whose seams are boundary loops with a copy of each vertex on
//! either side; a method that solves for positions on them treats every patch as a surface of its own. Weld the
//! mesh, compute on the welded one, and take the result back per input vertex (Weld::to_input()): the input's
//! vertices, order and faces stay, and coincident vertices stay coincident.

#include <array>
#include <vector>

#include "geotex/core/mesh.h"

namespace geotex {

//! Vertices within this many mean edge lengths of each other coincide (weld_coincident(), and the seams between
//! unwelded patches that the importance map does not read as outline).
inline constexpr double kCoincidentTolerance = 1e-6;

//! Groups of coincident vertices among \p subset (rows of \p X; all rows when null): two vertices within
//! \p tolerance of each other are in one group, and groups chain (single linkage). Sorted on a grid of cells of
//! 1024 × tolerance, so O(m log m) for m vertices whatever their layout.
//! \return #X.rows() labels: the smallest index of each vertex's group (its own index outside \p subset or alone).
std::vector<int> coincident_groups(const MatrixX3d& X, double tolerance, const std::vector<int>* subset = nullptr);

//! A mesh with its coincident vertices welded, and the way back to the input's vertices.
struct Weld {
  //! The welded mesh: one vertex per group, in the order of the groups' first input vertex, at that vertex's
  //! position; the input's faces in the input's order. Empty when identity() (use the input).
  Mesh mesh;
  std::vector<int> welded;  //!< #V: each input vertex's welded vertex
  std::vector<int> first;   //!< #W: each welded vertex's first input vertex
  int merged = 0;           //!< input vertices welded onto an earlier one
  int refused = 0;          //!< coincident groups left unwelded or welded per fan (see weld_coincident())
  //! Pairs of welded vertices that coincide but were welded per fan (a point contact: the teapot's handle on its
  //! body), a pair per further fan: a solve on #mesh should keep them together (resize ties them by stiff springs).
  std::vector<std::array<int, 2>> ties;
  bool identity() const { return merged == 0 && ties.empty(); }  // nothing welded or tied
  //! \return #V rows: each input vertex's welded vertex's row of \p W (#W rows).
  MatrixX3d to_input(const MatrixX3d& W) const;
  Eigen::VectorXd to_input(const Eigen::VectorXd& w) const;
  //! \return #W rows: each welded vertex's first input vertex's row of \p V (#V rows).
  MatrixX3d to_welded(const MatrixX3d& V) const;
  //! \return #W values: the largest of each group's values in \p v (#V; e.g. feature weights painted on one side).
  Eigen::VectorXd max_to_welded(const Eigen::VectorXd& v) const;
};

//! Weld the vertices of \p mesh that coincide (coincident_groups() within \p relative_tolerance mean edge lengths).
//! Welding must not make the mesh worse, so a group is left unwelded (all its vertices as they were) when welding
//! it would make a face degenerate (two of its corners in the group), or an edge with more than two faces or two
//! faces running along it the same way (an orientation OpenMesh cannot hold); a group whose faces would join at the
//! welded vertex in several fans (the teapot's handle touching its body at a point) is welded per fan. The rules
//! are applied in this order, one kind per round, until no group changes (each round only splits groups).
//! Identity (merged 0, no ties, no mesh) when nothing is welded or tied.
Weld weld_coincident(const Mesh& mesh, double relative_tolerance = kCoincidentTolerance);

//! A vertex held at a point of a triangle: Σ_k weights[k] · corners[k] (barycentric weights, summing to 1). A point
//! contact (Weld::ties) is one with a single corner of weight 1.
struct SurfaceTie {
  int vertex = -1;
  std::array<int, 3> corners{};
  Vec3 weights = Vec3(1, 0, 0);
};

//! Rim vertices within this many of their own edges' mean length of another part's faces touch them
//! (rim_contacts()). The teapot's handle's lower end rests on its body's faces (the body's facets chord the curved
//! surface the rim was cut from) 0.002 to 0.094 mean edge lengths off. Tied too, the handle's upper end (0.32 to 0.43
//! into the body; at 0.5) cost the teapot's ×2 x / y / z detail ratios 0.015 / 0.011 / 0.066, and the beetle's second
//! part's rim (0.19 to 0.23 off the body; at 0.25) its ×2 z 0.016 (bench/resize.md, issue 25, fifteenth session).
inline constexpr double kContactTolerance = 0.15;

//! A rim's part rests on a face when it leaves the face on its front at least this far off its plane (the cosine of
//! the angle between the face's normal and the direction from the rim vertex into its part): not along it, not
//! through it (rim_contacts()).
inline constexpr double kContactLeave = 0.0;

//! The rims of parts resting on another part's faces, as the teapot's handle ends on its body: each boundary vertex
//! of \p mesh within \p relative_tolerance of its edges' mean length of a face of another connected part (sharing no
//! vertex with its own: a point contact welded per fan leaves the two parts apart) whose front its part leaves from
//! (kContactLeave), tied to its closest point on the nearest such face; a rim vertex coinciding with a vertex of that
//! face is left to the weld (a point contact, Weld::ties, or a group it leaves apart). Only rims most of whose
//! boundary loop touches are tied (a loop passing near a face is not seated on it); isolated vertices are no rim.
//! A solve that keeps those points together keeps the parts in contact (T-junctions between parts, where only one
//! of a rim's vertices, or none, is a vertex of the other part). \return the ties, sorted by vertex.
std::vector<SurfaceTie> rim_contacts(const Mesh& mesh, double relative_tolerance = kContactTolerance);

//! Each tied vertex of \p Y moved with its point: y_v = Σ_k w_k y_{c_k} + (x_v − Σ_k w_k x_{c_k}), its offset from
//! the point in \p X kept (the repairs after a solve that holds \p ties: a tied vertex moves with its face point);
//! swept until no vertex moves (at most 16 sweeps: ties chained through each other's corners).
void hold_ties(MatrixX3d& Y, const MatrixX3d& X, const std::vector<SurfaceTie>& ties);

}  // namespace geotex
