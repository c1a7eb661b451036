#include "geotex/resize/feature_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/weld.h"
#include "geotex/resize/results.h"
#include "geotex/toolkit/diffusion.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/simplify.h"
#include "geotex/toolkit/smoothing.h"

namespace geotex {

const EnumNames<FeatureMapMethod>& feature_map_names() {
  static const EnumNames<FeatureMapMethod> names = {{"importance", FeatureMapMethod::Importance},
                                                     {"auto", FeatureMapMethod::Auto},
                                                     {"height", FeatureMapMethod::Height},
                                                     {"adf", FeatureMapMethod::Adf},
                                                     {"none", FeatureMapMethod::None}};
  return names;
}

const OptionTable<FeatureMapOptions>& FeatureMapOptions::table() {
  using O = FeatureMapOptions;
  static const auto t = OptionTable<O>()
      .choice("features", &O::method, feature_map_names(),
              "feature map: importance (continuous weights from relief, its variation and protrusions, default), "
              "auto (binary: adf, or height where the ADF finds no protrusion), height (binary, over a smoothed "
              "base), adf (binary, auto diffusion function), none", "Sec. 9.4")
      .add("detail_scale", &O::detail_scale,
           "importance: middle smoothing scale of the relief in mean edge lengths (scales s/2, s, 2s)", between(0.1, 1000))
      .add("importance_low", &O::importance_low,
           "importance: raw value (about 1 at the 90th percentile) below which a vertex has weight 0", non_negative())
      .add("importance_high", &O::importance_high, "importance: raw value above which a vertex has weight 1",
           positive())
      .add("variation_share", &O::variation_share,
           "importance: share of the raw value from the relief's variation (0 on flat, round or cylindrical areas)",
           between(0, 1))
      .add("importance_smoothing", &O::importance_smoothing,
           "importance: Laplacian diffusion steps that smooth the map (no crease at a region's rim)", between(0, 10000))
      .add("protrusions", &O::protrusions, "importance: protrusions (significant height basins) get weight 1")
      .add("importance_adf", &O::importance_adf,
           "importance: find the protrusions with the ADF instead of the height (slower)")
      .add("importance_outline", &O::importance_outline,
           "importance: the outline of an open or flat model counts as relief (a boundary vertex's distance from "
           "its boundary loop smoothed along itself)")
      .add("smoothing_scale", &O::smoothing_scale,
           "height: smoothing time of the base is (s R)^2, R the radius of a sphere of the same area", positive())
      .add("adf_t", &O::adf_t, "adf: diffusion time in units of 1/lambda_1", positive(), "Sec. 9.4 (Gebal et al. 2009)")
      .add("eigenpairs", &O::eigenpairs, "adf: Laplace eigenpairs summed", between(2, 1000))
      .add("significance", &O::significance,
           "a maximum is a feature when it exceeds the median by this many robust standard deviations (1.4826 MAD)",
           non_negative())
      .add("merge_pass", &O::merge_pass,
           "neighbouring basins whose pass stands this many robust standard deviations above the median are one "
           "feature (two-tipped protrusions)", non_negative())
      .add("adf_full_vertices", &O::adf_full_vertices,
           "adf: meshes with more vertices get the spectrum of a simplification (0: never)", non_negative())
      .add("adf_vertices", &O::adf_vertices, "adf: vertices of that simplification", at_least(100))
      .add("adf_levels", &O::adf_levels, "adf: diffusion times tried, each half the last, inside regions too large",
           between(1, 30))
      .add("max_extent", &O::max_extent,
           "a region spanning more than this share of the model's extent along an axis is a part, not a feature",
           between(0, 1))
      .add("dilate", &O::dilate, "grow the map by this many vertex rings", between(0, 10000))
      .add("close_gaps", &O::close_gaps,
           "importance: close gaps narrower than about twice this many vertex rings between important regions "
           "(ring maxima, then as many ring minima; 0: off)", between(0, 1000));
  return t;
}

namespace {

// Area-weighted median of v (weights w ≥ 0).
double weighted_median(const Eigen::VectorXd& v, const Eigen::VectorXd& w) {
  std::vector<int> order(v.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return v[a] < v[b]; });
  const double half = 0.5 * w.sum();
  double acc = 0;
  for (int i : order) {
    acc += w[i];
    if (acc >= half) return v[i];
  }
  return v[order.back()];
}

// Share of the surface per vertex: a third of the adjacent triangles' areas (0 for isolated vertices).
Eigen::VectorXd feature_vertex_areas(const Mesh& mesh) {
  const Eigen::VectorXd fa = face_areas(mesh);
  Eigen::VectorXd a = Eigen::VectorXd::Zero(mesh.n_vertices());
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) a[v.idx()] += fa[f.idx()] / 3.0;
  return a;
}

