#include "geotex/toolkit/linear_solver.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <new>

#include <fmt/format.h>
#include <Eigen/Cholesky>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#ifdef GEOTEX_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#include <omp.h>

#include "geotex/core/error.h"
#include "geotex/core/progress.h"
#include "geotex/core/resources.h"

namespace geotex {

// CHOLMOD 3's supernodal factorization opens OpenMP regions of CHOLMOD_OMP_NUM_THREADS = 4 threads (a
// compile-time clause that omp_set_num_threads and --threads do not reach) around loops of a few
// hundred assignments each: on a 2-core machine their wake-ups and futex waits cost more CPU than the
// arithmetic (igea's 134k-vertex scalar system in resize: 0.42 instead of 0.54 s of CPU a factorization,
// at load 5). While one of these guards lives, this thread's parallel regions run on one thread
// (max-active-levels 0); the BLAS keeps its own threads. (Even a one-thread region costs libgomp a futex
// system call at its closing barrier: fewer supernodes, below, cut the rest.)
class SerialOpenMP {
 public:
  SerialOpenMP() : levels_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
  ~SerialOpenMP() { omp_set_max_active_levels(levels_); }
  SerialOpenMP(const SerialOpenMP&) = delete;
  SerialOpenMP& operator=(const SerialOpenMP&) = delete;

