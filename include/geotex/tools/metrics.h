#pragma once
//! \file metrics.h Error measures of the mesh-denoising literature.
//! (Self-intersections, a spatial query the texture layer also counts: core/self_intersections.h.)

#include <vector>

#include "geotex/core/mesh.h"

namespace geotex {

struct Comparison {
  //! Mean angle between corresponding face normals, degrees. With the same connectivity, faces
  //! correspond by index; otherwise each result face is matched to the truth face closest to its centroid.
  double mean_normal_error_deg = 0;
  double max_normal_error_deg = 0;
  bool faces_by_index = true;  //!< how faces were matched (see above)
  //! Ev: RMS distance from result vertices to the true surface, absolute and divided by the
  //! truth's bounding-box diagonal.
  double ev = 0, ev_relative = 0;
  //! Symmetric Hausdorff distance (vertices of each to the surface of the other), absolute and relative.
  double hausdorff = 0, hausdorff_relative = 0;
  double mean_distance = 0;  //!< mean result-vertex-to-truth distance
  double diagonal = 0;       //!< truth's bounding-box diagonal
};

//! Compare a result with the ground truth. \throw InvalidInput for empty or non-finite meshes.
Comparison compare_meshes(const Mesh& result, const Mesh& truth);

//! Distance from each row of \p P to the surface of \p mesh (#P values).
Eigen::VectorXd point_to_surface_distances(const MatrixX3d& P, const Mesh& mesh);

//! Precision, recall and F1 of a set of labelled edges against true ones (vertex-index pairs,
//! matched regardless of direction).
struct LabelScore {
  double precision = 0, recall = 0, f1 = 0;
  size_t true_positive = 0, labelled = 0, truth = 0;
};
LabelScore score_edge_labels(const MatrixX2i& labelled, const MatrixX2i& truth);

}  // namespace geotex