// Robust z-score of a field: (g − median) / (1.4826 MAD), area-weighted; 0 where the spread vanishes.
Eigen::VectorXd robust_z(const Eigen::VectorXd& g, const Eigen::VectorXd& area) {
  const double med = weighted_median(g, area);
  const double mad = 1.4826 * weighted_median((g.array() - med).abs().matrix(), area);
  if (!(mad > 0)) return Eigen::VectorXd::Zero(g.size());
  return (g.array() - med) / mad;
}

}  // namespace

namespace {

// The height's smoothing: its cotangent time (scale R)² in units of h², at most 1e9 (smoothing's bound:
// by then the base is already each component's mean), and R = √(area / 4π).
std::pair<double, double> height_smoothing(const Mesh& mesh, double scale) {
  require_valid(mesh, "feature map input");
  if (!(scale > 0)) throw InvalidInput("smoothing scale must be positive");
  const double area = surface_area(mesh), h = mean_edge_length(mesh);
  if (!(area > 0) || !(h > 0)) throw InvalidInput("feature map: the mesh has no area");
  const double R = std::sqrt(area / (4 * M_PI));
  return {std::min(1e9, (scale * R) * (scale * R) / (h * h)), R};
}

// The height of \p mesh over its smoothed copy \p smoothed along the copy's normals, in units of \p R.
Eigen::VectorXd height_over(const Mesh& mesh, const MatrixX3d& smoothed, double R) {
  Mesh base = mesh;
  set_positions(base, smoothed);
  // Smoothing shrinks a closed surface: restore its volume, so that the height is measured from a base
  // through the middle of the features rather than from one inside the whole shape.
  if (boundary_loops(mesh).empty()) rescale_like(mesh, base);
  const MatrixX3d N = vertex_normals(base);
  const MatrixX3d d = positions(mesh) - positions(base);
  return d.cwiseProduct(N).rowwise().sum() / R;
}

}  // namespace

Eigen::VectorXd height_over_base(const Mesh& mesh, double scale) {
  const auto [lambda, R] = height_smoothing(mesh, scale);
  return height_over(mesh, implicit_cotan_steps(mesh, {lambda}).front(), R);
}