 private:
  int levels_;
};

#ifdef GEOTEX_HAVE_CHOLMOD
// Eigen keeps CHOLMOD's factor protected; the pivot audit reads its diagonal.
struct CholmodLLT : Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> {
  const cholmod_factor* factor() const { return m_cholmodFactor; }
};
#endif

struct SpdSolver::Impl {
#ifdef GEOTEX_HAVE_CHOLMOD
  CholmodLLT chol;
#else
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> chol;
#endif
  bool analyzed = false;
  bool factorized = false;
  Eigen::Index n = 0;
  //! Blocked analysis: the unknowns' permutation (old index → new index); empty otherwise.
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm;
  bool permuted() const { return perm.size() > 0; }
  SparseMatrix permute(const SparseMatrix& A) const {
    SparseMatrix Ap;
    Ap = A.selfadjointView<Eigen::Lower>().twistedBy(perm);
    return Ap;
  }
};

namespace {

constexpr int kNestedDissectionVertices = 50000;

// The ordering a graph of n vertices gets: Auto is minimum degree below kNestedDissectionVertices, nested
// dissection from there (the solver's blocked_ordering and the factor estimates alike).
BlockOrdering resolved_ordering(BlockOrdering ordering, Eigen::Index n) {
  if (ordering != BlockOrdering::Auto) return ordering;
  return n >= kNestedDissectionVertices ? BlockOrdering::NestedDissection : BlockOrdering::MinimumDegree;
}

#ifdef GEOTEX_HAVE_CHOLMOD
// CHOLMOD reports running out of memory in its status, not by throwing: without this check the
// failure surfaced as a bogus "non-finite result" solver error, or as a null factor dereferenced by
// Eigen (issue 14, class 8). Out of memory is std::bad_alloc everywhere in geotex.
void check_cholmod(const cholmod_common& c) {
  if (c.status == CHOLMOD_OUT_OF_MEMORY) throw std::bad_alloc();
}

// The symbolic analysis knows the numeric factor's size: its values (xsize), the largest update block
// (maxcsize) and the row indices (ssize). A factorization the machine cannot hold is refused here, in
// seconds, with the estimate (issue 30): a 2.6 M-vertex `deform` was killed for memory after 190 s.
// CHOLMOD's 32-bit indices address 2^31 − 1 values: a larger factor crashed in the factorization (a 2.6 M-
// vertex linear edit, 5.4e9 values), so it is refused here too.
void require_factor_memory(const cholmod_factor* L, const cholmod_common& c, Eigen::Index n) {
  if (c.status == CHOLMOD_TOO_LARGE || (L && L->is_super && std::max(L->xsize, L->ssize) > size_t(INT32_MAX)))
    throw OutOfMemory(fmt::format("factoring a {} x {} system needs a Cholesky factor of {:.2g} values, more than "
                                  "its 32-bit indices address (2^31); the mesh is too large for this method",
                                  n, n, L ? std::max(double(L->xsize), c.lnz) : c.lnz));
  if (!L || !L->is_super) return;
  const double bytes = 8.0 * (double(L->xsize) + double(L->maxcsize)) + double(sizeof(int)) * double(L->ssize);
  require_memory(fmt::format("factoring a {} x {} system ({:.2g} nonzeros and {:.2g} flops in its Cholesky factor)",
                             n, n, c.lnz, c.fl),
                 bytes >= 1.8e19 ? SIZE_MAX : static_cast<size_t>(bytes));
}
#endif

// Fill-reducing ordering of a coordinate-stacked system by its vertex graph: vertex i's unknowns
// d·n + i (d < k) get the consecutive new indices k·pos(i) + d, pos from AMD (METIS for large graphs) on
// the n-vertex graph.
Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> blocked_ordering(const SparseMatrix& A, int k,
                                                                                BlockOrdering ordering) {
  const int n = static_cast<int>(A.rows() / k);
  std::vector<Triplet> t;
  t.reserve(A.nonZeros() / (k * k) + n);
  for (int c = 0; c < A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(A, c); it; ++it)
      if (it.row() % n != c % n) t.emplace_back(it.row() % n, c % n, 1.0);
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, 1.0);
  // Vertex order → unknowns' permutation (old index → new index).
  auto expand = [&](const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int>& order) {
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm(static_cast<int>(A.rows()));
    for (int p = 0; p < n; ++p)
      for (int d = 0; d < k; ++d) perm.indices()[d * n + order.indices()[p]] = k * p + d;
    return perm;
  };
  SparseMatrix G(n, n);
  G.setFromTriplets(t.begin(), t.end(), [](double a, double) { return a; });
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;  // new position → old vertex
#ifdef GEOTEX_HAVE_CHOLMOD
  // Large graphs: METIS nested dissection, whose fill is far smaller than AMD's on big surface meshes
  // (655k vertices, 2×2 blocks: 1.6e11 against 5.2e11 flops, factorization 7.0 s against 14.2 s; igea's
  // 134k-vertex resize: 53 s of CPU against 70 s; the 36k-vertex bunny's: the same).
  if (resolved_ordering(ordering, n) == BlockOrdering::NestedDissection) {
    cholmod_common cc;
    cholmod_start(&cc);
    cc.print = 0;  // a failed METIS ordering falls back to AMD below, silently
    SparseMatrix lower = G.triangularView<Eigen::Lower>();
    cholmod_sparse view = Eigen::viewAsCholmod(lower);
    view.stype = -1;
    order.resize(n);
    const bool ok = cholmod_metis(&view, nullptr, 0, 1, order.indices().data(), &cc);
    cholmod_finish(&cc);
    if (ok) return expand(order);
  }
#endif
  Eigen::AMDOrdering<int>()(G, order);
  return expand(order);
}

// A factorization that succeeds with a pivot this small relative to its row's diagonal entry has met
// a (numerically) singular matrix: whether it succeeds at all is decided by rounding, i.e. by the BLAS
// kernel of the machine (issue 33): two digits or fewer are left of it. Legitimate ill-conditioning
// stays above it (the biharmonic systems of editing reach ~1/#V; the heat system of a needle
// triangle 1e-9 high, 4e-13). Singular systems a user can cause are refused before factoring, by
// name (a component without a handle or known value).
constexpr double kMinRelativePivot = 1e-14;

// The smallest pivot of the last factorization relative to the diagonal of the factored matrix Ap
// (already in the factor's own order where the ordering was given): min_k d_k / Ap(π(k), π(k)), with
// d_k = L_kk² for LLᵀ and D_kk for LDLᵀ.
#ifdef GEOTEX_HAVE_CHOLMOD
double smallest_relative_pivot(const CholmodLLT& chol, const Eigen::VectorXd& diag) {
  const cholmod_factor* L = chol.factor();
  if (!L || !L->is_super || !L->is_ll || L->itype != CHOLMOD_INT || L->xtype != CHOLMOD_REAL) return 1.0;  // no audit
  const int* perm = static_cast<const int*>(L->Perm);
  const double* x = static_cast<const double*>(L->x);
  double worst = 1.0;
  for (size_t s = 0; s < L->nsuper; ++s) {
    const int k1 = static_cast<const int*>(L->super)[s], k2 = static_cast<const int*>(L->super)[s + 1];
    const int nrows = static_cast<const int*>(L->pi)[s + 1] - static_cast<const int*>(L->pi)[s];
    const double* block = x + static_cast<const int*>(L->px)[s];
    for (int j = 0; j < k2 - k1; ++j) {
      const double l = block[static_cast<size_t>(j) * nrows + j];
      const double a = diag[perm ? perm[k1 + j] : k1 + j];
      worst = std::min(worst, a > 0 ? l * l / a : 0.0);
    }
  }
  return worst;
}
#else
double smallest_relative_pivot(const Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower>& chol,
                               const Eigen::VectorXd& diag) {
  const Eigen::VectorXd pd = chol.permutationP() * diag;  // (P A Pᵀ)_{P(i)P(i)} = A_ii
  const Eigen::VectorXd& D = chol.vectorD();
  double worst = 1.0;
  for (Eigen::Index k = 0; k < D.size(); ++k) worst = std::min(worst, pd[k] > 0 ? D[k] / pd[k] : 0.0);
  return worst;
}
#endif

}  // namespace

