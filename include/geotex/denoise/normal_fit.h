#pragma once
//! \file normal_fit.h Vertex positions from target face normals: the update of Sun et al. 2007
//! (the thesis' [127]), shared by the normal-field MRF (mrf_normal_denoise) and the surfels' fit
//! retrieval (surfel_fitted_mesh).

#include "geotex/core/mesh.h"

namespace geotex {

//! \p iterations simultaneous updates x_i ← x_i + 1/|F_i| Σ_{f ∋ i} n_f (n_f · (c_f − x_i)) (Sun et al.
//! 2007, Eq. 8; c_f the face centroid), from \p X. With \p relaxation > 0 each update also moves x_i by
//! relaxation × (mean of its faces' centroids − x_i) along the directions that its faces' target
//! normals leave free (the eigenvectors of their mean outer product below a tenth of the largest
//! eigenvalue: the tangent plane on a smooth part, the edge line on a sharp edge, none at a corner),
//! which untangles triangles that noise turned over (the normal update alone keeps them so).
//! \param F #F by 3 faces, \param X #V by 3 start positions, \param N #F by 3 unit target normals.
//! \return #V by 3 positions. \throw InvalidInput on sizes, a negative count or relaxation outside [0, 1].
MatrixX3d fit_vertices_to_normals(const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& N, int iterations,
                                  double relaxation = 0);

}  // namespace geotex
