#include "geotex/toolkit/editing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <fmt/format.h>
#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"

namespace geotex {

const EnumNames<EditMethod>& edit_method_names() {
  static const EnumNames<EditMethod> n = {
      {"plain", EditMethod::Plain}, {"membrane-fit", EditMethod::MembraneFit}, {"linear", EditMethod::Linear}};
  return n;
}

const OptionTable<EditOptions>& EditOptions::table() {
  using O = EditOptions;
  static const auto t = OptionTable<O>()
      .choice("method", &O::method, edit_method_names(),
              "plain (Eq. 5.20), membrane-fit (T_i fitted to a membrane, Eq. 5.23-5.24) or linear (T_i linear in the "
              "positions, Sorkine et al. 2004)", "Sec. 5.1.4")
      .choice("laplacian", &O::laplacian, laplacian_names(), "umbrella (Eq. 5.8) or cotan (row-normalised cotangent weights)",
              "Eq. (5.21)")
      .add("handle_weight", &O::handle_weight, "handle weight w_i of a handle vertex that has none of its own", positive(),
           "Eq. (5.19)")
      .alias("weight")
      .add("allow_scale", &O::allow_scale, "T_i a similarity (rotation and isotropic scale); false: a rotation",
           {}, "Eq. (5.22)")
      .alias("no_scale", "false")
      .add("fit_to_rest_membrane", &O::fit_to_rest_membrane,
           "membrane-fit: fit T_i between the rest membrane and the deformed one (false: the original 1-ring, as Eq. "
           "5.24 reads)", {}, "Eq. (5.24)")
      .alias("literal_fit", "false");
  return t;
}

namespace {

// Closed 1-ring {i} ∪ N_i of every vertex, flat (CSR).
struct Rings {
  std::vector<int> offset{0}, ids;
  explicit Rings(const Mesh& mesh) {
    offset.reserve(mesh.n_vertices() + 1);
    ids.reserve(mesh.n_vertices() + 2 * mesh.n_edges());
    for (auto v : mesh.vertices()) {
      ids.push_back(v.idx());
      for (auto w : mesh.vv_range(v)) ids.push_back(w.idx());
      offset.push_back(static_cast<int>(ids.size()));
    }
  }
  int size(int i) const { return offset[i + 1] - offset[i]; }
  const int* begin(int i) const { return ids.data() + offset[i]; }
  //! The rings as the columns of a pattern matrix R: R Rᵀ couples the vertices that the linear method's
  //! normal equations couple (the 2-ring). A ring longer than \p longest is a row the solver keeps out of
  //! its factor (a fan's hub): its column holds its own vertex only.
  SparseMatrix pattern(int longest) const {
    const int n = static_cast<int>(offset.size()) - 1;
    SparseMatrix R(n, n);
    std::vector<int> outer(n + 1, 0);
    for (int i = 0; i < n; ++i) outer[i + 1] = outer[i] + (size(i) > longest ? 1 : size(i));
    R.resizeNonZeros(outer[n]);
    std::copy(outer.begin(), outer.end(), R.outerIndexPtr());
    for (int i = 0; i < n; ++i) {
      int* col = R.innerIndexPtr() + outer[i];
      if (size(i) > longest) {
        col[0] = i;
        continue;
      }
      std::copy(begin(i), begin(i) + size(i), col);
      std::sort(col, col + size(i));
    }
    std::fill(R.valuePtr(), R.valuePtr() + outer[n], 1.0);
    return R;
  }
};

Eigen::MatrixX3d gather(const MatrixX3d& X, const int* ids, int k) {
  Eigen::MatrixX3d P(k, 3);
  for (int r = 0; r < k; ++r) P.row(r) = X.row(ids[r]);
  return P;
}

// Largest distance from p to the line through a with unit direction u (u = 0: to the point a), and the
// vertex of \p ids that attains it; ties (within 1e-9 of the largest) go to the lowest index, so that
// a symmetric mesh picks the same vertex on every machine.
int farthest_vertex(const MatrixX3d& X, const std::vector<int>& ids, const Vec3& a, const Vec3& u, double* dist) {
  auto distance = [&](int v) {
    const Vec3 d = X.row(v).transpose() - a;
    return (d - d.dot(u) * u).norm();
  };
  std::vector<double> d(ids.size());
  double best = -1;
  for (size_t k = 0; k < ids.size(); ++k) best = std::max(best, d[k] = distance(ids[k]));
  int pick = -1;
  for (size_t k = 0; k < ids.size(); ++k)
    if (d[k] >= best - 1e-9 * std::abs(best) && (pick < 0 || ids[k] < pick)) pick = ids[k];
  if (dist) *dist = best;
  return pick;
}

}  // namespace

std::vector<LaplacianEditor::Anchor> LaplacianEditor::anchors(const Mesh& mesh) const {
  // The linear method's T_i leave the whole similarity group free (Sorkine et al. 2004): translations,
  // rotations and scale map rest solutions to rest solutions. Handles pin it only when a component has
  // three non-collinear ones; otherwise the system is exactly singular and a factorization would
  // decide by rounding. Stated rule, the same on every machine: the component's vertex farthest from the
  // handles' line (one handle, or handles within 1e-3 of the component's size: the two farthest
  // vertices) gets a weak pin (1e-4 of the handles' mean weight²) at the place the handles' own
  // similarity takes it (minimal rotation taking the two extreme handles to their targets, and its
  // scale; a translation for a single handle).
  std::vector<Anchor> out;
  int k = 0;
  const Eigen::VectorXi comp = connected_components(mesh, &k);
  std::vector<std::vector<int>> members(k), held(k);  // vertices; indices into handles_
  for (auto v : mesh.vertices())
    if (!mesh.is_isolated(v)) members[comp[v.idx()]].push_back(v.idx());
  for (size_t h = 0; h < handles_.size(); ++h) held[comp[handles_[h]]].push_back(static_cast<int>(h));
  double mean_w2 = 0;
  for (double w : w2_) mean_w2 += w / static_cast<double>(w2_.size());
  for (int c = 0; c < k; ++c) {
    if (members[c].empty() || held[c].empty()) continue;
    Vec3 lo = X_.row(members[c][0]).transpose(), hi = lo;
    for (int v : members[c]) {
      lo = lo.cwiseMin(X_.row(v).transpose());
      hi = hi.cwiseMax(X_.row(v).transpose());
    }
    const double tol = 1e-3 * (hi - lo).norm();
    const int a = held[c][0];
    const Vec3 xa = X_.row(handles_[a]).transpose();
    // The handle farthest from the first one, then the largest distance of any handle from their line.
    int b = a;
    double ab = 0;
    for (int h : held[c]) {
      const double d = (X_.row(handles_[h]).transpose() - xa).norm();
      if (d > ab) { ab = d; b = h; }
    }
    if (ab <= tol) {  // one point: translation by the handles' mean displacement; two anchors
      Anchor first{-1, a, -1, 1e-4 * mean_w2};
      first.vertex = farthest_vertex(X_, members[c], xa, Vec3::Zero(), nullptr);
      const Vec3 u = (X_.row(first.vertex).transpose() - xa).normalized();
      Anchor second = first;
      second.vertex = farthest_vertex(X_, members[c], xa, u, nullptr);
      for (Anchor* an : {&first, &second}) {
        an->handles.assign(held[c].begin(), held[c].end());
        out.push_back(*an);
      }
      continue;
    }
    const Vec3 u = (X_.row(handles_[b]).transpose() - xa) / ab;
    double off_line = 0;
    for (int h : held[c]) {
      const Vec3 d = X_.row(handles_[h]).transpose() - xa;
      off_line = std::max(off_line, (d - d.dot(u) * u).norm());
    }
    if (off_line > tol) continue;  // three non-collinear handles: pinned
    Anchor an{farthest_vertex(X_, members[c], xa, u, nullptr), a, b, 1e-4 * mean_w2};
    out.push_back(an);
  }
  return out;
}

Vec3 LaplacianEditor::anchor_target(const Anchor& an, const MatrixX3d& C) const {
  const Vec3 p = X_.row(an.vertex).transpose();
  if (an.b < 0) {  // translation by the mean displacement of the handles
    Vec3 t = Vec3::Zero();
    for (int h : an.handles) t += (C.row(h) - X_.row(handles_[h])).transpose();
    return p + t / static_cast<double>(an.handles.size());
  }
  const Vec3 xa = X_.row(handles_[an.a]).transpose(), xb = X_.row(handles_[an.b]).transpose();
  const Vec3 ca = C.row(an.a).transpose(), cb = C.row(an.b).transpose();
  const Vec3 d0 = xb - xa, d1 = cb - ca;
  if (!(d1.norm() > 0)) return ca;
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(d0, d1);
  return ca + (d1.norm() / d0.norm()) * (q * (p - xa));
}

Similarity fit_similarity(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q, bool allow_scale) {
  if (P.rows() != Q.rows() || P.rows() == 0) throw InvalidInput("fit_similarity: P and Q need the same, non-zero row count");
  const Eigen::RowVector3d cp = P.colwise().mean(), cq = Q.colwise().mean();
  const Eigen::MatrixX3d Pc = P.rowwise() - cp, Qc = Q.rowwise() - cq;
  const double var = Pc.squaredNorm();
  Similarity T;
  if (!(var > 0)) {
    T.t = (cq - cp).transpose();
    return T;
  }
  // Umeyama (1991): H = Σ q pᵀ = U Σ Vᵀ, R = U S Vᵀ with S = diag(1, 1, det(U Vᵀ)), s = tr(Σ S) / Σ|p|².
  const Eigen::Matrix3d H = Qc.transpose() * Pc;
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d S(1, 1, (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1);
  T.R = svd.matrixU() * S.asDiagonal() * svd.matrixV().transpose();
  T.s = allow_scale ? svd.singularValues().dot(S) / var : 1.0;
  T.t = cq.transpose() - T.s * (T.R * cp.transpose());
  return T;
}

std::vector<Similarity> one_ring_similarities(const Mesh& mesh, const MatrixX3d& X0, const MatrixX3d& X1,
                                              bool allow_scale) {
  const int n = static_cast<int>(mesh.n_vertices());
  if (X0.rows() != n || X1.rows() != n) throw InvalidInput("one_ring_similarities: positions must be #V by 3");
  const Rings rings(mesh);
  std::vector<Similarity> T(n);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) {
    const int k = rings.size(i);
    T[i] = fit_similarity(gather(X0, rings.begin(i), k), gather(X1, rings.begin(i), k), allow_scale);
  }
  return T;
}

SparseMatrix editing_laplacian(const Mesh& mesh, LaplacianType type) {
  if (type == LaplacianType::Umbrella) return umbrella_laplacian(mesh);
  // Cotangent weights normalised per row: (L x)_i = Σ_j w_ij x_j / Σ_j w_ij − x_i.
  const SparseMatrix C = cotan_matrix(mesh);
  Eigen::VectorXd d = -C.diagonal();
  const double scale = d.size() ? d.cwiseAbs().mean() : 1.0;
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (!(std::abs(d[i]) > 1e-12 * scale)) d[i] = 0;  // isolated vertex: zero row
  Eigen::VectorXd inv = d.unaryExpr([](double x) { return x != 0 ? 1.0 / x : 0.0; });
  SparseMatrix L = inv.asDiagonal() * C;
  return L;
}

namespace {

// Eq. (5.22) with T_i linear in X' (Sorkine et al. 2004): T_i = [[s, −h3, h2], [h3, s, −h1], [−h2, h1, s]]
// plus a translation, with (s, h, t) = (A_iᵀ A_i)⁻¹ A_iᵀ b_i the least-squares fit (Eq. 5.24) of the
// rest 1-ring A_i to the unknown one b_i. Each row block is L_i X' − T_i(X') δ_i = 0; unknowns are
// ordered x-block, y-block, z-block.
// G is assembled row by row: row d·n + i holds the 3k coordinates of i's closed ring (k vertices),
// columns e·n + j in order (e the coordinate, j the ring's vertices sorted).
RowSparseMatrix linear_method_matrix(const Rings& rings, const MatrixX3d& X, const MatrixX3d& D, const SparseMatrix& L) {
  const int n = static_cast<int>(X.rows());
  const RowSparseMatrix Lr = L;
  RowSparseMatrix G(3 * n, 3 * n);
  {
    std::vector<int64_t> start(3 * static_cast<size_t>(n) + 1, 0);
    for (int d = 0; d < 3; ++d)
      for (int i = 0; i < n; ++i) start[size_t(d) * n + i + 1] = 3 * rings.size(i);
    for (size_t r = 0; r < 3 * static_cast<size_t>(n); ++r) start[r + 1] += start[r];
    if (start.back() > std::numeric_limits<int>::max())
      throw OutOfMemory(fmt::format("the linear method's system for {} vertices has {} nonzeros, more than a "
                                    "sparse matrix's 32-bit indices hold", n, start.back()));
    G.resizeNonZeros(static_cast<Eigen::Index>(start.back()));
    for (size_t r = 0; r <= 3 * static_cast<size_t>(n); ++r) G.outerIndexPtr()[r] = static_cast<int>(start[r]);
  }
#pragma omp parallel for schedule(dynamic, 256)
  for (int i = 0; i < n; ++i) {
    const int k = rings.size(i);
    const int* ids = rings.begin(i);
    Eigen::MatrixXd A(3 * k, 7);
    for (int r = 0; r < k; ++r) {
      const double x = X(ids[r], 0), y = X(ids[r], 1), z = X(ids[r], 2);
      A.row(3 * r + 0) << x, 0, z, -y, 1, 0, 0;
      A.row(3 * r + 1) << y, -z, 0, x, 0, 1, 0;
      A.row(3 * r + 2) << z, y, -x, 0, 0, 0, 1;
    }
    const Eigen::MatrixXd Pinv = (A.transpose() * A).ldlt().solve(A.transpose());  // 7 by 3k
    const double dx = D(i, 0), dy = D(i, 1), dz = D(i, 2);
    Eigen::Matrix<double, 3, 7> Dm;
    Dm << dx, 0, dz, -dy, 0, 0, 0,
          dy, -dz, 0, dx, 0, 0, 0,
          dz, dy, -dx, 0, 0, 0, 0;
    // Row block of vertex i: L_i on its own coordinate minus T_i(X') δ_i (3 by 3k, by ring position).
    Eigen::MatrixXd M = -(Dm * Pinv);
    std::vector<int> order(k);
    for (int r = 0; r < k; ++r) order[r] = r;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return ids[a] < ids[b]; });
    int p = 0;  // L's row and the sorted ring, walked together (the Laplacian lives on the ring)
    for (RowSparseMatrix::InnerIterator it(Lr, i); it; ++it) {
      while (p < k && ids[order[p]] < it.col()) ++p;
      if (p < k && ids[order[p]] == it.col())
        for (int d = 0; d < 3; ++d) M(d, 3 * order[p] + d) += it.value();
    }
    for (int d = 0; d < 3; ++d) {
      int at = G.outerIndexPtr()[size_t(d) * n + i];
      for (int e = 0; e < 3; ++e)
        for (int r : order) {
          G.innerIndexPtr()[at] = e * n + ids[r];
          G.valuePtr()[at++] = M(d, 3 * r + e);
        }
    }
  }
  return G;
}

}  // namespace