// CHOLMOD's supernodal factorization on this machine (OpenBLAS, one thread): a 164k-vertex linear edit,
// 4.8e11 flops, factored in 24 s of CPU (bench/bad-input.md).
constexpr double kFactorFlopsPerSecond = 2e10;

FactorEstimate estimate_block_factor(const SparseMatrix& R, int block_size, BlockOrdering ordering) {
  FactorEstimate e;
#ifdef GEOTEX_HAVE_CHOLMOD
  check_interrupt();
  if (R.rows() == 0) return e;
  SparseMatrix A = R;  // a compressed, sorted copy for CHOLMOD's view
  A.makeCompressed();
  cholmod_common cc;
  cholmod_start(&cc);
  cc.print = 0;
  cc.supernodal = CHOLMOD_SUPERNODAL;
  // The ordering SpdSolver::analyze gives the blocked system (blocked_ordering).
  const bool nd = resolved_ordering(ordering, R.rows()) == BlockOrdering::NestedDissection;
  cc.nmethods = 1;
  cc.method[0].ordering = nd ? CHOLMOD_METIS : CHOLMOD_AMD;
  cholmod_sparse view = Eigen::viewAsCholmod(A);
  view.stype = 0;  // unsymmetric: CHOLMOD analyzes R Rᵀ without forming the system
  cholmod_factor* L = cholmod_analyze(&view, &cc);
  if (!L && nd) {  // METIS failed (as blocked_ordering falls back): AMD
    cc.method[0].ordering = CHOLMOD_AMD;
    L = cholmod_analyze(&view, &cc);
  }
  if (L) {
    // Each scalar entry of the vertex graph's factor is a full k × k block of the system's (the unknowns of
    // a vertex are kept together), so its supernodes are the graph's, k times wider and taller.
    // The factor's nonzeros leave out the upper half of its diagonal blocks.
    const double k = block_size;
    e.nonzeros = k * k * cc.lnz - double(R.rows()) * k * (k - 1) / 2;
    e.flops = k * k * k * cc.fl;
    if (L->is_super) {
      e.values = k * k * double(L->xsize);
      e.bytes = 8.0 * k * k * (double(L->xsize) + double(L->maxcsize)) + double(sizeof(int)) * k * double(L->ssize);
    } else {
      e.values = e.nonzeros;
      e.bytes = 12.0 * e.nonzeros;
    }
    e.cpu_seconds = e.flops / kFactorFlopsPerSecond;
    cholmod_free_factor(&L, &cc);
  }
  const bool oom = cc.status == CHOLMOD_OUT_OF_MEMORY;
  cholmod_finish(&cc);
  if (oom) throw std::bad_alloc();
#else
  (void)R;
  (void)block_size;
  (void)ordering;
#endif
  return e;
}

