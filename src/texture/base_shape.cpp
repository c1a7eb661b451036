// The base shape under a textured surface (thesis Sec. 8.3.1): a robust screened bi-Laplacian fit with
// projection along the Phong normals, or the thesis' implicit smoothing.

#include "geotex/texture/base_shape.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/linear_solver.h"
#include "geotex/toolkit/phong_projection.h"
#include "geotex/toolkit/smoothing.h"

namespace geotex {

const EnumNames<BaseMethod>& base_method_names() {
  static const EnumNames<BaseMethod> n = {
      {"robust", BaseMethod::Robust}, {"smoothing", BaseMethod::Smoothing}, {"thesis", BaseMethod::Smoothing}};
  return n;
}

const OptionTable<BaseShapeOptions>& BaseShapeOptions::table() {
  using O = BaseShapeOptions;
  static const auto t = OptionTable<O>()
      .choice("base_method", &O::method, base_method_names(),
              "robust (reweighted screened bi-Laplacian fit, then projection) or smoothing (the thesis)", "Sec. 8.3.1")
      .add("base_scale", &O::scale, "robust: cutoff wavelength of the fit in mean edges (narrower bumps are texture)",
           positive())
      .add("size_share", &O::size_share,
           "robust: the cutoff wavelength at most this share of its connected component's size (its area's square "
           "root): a coarse or small part is shape, not texture (0: the cutoff alone)", between(0, 10))
      .add("hold_boundary", &O::hold_boundary,
           "robust: an open surface's boundary vertices hold their place (its outline is shape, not texture)", {})
      .add("outlier", &O::outlier, "robust: protrusion bound, in robust standard deviations of the first fit's distances",
           positive())
      .add("robust_passes", &O::robust_passes, "robust: reweighted fits after the first", between(0, 20))
      .add("project", &O::project, "robust: project textured vertices onto the fit along its Phong normals where it helps",
           {}, "Sec. 8.3.1, 5.2")
      .choice("laplacian", &O::laplacian, laplacian_names(), "smoothing: umbrella or cotan Laplacian", "Eq. (5.8), (5.11)")
      .add("lambda", &O::lambda, "smoothing: implicit step size", Bounds{0, 1e9, true, false}, "Eq. (5.14)")
      .add("steps", &O::steps, "smoothing: steps (0 = until the shape stops changing)", between(0, 100000), "Sec. 8.3.1")
      .add("max_steps", &O::max_steps, "smoothing, automatic: at most this many steps", between(1, 100000))
      .add("stop", &O::stop_tolerance,
           "smoothing, automatic: stop when a step moves no vertex more than this many mean edges", positive())
      .preset("thesis", "implicit umbrella smoothing until the shape stops changing (at most 30 steps), no projection",
              [](O& o) {
                o.method = BaseMethod::Smoothing;
                o.project = false;
              });
  return t;
}

namespace {

constexpr size_t kProjectionRings = 2;
constexpr size_t kHubValence = 64;  // see the projection in base_shape()

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto mid = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// The fit's cutoff wavelength per vertex, in the component's own mean edges (issue 26): o.scale, but at
// most o.size_share × the size (√area, in its own mean edges) of the vertex's connected component, so that
// a coarse model's legs and ears are shape rather than texture; a component smaller than kOwnShapeSize mean
// edges (its own or the whole mesh's: a button beside a body) keeps its own shape (scale 0: the base is the
// component itself, no texture). Each component's fit is then independent of the others.
constexpr double kOwnShapeSize = 4.0;

Eigen::VectorXd component_scales(const Mesh& mesh, const Eigen::VectorXi& comp, int count, double scale, double share) {
  const Eigen::Index n = mesh.n_vertices();
  const Eigen::VectorXd fa = face_areas(mesh);
  std::vector<double> area(std::max(count, 1), 0.0), length(area.size(), 0.0), edges(area.size(), 0.0);
  for (auto f : mesh.faces()) {
    const int c = comp[mesh.to_vertex_handle(mesh.halfedge_handle(f)).idx()];
    if (c >= 0) area[c] += fa[f.idx()];
  }
  for (auto e : mesh.edges()) {
    const int c = comp[mesh.to_vertex_handle(mesh.halfedge_handle(e, 0)).idx()];
    if (c < 0) continue;
    length[c] += mesh.calc_edge_length(e);
    edges[c] += 1;
  }
  const double h = std::max(mean_edge_length(mesh), 1e-300);
  Eigen::VectorXd out = Eigen::VectorXd::Constant(n, scale);
  for (Eigen::Index i = 0; i < n; ++i) {
    const int c = comp[i];
    if (c < 0) continue;
    const double own = std::sqrt(area[c]) / std::max(length[c] / std::max(edges[c], 1.0), 1e-300);
    const bool small = own < kOwnShapeSize || std::sqrt(area[c]) / h < kOwnShapeSize;
    out[i] = small ? 0.0 : share > 0 ? std::min(scale, share * own) : scale;
  }
  return out;
}

// Robust screened bi-Laplacian fit (see base_shape.h). Returns the fitted positions and the weights.
MatrixX3d robust_fit(const Mesh& mesh, const BaseShapeOptions& o, Eigen::VectorXd& w, int& passes) {
  const Eigen::Index n = mesh.n_vertices();
  const MatrixX3d X = positions(mesh);
  const SparseMatrix A = adjacency_matrix(mesh);
  const Eigen::VectorXd d = A * Eigen::VectorXd::Ones(n);
  // ‖L B‖²_D with the umbrella L = D⁻¹A − I = −D⁻¹K: Bᵀ K D⁻¹ K B, K = D − A (symmetric). An
  // isolated vertex has a zero row in K and keeps its position (data term alone).
  const SparseMatrix K = SparseMatrix(d.asDiagonal()) - A;
  // On a triangle lattice of spacing h, L ≈ (h²/4)Δ and D ≈ 6: the penalty is 6 μ (h²k²/4)² ‖b̂‖² at
  // wavenumber k. It equals the data term at the wavelength 2π/k = scale·h when μ = (scale/π)⁴/6.
  int count = 0;
  const Eigen::VectorXi comp = connected_components(mesh, &count);
  const Eigen::VectorXd scales = component_scales(mesh, comp, count, o.scale, o.size_share);
  Eigen::VectorXd mu(n);
  for (Eigen::Index i = 0; i < n; ++i) mu[i] = std::pow(scales[i] / M_PI, 4) / 6.0;
  // The outline of an open surface is shape: its boundary vertices (and those of a kept piece) hold
  // their place with a data weight that no reweighting lowers (a flat open model keeps its outline).
  std::vector<char> held(n, 0);
  for (auto v : mesh.vertices())
    held[v.idx()] = (o.hold_boundary && mesh.is_boundary(v)) || !(scales[v.idx()] > 0);
  // A held boundary vertex's one-sided Laplacian is no measure of smoothness: its row would pull the
  // vertices inside the outline towards it.
  for (Eigen::Index i = 0; i < n; ++i)
    if (held[i]) mu[i] = 0;
  // The system μ Kᵀ D⁻¹ K + W = GᵀG + W with G = √μ D^{-1/2} K, one row per vertex. The row of a vertex
  // of valence k couples its k neighbours in GᵀG (k² entries: 1 GB for a fan of 8,000); the solver
  // keeps such rows out of the factor (Woodbury), so memory stays linear in the valence.
  // Rows scaled in place: Eigen's diagonal × sparse product took 21 s for 60,000 disjoint triangles.
  SparseMatrix G = K;
  for (int c = 0; c < G.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(G, c); it; ++it)
      it.valueRef() *= d[it.row()] > 0 ? std::sqrt(mu[it.row()] / d[it.row()]) : 0.0;
  constexpr double kHeld = 1e3;
  w = Eigen::VectorXd::Ones(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (held[i]) w[i] = kHeld;
  LeastSquaresSolver solver;
  MatrixX3d B;
  std::vector<double> bound;  // per component: a flat piece beside a spiky one must not make it all protrusion
  const int total = 1 + o.robust_passes;
  for (int pass = 0; pass < total; ++pass) {
    if (pass == 0) solver.compute(G, w);
    else solver.refactor(w);
    B = solver.solve(w.asDiagonal() * X);
    // Undo the shrinking: B = (1 − (1 − S)³) X = 3 S X − 3 S² X + S³ X, with S the same filter: what
    // S keeps to first order (1 − s small) comes back to third order.
    {
      const MatrixX3d B2 = solver.solve(w.asDiagonal() * B);
      const MatrixX3d B3 = solver.solve(w.asDiagonal() * B2);
      B = 3 * (B - B2) + B3;
    }
    if (!B.allFinite()) throw SolverError("base shape: the fit diverged");
    passes = pass + 1;
    report(o.progress, double(pass + 1) / total, "base shape");
    if (pass + 1 == total) break;
    const Eigen::VectorXd r = (B - X).rowwise().norm();
    // The bound is set once, from the first fit: later fits move away from protrusions, and a bound
    // that followed them would let the filled region creep outwards.
    if (pass == 0) {
      std::vector<std::vector<double>> rc(std::max(count, 1));
      for (Eigen::Index i = 0; i < n; ++i)
        if (comp[i] >= 0 && !held[i]) rc[comp[i]].push_back(r[i]);
      bound.resize(rc.size());
      for (size_t c = 0; c < rc.size(); ++c) bound[c] = o.outlier * 1.4826 * median(std::move(rc[c]));
    }
    for (Eigen::Index i = 0; i < n; ++i) {
      // A component that is its own fit (bound 0) has nothing to reweight.
      if (comp[i] < 0 || !(bound[comp[i]] > 0)) continue;
      const double u = r[i] / bound[comp[i]];
      w[i] = u < 1 ? (1 - u * u) * (1 - u * u) : 0.0;
      w[i] = std::max(w[i], 1e-8);  // keeps the system definite on a component that is all protrusion
      if (held[i]) w[i] = kHeld;
    }
  }
  return B;
}

// Faces of P whose orientation turned against B's, or whose area collapsed: the projection folded them.
std::vector<int> folded_faces(const MatrixX3i& F, const MatrixX3d& P, const MatrixX3d& B) {
  std::vector<int> out;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 a = B.row(F(f, 0)), b = B.row(F(f, 1)), c = B.row(F(f, 2));
    const Vec3 p = P.row(F(f, 0)), q = P.row(F(f, 1)), r = P.row(F(f, 2));
    const Vec3 nb = (b - a).cross(c - a), np = (q - p).cross(r - p);
    const double ab = nb.norm(), ap = np.norm();
    if (!(ab > 0)) continue;
    if (np.dot(nb) < 0.3 * ab * ap || ap < 0.1 * ab) out.push_back(static_cast<int>(f));
  }
  return out;
}

}  // namespace

Eigen::VectorXd off_normal_angles(const Mesh& base, const MatrixX3d& textured) {
  const MatrixX3d B = positions(base);
  if (textured.rows() != B.rows()) throw InvalidInput("off-normal angles: the textured surface has another vertex count");
  const MatrixX3d N = vertex_normals(base, NormalWeighting::Angle);
  const double tiny = 1e-9 * mean_edge_length(base);
  Eigen::VectorXd a(B.rows());
  for (Eigen::Index i = 0; i < B.rows(); ++i) {
    const Vec3 dv = (textured.row(i) - B.row(i)).transpose();
    const double len = dv.norm();
    a[i] = len > tiny ? std::acos(std::clamp(std::abs(dv.dot(Vec3(N.row(i)))) / len, 0.0, 1.0)) * 180.0 / M_PI : 0.0;
  }
  return a;
}

namespace {

// Smoothing (Sec. 8.3.1): implicit steps, a given number or, automatic, until the shape stops changing.
void smoothing_base(const Mesh& textured, const BaseShapeOptions& o, BaseShape& out) {
  SmoothingOptions s;
  s.laplacian = o.laplacian;
  s.implicit = true;
  s.lambda = o.lambda;
  int steps = 0;
  s.progress = [&](double f, std::string_view stage) {
    ++steps;
    report(o.progress, f, stage);
  };
  if (o.steps > 0) {
    s.steps = o.steps;
  } else {  // automatic (Sec. 8.3.1): step until the shape stops changing; one factorization for all steps
    s.steps = o.max_steps;
    s.stop_tolerance = o.stop_tolerance;
  }
  out.positions = smooth(textured, s);
  out.passes = steps;
  out.stopped = o.steps > 0 || steps < o.max_steps;
}

// The robust fit's vertices projected onto the fit's Phong surface near them, as far as the weights allow
// and where that folds no face (out.positions: the fit, then the projected fit).
void project_onto_fit(const Mesh& textured, BaseShape& out) {
  const Eigen::Index n = textured.n_vertices();
  const MatrixX3d X = positions(textured);
  const MatrixX3d B = out.positions;
  Mesh fitted = textured;
  set_positions(fitted, B);
  // Each textured vertex is projected onto the faces around its own fitted vertex (its rings up to
  // kProjectionRings): the fit keeps the correspondence, and a projection that lands farther away
  // would tear the base (a global search also costs milliseconds per point where the Phong field
  // converges). No inside solution there, or an isolated vertex: the vertex keeps the fit.
  const MatrixX3d N = vertex_normals(fitted, NormalWeighting::Angle);
  const MatrixX3i F = faces(textured);
  std::vector<PhongTriangle> tri(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    tri[f] = PhongTriangle(B.row(F(f, 0)), B.row(F(f, 1)), B.row(F(f, 2)), N.row(F(f, 0)), N.row(F(f, 1)),
                           N.row(F(f, 2)));
  MatrixX3d Q = B;
  Eigen::VectorXd p = Eigen::VectorXd::Zero(n);
  // A vertex of high valence lends its faces only to its own projection: through the rings it would
  // hand all of them to each of its neighbours (cost valence² on a fan of 8,000).
  std::vector<char> hub(n, 0);
  for (Eigen::Index i = 0; i < n; ++i)
    hub[i] = textured.valence(textured.vertex_handle(static_cast<int>(i))) > kHubValence;
#pragma omp parallel
  {
    std::vector<int> ring, next;
    std::vector<char> seen(n, 0), face_seen(F.rows(), 0);
    std::vector<int> faces_seen;
#pragma omp for schedule(dynamic, 256)
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto vh = textured.vertex_handle(static_cast<int>(i));
      if (textured.is_isolated(vh)) continue;
      const Vec3 x = X.row(i).transpose();
      double best = std::numeric_limits<double>::infinity();
      // Ring by ring: the faces around the vertex, then those around its neighbours, … (most
      // projections land in the first ring).
      ring.assign(1, static_cast<int>(i));
      seen[i] = 1;
      std::vector<int> visited = ring;
      for (size_t r = 0; r < kProjectionRings && best == std::numeric_limits<double>::infinity(); ++r) {
        for (int v : ring) {
          if (r > 0 && hub[v]) continue;
          for (auto f : textured.vf_range(textured.vertex_handle(v))) {
            if (face_seen[f.idx()]) continue;
            face_seen[f.idx()] = 1;
            faces_seen.push_back(f.idx());
            for (const PhongCandidate& c : phong_project_analytic(x, tri[f.idx()]))
              if (c.inside && std::abs(c.d) < best) {
                best = std::abs(c.d);
                Q.row(i) = c.point.transpose();
              }
          }
        }
        if (r + 1 == kProjectionRings) break;
        next.clear();
        for (int v : ring) {
          if (r > 0 && hub[v]) continue;
          for (auto w : textured.vv_range(textured.vertex_handle(v)))
            if (!seen[w.idx()]) {
              seen[w.idx()] = 1;
              next.push_back(w.idx());
              visited.push_back(w.idx());
            }
        }
        ring.swap(next);
      }
      for (int v : visited) seen[v] = 0;
      for (int f : faces_seen) face_seen[f] = 0;
      faces_seen.clear();
      // Full projection up to Tukey weight 1/4 (residual 0.7 × the bound), fading to none on protrusions.
      if (best < std::numeric_limits<double>::infinity()) p[i] = std::min(1.0, 4 * out.weight[i]);
    }
  }
  // Where the projection folds the base (overhangs at the scale of an edge, crossings near a
  // protrusion), those vertices keep the fit; repeat until nothing folds.
  std::vector<char> kept(n, 0);
  for (int round = 0; round < 20; ++round) {
    const MatrixX3d P = B + p.asDiagonal() * (Q - B);
    const std::vector<int> bad = folded_faces(F, P, B);
    if (bad.empty()) break;
    for (int f : bad)
      for (int k = 0; k < 3; ++k) {
        const int v = F(f, k);
        if (p[v] > 0) kept[v] = 1;
        p[v] = 0;
      }
  }
  out.unfolded = std::count(kept.begin(), kept.end(), 1);
  out.positions = B + p.asDiagonal() * (Q - B);
  out.projected = p;
}

}  // namespace

BaseShape base_shape(const Mesh& textured, const BaseShapeOptions& o) {
  require_valid(textured, "base shape: textured mesh");
  BaseShapeOptions::table().check(o);
  const Eigen::Index n = textured.n_vertices();
  BaseShape out;
  out.projected = Eigen::VectorXd::Zero(n);
  out.weight = Eigen::VectorXd::Ones(n);
  if (o.method == BaseMethod::Smoothing) {
    smoothing_base(textured, o, out);
  } else {
    out.positions = robust_fit(textured, o, out.weight, out.passes);
    if (o.project) project_onto_fit(textured, out);
  }
  Mesh base = textured;
  set_positions(base, out.positions);
  out.off_normal_deg = off_normal_angles(base, positions(textured));
  out.median_off_normal_deg = median(std::vector<double>(out.off_normal_deg.data(), out.off_normal_deg.data() + n));
  return out;
}

MatrixX3d extract_base_shape(const Mesh& textured, const BaseShapeOptions& o) { return base_shape(textured, o).positions; }

Mesh project_onto_base(const Mesh& textured, const Mesh& base, size_t* missed) {
  require_valid(textured, "projection: textured mesh");
  const PhongProjector proj(base);
  const std::vector<PhongHit> hits = proj.project(positions(textured));
  MatrixX3d X(hits.size(), 3);
  size_t miss = 0;
  for (size_t i = 0; i < hits.size(); ++i) {
    X.row(i) = hits[i].point.transpose();
    miss += !hits[i].found;
  }
  if (missed) *missed = miss;
  Mesh out = textured;
  set_positions(out, X);
  return out;
}

}  // namespace geotex
