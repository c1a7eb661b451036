// Discrete 1-forms: line integrals, Whitney interpolation, vertex reconstruction, least-squares fit
// (thesis Sec. 5.3 and 8.2).

#include "geotex/toolkit/one_form.h"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>
#include <vector>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/progress.h"

namespace geotex {

const OptionTable<OneFormFitOptions>& OneFormFitOptions::table() {
  using O = OneFormFitOptions;
  static const auto t = OptionTable<O>()
      .add("tangential", &O::tangential, "fit only the field's components tangent to the vertex normals", {}, "Eq. (5.81)")
      .add("bound_by_edge_length", &O::bound_by_edge_length, "keep |c_ij| <= |e_ij| (a tilt has magnitude at most one)",
           {}, "Sec. 8.5")
      .add("regularization", &O::regularization, "pull towards the averaging estimate, relative to the mean diagonal",
           non_negative(), "Eq. (5.80)")
      .add("bound_rounds", &O::bound_rounds, "active-set rounds that pin violating coefficients", non_negative())
      .add("bound_stiffness", &O::bound_stiffness, "penalty pinning a violator, relative to the mean diagonal", positive());
  return t;
}
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// A face with its corners (faces(mesh) order), the mesh edge under each local edge l (corner l →
// corner l+1) with the sign of that edge's orientation relative to the face, its area, and the local
// edges rotated by π/2 in the face's plane.
struct FaceFrame {
  int v[3];
  int e[3];
  double s[3];
  double area;
  Vec3 perp[3];
};

FaceFrame face_frame(const Mesh& mesh, int f) {
  if (f < 0 || f >= static_cast<int>(mesh.n_faces())) throw InvalidInput("1-form: face index out of range");
  FaceFrame fr;
  int k = 0;
  for (auto v : mesh.fv_range(mesh.face_handle(f))) fr.v[k++] = v.idx();
  auto X = [&](int l) { return to_eigen(mesh.point(mesh.vertex_handle(fr.v[l]))); };
  const Vec3 cr = (X(1) - X(0)).cross(X(2) - X(0));
  fr.area = 0.5 * cr.norm();
  const Vec3 n = fr.area > 0 ? Vec3(cr / (2 * fr.area)) : Vec3::Zero();
  for (int l = 0; l < 3; ++l) {
    const auto h = mesh.find_halfedge(mesh.vertex_handle(fr.v[l]), mesh.vertex_handle(fr.v[(l + 1) % 3]));
    const auto eh = mesh.edge_handle(h);
    fr.e[l] = eh.idx();
    fr.s[l] = mesh.halfedge_handle(eh, 0) == h ? 1.0 : -1.0;
    fr.perp[l] = n.cross(X((l + 1) % 3) - X(l));  // e^⊥, Eq. (5.72)
  }
  return fr;
}

void check_coefficients(const Mesh& mesh, const Eigen::VectorXd& c) {
  if (c.size() != static_cast<Eigen::Index>(mesh.n_edges()))
    throw InvalidInput("1-form: expected one coefficient per edge (" + std::to_string(mesh.n_edges()) + "), got " +
                       std::to_string(c.size()));
}

}  // namespace

Eigen::VectorXd one_form_from_function(const Mesh& mesh, const std::function<Vec3(const Vec3&)>& field) {
  // 5-point Gauss–Legendre on [0, 1].
  static const double x[5] = {0.0469100770306680, 0.2307653449471585, 0.5, 0.7692346550528415, 0.9530899229693320};
  static const double w[5] = {0.1184634425280945, 0.2393143352496832, 0.2844444444444444, 0.2393143352496832,
                              0.1184634425280945};
  const MatrixX3d V = positions(mesh);
  const MatrixX2i E = edges(mesh);
  Eigen::VectorXd c(E.rows());
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const Vec3 a = V.row(E(e, 0)), b = V.row(E(e, 1)), d = b - a;
    double s = 0;
    for (int k = 0; k < 5; ++k) s += w[k] * field(a + x[k] * d).dot(d);  // Eq. (5.69)
    c[e] = s;
  }
  return c;
}