namespace {

// The first `count` vertices reached breadth first over R's columns (the rings), component after component,
// and R restricted to them (renumbered in that order).
SparseMatrix sample_graph(const SparseMatrix& R, int count) {
  const int n = static_cast<int>(R.cols());
  std::vector<int> order, id(n, -1);
  order.reserve(count);
  for (int seed = 0; seed < n && static_cast<int>(order.size()) < count; ++seed) {
    if (id[seed] >= 0) continue;
    id[seed] = static_cast<int>(order.size());
    order.push_back(seed);
    for (size_t head = order.size() - 1; head < order.size() && static_cast<int>(order.size()) < count; ++head)
      for (SparseMatrix::InnerIterator it(R, order[head]); it && static_cast<int>(order.size()) < count; ++it)
        if (id[it.row()] < 0) {
          id[it.row()] = static_cast<int>(order.size());
          order.push_back(static_cast<int>(it.row()));
        }
  }
  const int m = static_cast<int>(order.size());
  std::vector<Triplet> t;
  for (int c = 0; c < m; ++c)
    for (SparseMatrix::InnerIterator it(R, order[c]); it; ++it)
      if (id[it.row()] >= 0) t.emplace_back(id[it.row()], c, 1.0);
  SparseMatrix S(m, m);
  S.setFromTriplets(t.begin(), t.end());
  return S;
}

}  // namespace

FactorEstimate extrapolate_block_factor(const SparseMatrix& R, int block_size, int sample, BlockOrdering ordering) {
  const double n = static_cast<double>(R.rows());
  if (sample < 16 || n <= sample) return estimate_block_factor(R, block_size, ordering);
  // Both samples are ordered as the whole graph would be (its size decides Auto's ordering).
  const BlockOrdering o = resolved_ordering(ordering, R.rows());
  const SparseMatrix S1 = sample_graph(R, sample);
  const SparseMatrix S0 = sample_graph(S1, sample / 4);  // a prefix of the same breadth-first order
  const FactorEstimate a = estimate_block_factor(S0, block_size, o), b = estimate_block_factor(S1, block_size, o);
  const double n0 = static_cast<double>(S0.rows()), n1 = static_cast<double>(S1.rows());
  auto grow = [&](double q0, double q1) {
    if (q0 <= 0 || q1 <= 0) return q1 * n / n1;
    const double e = std::clamp(std::log(q1 / q0) / std::log(n1 / n0), 1.0, 2.0);
    return q1 * std::pow(n / n1, e);
  };
  FactorEstimate e;
  e.values = grow(a.values, b.values);
  e.nonzeros = grow(a.nonzeros, b.nonzeros);
  e.flops = grow(a.flops, b.flops);
  e.bytes = grow(a.bytes, b.bytes);
  e.cpu_seconds = e.flops / kFactorFlopsPerSecond;
  e.sampled_vertices = static_cast<int>(n1);
  return e;
}

namespace {

// Above this many vertices the factor is first extrapolated from a sample of this size (a few seconds):
// a system far beyond the machine is refused from it; one within reach gets the exact analysis.
constexpr int kFactorSampleVertices = 200000;
// How far past a limit the extrapolation must be to refuse without the exact analysis.
constexpr double kSampleRefusalMargin = 2.0;

}  // namespace

