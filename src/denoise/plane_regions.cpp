// Flat regions read as planes (plane_regions.h).
#include "plane_regions.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

#include <Eigen/Dense>

namespace geotex::detail {
namespace {

// Regions of at least this many vertices: smaller regions of an organic model at high noise (61-91 vertices on
// cheburashka, the cow and the bunny at σ 0.2-0.7) pass the misfit test on a curvature below their noise.
constexpr int kMinPlaneVertices = 150;
// The neighbouring faces of one region: normals within the sharp pass's last threshold (kSharpEnd, 10°).
const double kSameRegionCos = std::cos(10.0 * M_PI / 180.0);
// F(3, n) at the 1 % level for n of a few hundred: a quadric's three curvature terms above it are shape.
constexpr double kCurvedF = 3.8;

int find_root(std::vector<int>& parent, int a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

// Per face, its region (a union over edges whose faces' unit normals \p FN are within kSameRegionCos).
std::vector<int> flat_regions(const MatrixX3i& F, const MatrixX3d& FN) {
  std::vector<int> parent(F.rows());
  std::iota(parent.begin(), parent.end(), 0);
  std::map<std::pair<int, int>, int> first;  // an edge's first face
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      const auto [it, added] = first.emplace(std::minmax(a, b), static_cast<int>(f));
      if (!added && FN.row(f).dot(FN.row(it->second)) > kSameRegionCos)
        parent[find_root(parent, static_cast<int>(f))] = find_root(parent, it->second);
    }
  for (Eigen::Index f = 0; f < F.rows(); ++f) parent[f] = find_root(parent, static_cast<int>(f));
  return parent;
}

// Whether the points \p P (a region's input) lie on one plane to within \p noise (absolute, along the normal):
// (a) and (b) of plane_regions().
bool is_plane(const MatrixX3d& P, double noise, double misfit) {
  const Eigen::Index n = P.rows();
  const Eigen::RowVector3d c = P.colwise().mean();
  const MatrixX3d Q = P.rowwise() - c;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Q.transpose() * Q);
  const Eigen::Matrix3d B = es.eigenvectors();  // column 0: the plane's normal
  const double plane_ss = std::max(es.eigenvalues()[0], 0.0);
  if (std::sqrt(plane_ss / double(n)) > misfit * noise) return false;
  Eigen::MatrixXd A(n, 6);
  Eigen::VectorXd z(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double u = Q.row(i).dot(B.col(1)), v = Q.row(i).dot(B.col(2));
    A.row(i) << 1, u, v, u * u, u * v, v * v;
    z[i] = Q.row(i).dot(B.col(0));
  }
  const Eigen::VectorXd coef = A.colPivHouseholderQr().solve(z);
  const double quad_ss = (A * coef - z).squaredNorm();
  if (!(quad_ss > 0)) return false;
  return (plane_ss - quad_ss) / 3 <= kCurvedF * quad_ss / double(n - 6);
}

}  // namespace

Eigen::VectorXd plane_regions(const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& Xs,
                              const Eigen::VectorXd& noise_map, double h, double misfit) {
  Eigen::VectorXd plane = Eigen::VectorXd::Zero(X.rows());
  if (!(misfit > 0) || F.rows() == 0) return plane;
  MatrixX3d FN(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 n = (Xs.row(F(f, 1)) - Xs.row(F(f, 0))).cross(Xs.row(F(f, 2)) - Xs.row(F(f, 0)));
    FN.row(f) = (n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero()).transpose();
  }
  const std::vector<int> region = flat_regions(F, FN);
  std::map<int, std::vector<int>> verts;  // per region, its vertices (with repeats)
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) verts[region[f]].push_back(F(f, k));
  for (auto& [id, vs] : verts) {
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    if (static_cast<int>(vs.size()) < kMinPlaneVertices) continue;
    MatrixX3d P(vs.size(), 3);
    std::vector<double> level(vs.size());
    for (size_t i = 0; i < vs.size(); ++i) P.row(i) = X.row(vs[i]), level[i] = noise_map[vs[i]];
    const auto mid = level.begin() + static_cast<std::ptrdiff_t>(level.size() / 2);
    std::nth_element(level.begin(), mid, level.end());
    if (!(*mid > 0) || !is_plane(P, *mid * h, misfit)) continue;
    for (int v : vs) plane[v] = 1;
  }
  return plane;
}

}  // namespace geotex::detail