Eigen::VectorXd one_form_average(const Mesh& mesh, const MatrixX3d& T) {
  if (T.rows() != static_cast<Eigen::Index>(mesh.n_vertices()))
    throw InvalidInput("1-form: expected one vector per vertex");
  const MatrixX3d V = positions(mesh);
  const MatrixX2i E = edges(mesh);
  Eigen::VectorXd c(E.rows());
#pragma omp parallel for schedule(static)
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const int i = E(e, 0), j = E(e, 1);
    c[e] = 0.5 * (T.row(i) + T.row(j)).dot(V.row(j) - V.row(i));  // Eq. (5.80)
  }
  return c;
}

Vec3 whitney_basis(const Mesh& mesh, int face, int l, const Vec3& bary) {
  if (l < 0 || l > 2) throw InvalidInput("whitney_basis: local edge must be 0, 1 or 2");
  const FaceFrame fr = face_frame(mesh, face);
  if (!(fr.area > 0)) return Vec3::Zero();
  const int a = l, b = (l + 1) % 3;
  // dφ_m = (edge opposite corner m)^⊥ / 2A (Eq. 5.72); φ_ab = α_a dφ_b − α_b dφ_a (Eq. 5.71, 5.73).
  const Vec3 dphi_a = fr.perp[(a + 1) % 3] / (2 * fr.area), dphi_b = fr.perp[(b + 1) % 3] / (2 * fr.area);
  return bary[a] * dphi_b - bary[b] * dphi_a;
}

Vec3 whitney_interpolate(const Mesh& mesh, const Eigen::VectorXd& c, int face, const Vec3& al) {
  check_coefficients(mesh, c);
  const FaceFrame fr = face_frame(mesh, face);
  if (!(fr.area > 0)) return Vec3::Zero();
  const double cij = fr.s[0] * c[fr.e[0]], cjk = fr.s[1] * c[fr.e[1]], cki = fr.s[2] * c[fr.e[2]];
  // Eq. (5.77) with (i, j, k) the face's corners 0, 1, 2.
  return ((cki * al[2] - cij * al[1]) * fr.perp[1] + (cij * al[0] - cjk * al[2]) * fr.perp[2] +
          (cjk * al[1] - cki * al[0]) * fr.perp[0]) /
         (2 * fr.area);
}

