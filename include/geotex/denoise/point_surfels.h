#pragma once
//! \file point_surfels.h Surfel reconstruction of a point cloud (thesis ch. 7 with k-nearest-neighbour
//! neighbourhoods, Sec. 7.4.3.2): oriented points out.

#include <optional>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/core/progress.h"
#include "geotex/denoise/surfel.h"

namespace geotex {

struct PointSurfelOptions {
  int neighbors = 10;         //!< k nearest neighbours forming each surfel's neighbourhood
  int normal_neighbors = 10;  //!< k nearest neighbours of the initial PCA normals
  double alpha = 0.1;         //!< data weight α (Eq. 7.16)
  double beta = 100;          //!< parallelism weight β (Eq. 7.14)
  double t_start_deg = 45;    //!< first angle threshold t, degrees (Sec. 7.4.3.4: 45–60°)
  double t_end_deg = 10;      //!< last angle threshold t, degrees (Sec. 7.4.3.4: 10–20°)
  int iterations = 10;        //!< threshold values (ICM sweeps; Sec. 7.4.3.5: "usually 10")
  //! Unit length of the energy (Sec. 7.4.3.4); unset: the mean spacing to the 6 nearest neighbours.
  std::optional<double> unit;
  ProgressFn progress;
  static const OptionTable<PointSurfelOptions>& table();
};

struct PointSurfelResult {
  MatrixX3d centers;  //!< #P by 3 surfel centres (Eq. 7.6): the denoised points
  MatrixX3d normals;  //!< #P by 3 unit normals
  SurfelResult surfels;  //!< energies, thresholds, unit length
};

//! Surfels of a point cloud: kNN neighbourhoods, PCA normals oriented by propagation, ICM.
//! \param P #P by 3 points. \throw InvalidInput for too few or non-finite points; InvalidOption.
PointSurfelResult point_surfels(const MatrixX3d& P, const PointSurfelOptions& options = {});

}  // namespace geotex
