#include "geotex/toolkit/smoothing.h"

#include <cmath>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"

namespace geotex {

const OptionTable<SmoothingOptions>& SmoothingOptions::table() {
  using O = SmoothingOptions;
  static const auto t = OptionTable<O>()
      .choice("laplacian", &O::laplacian, laplacian_names(), "umbrella (Eq. 5.8) or cotan (Eq. 5.11) Laplacian", "Eq. (5.8), (5.11)")
      .add("implicit", &O::implicit, "backward Euler steps (stable for any lambda); false: forward Euler", {}, "Eq. (5.12), (5.14)")
      .alias("explicit", "false")
      // Bounded: past ~1e15 the implicit system's last pivot is round-off (the mass is lost beside λL) and
      // the factorization is refused as numerically singular; 1e9 is already the limit (component means).
      .add("lambda", &O::lambda, "step size: dimensionless for umbrella; in squared mean edge lengths (of each connected part) for cotan",
           Bounds{0, 1e9, true, false}, "Eq. (5.12), (5.14)")
      .add("steps", &O::steps, "number of steps", between(0, 100000))
      .choice("mass", &O::mass, mass_names(), "cotan mass matrix: voronoi, barycentric, or thesis (Eq. 5.11 verbatim)", "Eq. (5.11)")
      .add("fix_boundary", &O::fix_boundary, "keep boundary vertices where they are (open meshes)")
      .alias("move_boundary", "false")
      .add("rescale", &O::rescale, "restore volume (closed) or area (open) and centroid after each step")
      .add("update_weights", &O::update_weights, "cotan implicit: recompute the weights each step (false: factor once)")
      .alias("freeze_weights", "false")
      .add("stop_tolerance", &O::stop_tolerance,
           "stop once a step moves no vertex by more than this many mean edge lengths (0: run every step)", non_negative());
  return t;
}

namespace {

// Restore size and position after a smoothing step that shrank the surface.
void rescale_to(Mesh& mesh, bool closed, double target_size, const Vec3& target_centroid) {
  const Vec3 c = surface_centroid(mesh);
  const double size = closed ? std::abs(signed_volume(mesh)) : surface_area(mesh);
  if (!(size > 0)) return;
  const double s = closed ? std::cbrt(target_size / size) : std::sqrt(target_size / size);
  for (auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    mesh.set_point(v, to_point(target_centroid + s * (p - c)));
  }
}

// Solve A_ff X_f = B_f − A_fc X_c for the free rows (Dirichlet elimination), A symmetric.
class ConstrainedSystem {
 public:
  ConstrainedSystem(const std::vector<char>& fixed) : fixed_(fixed) {
    const int n = static_cast<int>(fixed.size());
    index_.assign(n, -1);
    for (int i = 0; i < n; ++i)
      if (!fixed[i]) index_[i] = n_free_++;
  }
  int n_free() const { return n_free_; }

  void factorize(const SparseMatrix& A) {
    SparseMatrix Aff(n_free_, n_free_);
    std::vector<Triplet> t;
    t.reserve(A.nonZeros());
    couple_.clear();
    for (int k = 0; k < A.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(A, k); it; ++it) {
        const int r = static_cast<int>(it.row()), c = static_cast<int>(it.col());
        if (index_[r] < 0) continue;
        if (index_[c] >= 0) t.emplace_back(index_[r], index_[c], it.value());
        else couple_.emplace_back(index_[r], c, it.value());
      }
    Aff.setFromTriplets(t.begin(), t.end());
    if (!solver_.analyzed()) solver_.analyze(Aff);
    solver_.factorize(Aff);
  }

  // Returns full X with fixed rows copied from X_fixed.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B, const Eigen::MatrixXd& X_fixed) const {
    Eigen::MatrixXd Bf(n_free_, B.cols());
    for (size_t i = 0; i < index_.size(); ++i)
      if (index_[i] >= 0) Bf.row(index_[i]) = B.row(i);
    for (const auto& t : couple_) Bf.row(t.row()) -= t.value() * X_fixed.row(t.col());
    const Eigen::MatrixXd Xf = solver_.solve(Bf);
    Eigen::MatrixXd X = X_fixed;
    for (size_t i = 0; i < index_.size(); ++i)
      if (index_[i] >= 0) X.row(i) = Xf.row(index_[i]);
    return X;
  }