Eigen::VectorXd significant_basins(const Mesh& mesh, const Eigen::VectorXd& g, double significance,
                                   double merge_pass) {
  const int n = static_cast<int>(mesh.n_vertices());
  if (g.size() != n) throw InvalidInput(fmt::format("{} field values for {} vertices", g.size(), n));
  if (!g.allFinite()) throw InvalidInput("feature field must be finite");
  const Eigen::VectorXd z = robust_z(g, feature_vertex_areas(mesh));
  // Steepest ascent: each vertex points at its highest neighbour, if higher than itself.
  std::vector<int> up(n);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) {
    int best = i;
    for (auto w : mesh.vv_range(mesh.vertex_handle(i)))
      if (g[w.idx()] > g[best]) best = w.idx();
    up[i] = best;
  }
  // Follow the pointers to each vertex's peak (with path compression).
  std::vector<int> peak(n, -1), path;
  for (int i = 0; i < n; ++i) {
    int r = i;
    path.clear();
    while (peak[r] < 0 && up[r] != r) {
      path.push_back(r);
      r = up[r];
    }
    const int p = peak[r] >= 0 ? peak[r] : r;
    peak[r] = p;
    for (int v : path) peak[v] = p;
  }
  // A peak counts if it is significant and not on the boundary.
  auto counts = [&](int p) { return !mesh.is_boundary(mesh.vertex_handle(p)) && z[p] > significance; };
  // Basins joined by a high pass are one feature: union the peaks of the two ends of every edge that
  // crosses between basins with both ends above the pass level (then the pass, the highest such edge's
  // lower end, is above it too).
  std::vector<int> root(n);
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int a) {
    while (root[a] != a) a = root[a] = root[root[a]];
    return a;
  };
  if (std::isfinite(merge_pass)) {
    for (auto e : mesh.edges()) {
      const int a = e.v0().idx(), b = e.v1().idx();
      if (peak[a] != peak[b] && z[a] > merge_pass && z[b] > merge_pass) root[find(peak[a])] = find(peak[b]);
    }
  }
  std::vector<char> marked(n, 0);  // per union root: holds a peak that counts
  for (int i = 0; i < n; ++i)
    if (peak[i] == i && counts(i)) marked[find(i)] = 1;
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i)
    if (!mesh.is_isolated(mesh.vertex_handle(i)) && marked[find(peak[i])]) f[i] = 1;
  return f;
}

namespace {

// Connected components of the vertices with mask > ½.
std::vector<std::vector<int>> components(const Mesh& mesh, const Eigen::VectorXd& mask) {
  const int n = static_cast<int>(mesh.n_vertices());
  std::vector<char> seen(n, 0);
  std::vector<std::vector<int>> out;
  std::vector<int> stack;
  for (int s = 0; s < n; ++s) {
    if (!(mask[s] > 0.5) || seen[s]) continue;
    out.emplace_back();
    seen[s] = 1;
    stack.assign(1, s);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      out.back().push_back(v);
      for (auto w : mesh.vv_range(mesh.vertex_handle(v)))
        if (mask[w.idx()] > 0.5 && !seen[w.idx()]) {
          seen[w.idx()] = 1;
          stack.push_back(w.idx());
        }
    }
  }
  return out;
}

// Does a region span more than max_extent of the model's extent along some axis (a part of the
// model, not a detail on it)? Only axes along which the model extends at least a quarter of its
// largest extent count.
bool too_large(const MatrixX3d& X, const std::vector<int>& region, const Vec3& model_extent, double max_extent) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int v : region) {
    lo = lo.cwiseMin(X.row(v).transpose());
    hi = hi.cwiseMax(X.row(v).transpose());
  }
  for (int a = 0; a < 3; ++a)  // along the axes the model really extends in (not a plate's thickness)
    if (model_extent[a] >= 0.25 * model_extent.maxCoeff() && hi[a] - lo[a] > max_extent * model_extent[a]) return true;
  return false;
}

}  // namespace