LaplacianEditor::LaplacianEditor(const Mesh& mesh, std::vector<int> handles, std::vector<double> weights,
                                 const EditOptions& options)
    : mesh_(&mesh), handles_(std::move(handles)), options_(options) {
  check_options(options);
  require_valid(mesh, "editing input");
  const int n = static_cast<int>(mesh.n_vertices());
  if (handles_.empty()) throw InvalidInput("Laplacian editing needs at least one handle vertex");
  if (!weights.empty() && weights.size() != handles_.size())
    throw InvalidInput(fmt::format("{} handle weights for {} handle vertices", weights.size(), handles_.size()));
  std::vector<char> seen(n, 0);
  w2_.resize(handles_.size());
  for (size_t h = 0; h < handles_.size(); ++h) {
    const int v = handles_[h];
    if (v < 0 || v >= n) throw InvalidInput(fmt::format("handle vertex {} is out of range [0, {})", v, n));
    if (seen[v]++) throw InvalidInput(fmt::format("handle vertex {} is given twice", v));
    const double w = weights.empty() ? options.handle_weight : weights[h];
    if (!(w > 0) || !std::isfinite(w)) throw InvalidInput(fmt::format("handle weight {} must be positive", w));
    w2_[h] = w * w;
  }

  // Decided on the input, before any factorization (issue 33): every component needs a handle.
  if (const std::string c = component_without(mesh, handles_); !c.empty())
    throw InvalidInput(fmt::format("the handles do not pin the mesh: {} holds no handle vertex; give every "
                                   "connected component a handle", c));
  X_ = positions(mesh);
  L_ = editing_laplacian(mesh, options.laplacian);
  D_ = L_ * X_;  // Eq. (5.16)
  // Isolated vertices (zero Laplacian rows) stay where they are; the linear method's free similarities
  // are fixed by weak anchors (anchors()).
  for (auto v : mesh.vertices())
    if (mesh.is_isolated(v) && !seen[v.idx()]) isolated_.push_back(v.idx());
  if (options.method == EditMethod::Linear) anchors_ = anchors(mesh);
  if (options.method == EditMethod::MembraneFit) {
    // The membrane of fewer than three non-collinear handles is a point or a line: the rotations fitted
    // to it would be decided by rounding. There the details keep their rest frame (the plain method).
    const Eigen::VectorXi comp = connected_components(mesh);
    std::vector<char> bad(comp.size() ? comp.maxCoeff() + 1 : 0, 0);
    for (const Anchor& an : anchors(mesh)) bad[comp[an.vertex]] = 1;
    rest_frame_.assign(n, 0);
    for (int v = 0; v < n; ++v) rest_frame_[v] = bad[comp[v]];
  }
  const std::string pin_msg = "the handles do not pin the mesh";

  SparseMatrix Wd(n, n);  // W² on the handle rows (and the isolated vertices' and anchors')
  {
    std::vector<Triplet> t;
    for (size_t h = 0; h < handles_.size(); ++h) t.emplace_back(handles_[h], handles_[h], w2_[h]);
    for (int v : isolated_) t.emplace_back(v, v, 1.0);
    for (const Anchor& an : anchors_) t.emplace_back(an.vertex, an.vertex, an.w2);
    Wd.setFromTriplets(t.begin(), t.end());
  }

  if (options.method != EditMethod::Linear) {
    // Normal equations of Eq. (5.20): (LᵀL + W²) X = Lᵀ D + W² C.
    try {
      solver_.compute(L_, Eigen::VectorXd(Wd.diagonal()));
    } catch (const SolverError& e) {
      throw SolverError(fmt::format("{}: {}", pin_msg, e.what()));
    }
    if (options.method == EditMethod::MembraneFit && options.fit_to_rest_membrane) {
      MatrixX3d C(handles_.size(), 3);
      for (size_t h = 0; h < handles_.size(); ++h) C.row(h) = X_.row(handles_[h]);
      membrane_rest_ = membrane(C);
    }
    return;
  }

  // Eq. (5.22) with T_i linear in X' (Sorkine et al. 2004): see linear_method_matrix(). Its factor is
  // estimated from the 2-ring first: a mesh too large for the method is refused in seconds, not after
  // minutes of assembly (a 2.6 M-vertex sphere: 218 s; issue 30).
  const Rings rings(mesh);
  require_block_factor_memory("the linear editing method", rings.pattern(kDenseRowNonzeros / 3), 3);
  RowSparseMatrix G = linear_method_matrix(rings, X_, D_, L_);
  Eigen::VectorXd w3(3 * n);
  for (int d = 0; d < 3; ++d) w3.segment(d * n, n) = Wd.diagonal();
  try {
    linear_solver_.compute(std::move(G), w3);
  } catch (const SolverError& e) {
    throw SolverError(fmt::format("{}: {}", pin_msg, e.what()));
  }
}

