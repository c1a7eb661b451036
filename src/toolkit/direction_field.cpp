// A smooth tangent direction field following a guide (see direction_field.h).

#include "geotex/toolkit/direction_field.h"

#include <cmath>
#include <complex>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/linear_solver.h"

namespace geotex {

const EnumNames<FieldMethod>& field_method_names() {
  static const EnumNames<FieldMethod> n = {{"smooth", FieldMethod::Smooth}, {"projected", FieldMethod::Projected}};
  return n;
}

const OptionTable<DirectionFieldOptions>& DirectionFieldOptions::table() {
  using O = DirectionFieldOptions;
  static const auto t = OptionTable<O>()
      .choice("field", &O::method, field_method_names(),
              "smooth (follows the direction, smooth where it is nearly normal) or projected (its tangent part)",
              "Knöppel et al. 2013")
      .add("field_smoothing", &O::smoothing,
           "smooth field: smoothing length as a share of sqrt(surface area) (longer: smoother, follows less)",
           positive());
  return t;
}

namespace {

// The tangent part of x (else y) at normal n: the fallback where a field has no direction.
Vec3 fallback_tangent(const Vec3& n) {
  Vec3 t = Vec3::UnitX() - n.x() * n;
  if (t.norm() < 0.1) t = Vec3::UnitY() - n.y() * n;
  return t.normalized();
}

}  // namespace

MatrixX3d direction_field(const Mesh& mesh, const MatrixX3d& guide, const DirectionFieldOptions& options) {
  DirectionFieldOptions::table().check(options);
  require_valid(mesh, "direction field: mesh");
  const Eigen::Index n = mesh.n_vertices();
  if (guide.rows() != 1 && guide.rows() != n)
    throw InvalidInput("direction field: expected one guide direction, or one per vertex (" + std::to_string(n) + ")");
  if (!guide.allFinite()) throw InvalidInput("direction field: the guide must be finite");
  const MatrixX3d N = vertex_normals(mesh, NormalWeighting::Angle);
  auto g = [&](Eigen::Index i) -> Vec3 { return guide.row(guide.rows() == 1 ? 0 : i).transpose(); };
  MatrixX3d out = MatrixX3d::Zero(n, 3);

  if (options.method == FieldMethod::Projected) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const Vec3 nr = N.row(i).transpose();
      if (nr.squaredNorm() == 0) continue;
      const Vec3 gi = g(i);
      Vec3 t = gi - gi.dot(nr) * nr;
      out.row(i) = (t.norm() > 1e-9 * std::max(1.0, gi.norm()) ? Vec3(t.normalized()) : fallback_tangent(nr)).transpose();
    }
    return out;
  }

  // A tangent basis per vertex: b1 the tangent part of x (else y), b2 = n × b1.
  const MatrixX3d X = positions(mesh);
  MatrixX3d B1(n, 3), B2(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 nr = N.row(i).transpose();
    const Vec3 b1 = nr.squaredNorm() > 0 ? fallback_tangent(nr) : Vec3::UnitX();
    B1.row(i) = b1.transpose();
    B2.row(i) = nr.cross(b1).transpose();
  }
  auto angle_at = [&](Eigen::Index i, const Vec3& e) { return std::atan2(B2.row(i).dot(e), B1.row(i).dot(e)); };

  // Cotangent weights (clamped at 0) and vertex areas.
  const Eigen::VectorXd fa = face_areas(mesh);
  Eigen::VectorXd area = Eigen::VectorXd::Zero(n);
  std::vector<double> w(mesh.n_edges(), 0.0);
  for (auto f : mesh.faces()) {
    for (auto h : mesh.fh_range(f)) {
      // The corner opposite halfedge h.
      const auto hn = mesh.next_halfedge_handle(h);
      const Vec3 p = X.row(mesh.to_vertex_handle(hn).idx());
      const Vec3 a = X.row(mesh.from_vertex_handle(h).idx()), b = X.row(mesh.to_vertex_handle(h).idx());
      const Vec3 u = a - p, v = b - p;
      const double c = u.cross(v).norm();
      if (c > 0) w[mesh.edge_handle(h).idx()] += 0.5 * u.dot(v) / c;
    }
    for (auto v : mesh.fv_range(f)) area[v.idx()] += fa[f.idx()] / 3;
  }
  const double total = area.sum();
  const double ell = options.smoothing * std::sqrt(total);
  const double lambda = ell > 0 ? 1.0 / (ell * ell) : 0.0;

  // Hermitian H z = b as the real symmetric system on (Re z, Im z) interleaved.
  using C = std::complex<double>;
  std::vector<Triplet> t;
  t.reserve(4 * (n + 2 * mesh.n_edges()));
  Eigen::VectorXd diag = Eigen::VectorXd::Zero(n), rhs = Eigen::VectorXd::Zero(2 * n);
  auto put = [&](Eigen::Index i, Eigen::Index j, C h) {  // the block of H_ij = p + i q: [p −q; q p]
    t.emplace_back(2 * i, 2 * j, h.real());
    t.emplace_back(2 * i, 2 * j + 1, -h.imag());
    t.emplace_back(2 * i + 1, 2 * j, h.imag());
    t.emplace_back(2 * i + 1, 2 * j + 1, h.real());
  };
  for (auto e : mesh.edges()) {
    const double we = std::max(0.0, w[e.idx()]);
    if (!(we > 0)) continue;
    const auto h = mesh.halfedge_handle(e, 0);
    const int i = mesh.from_vertex_handle(h).idx(), j = mesh.to_vertex_handle(h).idx();
    const Vec3 eij = X.row(j) - X.row(i);
    const C r = std::polar(1.0, angle_at(i, eij) - angle_at(j, -eij) + M_PI);  // j's tangent plane → i's
    diag[i] += we;
    diag[j] += we;
    put(i, j, -we * r);
    put(j, i, -we * std::conj(r));
  }
  // The alignment term, and a tiny shift so that the system is definite on any mesh (isolated vertices).
  const double eps = 1e-12 * (diag.maxCoeff() + 1);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 gi = g(i);
    const double a = lambda * area[i];
    put(i, i, C(diag[i] + a + eps, 0));
    rhs[2 * i] = a * B1.row(i).dot(gi);
    rhs[2 * i + 1] = a * B2.row(i).dot(gi);
  }
  SparseMatrix H(2 * n, 2 * n);
  H.setFromTriplets(t.begin(), t.end());
  SpdSolver solver;
  solver.compute(H);
  const Eigen::VectorXd z = solver.solve(rhs);
  const double scale = z.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 nr = N.row(i).transpose();
    if (nr.squaredNorm() == 0) continue;
    const Vec3 v = z[2 * i] * B1.row(i).transpose() + z[2 * i + 1] * B2.row(i).transpose();
    out.row(i) = (v.norm() > 1e-9 * scale ? Vec3(v.normalized()) : fallback_tangent(nr)).transpose();
  }
  return out;
}

}  // namespace geotex