namespace {

// The ADF at each diffusion time tried, #V by levels, of a mesh whose faced vertices are connected.
// On a large mesh the spectrum comes from a simplification (its low end does not change with
// resolution) and the ADF is extended back harmonically, which adds no maxima of its own.
Eigen::MatrixXd adf_levels_connected(const Mesh& mesh, const FeatureMapOptions& o, int levels, bool quiet) {
  int n_faced = vertices_in_faces(mesh);
  const bool coarse = o.adf_full_vertices > 0 && n_faced > o.adf_full_vertices && n_faced > o.adf_vertices;
  if (coarse && !quiet) report(o.progress, 0.02, fmt::format("adf: simplification to {} vertices", o.adf_vertices));
  const SimplifiedMesh simple = coarse ? simplify(mesh, o.adf_vertices) : SimplifiedMesh{};
  const Mesh& spectral = coarse ? simple.mesh : mesh;
  if (coarse) n_faced = vertices_in_faces(spectral);
  if (!quiet) report(o.progress, 0.1, "adf: Laplace spectrum");
  const LaplaceSpectrum spectrum = laplace_spectrum(spectral, std::min(o.eigenpairs, n_faced - 1));
  Eigen::MatrixXd G(spectral.n_vertices(), levels);
  double t = o.adf_t;
  for (int level = 0; level < levels; ++level, t *= 0.5) G.col(level) = auto_diffusion_function(spectrum, t);
  if (coarse) {
    if (!quiet) report(o.progress, 0.7, "adf: extension to every vertex");
    G = extend_harmonic(mesh, simple.original, G);
  }
  return G;
}

// The ADF of a mesh of several components: each component's own (its own eigenpairs and λ_1), times
// its share of the total area. A Laplacian of k components has k zero eigenvalues, so one spectrum
// of the whole would spend its eigenpairs on component indicators (10^5 disjoint triangles: minutes
// of Lanczos for nothing); per component the cost is linear in the component count. The area share
// keeps ∫ADF dA of every component comparable (φ² scales as 1/area), as in a single spectrum.
Eigen::MatrixXd adf_levels(const Mesh& mesh, const FeatureMapOptions& o, int levels) {
  int k = 0;
  const Eigen::VectorXi comp = connected_components(mesh, &k);
  std::vector<std::vector<int>> members(k);
  for (int v = 0; v < comp.size(); ++v)
    if (!mesh.is_isolated(mesh.vertex_handle(v))) members[comp[v]].push_back(v);
  std::erase_if(members, [](const std::vector<int>& m) { return m.empty(); });  // isolated vertices: ADF 0
  if (members.size() <= 1) return adf_levels_connected(mesh, o, levels, false);  // unchanged for one component
  report(o.progress, 0.1, fmt::format("adf: Laplace spectra of {} components", members.size()));
  const MatrixX3d X = positions(mesh);
  const MatrixX3i F = faces(mesh);
  std::vector<std::vector<int>> component_faces(members.size());
  std::vector<int> local(X.rows(), -1), which(X.rows(), -1);
  for (int c = 0; c < static_cast<int>(members.size()); ++c)
    for (int i = 0; i < static_cast<int>(members[c].size()); ++i) {
      local[members[c][i]] = i;
      which[members[c][i]] = c;
    }
  for (int f = 0; f < F.rows(); ++f) component_faces[which[F(f, 0)]].push_back(f);
  const Eigen::VectorXd fa = face_areas(mesh);
  const double total_area = fa.sum();
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(X.rows(), levels);
  for (int c = 0; c < static_cast<int>(members.size()); ++c) {
    const std::vector<int>& m = members[c];
    MatrixX3d Xc(m.size(), 3);
    for (size_t i = 0; i < m.size(); ++i) Xc.row(i) = X.row(m[i]);
    MatrixX3i Fc(component_faces[c].size(), 3);
    double area = 0;
    for (size_t j = 0; j < component_faces[c].size(); ++j) {
      const int f = component_faces[c][j];
      for (int a = 0; a < 3; ++a) Fc(j, a) = local[F(f, a)];
      area += fa[f];
    }
    const Eigen::MatrixXd Gc = adf_levels_connected(make_mesh(Xc, Fc), o, levels, true);
    const double share = total_area > 0 ? area / total_area : 0.0;
    for (size_t i = 0; i < m.size(); ++i) G.row(m[i]) = share * Gc.row(i);
    check_interrupt();
  }
  return G;
}

}  // namespace