MatrixX3d LaplacianEditor::handle_rhs(const MatrixX3d& C) const {
  if (C.rows() != static_cast<Eigen::Index>(handles_.size()))
    throw InvalidInput(fmt::format("{} handle targets for {} handle vertices", C.rows(), handles_.size()));
  if (!C.allFinite()) throw InvalidInput("handle targets must be finite");
  MatrixX3d B = MatrixX3d::Zero(X_.rows(), 3);
  for (size_t h = 0; h < handles_.size(); ++h) B.row(handles_[h]) = w2_[h] * C.row(h);
  for (int v : isolated_) B.row(v) = X_.row(v);
  for (const Anchor& an : anchors_) B.row(an.vertex) += an.w2 * anchor_target(an, C).transpose();
  return B;
}

MatrixX3d LaplacianEditor::membrane(const MatrixX3d& C) const {
  if (options_.method == EditMethod::Linear) {
    // The membrane needs the LᵀL + W² factor; the linear editor does not keep one.
    EditOptions o = options_;
    o.method = EditMethod::Plain;
    std::vector<double> w(w2_.size());
    for (size_t h = 0; h < w.size(); ++h) w[h] = std::sqrt(w2_[h]);
    return LaplacianEditor(*mesh_, handles_, w, o).membrane(C);
  }
  return solver_.solve(handle_rhs(C));  // Eq. (5.23): L X̃ = 0 with the handle rows
}