void require_block_factor_memory(const std::string& what, const SparseMatrix& R, int block_size,
                                 BlockOrdering ordering) {
  FactorEstimate e;
  if (R.rows() > 4 * kFactorSampleVertices) {
    e = extrapolate_block_factor(R, block_size, kFactorSampleVertices, ordering);
    const bool far = e.values > kSampleRefusalMargin * double(INT32_MAX) ||
                     e.bytes > kSampleRefusalMargin * double(available_memory_bytes());
    if (!far) e = estimate_block_factor(R, block_size, ordering);
  } else {
    e = estimate_block_factor(R, block_size, ordering);
  }
  const std::string source = e.sampled_vertices > 0
                                 ? fmt::format("extrapolated from a {}-vertex sample of its {}-vertex graph",
                                               e.sampled_vertices, R.rows())
                                 : fmt::format("estimated from its {}-vertex graph", R.rows());
  const double n = double(R.rows()) * block_size;
  const std::string minutes = e.cpu_seconds >= 120 ? fmt::format("{:.0f} minutes", e.cpu_seconds / 60)
                                                   : fmt::format("{:.0f} s", e.cpu_seconds);
  if (e.values > double(INT32_MAX))
    throw OutOfMemory(fmt::format("{}: factoring its {:.0f} x {:.0f} system needs a Cholesky factor of about {:.2g} "
                                  "values ({} before assembling it), more than its 32-bit indices address (2^31), and "
                                  "about {} of CPU; the mesh is too large for this method",
                                  what, n, n, e.values, source, minutes));
  if (e.bytes <= 0) return;
  require_memory(fmt::format("{}: factoring its {:.0f} x {:.0f} system (about {:.2g} nonzeros and {:.2g} flops in its "
                             "Cholesky factor, about {} of CPU; {})",
                             what, n, n, e.nonzeros, e.flops, minutes, source),
                 e.bytes >= 1.8e19 ? SIZE_MAX : static_cast<size_t>(e.bytes));
}

SpdSolver::SpdSolver() : impl_(std::make_unique<Impl>()) {
#ifdef GEOTEX_HAVE_CHOLMOD
  impl_->chol.cholmod().print = 0;  // errors reach the caller as exceptions, not as lines on stderr
#endif
}
SpdSolver::~SpdSolver() = default;
SpdSolver::SpdSolver(SpdSolver&&) noexcept = default;
SpdSolver& SpdSolver::operator=(SpdSolver&&) noexcept = default;

// A factorization is one call into CHOLMOD that cannot stop halfway: every entry is a cancellation point,
// so a loop of solves (time steps, shift-invert Lanczos, robust passes) stops at its next one.
void SpdSolver::analyze(const SparseMatrix& A, int block_size, BlockOrdering ordering) {
  check_interrupt();
  if (A.rows() != A.cols()) throw SolverError("SpdSolver: matrix is not square");
  if (block_size < 1 || A.rows() % block_size != 0)
    throw SolverError(fmt::format("SpdSolver: {} unknowns are not {} blocks", A.rows(), block_size));
  impl_->perm.resize(0);
#ifdef GEOTEX_HAVE_CHOLMOD
  cholmod_common& c = impl_->chol.cholmod();
  if (block_size > 1 && A.rows() > 0) {
    c.nrelax[0] = 4;  // CHOLMOD's defaults: a vertex's block already makes supernodes wide
    c.nrelax[1] = 16;
    c.nrelax[2] = 48;
    impl_->perm = blocked_ordering(A, block_size, ordering);
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_NATURAL;  // the matrix comes ordered
    impl_->chol.analyzePattern(impl_->permute(A));
  } else {
    c.nmethods = 0;  // CHOLMOD's default: AMD, and METIS where AMD fills badly
    c.method[0].ordering = CHOLMOD_GIVEN;
    // Scalar systems of a surface mesh: CHOLMOD's default amalgamation leaves thin supernodes (igea's
    // 134k-vertex Laplacian: 14,800), and each supernode and descendant update costs OpenMP regions and
    // BLAS calls of a few rows. Relaxing more (fewer, wider supernodes, some explicit zeros) cut the
    // factorization from 0.33 to 0.23 s of CPU there (6,200 supernodes, 50% more values).
    c.nrelax[0] = 16;
    c.nrelax[1] = 48;
    c.nrelax[2] = 128;
    impl_->chol.analyzePattern(A);
  }
  check_cholmod(c);
  require_factor_memory(impl_->chol.factor(), c, A.rows());
#else
  impl_->chol.analyzePattern(A);
#endif
  impl_->analyzed = true;
  impl_->factorized = false;
  impl_->n = A.rows();
}