Eigen::VectorXd adf_features(const Mesh& mesh, const FeatureMapOptions& o, Eigen::VectorXd* field) {
  check_options(o);
  const int levels = std::max(1, o.adf_levels);
  const Eigen::MatrixXd G = adf_levels(mesh, o, levels);  // the ADF at each diffusion time tried, #V by levels
  const MatrixX3d X = positions(mesh);
  const Vec3 extent = X.colwise().maxCoeff() - X.colwise().minCoeff();
  const Eigen::Index n = X.rows();
  Eigen::VectorXd f = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd search = Eigen::VectorXd::Ones(n);  // where finer times may still find features
  if (field) *field = G.col(0);
  for (int level = 0; level < levels; ++level) {
    const Eigen::VectorXd basins = significant_basins(mesh, G.col(level), o.significance, o.merge_pass).cwiseProduct(search);
    search.setZero();
    for (const auto& region : components(mesh, basins)) {
      const bool part = too_large(X, region, extent, o.max_extent);
      for (int v : region) (part ? search : f)[v] = 1;
    }
    if (search.sum() == 0) break;
  }
  return f;
}

namespace {
// \p f without its connected regions (f > ½) that span more than \p max_extent of the model's extent along an axis.
Eigen::VectorXd drop_large_regions(const Mesh& mesh, const Eigen::VectorXd& f, double max_extent) {
  const MatrixX3d X = positions(mesh);
  const Vec3 extent = X.colwise().maxCoeff() - X.colwise().minCoeff();
  Eigen::VectorXd out = f;
  for (const auto& region : components(mesh, f))
    if (too_large(X, region, extent, max_extent))
      for (int v : region) out[v] = 0;
  return out;
}
}  // namespace

FeatureSummary summarize_features(const Mesh& mesh, const Eigen::VectorXd& f) {
  const int n = static_cast<int>(mesh.n_vertices());
  if (f.size() != n) throw InvalidInput(fmt::format("feature map: {} weights for {} vertices", f.size(), n));
  FeatureSummary s;
  const Eigen::VectorXd area = feature_vertex_areas(mesh);
  const double total = area.sum();
  std::vector<int> region(n, -1), stack;
  for (int i = 0; i < n; ++i) {
    if (!(f[i] > 0.5)) continue;
    ++s.marked_vertices;
    s.marked_fraction += area[i];
    if (region[i] >= 0) continue;
    region[i] = s.regions;
    stack.assign(1, i);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (auto w : mesh.vv_range(mesh.vertex_handle(v)))
        if (f[w.idx()] > 0.5 && region[w.idx()] < 0) {
          region[w.idx()] = s.regions;
          stack.push_back(w.idx());
        }
    }
    ++s.regions;
  }
  s.marked_fraction = total > 0 ? s.marked_fraction / total : 0.0;
  if (s.marked_fraction > 0.5)
    s.warning = fmt::format("features cover {:.1f}% of the surface (more than half): the features hold the shape "
                            "together and the result will be close to a rigid copy, not the asked deformation",
                            100 * s.marked_fraction);
  else if (s.marked_fraction < 0.005)
    s.warning = fmt::format("features cover {:.2f}% of the surface (less than 0.5%): the result will be close to "
                            "the plain space map", 100 * s.marked_fraction);
  return s;
}

std::string FeatureSummary::describe() const {
  // Said as the report and Python name it (results.h: figures()).
  return "features: " + feature_summary_results().figures(*this, {"marked_fraction", "marked_vertices", "regions"});
}

namespace {

// Area-weighted q-quantile of v.
double weighted_quantile(const Eigen::VectorXd& v, const Eigen::VectorXd& w, double q) {
  std::vector<int> order(v.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return v[a] < v[b]; });
  const double target = q * w.sum();
  double acc = 0;
  for (int i : order) {
    acc += w[i];
    if (acc >= target) return v[i];
  }
  return order.empty() ? 0.0 : v[order.back()];
}

