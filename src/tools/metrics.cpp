#include "geotex/tools/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/spatial.h"

namespace geotex {

Eigen::VectorXd point_to_surface_distances(const MatrixX3d& P, const Mesh& mesh) {
  const TriangleTree tree(mesh);
  Eigen::VectorXd d(P.rows());
#pragma omp parallel for schedule(dynamic, 1024)
  for (Eigen::Index i = 0; i < P.rows(); ++i) d[i] = std::sqrt(tree.closest(P.row(i).transpose()).sq_distance);
  return d;
}

Comparison compare_meshes(const Mesh& result, const Mesh& truth) {
  require_valid(result, "result mesh");
  require_valid(truth, "truth mesh");
  Comparison c;
  const MatrixX3d Nr = face_normals(result), Nt = face_normals(truth);
  const MatrixX3i Fr = faces(result), Ft = faces(truth);
  c.faces_by_index = Fr.rows() == Ft.rows() && Fr == Ft;
  Eigen::VectorXd angle(Fr.rows());
  if (c.faces_by_index) {
#pragma omp parallel for schedule(static)
    for (Eigen::Index f = 0; f < Fr.rows(); ++f) {
      const Vec3 a = Nr.row(f), b = Nt.row(f);
      angle[f] = std::atan2(a.cross(b).norm(), a.dot(b));
    }
  } else {
    const TriangleTree tree(truth);
    const MatrixX3d Vr = positions(result);
#pragma omp parallel for schedule(static)
    for (Eigen::Index f = 0; f < Fr.rows(); ++f) {
      const Vec3 centroid = (Vr.row(Fr(f, 0)) + Vr.row(Fr(f, 1)) + Vr.row(Fr(f, 2))).transpose() / 3.0;
      const Vec3 a = Nr.row(f), b = Nt.row(tree.closest(centroid).face);
      angle[f] = std::atan2(a.cross(b).norm(), a.dot(b));
    }
  }
  c.mean_normal_error_deg = angle.mean() * 180.0 / M_PI;
  c.max_normal_error_deg = angle.maxCoeff() * 180.0 / M_PI;

  const Eigen::VectorXd d_rt = point_to_surface_distances(positions(result), truth);
  const Eigen::VectorXd d_tr = point_to_surface_distances(positions(truth), result);
  c.diagonal = bounding_box(truth).diagonal();
  c.ev = std::sqrt(d_rt.squaredNorm() / d_rt.size());
  c.mean_distance = d_rt.mean();
  c.hausdorff = std::max(d_rt.maxCoeff(), d_tr.maxCoeff());
  c.ev_relative = c.ev / c.diagonal;
  c.hausdorff_relative = c.hausdorff / c.diagonal;
  return c;
}

LabelScore score_edge_labels(const MatrixX2i& labelled, const MatrixX2i& truth) {
  auto key = [](int a, int b) { return (uint64_t(std::min(a, b)) << 32) | uint64_t(std::max(a, b)); };
  std::unordered_set<uint64_t> t;
  for (Eigen::Index i = 0; i < truth.rows(); ++i) t.insert(key(truth(i, 0), truth(i, 1)));
  std::unordered_set<uint64_t> l;
  for (Eigen::Index i = 0; i < labelled.rows(); ++i) l.insert(key(labelled(i, 0), labelled(i, 1)));
  LabelScore s;
  s.labelled = l.size();
  s.truth = t.size();
  for (auto k : l) s.true_positive += t.count(k);
  s.precision = s.labelled ? double(s.true_positive) / s.labelled : (s.truth ? 0.0 : 1.0);
  s.recall = s.truth ? double(s.true_positive) / s.truth : 1.0;
  s.f1 = s.precision + s.recall > 0 ? 2 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
  return s;
}

}  // namespace geotex