MatrixX3d LaplacianEditor::solve(const MatrixX3d& C) const {
  const MatrixX3d B = handle_rhs(C);
  const int n = static_cast<int>(X_.rows());
  switch (options_.method) {
    case EditMethod::Plain:
      return solver_.solve(L_.transpose() * D_ + B);
    case EditMethod::MembraneFit: {
      const MatrixX3d M = solver_.solve(B);  // Eq. (5.23)
      const MatrixX3d& rest = options_.fit_to_rest_membrane ? membrane_rest_ : X_;
      const std::vector<Similarity> T = one_ring_similarities(*mesh_, rest, M, options_.allow_scale);  // Eq. (5.24)
      MatrixX3d Dt(n, 3);
#pragma omp parallel for schedule(static)
      for (int i = 0; i < n; ++i)
        Dt.row(i) = rest_frame_[i] ? Eigen::RowVector3d(D_.row(i))
                                   : Eigen::RowVector3d((T[i].linear() * D_.row(i).transpose()).transpose());
      return solver_.solve(L_.transpose() * Dt + B);  // Eq. (5.22) with the fitted T_i
    }
    case EditMethod::Linear: {
      Eigen::VectorXd b(3 * n);
      for (int d = 0; d < 3; ++d) b.segment(d * n, n) = B.col(d);
      const Eigen::VectorXd x = linear_solver_.solve(b);
      MatrixX3d X(n, 3);
      for (int d = 0; d < 3; ++d) X.col(d) = x.segment(d * n, n);
      return X;
    }
  }
  return X_;
}

MatrixX3d laplacian_edit(const Mesh& mesh, const std::vector<int>& handles, const MatrixX3d& targets,
                         const EditOptions& options) {
  return LaplacianEditor(mesh, handles, {}, options).solve(targets);
}

Eigen::VectorXd detail_error(const Mesh& mesh, const MatrixX3d& X0, const MatrixX3d& X1, LaplacianType type) {
  const SparseMatrix L = editing_laplacian(mesh, type);
  const MatrixX3d D0 = L * X0, D1 = L * X1;
  const std::vector<Similarity> T = one_ring_similarities(mesh, X0, X1, true);
  const double mean = D0.rowwise().norm().mean();
  Eigen::VectorXd e(X0.rows());
  for (Eigen::Index i = 0; i < e.size(); ++i)
    e[i] = (D1.row(i).transpose() - T[i].linear() * D0.row(i).transpose()).norm() / (mean > 0 ? mean : 1.0);
  return e;
}

}  // namespace geotex