// Lazy umbrella diffusion, steps × (½ f + ½ mean of the neighbours). The neighbours are listed once
// (compressed rows, in the circulator's order: the same sums as circulating each step, without its
// cost or a heap vector per vertex and step).
Eigen::VectorXd diffuse(const Mesh& mesh, Eigen::VectorXd f, int steps) {
  const int n = static_cast<int>(mesh.n_vertices());
  std::vector<int> start(n + 1, 0), nbr;
  nbr.reserve(2 * mesh.n_edges());
  for (int i = 0; i < n; ++i) {
    for (auto w : mesh.vv_range(mesh.vertex_handle(i))) nbr.push_back(w.idx());
    start[i + 1] = static_cast<int>(nbr.size());
  }
  Eigen::VectorXd g(n);
  for (int s = 0; s < steps; ++s) {
#pragma omp parallel for schedule(static)
    for (int i = 0; i < n; ++i) {
      const int k = start[i + 1] - start[i];
      double acc = 0;
      for (int e = start[i]; e < start[i + 1]; ++e) acc += f[nbr[e]];
      g[i] = k > 0 ? 0.5 * f[i] + 0.5 * acc / k : f[i];
    }
    f.swap(g);
  }
  return f;
}

// The boundary vertices that lie on another boundary vertex (coincident_groups(), within kCoincidentTolerance mean
// edge lengths): a seam between unwelded patches (the teapot's Bézier patches), not an outline. Two patches whose
// seam was read as outline were each held to their own shape and tore apart under a stretch. (Resize welds such
// seams before the map (weld.h); this keeps feature_map() on an unwelded mesh, and the groups the weld refuses.)
std::vector<int> seam_vertices(const Mesh& mesh, const std::vector<std::vector<int>>& loops) {
  std::vector<int> b;
  for (const std::vector<int>& loop : loops) b.insert(b.end(), loop.begin(), loop.end());
  const std::vector<int> group = coincident_groups(positions(mesh), kCoincidentTolerance * mean_edge_length(mesh), &b);
  std::vector<char> on(mesh.n_vertices(), 0);
  for (int v : b)
    if (group[v] != v) on[v] = on[group[v]] = 1;
  std::vector<int> seam;
  for (int v : b)
    if (on[v]) seam.push_back(v);
  return seam;
}

// Each boundary vertex's two neighbours along its boundary loop (boundary_loops()), {-1, -1} off the boundary
// (empty: a closed mesh).
std::vector<std::array<int, 2>> boundary_neighbours(const Mesh& mesh) {
  const std::vector<std::vector<int>> loops = boundary_loops(mesh);
  if (loops.empty()) return {};
  std::vector<std::array<int, 2>> nb(mesh.n_vertices(), {-1, -1});
  for (const std::vector<int>& loop : loops)
    for (size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];  // a boundary halfedge a -> b
      nb[a][1] = b, nb[b][0] = a;
    }
  for (int v : seam_vertices(mesh, loops)) nb[v] = {-1, -1};
  return nb;
}

// \p X with its boundary loops (\p loop, boundary_neighbours()) smoothed along themselves: \p steps lazy steps
// of ½ x + ¼ (previous + next).
MatrixX3d smooth_along_loops(const MatrixX3d& X, const std::vector<std::array<int, 2>>& loop, int steps) {
  MatrixX3d B = X, next = X;
  for (int s = 0; s < steps; ++s) {
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      if (loop[i][0] >= 0) next.row(i) = 0.5 * B.row(i) + 0.25 * (B.row(loop[i][0]) + B.row(loop[i][1]));
    B.swap(next);
  }
  return B;
}

}  // namespace