namespace {

// P of Eq. (5.81)–(5.82) assembled row by row: row d·#V + i holds vertex i's spoke edges, whose
// coefficients give component d of the averaged face contributions at x_i (Eq. 5.78, 5.79).
RowSparse reconstruction_rows(const Mesh& mesh) {
  const Eigen::Index n = mesh.n_vertices(), m = mesh.n_edges();
  std::vector<Eigen::Index> start(n + 1, 0);  // spoke count prefix sums = one block's row offsets
  for (Eigen::Index i = 0; i < n; ++i) start[i + 1] = start[i] + mesh.valence(mesh.vertex_handle(static_cast<int>(i)));
  const Eigen::Index nb = start[n];
  RowSparse A(3 * n, m);
  A.resizeNonZeros(3 * nb);
  int* outer = A.outerIndexPtr();
  int* inner = A.innerIndexPtr();
  double* val = A.valuePtr();
  for (int d = 0; d < 3; ++d)
    for (Eigen::Index i = 0; i < n; ++i) outer[d * n + i] = static_cast<int>(d * nb + start[i]);
  outer[3 * n] = static_cast<int>(3 * nb);
#pragma omp parallel
  {
    std::vector<std::pair<int, Vec3>> row;  // (edge, coefficient vector) of one vertex's spokes
#pragma omp for schedule(dynamic, 1024)
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto vh = mesh.vertex_handle(static_cast<int>(i));
      row.clear();
      int nfaces = 0;
      for (auto h : mesh.voh_range(vh)) {
        row.emplace_back(mesh.edge_handle(h).idx(), Vec3::Zero());
        nfaces += mesh.face_handle(h).is_valid();
      }
      auto add = [&](int e, const Vec3& g) {
        for (auto& [edge, sum] : row)
          if (edge == e) {
            sum += g;
            return;
          }
      };
      const Vec3 xi = to_eigen(mesh.point(vh));
      for (auto h : mesh.voh_range(vh)) {  // corner of face(h) at i: h = i→j, prev(h) = k→i
        if (!mesh.face_handle(h).is_valid()) continue;
        const auto hp = mesh.prev_halfedge_handle(h);
        const Vec3 xj = to_eigen(mesh.point(mesh.to_vertex_handle(h)));
        const Vec3 xk = to_eigen(mesh.point(mesh.from_vertex_handle(hp)));
        const Vec3 cr = (xj - xi).cross(xk - xi);
        const double area = 0.5 * cr.norm();
        if (!(area > 0)) continue;
        const Vec3 nf = cr / (2 * area);
        const auto eij = mesh.edge_handle(h), eki = mesh.edge_handle(hp);
        const double sij = mesh.halfedge_handle(eij, 0) == h ? 1.0 : -1.0;
        const double ski = mesh.halfedge_handle(eki, 0) == hp ? 1.0 : -1.0;
        const double w = 1.0 / (2 * area * nfaces);
        // Eq. (5.78): t_ijk(x_i) = (c_ij e_ki^⊥ − c_ki e_ij^⊥) / 2A, averaged over the faces (5.79).
        add(eij.idx(), w * sij * nf.cross(xi - xk));
        add(eki.idx(), -w * ski * nf.cross(xj - xi));
      }
      std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      for (int d = 0; d < 3; ++d) {
        const Eigen::Index o = d * nb + start[i];
        for (size_t k = 0; k < row.size(); ++k) {
          inner[o + k] = row[k].first;
          val[o + k] = row[k].second[d];
        }
      }
    }
  }
  return A;
}

}  // namespace

SparseMatrix one_form_reconstruction_matrix(const Mesh& mesh) { return SparseMatrix(reconstruction_rows(mesh)); }

MatrixX3d one_form_to_vertices(const Mesh& mesh, const Eigen::VectorXd& c) {
  check_coefficients(mesh, c);
  const SparseMatrix P = one_form_reconstruction_matrix(mesh);
  const Eigen::VectorXd t = P * c;
  const Eigen::Index n = mesh.n_vertices();
  MatrixX3d T(n, 3);
  for (int d = 0; d < 3; ++d) T.col(d) = t.segment(d * n, n);
  return T;
}

struct OneFormFitter::Impl {
  const Mesh* mesh = nullptr;
  OneFormFitOptions opt;
  SparseMatrix P;       // 3n × m
  SparseMatrix A;       // the tangent-projected P (tangential mode; built with the normal matrix)
  SparseMatrix proj;    // 3n × 3n tangent projector (tangential mode; built with the normal matrix)
  MatrixX3d normals;    // the projector's unit normals, one row per vertex (tangential mode)
  double eps = 0;        // ε of the unweighted fit
  double trace = 0;      // trace of AᵀA
  Eigen::VectorXd edge_len;
  // The unweighted direct fit AᵀA + ε I, as the least-squares system of A: a vertex of valence k puts a
  // k × k block into AᵀA (a fan of 8,000: 0.5 GB), which LeastSquaresSolver keeps out of its factor.
  LeastSquaresSolver unweighted;
  bool unweighted_factored = false;
  bool has_normal = false;    // A (tangential), `eps` and `trace` exist (built on first direct fit)
  RowSparse A_rows;     // P row-major, for the iterative fit's vertex-parallel products

