// Vertex positions from target face normals (Sun et al. 2007).

#include "geotex/denoise/normal_fit.h"

#include <vector>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "geotex/core/error.h"

namespace geotex {

MatrixX3d fit_vertices_to_normals(const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& N, int iterations,
                                  double relaxation) {
  if (N.rows() != F.rows())
    throw InvalidInput(fmt::format("normal fit: {} faces but {} normals", F.rows(), N.rows()));
  if (iterations < 0) throw InvalidInput("normal fit: iterations must be non-negative");
  if (!(relaxation >= 0 && relaxation <= 1)) throw InvalidInput("normal fit: relaxation must lie in [0, 1]");
  const Eigen::Index nv = X.rows(), nf = F.rows();
  if (nf > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= nv)) throw InvalidInput("normal fit: face index out of range");
  // Vertex → incident faces (CSR, faces in increasing order).
  std::vector<int> off(nv + 1, 0), vf;
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) ++off[F(f, k) + 1];
  for (Eigen::Index v = 0; v < nv; ++v) off[v + 1] += off[v];
  vf.resize(off[nv]);
  {
    std::vector<int> fill(off.begin(), off.end() - 1);
    for (Eigen::Index f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) vf[fill[F(f, k)]++] = static_cast<int>(f);
  }
  // The relaxation's directions depend on the target normals only: the projector onto the eigenvectors
  // of the mean outer product n nᵀ below a tenth of its largest eigenvalue, once per vertex.
  std::vector<Eigen::Matrix3d> free_directions;
  if (relaxation > 0) {
    free_directions.resize(nv);
#pragma omp parallel for schedule(static) if (nv > 4096)
    for (Eigen::Index v = 0; v < nv; ++v) {
      const int k = off[v + 1] - off[v];
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
      for (int q = off[v]; q < off[v + 1]; ++q) {
        const Vec3 nf_ = N.row(vf[q]).transpose();
        M += nf_ * nf_.transpose();
      }
      Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
      if (k > 0) {
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
        es.computeDirect(M / k);
        for (int e = 0; e < 3; ++e)
          if (es.eigenvalues()[e] < 0.1 * es.eigenvalues()[2]) P += es.eigenvectors().col(e) * es.eigenvectors().col(e).transpose();
      }
      free_directions[v] = P;
    }
  }
  MatrixX3d x = X, y(nv, 3), c(nf, 3);
  for (int it = 0; it < iterations; ++it) {
#pragma omp parallel for schedule(static) if (nf > 4096)
    for (Eigen::Index f = 0; f < nf; ++f) c.row(f) = (x.row(F(f, 0)) + x.row(F(f, 1)) + x.row(F(f, 2))) / 3.0;
#pragma omp parallel for schedule(static) if (nv > 4096)
    for (Eigen::Index v = 0; v < nv; ++v) {
      y.row(v) = x.row(v);
      const int k = off[v + 1] - off[v];
      if (k == 0) continue;
      const Vec3 xv = x.row(v).transpose();
      Vec3 d = Vec3::Zero();
      for (int q = off[v]; q < off[v + 1]; ++q) {
        const Vec3 nf_ = N.row(vf[q]).transpose();
        d += nf_ * nf_.dot(Vec3(c.row(vf[q]).transpose()) - xv);  // Eq. (8)
      }
      y.row(v) += d.transpose() / k;
      if (relaxation > 0) {
        Vec3 mean = Vec3::Zero();
        for (int q = off[v]; q < off[v + 1]; ++q) mean += c.row(vf[q]).transpose();
        y.row(v) += relaxation * (free_directions[v] * (mean / k - xv)).transpose();
      }
    }
    x.swap(y);
  }
  return x;
}

}  // namespace geotex
