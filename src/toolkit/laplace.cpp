#include "geotex/toolkit/laplace.h"

#include <algorithm>
#include <cmath>

namespace geotex {

const EnumNames<LaplacianType>& laplacian_names() {
  static const EnumNames<LaplacianType> n = {
      {"umbrella", LaplacianType::Umbrella}, {"cotan", LaplacianType::Cotangent}, {"cotangent", LaplacianType::Cotangent}};
  return n;
}

const EnumNames<MassType>& mass_names() {
  static const EnumNames<MassType> n = {
      {"voronoi", MassType::Voronoi}, {"barycentric", MassType::Barycentric}, {"thesis", MassType::Thesis}};
  return n;
}

namespace {
inline Vec3 P(const Mesh& m, Mesh::VertexHandle v) { return to_eigen(m.point(v)); }

// cot of the angle between u and v (Fig. 5.4: dot over |cross|), with |cross| (twice the triangle's
// area) floored at min_cross. Each triangle passes the same floor for its three corners: its weights
// are then those of a triangle with a positive area, whose Dirichlet form is positive semi-definite,
// so zero-area triangles cannot make C indefinite (clamping each corner's cot separately can: a
// collinear triangle would give +max, +max, −max). Unchanged for every triangle above the floor.
inline double cot(const Vec3& u, const Vec3& v, double min_cross, double max_cot) {
  const double c = std::max(u.cross(v).norm(), min_cross);
  const double d = u.dot(v);
  if (!(c > 0)) return 0;  // all three corners at one point: no gradient, no weight
  return std::clamp(d / c, -max_cot, max_cot);
}
}  // namespace

SparseMatrix adjacency_matrix(const Mesh& mesh) {
  std::vector<Triplet> t;
  t.reserve(2 * mesh.n_edges());
  for (auto e : mesh.edges()) {
    const int i = e.v0().idx(), j = e.v1().idx();
    t.emplace_back(i, j, 1.0);
    t.emplace_back(j, i, 1.0);
  }
  SparseMatrix A(mesh.n_vertices(), mesh.n_vertices());
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

SparseMatrix umbrella_laplacian(const Mesh& mesh) {
  const int n = static_cast<int>(mesh.n_vertices());
  std::vector<Triplet> t;
  t.reserve(2 * mesh.n_edges() + n);
  for (auto v : mesh.vertices()) {
    const int d = static_cast<int>(mesh.valence(v));
    if (d == 0) continue;
    for (auto w : mesh.vv_range(v)) t.emplace_back(v.idx(), w.idx(), 1.0 / d);
    t.emplace_back(v.idx(), v.idx(), -1.0);
  }
  SparseMatrix L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

SparseMatrix cotan_matrix(const Mesh& mesh, const CotanOptions& options) {
  const int n = static_cast<int>(mesh.n_vertices());
  std::vector<Triplet> t;
  t.reserve(4 * mesh.n_edges());
  // Each face adds ½ cot(angle at k) to the edge (i, j) opposite corner k.
  for (auto f : mesh.faces()) {
    int id[3], k = 0;
    Vec3 p[3];
    for (auto v : f.vertices()) { id[k] = v.idx(); p[k++] = P(mesh, v); }
    // |cot| <= |u||v| / min_cross <= max_cot: the bound of CotanOptions::max_cot.
    const double l2 = std::max({(p[1] - p[0]).squaredNorm(), (p[2] - p[1]).squaredNorm(), (p[0] - p[2]).squaredNorm()});
    const double min_cross = l2 / options.max_cot;
    for (int c = 0; c < 3; ++c) {
      const int i = id[(c + 1) % 3], j = id[(c + 2) % 3];
      const double w = 0.5 * cot(p[(c + 1) % 3] - p[c], p[(c + 2) % 3] - p[c], min_cross, options.max_cot);
      t.emplace_back(i, j, w);
      t.emplace_back(j, i, w);
      t.emplace_back(i, i, -w);
      t.emplace_back(j, j, -w);
    }
  }
  SparseMatrix C(n, n);
  C.setFromTriplets(t.begin(), t.end());
  return C;
}

Eigen::VectorXd mass_diagonal(const Mesh& mesh, MassType type) {
  Eigen::VectorXd m = Eigen::VectorXd::Zero(mesh.n_vertices());
  for (auto f : mesh.faces()) {
    int id[3], k = 0;
    Vec3 p[3];
    for (auto v : f.vertices()) { id[k] = v.idx(); p[k++] = P(mesh, v); }
    const double area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    if (type == MassType::Barycentric) {
      for (int c = 0; c < 3; ++c) m[id[c]] += area / 3.0;
    } else if (type == MassType::Thesis) {
      for (int c = 0; c < 3; ++c) m[id[c]] += 2.0 * area;
    } else {
      // Mixed Voronoi areas (Meyer, Desbrun, Schröder, Barr 2003).
      int obtuse = -1;
      for (int c = 0; c < 3; ++c)
        if ((p[(c + 1) % 3] - p[c]).dot(p[(c + 2) % 3] - p[c]) < 0) obtuse = c;
      if (obtuse >= 0) {
        for (int c = 0; c < 3; ++c) m[id[c]] += c == obtuse ? area / 2.0 : area / 4.0;
      } else if (area > 0) {
        for (int c = 0; c < 3; ++c) {
          const Vec3 &a = p[c], &b = p[(c + 1) % 3], &d = p[(c + 2) % 3];
          const double cot_b = (a - b).dot(d - b) / (2.0 * area);  // |cross| = 2 area
          const double cot_d = (a - d).dot(b - d) / (2.0 * area);
          m[id[c]] += ((a - d).squaredNorm() * cot_b + (a - b).squaredNorm() * cot_d) / 8.0;
        }
      }
    }
  }
  // Isolated vertices and vertices surrounded by zero-area faces: keep M invertible.
  for (Eigen::Index i = 0; i < m.size(); ++i)
    if (!(m[i] > 0)) m[i] = 1.0;
  return m;
}

SparseMatrix mass_matrix(const Mesh& mesh, MassType type) {
  const Eigen::VectorXd m = mass_diagonal(mesh, type);
  SparseMatrix M(m.size(), m.size());
  M.reserve(Eigen::VectorXi::Constant(m.size(), 1));
  for (Eigen::Index i = 0; i < m.size(); ++i) M.insert(i, i) = m[i];
  M.makeCompressed();
  return M;
}

SparseMatrix cotan_laplacian(const Mesh& mesh, MassType type, const CotanOptions& options) {
  const Eigen::VectorXd m = mass_diagonal(mesh, type);
  SparseMatrix L = m.cwiseInverse().asDiagonal() * cotan_matrix(mesh, options);
  return L;
}

SparseMatrix laplacian(const Mesh& mesh, LaplacianType type, MassType mass) {
  return type == LaplacianType::Umbrella ? umbrella_laplacian(mesh) : cotan_laplacian(mesh, mass);
}

MatrixX3d mean_curvature_normals(const Mesh& mesh) {
  const MatrixX3d X = positions(mesh);
  return -0.5 * (cotan_laplacian(mesh, MassType::Voronoi) * X);
}

}  // namespace geotex