  // Tangential direct fit in vertex form (see fit_tangential()): B = [Uᵀ P; Vᵀ P] (2n × m), the
  // tangent components of P c in a per-vertex basis (u_i, v_i) of the plane ⊥ n_i.
  SparseMatrix B, BBt;
  SpdSolver tangent_solver;
  Eigen::VectorXd tangent_weights;  // the weights tangent_solver's factor was made with
  double tangent_eps = 0;
  bool tangent_factored = false;

  Vec3 basis(Eigen::Index i, int a) const {
    const Vec3 n = normals.row(i).transpose();
    if (!(n.squaredNorm() > 0.5)) return a == 0 ? Vec3::UnitX() : Vec3::UnitY();  // isolated vertex: no normal
    const Vec3 u = n.unitOrthogonal();
    return a == 0 ? u : Vec3(n.cross(u));
  }

  void ensure_tangent_system() {
    if (B.size() > 0) return;
    const Eigen::Index n = normals.rows();
    const int* outer = A_rows.outerIndexPtr();
    const int* inner = A_rows.innerIndexPtr();
    const double* val = A_rows.valuePtr();
    const Eigen::Index nb = outer[n];
    RowSparse Br(2 * n, P.cols());
    Br.resizeNonZeros(2 * nb);
    for (int a = 0; a < 2; ++a)
      for (Eigen::Index i = 0; i <= n; ++i) Br.outerIndexPtr()[a * n + i] = static_cast<int>(a * nb + outer[i]);
#pragma omp parallel for schedule(static)
    for (Eigen::Index i = 0; i < n; ++i)
      for (int a = 0; a < 2; ++a) {
        const Vec3 e = basis(i, a);
        for (int k = outer[i]; k < outer[i + 1]; ++k) {
          Br.innerIndexPtr()[a * nb + k] = inner[k];
          Br.valuePtr()[a * nb + k] = e[0] * val[k] + e[1] * val[nb + k] + e[2] * val[2 * nb + k];
        }
      }
    B = SparseMatrix(Br);
    BBt = B * SparseMatrix(B.transpose());
    BBt.makeCompressed();
    tangent_solver.analyze(BBt, 2);  // vertex graph ordering, each vertex's two unknowns together
  }
  Eigen::VectorXd fit_tangential(const MatrixX3d& T, const Eigen::VectorXd& weights);

  const SparseMatrix& matrix() const { return opt.tangential ? A : P; }  // the direct fit's design matrix

  // The direct route's design matrix and regularization, built on first use so that an iterative-only
  // caller never pays for them.
  void ensure_normal() {
    if (has_normal) return;
    if (opt.tangential) {
      const Eigen::Index n = normals.rows();
      std::vector<Triplet> trip;
      trip.reserve(9 * n);
      for (Eigen::Index i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)
            trip.emplace_back(a * n + i, b * n + i, (a == b ? 1.0 : 0.0) - normals(i, a) * normals(i, b));
      proj.resize(3 * n, 3 * n);
      proj.setFromTriplets(trip.begin(), trip.end());
      A = proj * P;
    }
    trace = matrix().squaredNorm();
    eps = opt.regularization * trace / std::max<Eigen::Index>(matrix().cols(), 1);
    has_normal = true;
  }
};

OneFormFitter::OneFormFitter(const Mesh& mesh, const OneFormFitOptions& options, const MatrixX3d& normals)
    : impl_(std::make_unique<Impl>()) {
  check_options(options);
  require_valid(mesh, "1-form fit: mesh");
  Impl& s = *impl_;
  s.mesh = &mesh;
  s.opt = options;
  s.A_rows = reconstruction_rows(mesh);
  s.P = SparseMatrix(s.A_rows);
  s.edge_len = edge_lengths(mesh);
  const Eigen::Index n = mesh.n_vertices(), m = mesh.n_edges();
  if (options.tangential) {
    s.normals = normals.rows() ? normals : vertex_normals(mesh);
    if (s.normals.rows() != n) throw InvalidInput("1-form fit: expected one normal per vertex");
  }
  (void)m;
}