Eigen::VectorXd importance_map(const Mesh& mesh, const FeatureMapOptions& o, Eigen::VectorXd* raw_out) {
  check_options(o);
  require_valid(mesh, "feature map input");
  if (!(o.importance_high > o.importance_low))
    throw InvalidInput("importance_high must be above importance_low");
  const int n = static_cast<int>(mesh.n_vertices());
  const double h = mean_edge_length(mesh);
  if (!(h > 0)) throw InvalidInput("feature map: the mesh has no edges of positive length");
  const Eigen::VectorXd area = feature_vertex_areas(mesh);
  const MatrixX3d X = positions(mesh);
  // Relief over smoothed copies at three scales, each in units of its 90th percentile (times (c h)², in
  // units of h²), and the protrusions' base: one cotangent matrix and analysis for the four.
  report(o.progress, 0.1, "importance: relief");
  const double scales[3] = {0.5 * o.detail_scale, o.detail_scale, 2.0 * o.detail_scale};
  const bool height = o.protrusions && !o.importance_adf;
  const auto [height_lambda, R] = height ? height_smoothing(mesh, o.smoothing_scale) : std::pair<double, double>{0, 1};
  std::vector<double> lambdas = {scales[0] * scales[0], scales[1] * scales[1], scales[2] * scales[2]};
  if (height) lambdas.push_back(height_lambda);
  const std::vector<MatrixX3d> smoothed = implicit_cotan_steps(mesh, lambdas);
  Eigen::MatrixXd Z(n, 3);
  const std::vector<std::array<int, 2>> loop = o.importance_outline ? boundary_neighbours(mesh) : std::vector<std::array<int, 2>>{};
  for (int k = 0; k < 3; ++k) {
    const Eigen::VectorXd r = (X - smoothed[k]).rowwise().norm();
    const double q = weighted_quantile(r, area, 0.9);
    Z.col(k) = q > 0 ? Eigen::VectorXd(r / q) : Eigen::VectorXd::Zero(n);
    if (!loop.empty() && q > 0) {
      // The outline: 2 s² lazy steps along the loop (about the surface's smoothing radius s).
      const MatrixX3d B = smooth_along_loops(X, loop, static_cast<int>(std::ceil(2 * scales[k] * scales[k])));
      for (int i = 0; i < n; ++i)
        if (loop[i][0] >= 0) Z(i, k) = std::max(Z(i, k), (X.row(i) - B.row(i)).norm() / q);
    }
  }
  const Eigen::VectorXd detail = Z.rowwise().mean();
  // Its variation: the relief minus its own smoothed copy (constant relief, on a sphere, a cylinder or a
  // plane, gives none).
  const Eigen::VectorXd base = diffuse(mesh, detail, static_cast<int>(std::ceil(4 * o.detail_scale * o.detail_scale)));
  Eigen::VectorXd variation = (detail - base).cwiseAbs();
  {
    // In units of its own 90th percentile, but not of less than a twentieth of the relief's: a shape
    // whose relief hardly varies (a cylinder) would otherwise show its noise as variation.
    const double q = std::max(weighted_quantile(variation, area, 0.9), 0.05);
    variation /= q;
  }
  Eigen::VectorXd raw = (1 - o.variation_share) * detail + o.variation_share * variation;
  Eigen::VectorXd f(n);
  for (int i = 0; i < n; ++i) {
    const double t = std::clamp((raw[i] - o.importance_low) / (o.importance_high - o.importance_low), 0.0, 1.0);
    f[i] = t * t * (3 - 2 * t);
  }
  if (o.protrusions) {
    report(o.progress, 0.7, "importance: protrusions");
    Eigen::VectorXd p;
    if (o.importance_adf) {
      p = adf_features(mesh, o);
    } else {
      p = significant_basins(mesh, height_over(mesh, smoothed[3], R), o.significance, o.merge_pass);
      p = drop_large_regions(mesh, p, o.max_extent);
    }
    f = f.cwiseMax(p);
  }
  f = diffuse(mesh, f, o.importance_smoothing).cwiseMax(0.0).cwiseMin(1.0);
  if (o.close_gaps > 0) f = close_features(mesh, f, o.close_gaps);
  for (int i = 0; i < n; ++i)
    if (mesh.is_isolated(mesh.vertex_handle(i))) f[i] = 0;
  if (raw_out) *raw_out = std::move(raw);
  return f;
}