 private:
  std::vector<char> fixed_;
  std::vector<int> index_;
  int n_free_ = 0;
  std::vector<Triplet> couple_;
  SpdSolver solver_;
};

// The mean edge length of each vertex's connected component (\p fallback for isolated vertices).
Eigen::VectorXd component_edge_lengths(const Mesh& mesh, double fallback) {
  int nc = 0;
  const Eigen::VectorXi comp = connected_components(mesh, &nc);
  std::vector<double> length(std::max(nc, 1), 0.0);
  std::vector<int> count(std::max(nc, 1), 0);
  for (auto e : mesh.edges()) {
    const int c = comp[e.v0().idx()];
    if (c < 0) continue;
    length[c] += mesh.calc_edge_length(e);
    ++count[c];
  }
  Eigen::VectorXd hc(mesh.n_vertices());
  for (Eigen::Index v = 0; v < hc.size(); ++v) {
    const int c = comp[v];
    hc[v] = c >= 0 && count[c] > 0 ? length[c] / count[c] : fallback;
  }
  return hc;
}

}  // namespace

void rescale_like(const Mesh& reference, Mesh& mesh) {
  const bool closed = boundary_loops(reference).empty();
  const double size = closed ? std::abs(signed_volume(reference)) : surface_area(reference);
  rescale_to(mesh, closed, size, surface_centroid(reference));
}

MatrixX3d smooth(const Mesh& input, const SmoothingOptions& opt) {
  check_options(opt);
  require_valid(input, "smooth: input mesh");

  Mesh mesh = input;
  const bool closed = boundary_loops(mesh).empty();
  const double size0 = closed ? std::abs(signed_volume(mesh)) : surface_area(mesh);
  const Vec3 centroid0 = surface_centroid(mesh);
  const double h = mean_edge_length(mesh);
  // The cotangent step is a length²: λ h², with h the mean edge length of each vertex's own connected
  // component, so that parts at different scales (a unit sphere ×10^6 beside one ×10^-6) each take the
  // same step relative to their size. One h for the whole mesh made the small part's system M − λC a
  // multiple of −C, singular: "sparse Cholesky failed" (issue 30). C couples no two components, so
  // diag(λ) C stays symmetric.
  Eigen::VectorXd lambda_v = Eigen::VectorXd::Constant(mesh.n_vertices(), opt.lambda);
  if (opt.laplacian == LaplacianType::Cotangent) {
    const Eigen::VectorXd hc = component_edge_lengths(mesh, h);
    for (Eigen::Index v = 0; v < lambda_v.size(); ++v) lambda_v[v] = opt.lambda * hc[v] * hc[v];
  }
  const double lambda = opt.lambda;  // the umbrella step (dimensionless)

  std::vector<char> fixed(mesh.n_vertices(), 0);
  for (auto v : mesh.vertices())
    if ((opt.fix_boundary && mesh.is_boundary(v)) || mesh.is_isolated(v)) fixed[v.idx()] = 1;

  MatrixX3d X = positions(mesh);
  ConstrainedSystem system(fixed);
  if (system.n_free() == 0) return X;

  // Umbrella: L = D⁻¹A − I. Symmetrized implicit system ((1+λ)D − λA) X' = D X (5.14 times D),
  // constant across steps, so it is factored once.
  SparseMatrix D, A;
  if (opt.laplacian == LaplacianType::Umbrella) {
    A = adjacency_matrix(mesh);
    Eigen::VectorXd d = A * Eigen::VectorXd::Ones(A.cols());
    for (Eigen::Index i = 0; i < d.size(); ++i)
      if (d[i] == 0) d[i] = 1;
    D = SparseMatrix(d.asDiagonal());
    if (opt.implicit) system.factorize((1 + lambda) * D - lambda * A);
  }

  SparseMatrix C;     // cotangent matrix, kept across steps when weights are frozen
  Eigen::VectorXd m;  // mass diagonal
  for (int step = 0; step < opt.steps; ++step) {
    const MatrixX3d X_before = opt.stop_tolerance > 0 ? X : MatrixX3d();
    if (opt.laplacian == LaplacianType::Umbrella) {
      if (opt.implicit) {
        X = system.solve(D * X, X);
      } else {
        const MatrixX3d LX = umbrella_laplacian(mesh) * X;  // (5.13)
        for (Eigen::Index i = 0; i < X.rows(); ++i)
          if (!fixed[i]) X.row(i) += lambda * LX.row(i);
      }
    } else {
      const bool rebuild = opt.update_weights || step == 0 || !opt.implicit;
      if (rebuild) {
        C = cotan_matrix(mesh);
        m = mass_diagonal(mesh, opt.mass);
      }
      if (opt.implicit) {
        // (M − λC) X' = M X: Eq. (5.14) multiplied by M, symmetric positive definite.
        if (rebuild) system.factorize(SparseMatrix(m.asDiagonal()) - SparseMatrix(lambda_v.asDiagonal() * C));
        X = system.solve(m.asDiagonal() * X, X);
      } else {
        const MatrixX3d LX = m.cwiseInverse().asDiagonal() * (C * X);  // (5.12)
        for (Eigen::Index i = 0; i < X.rows(); ++i)
          if (!fixed[i]) X.row(i) += lambda_v[i] * LX.row(i);
      }
    }
    if (!X.allFinite())
      throw SolverError(fmt::format("smoothing diverged at step {} (explicit step too large? try "
                                    "--implicit or a smaller --lambda)", step + 1));
    set_positions(mesh, X);
    if (opt.rescale) {
      rescale_to(mesh, closed, size0, centroid0);
      X = positions(mesh);
    }
    report(opt.progress, double(step + 1) / opt.steps, "smoothing");
    if (opt.stop_tolerance > 0 && (X - X_before).rowwise().norm().maxCoeff() < opt.stop_tolerance * h) break;
  }
  return X;
}