OneFormFitter::~OneFormFitter() = default;
OneFormFitter::OneFormFitter(OneFormFitter&&) noexcept = default;
OneFormFitter& OneFormFitter::operator=(OneFormFitter&&) noexcept = default;
const SparseMatrix& OneFormFitter::matrix() const { return impl_->P; }

Eigen::VectorXd OneFormFitter::fit(const MatrixX3d& T) { return fit(T, Eigen::VectorXd()); }

// The tangential fit without the bound, in vertex form. Its objective ‖W^½ (B c − b)‖² + ε ‖c − c0‖²
// (B: the tangent rows of Eq. 5.81, c0: Eq. 5.80) has the minimiser c = c0 + Bᵀ (B Bᵀ + ε W⁻¹)⁻¹
// (b − B c0), the same as the #E × #E normal equations (BᵀWB + εI)⁻¹ give. B has 2#V rows against #E
// ≈ 3#V columns, so this system is a third smaller and has the vertex graph's 2×2-block pattern: its
// ordering and factorization cost a fraction of the edge system's (bench/texture.md).
Eigen::VectorXd OneFormFitter::Impl::fit_tangential(const MatrixX3d& T, const Eigen::VectorXd& weights) {
  Impl& s = *this;
  const Eigen::Index n = T.rows(), m = s.P.cols();
  s.ensure_tangent_system();
  const Eigen::VectorXd w = weights.size() ? weights : Eigen::VectorXd::Ones(n);
  if (!s.tangent_factored || s.tangent_weights.size() != w.size() || s.tangent_weights != w) {
    // ε as in the edge form: regularization × mean diagonal of BᵀWB (trace(BᵀWB) = Σ w_k (BBᵀ)_kk).
    Eigen::VectorXd w2(2 * n), diag = s.BBt.diagonal();
    w2 << w, w;
    s.tangent_eps = s.opt.regularization * w2.dot(diag) / std::max<Eigen::Index>(m, 1);
    SparseMatrix S = s.BBt;
    for (Eigen::Index k = 0; k < 2 * n; ++k) S.coeffRef(k, k) += s.tangent_eps / w2[k];
    s.tangent_solver.factorize(S);
    s.tangent_weights = w;
    s.tangent_factored = true;
  }
  const Eigen::VectorXd c0 = one_form_average(*s.mesh, T);  // Eq. (5.80)
  Eigen::VectorXd b(2 * n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int a = 0; a < 2; ++a) b[a * n + i] = s.basis(i, a).dot(T.row(i).transpose());
  const Eigen::VectorXd y = s.tangent_solver.solve(b - s.B * c0);
  return c0 + s.B.transpose() * y;
}