FeatureMap feature_map(const Mesh& mesh, const FeatureMapOptions& o) {
  check_options(o);
  require_valid(mesh, "feature map input");
  const Eigen::Index n = mesh.n_vertices();
  FeatureMap out;
  out.weights = Eigen::VectorXd::Zero(n);
  out.field = Eigen::VectorXd::Zero(n);
  out.method = FeatureMapMethod::None;
  if (o.method == FeatureMapMethod::Importance) {
    out.weights = importance_map(mesh, o, &out.field);
    out.method = FeatureMapMethod::Importance;
  }
  if (o.method == FeatureMapMethod::Adf || o.method == FeatureMapMethod::Auto) {
    report(o.progress, 0.0, "adf");
    out.weights = adf_features(mesh, o, &out.field);
    // Auto: the ADF finds protrusions (the thesis' choice, Sec. 9.4); a surface without any, such as
    // a relief on an open plate (where the ADF peaks at the border instead), gets the height map.
    if (o.method == FeatureMapMethod::Auto && summarize_features(mesh, out.weights).marked_fraction < 0.005)
      out.method = FeatureMapMethod::Height;
    else
      out.method = FeatureMapMethod::Adf;
  }
  if (o.method == FeatureMapMethod::Height || out.method == FeatureMapMethod::Height) {
    report(o.progress, o.method == FeatureMapMethod::Height ? 0.0 : 0.8, "height");
    out.field = height_over_base(mesh, o.smoothing_scale);
    out.weights = significant_basins(mesh, out.field, o.significance, o.merge_pass);
    out.method = FeatureMapMethod::Height;
  }
  if (o.dilate > 0) out.weights = dilate_features(mesh, out.weights, o.dilate);
  out.summary = summarize_features(mesh, out.weights);
  if (o.method == FeatureMapMethod::None) out.summary.warning.clear();  // asked for: the plain map is meant
  // Continuous weights over most of the surface still leave the rest to take the stretch.
  if (out.method == FeatureMapMethod::Importance && out.summary.marked_fraction > 0.5) out.summary.warning.clear();
  report(o.progress, 1.0, "done");
  return out;
}

// ---------------------------------------------------------------------------------------------

// Each vertex the largest (\p largest) or smallest weight within \p rings vertex rings.
static Eigen::VectorXd ring_extremum(const Mesh& mesh, const Eigen::VectorXd& f, int rings, bool largest) {
  Eigen::VectorXd g = f;
  for (int r = 0; r < rings; ++r) {
    Eigen::VectorXd h = g;
    for (auto e : mesh.edges()) {
      const int a = e.v0().idx(), b = e.v1().idx();
      h[a] = largest ? std::max(h[a], g[b]) : std::min(h[a], g[b]);
      h[b] = largest ? std::max(h[b], g[a]) : std::min(h[b], g[a]);
    }
    g = h;
  }
  return g;
}

Eigen::VectorXd dilate_features(const Mesh& mesh, const Eigen::VectorXd& f, int rings) {
  return ring_extremum(mesh, f, rings, true);
}

Eigen::VectorXd close_features(const Mesh& mesh, const Eigen::VectorXd& f, int rings) {
  return ring_extremum(mesh, dilate_features(mesh, f, rings), rings, false).cwiseMax(f);
}

Eigen::VectorXd features_from_values(const Mesh& mesh, const Eigen::VectorXd& height, double threshold, int dilate) {
  if (height.size() != static_cast<Eigen::Index>(mesh.n_vertices()))
    throw InvalidInput(fmt::format("{} height values for {} vertices", height.size(), mesh.n_vertices()));
  Eigen::VectorXd f = (height.array().abs() > threshold).cast<double>();
  return dilate_features(mesh, f, dilate);
}

Eigen::VectorXd features_from_height(const Mesh& mesh, const FeatureMapOptions& options) {
  FeatureMapOptions o = options;
  o.method = FeatureMapMethod::Height;
  return feature_map(mesh, o).weights;
}

}  // namespace geotex