std::vector<MatrixX3d> implicit_cotan_steps(const Mesh& mesh, const std::vector<double>& lambdas, MassType mass,
                                            bool fix_boundary) {
  require_valid(mesh, "smooth: input mesh");
  for (double l : lambdas)
    if (!(l >= 0 && l <= 1e9)) throw InvalidInput(fmt::format("smoothing step {} outside [0, 1e9]", l));
  const MatrixX3d X = positions(mesh);
  std::vector<char> fixed(mesh.n_vertices(), 0);
  for (auto v : mesh.vertices())
    if ((fix_boundary && mesh.is_boundary(v)) || mesh.is_isolated(v)) fixed[v.idx()] = 1;
  ConstrainedSystem system(fixed);
  if (system.n_free() == 0) return std::vector<MatrixX3d>(lambdas.size(), X);
  const Eigen::VectorXd hc = component_edge_lengths(mesh, mean_edge_length(mesh));
  const SparseMatrix C = cotan_matrix(mesh);
  const Eigen::VectorXd m = mass_diagonal(mesh, mass);
  const MatrixX3d MX = m.asDiagonal() * X;
  std::vector<MatrixX3d> out;
  for (double lambda : lambdas) {
    Eigen::VectorXd lambda_v(hc.size());
    for (Eigen::Index v = 0; v < hc.size(); ++v) lambda_v[v] = lambda * hc[v] * hc[v];
    // (M − λC) X' = M X (Eq. 5.14 times M); the analysis of the first λ serves every other.
    system.factorize(SparseMatrix(m.asDiagonal()) - SparseMatrix(lambda_v.asDiagonal() * C));
    out.push_back(system.solve(MX, X));
    if (!out.back().allFinite()) throw SolverError("implicit smoothing step is not finite");
  }
  return out;
}

}  // namespace geotex