Eigen::VectorXd OneFormFitter::fit(const MatrixX3d& T, const Eigen::VectorXd& weights) {
  Impl& s = *impl_;
  const Eigen::Index n = s.mesh->n_vertices(), m = s.mesh->n_edges();
  if (T.rows() != n) throw InvalidInput("1-form fit: expected one vector per vertex");
  const bool weighted = weights.size() > 0;
  if (weighted && (weights.size() != n || !(weights.minCoeff() > 0) || !weights.allFinite()))
    throw InvalidInput("1-form fit: expected one positive weight per vertex");
  if (s.opt.tangential && !s.opt.bound_by_edge_length) return s.fit_tangential(T, weights);
  s.ensure_normal();
  Eigen::VectorXd t(3 * n);
  for (int d = 0; d < 3; ++d) t.segment(d * n, n) = T.col(d);
  if (s.opt.tangential) t = s.proj * t;
  // Normal equations of ‖W (A c − t)‖² + ε ‖c − c_avg‖² (Eq. 5.81 and the estimate 5.80), solved as the
  // least-squares system of G = W^½ A (see Impl::unweighted).
  const Eigen::VectorXd c_avg = one_form_average(*s.mesh, T);
  LeastSquaresSolver local;
  const LeastSquaresSolver* solver = &s.unweighted;
  SparseMatrix G;  // weighted: W^½ A
  Eigen::VectorXd rhs;
  double eps = s.eps, trace = s.trace;
  if (weighted) {
    Eigen::VectorXd w3(3 * n);
    for (int d = 0; d < 3; ++d) w3.segment(d * n, n) = weights;
    G = s.matrix();  // rows scaled in place: Eigen's diagonal × sparse product copied per row here
    const Eigen::VectorXd sw = w3.cwiseSqrt();
    for (int col = 0; col < G.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(G, col); it; ++it) it.valueRef() *= sw[it.row()];
    trace = G.squaredNorm();
    eps = s.opt.regularization * trace / std::max<Eigen::Index>(m, 1);
    local.compute(G, Eigen::VectorXd::Constant(m, eps));
    solver = &local;
    rhs = s.matrix().transpose() * w3.cwiseProduct(t) + eps * c_avg;
  } else {
    if (!s.unweighted_factored) s.unweighted.compute(s.matrix(), Eigen::VectorXd::Constant(m, s.eps));
    s.unweighted_factored = true;
    rhs = s.matrix().transpose() * t + s.eps * c_avg;
  }
  Eigen::VectorXd c = solver->solve(rhs);
  if (!s.opt.bound_by_edge_length) return c;

  // |c_ij| ≤ ‖e_ij‖ (Sec. 8.5): pin violators to ±‖e_ij‖ with a stiff penalty on the diagonal (same
  // sparsity, so the symbolic analysis is reused), re-solve, repeat while new violators appear.
  std::vector<double> target(m, 0.0);
  std::vector<char> pinned(m, 0);
  const double stiff = s.opt.bound_stiffness * (trace + eps * m) / std::max<Eigen::Index>(m, 1);

  for (int round = 0; round < s.opt.bound_rounds; ++round) {
    int added = 0;
    for (Eigen::Index e = 0; e < m; ++e)
      if (!pinned[e] && std::abs(c[e]) > s.edge_len[e]) {
        pinned[e] = 1;
        target[e] = std::copysign(s.edge_len[e], c[e]);
        ++added;
      }
    if (added == 0) break;
    Eigen::VectorXd diag = Eigen::VectorXd::Constant(m, eps);
    Eigen::VectorXd r = rhs;
    for (Eigen::Index e = 0; e < m; ++e)
      if (pinned[e]) {
        diag[e] += stiff;
        r[e] += stiff * target[e];
      }
    if (weighted) local.refactor(diag);
    else if (solver == &s.unweighted) local.compute(s.matrix(), diag);  // keep the unweighted factor
    else local.refactor(diag);
    solver = &local;
    c = local.solve(r);
  }
  for (Eigen::Index e = 0; e < m; ++e) c[e] = std::clamp(c[e], -s.edge_len[e], s.edge_len[e]);
  return c;
}