void SpdSolver::factorize(const SparseMatrix& A) {
  check_interrupt();
  if (!impl_->analyzed || A.rows() != impl_->n) analyze(A);
  Eigen::VectorXd diag;
  if (impl_->permuted()) {
    const SparseMatrix Ap = impl_->permute(A);
    diag = Ap.diagonal();
    SerialOpenMP serial;
    impl_->chol.factorize(Ap);
  } else {
    diag = A.diagonal();
    SerialOpenMP serial;
    impl_->chol.factorize(A);
  }
#ifdef GEOTEX_HAVE_CHOLMOD
  check_cholmod(impl_->chol.cholmod());
#endif
  // LDLᵀ succeeds on indefinite and singular matrices, and either backend may "succeed" on a singular
  // one by rounding: a non-positive or relatively tiny pivot is a failure on every machine alike.
  const bool ok = impl_->chol.info() == Eigen::Success;
  const double pivot = ok && A.rows() > 0 ? smallest_relative_pivot(impl_->chol, diag) : 1.0;
  if (!ok || !(pivot > 0))
    throw SolverError(fmt::format("sparse Cholesky failed on a {}x{} system (not positive definite?)",
                                  A.rows(), A.cols()));
  if (pivot < kMinRelativePivot)
    throw SolverError(fmt::format("sparse Cholesky of a {}x{} system met a pivot {:.1e} of its diagonal: the "
                                  "system is numerically singular", A.rows(), A.cols(), pivot));
  impl_->factorized = true;
}

Eigen::MatrixXd SpdSolver::solve(const Eigen::MatrixXd& B) const {
  check_interrupt();
  if (!impl_->factorized) throw SolverError("SpdSolver: solve() before factorize()");
  if (B.rows() != impl_->n) throw SolverError("SpdSolver: right-hand side has the wrong size");
  Eigen::MatrixXd X;
  if (impl_->permuted())
    X = impl_->perm.transpose() * Eigen::MatrixXd(impl_->chol.solve(impl_->perm * B));
  else
    X = impl_->chol.solve(B);
#ifdef GEOTEX_HAVE_CHOLMOD
  check_cholmod(impl_->chol.cholmod());
#endif
  if (impl_->chol.info() != Eigen::Success || !X.allFinite())
    throw SolverError("sparse solve failed (non-finite result)");
  return X;
}

bool SpdSolver::analyzed() const { return impl_->analyzed; }

const char* SpdSolver::backend() {
#ifdef GEOTEX_HAVE_CHOLMOD
  return "cholmod-supernodal";
#else
  return "eigen-simplicial-ldlt";
#endif
}

