#include "geotex/denoise/point_surfels.h"

#include <fmt/format.h>

#include "geotex/core/error.h"

namespace geotex {

const OptionTable<PointSurfelOptions>& PointSurfelOptions::table() {
  using O = PointSurfelOptions;
  static const auto t = OptionTable<O>()
      .add("neighbors", &O::neighbors, "k nearest neighbours forming each surfel's neighbourhood", between(1, 1000),
           "Sec. 7.4.3.2")
      .add("normal_neighbors", &O::normal_neighbors, "k nearest neighbours for the initial PCA normals", between(2, 1000))
      .add("alpha", &O::alpha, "data weight alpha", non_negative(), "Eq. (7.16)")
      .add("beta", &O::beta, "parallelism weight beta", non_negative(), "Eq. (7.14)")
      .add("t_start", &O::t_start_deg, "first angle threshold t, degrees", {0, 180, true, false}, "Sec. 7.4.3.4")
      .add("t_end", &O::t_end_deg, "last angle threshold t, degrees", {0, 180, true, false}, "Sec. 7.4.3.4")
      .add("iterations", &O::iterations, "threshold values (ICM sweeps)", between(0, 100000), "Sec. 7.4.3.5")
      .add("unit", &O::unit, "unit length; auto: the mean spacing to the 6 nearest neighbours", positive(),
           "Sec. 7.4.3.4");
  return t;
}

PointSurfelResult point_surfels(const MatrixX3d& P, const PointSurfelOptions& o) {
  PointSurfelOptions::table().check(o);
  if (P.rows() == 0) throw InvalidInput("point surfels: no points");
  if (!P.allFinite()) throw InvalidInput("point surfels: a point has a non-finite coordinate");
  if (P.rows() <= std::max(o.neighbors, o.normal_neighbors))
    throw InvalidInput(fmt::format("point surfels: {} points, need more than {} (the neighbourhood size)", P.rows(),
                                   std::max(o.neighbors, o.normal_neighbors)));
  SurfelOptions so;
  so.alpha = o.alpha;
  so.beta = o.beta;
  so.t_start_deg = o.t_start_deg;
  so.t_end_deg = o.t_end_deg;
  so.iterations = o.iterations;
  so.unit_length = o.unit ? *o.unit : mean_neighbor_spacing(P);
  so.progress = o.progress;
  const Neighborhoods N = knn_neighborhoods(P, o.neighbors);
  PointSurfelResult r;
  r.surfels = optimize_surfels(P, N, surfels_from_normals(P, pca_normals(P, o.normal_neighbors)), so);
  r.centers = surfel_centers(P, r.surfels.surfels);
  r.normals = r.surfels.surfels.normals;
  return r;
}

}  // namespace geotex