namespace {

// Removes from (a0, a1, a2) its component along vertex i's unit normal.
void project_to_tangent(const MatrixX3d& normals, Eigen::Index i, double& a0, double& a1, double& a2) {
  const double dn = a0 * normals(i, 0) + a1 * normals(i, 1) + a2 * normals(i, 2);
  a0 -= dn * normals(i, 0);
  a1 -= dn * normals(i, 1);
  a2 -= dn * normals(i, 2);
}

// 1 / ‖column j of W^½ Π P‖ for every edge j (1 for an empty column): the iterative fit's Jacobi
// scaling. A: P row-major (rows d·#V + i), Pcol: P column-major, sw: W^½ stacked [x; y; z].
Eigen::VectorXd column_scales(const RowSparse& A, const SparseMatrix& Pcol, const MatrixX3d& normals,
                              const Eigen::VectorXd& sw, bool tangential, bool par) {
  const Eigen::Index n = sw.size() / 3, m = Pcol.cols();
  const Eigen::Index nb = A.outerIndexPtr()[n];
  Eigen::VectorXd col(m);
  Eigen::VectorXd sq = Eigen::VectorXd::Zero(m);
  if (!tangential) {
#pragma omp parallel for schedule(static) if (par)
    for (Eigen::Index j = 0; j < m; ++j)
      for (SparseMatrix::InnerIterator it(Pcol, j); it; ++it) sq[j] += sw[it.index()] * sw[it.index()] * it.value() * it.value();
  } else {  // a column's entries at vertex i form the vector (P_x, P_y, P_z); project it, then square
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const double* val = A.valuePtr();
    for (Eigen::Index i = 0; i < n; ++i)
      for (int k = outer[i]; k < outer[i + 1]; ++k) {
        double a0 = val[k], a1 = val[nb + k], a2 = val[2 * nb + k];
        project_to_tangent(normals, i, a0, a1, a2);
        sq[inner[k]] += sw[i] * sw[i] * (a0 * a0 + a1 * a1 + a2 * a2);
      }
  }
  for (Eigen::Index j = 0; j < m; ++j) col[j] = sq[j] > 0 ? 1.0 / std::sqrt(sq[j]) : 1.0;
  return col;
}

}  // namespace