namespace {

// The lower triangle of GᵀG over the rows of G that \p keep (row-major G, sorted columns), one column at
// a time in parallel: column j gathers G(r, j) · G(r, c) for c ≥ j over the rows r of its column, its
// diagonal entry first (stored even when zero, for LeastSquaresSolver::factor to rewrite). Linear
// in the products, without the triplets and the full product Eigen's GᵀG builds (a 164k-vertex linear
// edit: 5.3 s; issue 30).
SparseMatrix lower_normal_matrix(const RowSparseMatrix& G, const std::vector<char>& keep) {
  const int nc = static_cast<int>(G.cols()), nr = static_cast<int>(G.rows());
  // G's kept rows by column (the transpose's pattern, rows ascending).
  std::vector<int> cstart(nc + 1, 0);
  for (int r = 0; r < nr; ++r)
    if (keep[r])
      for (RowSparseMatrix::InnerIterator it(G, r); it; ++it) ++cstart[it.col() + 1];
  for (int c = 0; c < nc; ++c) cstart[c + 1] += cstart[c];
  std::vector<int> crow(cstart[nc]);
  std::vector<double> cval(cstart[nc]);
  {
    std::vector<int> next(cstart.begin(), cstart.end() - 1);
    for (int r = 0; r < nr; ++r)
      if (keep[r])
        for (RowSparseMatrix::InnerIterator it(G, r); it; ++it) {
          crow[next[it.col()]] = r;
          cval[next[it.col()]++] = it.value();
        }
  }
  // Columns in chunks; each chunk's entries, then concatenated in order.
  const int chunks = std::max(1, std::min(nc, 1024));
  std::vector<std::vector<int>> chunk_rows(chunks);
  std::vector<std::vector<double>> chunk_vals(chunks);
  std::vector<int> count(nc, 0);
  const int* outer = G.outerIndexPtr();
  const int* inner = G.innerIndexPtr();
  const double* value = G.valuePtr();
#pragma omp parallel
  {
    std::vector<double> acc(nc, 0.0);
    std::vector<char> seen(nc, 0);
    std::vector<int> touched;
#pragma omp for schedule(dynamic, 1)
    for (int k = 0; k < chunks; ++k) {
      const int j0 = static_cast<int>(int64_t(nc) * k / chunks), j1 = static_cast<int>(int64_t(nc) * (k + 1) / chunks);
      for (int j = j0; j < j1; ++j) {
        touched.assign(1, j);
        seen[j] = 1;
        for (int p = cstart[j]; p < cstart[j + 1]; ++p) {
          const int r = crow[p];
          const double v = cval[p];
          const int* first = std::lower_bound(inner + outer[r], inner + outer[r + 1], j);
          for (const int* q = first; q != inner + outer[r + 1]; ++q) {
            const int c = *q;
            if (!seen[c]) { seen[c] = 1; touched.push_back(c); }
            acc[c] += v * value[q - inner];
          }
        }
        std::sort(touched.begin(), touched.end());
        count[j] = static_cast<int>(touched.size());
        for (int c : touched) {
          chunk_rows[k].push_back(c);
          chunk_vals[k].push_back(acc[c]);
          acc[c] = 0;
          seen[c] = 0;
        }
      }
    }
  }
  SparseMatrix A(nc, nc);
  int64_t nnz = 0;
  for (int c = 0; c < nc; ++c) nnz += count[c];
  A.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  A.outerIndexPtr()[0] = 0;
  for (int c = 0; c < nc; ++c) A.outerIndexPtr()[c + 1] = A.outerIndexPtr()[c] + count[c];
  int64_t at = 0;
  for (int k = 0; k < chunks; ++k) {
    std::copy(chunk_rows[k].begin(), chunk_rows[k].end(), A.innerIndexPtr() + at);
    std::copy(chunk_vals[k].begin(), chunk_vals[k].end(), A.valuePtr() + at);
    at += static_cast<int64_t>(chunk_rows[k].size());
  }
  return A;
}

}  // namespace

void LeastSquaresSolver::compute(RowSparseMatrix G, const Eigen::VectorXd& d, int block_size, int dense_row_nnz) {
  if (d.size() != G.cols()) throw SolverError("LeastSquaresSolver: the diagonal must have one entry per unknown");
  check_interrupt();
  G_ = std::move(G);
  G_.makeCompressed();
  // The long rows become the columns of U; the rest make up S's GᵀG.
  std::vector<char> keep(G_.rows(), 1);
  std::vector<Triplet> tu;
  int m = 0;
  for (Eigen::Index r = 0; r < G_.rows(); ++r) {
    if (G_.outerIndexPtr()[r + 1] - G_.outerIndexPtr()[r] <= dense_row_nnz) continue;
    keep[r] = 0;
    for (RowSparseMatrix::InnerIterator it(G_, r); it; ++it) tu.emplace_back(it.col(), m, it.value());
    ++m;
  }
  U_.resize(G_.cols(), m);
  U_.setFromTriplets(tu.begin(), tu.end());
  S_ = lower_normal_matrix(G_, keep);
  gtg_diagonal_.resize(S_.cols());
  for (Eigen::Index j = 0; j < S_.cols(); ++j) gtg_diagonal_[j] = S_.valuePtr()[S_.outerIndexPtr()[j]];
  d_ = d;
  base_.analyze(S_, block_size);  // the pattern only: factor() writes the diagonal
  factor();
}

