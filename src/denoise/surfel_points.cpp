// Neighbourhoods and normals for surfels: mesh one-rings, k nearest neighbours (nanoflann) and
// consistently oriented PCA normals for point clouds (thesis Sec. 7.3, 7.4.2).

#include <algorithm>
#include <cmath>
#include <memory>
#include <queue>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>
#include <nanoflann.hpp>

#include "geotex/core/error.h"
#include "geotex/denoise/surfel.h"

namespace geotex {

namespace {

struct Cloud {
  const MatrixX3d& P;
  size_t kdtree_get_point_count() const { return static_cast<size_t>(P.rows()); }
  double kdtree_get_pt(size_t i, size_t d) const { return P(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(d)); }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud>, Cloud, 3, uint32_t>;

void check_points(const MatrixX3d& P, int k) {
  if (k < 1) throw InvalidInput(fmt::format("k nearest neighbours: k must be at least 1 (got {})", k));
  if (P.rows() <= k)
    throw InvalidInput(fmt::format("k nearest neighbours: {} points are too few for k = {}", P.rows(), k));
  if (!P.allFinite()) throw InvalidInput("k nearest neighbours: non-finite point");
}

// The k nearest other points of every point, in rows of k (self excluded, nearest first), with squared distances.
void knn(const MatrixX3d& P, int k, std::vector<uint32_t>& idx, std::vector<double>& d2) {
  check_points(P, k);
  Cloud cloud{P};
  KdTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  tree.buildIndex();
  const Eigen::Index n = P.rows();
  idx.assign(size_t(n) * k, 0);
  d2.assign(size_t(n) * k, 0.0);
#pragma omp parallel
  {
    std::vector<uint32_t> ii(k + 1);
    std::vector<double> dd(k + 1);
#pragma omp for schedule(static)
    for (Eigen::Index i = 0; i < n; ++i) {
      const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
      const size_t found = tree.knnSearch(q, k + 1, ii.data(), dd.data());
      int m = 0;
      for (size_t r = 0; r < found && m < k; ++r) {
        if (ii[r] == static_cast<uint32_t>(i)) continue;
        idx[size_t(i) * k + m] = ii[r];
        d2[size_t(i) * k + m] = dd[r];
        ++m;
      }
      // Duplicated points can push i itself out of the k+1 results; then the list is already full.
      for (; m < k; ++m) {
        idx[size_t(i) * k + m] = ii[std::min<size_t>(m, found - 1)];
        d2[size_t(i) * k + m] = dd[std::min<size_t>(m, found - 1)];
      }
    }
  }
}

}  // namespace

Neighborhoods one_ring_neighborhoods(const Mesh& mesh) {
  Neighborhoods N;
  N.offsets.reserve(mesh.n_vertices() + 1);
  N.indices.reserve(mesh.n_halfedges());
  for (auto v : mesh.vertices()) {
    for (auto w : mesh.vv_range(v)) N.indices.push_back(w.idx());
    N.offsets.push_back(static_cast<int>(N.indices.size()));
  }
  return N;
}

Neighborhoods knn_neighborhoods(const MatrixX3d& P, int k) {
  std::vector<uint32_t> idx;
  std::vector<double> d2;
  knn(P, k, idx, d2);
  Neighborhoods N;
  N.offsets.resize(P.rows() + 1);
  for (Eigen::Index i = 0; i <= P.rows(); ++i) N.offsets[i] = static_cast<int>(i * k);
  N.indices.assign(idx.begin(), idx.end());
  return N;
}

double mean_neighbor_spacing(const MatrixX3d& P, int k) {
  std::vector<uint32_t> idx;
  std::vector<double> d2;
  knn(P, k, idx, d2);
  double sum = 0;
  for (double v : d2) sum += std::sqrt(v);
  return sum / double(d2.size());
}

MatrixX3d pca_normals(const MatrixX3d& P, int k) {
  std::vector<uint32_t> idx;
  std::vector<double> d2;
  knn(P, k, idx, d2);
  const Eigen::Index n = P.rows();
  MatrixX3d N(n, 3);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < n; ++i) {
    Vec3 mean = P.row(i).transpose();
    for (int m = 0; m < k; ++m) mean += P.row(idx[size_t(i) * k + m]).transpose();
    mean /= double(k + 1);
    Eigen::Matrix3d cov = (P.row(i).transpose() - mean) * (P.row(i).transpose() - mean).transpose();
    for (int m = 0; m < k; ++m) {
      const Vec3 d = P.row(idx[size_t(i) * k + m]).transpose() - mean;
      cov.noalias() += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(cov);
    N.row(i) = es.eigenvectors().col(0).transpose();  // smallest eigenvalue: the normal direction
  }

  // Symmetric kNN graph for orientation propagation.
  std::vector<std::vector<uint32_t>> adj(n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int m = 0; m < k; ++m) {
      const uint32_t j = idx[size_t(i) * k + m];
      if (j == static_cast<uint32_t>(i)) continue;
      adj[i].push_back(j);
      adj[j].push_back(static_cast<uint32_t>(i));
    }
  // Prim's algorithm on weights 1 − |n_i·n_j|: flip each point to agree with its tree parent, so
  // orientation travels along the smoothest paths first (Hoppe et al. 1992).
  std::vector<char> done(n, 0);
  using Item = std::pair<double, std::pair<uint32_t, uint32_t>>;  // (|n_i·n_j|, (to, from))
  for (Eigen::Index seed = 0; seed < n; ++seed) {
    if (done[seed]) continue;
    std::vector<uint32_t> part;
    std::priority_queue<Item> heap;
    heap.push({2.0, {static_cast<uint32_t>(seed), static_cast<uint32_t>(seed)}});
    while (!heap.empty()) {
      const auto [score, edge] = heap.top();
      heap.pop();
      const auto [v, from] = edge;
      if (done[v]) continue;
      done[v] = 1;
      part.push_back(v);
      if (v != from && N.row(v).dot(N.row(from)) < 0) N.row(v) *= -1.0;
      for (uint32_t w : adj[v])
        if (!done[w]) heap.push({std::abs(N.row(v).dot(N.row(w))), {w, v}});
    }
    // Point outward on average: Σ (x_i − centroid)·n_i > 0.
    Vec3 centroid = Vec3::Zero();
    for (uint32_t v : part) centroid += P.row(v).transpose();
    centroid /= double(part.size());
    double s = 0;
    for (uint32_t v : part) s += (P.row(v).transpose() - centroid).dot(N.row(v).transpose());
    if (s < 0)
      for (uint32_t v : part) N.row(v) *= -1.0;
  }
  return N;
}

}  // namespace geotex