IterativeFitResult OneFormFitter::fit_iterative(const MatrixX3d& T, const Eigen::VectorXd& weights,
                                                const OneFormFitMonitor& converged, const IterativeFitOptions& o) {
  Impl& s = *impl_;
  const Eigen::Index n = s.mesh->n_vertices(), m = s.mesh->n_edges();
  if (T.rows() != n) throw InvalidInput("1-form fit: expected one vector per vertex");
  if (weights.size() > 0 && (weights.size() != n || !(weights.minCoeff() > 0) || !weights.allFinite()))
    throw InvalidInput("1-form fit: expected one positive weight per vertex");
  if (o.max_iterations < 0 || o.check_every < 1)
    throw InvalidInput("1-form fit: max_iterations must be non-negative and check_every positive");
  const RowSparse& A = s.A_rows;  // P row-major: rows d·#V + i, vertex i's spokes
  const SparseMatrix& Pcol = s.P;  // P column-major: its outer index runs over the edges, i.e. Pᵀ's rows

  // Weighted objective ‖W^½ (Π P c − Π t)‖² (Eq. 5.81; Π = I, or the per-vertex tangent projector
  // when tangential), solved for x = c ./ col in the column-scaled variables (Jacobi preconditioning:
  // every column of W^½ Π P S has unit length).
  Eigen::VectorXd sw = Eigen::VectorXd::Ones(3 * n), t(3 * n);
  for (int d = 0; d < 3; ++d) {
    if (weights.size()) sw.segment(d * n, n) = weights.cwiseSqrt();
    t.segment(d * n, n) = T.col(d);
  }
  Eigen::VectorXd b = sw.cwiseProduct(t);  // projected below, once `project` exists
  // Threads only for large meshes: on small ones the per-product barriers cost more than they save.
  const bool par = A.nonZeros() > 500000;
  // Rows i, #V + i, 2#V + i of P share their columns (vertex i's spokes, reconstruction_rows()): one
  // pass over vertex i's spokes gives all three; the tangent projection is applied per vertex on the fly.
  const Eigen::Index nb = A.outerIndexPtr()[n];
  auto project = [&](Eigen::Index i, double& a0, double& a1, double& a2) { project_to_tangent(s.normals, i, a0, a1, a2); };
  // y = diag(out) Π P diag(in) x (Π = I when !projected; in, out optional). Writes into y, allocated
  // once by the caller: fresh 3#V vectors every iteration cost more in page faults than the product.
  auto vertex_product = [&, par](const Eigen::VectorXd* in, const Eigen::VectorXd& x, const Eigen::VectorXd* out,
                                 bool projected, Eigen::VectorXd& y) {
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const double* val = A.valuePtr();
#pragma omp parallel for schedule(static) if (par)
    for (Eigen::Index i = 0; i < n; ++i) {
      double a0 = 0, a1 = 0, a2 = 0;
      for (int k = outer[i]; k < outer[i + 1]; ++k) {
        const double zk = in ? (*in)[inner[k]] * x[inner[k]] : x[inner[k]];
        a0 += val[k] * zk;
        a1 += val[nb + k] * zk;
        a2 += val[2 * nb + k] * zk;
      }
      if (projected) project(i, a0, a1, a2);
      y[i] = out ? (*out)[i] * a0 : a0;
      y[n + i] = out ? (*out)[n + i] * a1 : a1;
      y[2 * n + i] = out ? (*out)[2 * n + i] * a2 : a2;
    }
  };
  if (s.opt.tangential)
    for (Eigen::Index i = 0; i < n; ++i) project(i, b[i], b[n + i], b[2 * n + i]);
  const Eigen::VectorXd col = column_scales(A, Pcol, s.normals, sw, s.opt.tangential, par);  // 1 / ‖column j of W^½ Π P‖
  auto apply_A = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) { vertex_product(&col, x, &sw, s.opt.tangential, y); };
  Eigen::VectorXd v(3 * n);
  auto apply_At = [&, par](const Eigen::VectorXd& r, Eigen::VectorXd& y) {  // diag(col) Pᵀ Π W^½ r (Π symmetric)
#pragma omp parallel for schedule(static) if (par)
    for (Eigen::Index i = 0; i < n; ++i) {
      v[i] = sw[i] * r[i];
      v[n + i] = sw[n + i] * r[n + i];
      v[2 * n + i] = sw[2 * n + i] * r[2 * n + i];
      if (s.opt.tangential) project(i, v[i], v[n + i], v[2 * n + i]);
    }
#pragma omp parallel for schedule(static) if (par)
    for (Eigen::Index j = 0; j < m; ++j) {
      double sum = 0;
      for (SparseMatrix::InnerIterator it(Pcol, j); it; ++it) sum += it.value() * v[it.index()];
      y[j] = col[j] * sum;
    }
  };

  IterativeFitResult res;
  res.c = one_form_average(*s.mesh, T);  // start: Eq. (5.80)
  Eigen::VectorXd field(3 * n);
  auto check = [&]() {
    vertex_product(nullptr, res.c, nullptr, false, field);  // the monitor gets P c unprojected
    return converged && converged(res.c, field);
  };
  if (check()) {
    res.converged = true;
    return res;
  }
  // CGLS (conjugate gradients on the normal equations without forming them).
  Eigen::VectorXd x = res.c.cwiseQuotient(col);
  Eigen::VectorXd q(3 * n), r(3 * n), g(m);
  apply_A(x, q);
  r = b - q;
  apply_At(r, g);
  Eigen::VectorXd p = g;
  double gamma = g.squaredNorm();
  while (res.iterations < o.max_iterations && gamma > 0) {
    check_interrupt();
    apply_A(p, q);
    const double qq = q.squaredNorm();
    if (!(qq > 0)) break;
    const double alpha = gamma / qq;
    x += alpha * p;
    r -= alpha * q;
    apply_At(r, g);
    const double gamma_next = g.squaredNorm();
    p = g + (gamma_next / gamma) * p;
    gamma = gamma_next;
    ++res.iterations;
    if (res.iterations % o.check_every == 0 || res.iterations == o.max_iterations) {
      res.c = col.cwiseProduct(x);
      if (check()) {
        res.converged = true;
        return res;
      }
    }
  }
  res.c = col.cwiseProduct(x);
  res.converged = check();
  return res;
}

Eigen::VectorXd fit_one_form(const Mesh& mesh, const MatrixX3d& T, const OneFormFitOptions& options) {
  return OneFormFitter(mesh, options).fit(T);
}

}  // namespace geotex