void LeastSquaresSolver::refactor(const Eigen::VectorXd& d) {
  if (d.size() != G_.cols()) throw SolverError("LeastSquaresSolver: the diagonal must have one entry per unknown");
  d_ = d;
  factor();
}

// S's diagonal: GᵀG's plus d plus \p shift, written in place (each column's first entry).
void LeastSquaresSolver::set_diagonal(double shift) {
  for (Eigen::Index j = 0; j < S_.cols(); ++j)
    S_.valuePtr()[S_.outerIndexPtr()[j]] = gtg_diagonal_[j] + d_[j] + shift;
}

void LeastSquaresSolver::factor() {
  const Eigen::Index m = U_.cols();
  set_diagonal(0.0);
  regularized_ = false;
  try {
    base_.factorize(S_);
  } catch (const SolverError&) {
    if (m == 0) throw;
    // Taking the long rows out may leave S singular (an unknown only they constrain): factor it with a
    // tiny shift; solve() refines against the true matrix.
    const double mean = S_.cols() ? (gtg_diagonal_ + d_).cwiseAbs().mean() : 0.0;
    set_diagonal(1e-8 * std::max(mean, 1e-300));
    base_.factorize(S_);
    regularized_ = true;
  }
  if (m > 0) {
    Z_ = base_.solve(Eigen::MatrixXd(U_));
    Eigen::MatrixXd C = Eigen::MatrixXd::Identity(m, m) + Eigen::MatrixXd(U_.transpose() * Z_);
    capacitance_inverse_ = C.ldlt().solve(Eigen::MatrixXd::Identity(m, m));
  } else {
    Z_.resize(0, 0);
    capacitance_inverse_.resize(0, 0);
  }
}

Eigen::MatrixXd LeastSquaresSolver::solve(const Eigen::MatrixXd& B) const {
  const auto apply_inverse = [&](const Eigen::MatrixXd& R) -> Eigen::MatrixXd {
    Eigen::MatrixXd Y = base_.solve(R);
    if (U_.cols() > 0) Y -= Z_ * (capacitance_inverse_ * Eigen::MatrixXd(U_.transpose() * Y));
    return Y;
  };
  Eigen::MatrixXd X = apply_inverse(B);
  if (regularized_ || U_.cols() > 0) {
    // The factor is of the shifted matrix, or the Woodbury update lost digits to an ill-conditioned S
    // (tiny d where only long rows constrain): conjugate gradients on the true GᵀG + diag(d),
    // preconditioned by the approximate inverse (the preconditioned spectrum is near 1: a few
    // iterations, none when the first solve is already accurate).
    const auto A = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      return G_.transpose() * (G_ * x) + d_.cwiseProduct(x);
    };
    for (Eigen::Index c = 0; c < B.cols(); ++c) {
      Eigen::VectorXd x = X.col(c), r = B.col(c) - A(x);
      Eigen::VectorXd z = apply_inverse(r), p = z;
      double rz = r.dot(z);
      const double stop = 1e-14 * B.col(c).squaredNorm();
      for (int it = 0; it < 100 && r.squaredNorm() > stop; ++it) {
        const Eigen::VectorXd Ap = A(p);
        const double alpha = rz / p.dot(Ap);
        x += alpha * p;
        r -= alpha * Ap;
        z = apply_inverse(r);
        const double rz_next = r.dot(z);
        p = z + (rz_next / rz) * p;
        rz = rz_next;
      }
      X.col(c) = x;
    }
  }
  if (!X.allFinite()) throw SolverError("least-squares solve failed (non-finite result)");
  return X;
}

}  // namespace geotex
