#include "keep_out.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <vector>

#include "geotex/core/geometry.h"
#include "geotex/toolkit/laplace.h"

namespace geotex::detail {

namespace {

// 0 below a, 1 above b, smooth between.
double ramp(double x, double a, double b) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Distance along edges from the vertices where `seed` is set, up to `limit` (beyond: limit). With `owner`
// (#V, the seeds' labels), each vertex reached gets its nearest seed's label (−1 where none is reached).
Eigen::VectorXd edge_distance(const Mesh& mesh, const MatrixX3d& X, const std::vector<char>& seed, double limit,
                              std::vector<int>* owner = nullptr) {
  const int n = static_cast<int>(mesh.n_vertices());
  Eigen::VectorXd d = Eigen::VectorXd::Constant(n, limit);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  for (int v = 0; v < n; ++v) {
    if (seed[v]) d[v] = 0, q.emplace(0.0, v);
    if (owner && !seed[v]) (*owner)[v] = -1;
  }
  while (!q.empty()) {
    const auto [dv, v] = q.top();
    q.pop();
    if (dv > d[v]) continue;
    for (auto w : mesh.vv_range(mesh.vertex_handle(v))) {
      const double dw = dv + (X.row(v) - X.row(w.idx())).norm();
      if (dw < d[w.idx()]) {
        d[w.idx()] = dw, q.emplace(dw, w.idx());
        if (owner) (*owner)[w.idx()] = (*owner)[v];
      }
    }
  }
  return d;
}

// The vertices within `span` of one vertex along edges (Dijkstra), its buffers reused from vertex to vertex
// by one thread: grow() calls visit(u) on each vertex as it is settled, nearest first, and stops when visit
// returns false; dist and touched then hold what was reached until clear().
struct EdgeBall {
  std::vector<double> dist;
  std::vector<int> touched;
  explicit EdgeBall(int n) : dist(n, std::numeric_limits<double>::infinity()) {}
  template <class Visit>
  void grow(const Mesh& mesh, const MatrixX3d& X, int v, double span, Visit visit) {
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
    dist[v] = 0;
    touched.push_back(v);
    q.emplace(0.0, v);
    while (!q.empty()) {
      const auto [du, u] = q.top();
      q.pop();
      if (du > dist[u]) continue;
      if (!visit(u)) break;
      for (auto t : mesh.vv_range(mesh.vertex_handle(u))) {
        const double dt = du + (X.row(u) - X.row(t.idx())).norm();
        if (dt < span && dt < dist[t.idx()]) {
          if (!std::isfinite(dist[t.idx()])) touched.push_back(t.idx());
          dist[t.idx()] = dt;
          q.emplace(dt, t.idx());
        }
      }
    }
  }
  void clear() {
    for (int t : touched) dist[t] = std::numeric_limits<double>::infinity();
    touched.clear();
  }
};

// Creases: vertices on an edge whose dihedral angle exceeds the threshold; the weight rises with the
// distance from them, from a quarter of the texture's span to the span (a feature rooted farther than its
// own length cannot lean over one).
Eigen::VectorXd crease_weight(const Mesh& mesh, const MatrixX3d& X, double reach, double angle_deg) {
  const Eigen::VectorXd a = dihedral_angles(mesh);
  std::vector<char> on(mesh.n_vertices(), 0);
  const double limit = angle_deg * M_PI / 180;
  for (auto e : mesh.edges())
    if (std::abs(a[e.idx()]) > limit) on[e.v0().idx()] = on[e.v1().idx()] = 1;
  const Eigen::VectorXd d = edge_distance(mesh, X, on, reach);
  return d.unaryExpr([&](double x) { return ramp(x, 0.25 * reach, reach); });
}

// Parts smaller than the texture: the surface area within `span` of the vertex (along edges) against a flat
// disk's, π span². A finger or a leg of radius ρ holds about 4ρ / span of it, a small piece its own area, a
// wide sheet (an ear) all of it, however thin: 0 under a quarter, 1 from a half on.
Eigen::VectorXd thin_weight(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& area, double span) {
  const int n = static_cast<int>(X.rows());
  Eigen::VectorXd w = Eigen::VectorXd::Ones(n);
  const double disk = M_PI * span * span;
#pragma omp parallel
  {
    EdgeBall ball(n);
#pragma omp for schedule(dynamic, 256)
    for (int v = 0; v < n; ++v) {
      double reached = 0;
      ball.grow(mesh, X, v, span, [&](int u) { return (reached += area[u]) < 0.5 * disk; });
      w[v] = ramp(reached / disk, 0.25, 0.5);
      ball.clear();
    }
  }
  return w;
}

// Closed pits smaller than the texture (an eye socket with no crease round it): at each vertex, for rings at
// r = span / 4, span / 2 and span (the band r/2 … r along edges), the ring's height above the vertex along the
// disk's mean normal, in 8 sectors round that normal: the lowest sector's mean over r is how deep the vertex
// sits in a pit closed on every side (a convex or flat place: ≤ 0; a groove or a saddle: about 0 along its open
// side). The deepest over the three rings; bands under an edge wide are skipped (noise). The weight is 0 where
// the depth is at least `depth` (and within a quarter of the span of such a vertex), rising to 1 at the span.
Eigen::VectorXd pit_weight(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& area, double span,
                           double depth) {
  const int n = static_cast<int>(X.rows());
  const MatrixX3d N = vertex_normals(mesh);
  const double edge = mean_edge_length(mesh);
  std::vector<char> pit(n, 0);
#pragma omp parallel
  {
    EdgeBall ball(n);
    const std::vector<double>& dist = ball.dist;
    const std::vector<int>& touched = ball.touched;
#pragma omp for schedule(dynamic, 256)
    for (int v = 0; v < n; ++v) {
      ball.grow(mesh, X, v, span, [](int) { return true; });
      for (double r : {0.25 * span, 0.5 * span, span}) {
        if (r < 2 * edge) continue;  // the band r/2 … r under an edge wide
        Vec3 nm = Vec3::Zero();
        for (int t : touched)
          if (dist[t] <= r) nm += area[t] * N.row(t).transpose();
        if (!(nm.norm() > 0)) continue;
        nm.normalize();
        const Vec3 e1 = nm.unitOrthogonal(), e2 = nm.cross(e1);
        double sum[8] = {}, cnt[8] = {};
        for (int t : touched) {
          if (dist[t] < 0.5 * r || dist[t] > r) continue;
          const Vec3 d = X.row(t) - X.row(v);
          const double a = std::atan2(d.dot(e2), d.dot(e1));
          const int k = std::clamp(static_cast<int>((a + M_PI) / (2 * M_PI) * 8), 0, 7);
          sum[k] += area[t] * d.dot(nm), cnt[k] += area[t];
        }
        double low = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 8; ++k) low = std::min(low, cnt[k] > 0 ? sum[k] / cnt[k] : -1.0);
        if (low >= depth * r) pit[v] = 1;
      }
      ball.clear();
    }
  }
  const Eigen::VectorXd d = edge_distance(mesh, X, pit, span);
  return d.unaryExpr([&](double x) { return ramp(x, 0.25 * span, span); });
}

// Mean curvature (positive where convex, Eq. 5.10), averaged over each vertex's one ring by area (the
// cotangent formula's noise on scanned surfaces is an edge wide).
Eigen::VectorXd smooth_mean_curvature(const Mesh& mesh, const Eigen::VectorXd& area) {
  const MatrixX3d Hn = mean_curvature_normals(mesh), N = vertex_normals(mesh);
  const int n = static_cast<int>(area.size());
  Eigen::VectorXd H(n), S(n);
  for (int v = 0; v < n; ++v) H[v] = std::isfinite(Hn(v, 0)) ? Hn.row(v).dot(N.row(v)) : 0.0;
  for (int v = 0; v < n; ++v) {
    double h = area[v] * H[v], a = area[v];
    for (auto w : mesh.vv_range(mesh.vertex_handle(v))) h += area[w.idx()] * H[w.idx()], a += area[w.idx()];
    S[v] = a > 0 ? h / a : 0.0;
  }
  return S;
}

// The islands of the surface closed round by strong curvature: connected components of the vertices whose
// smoothed mean curvature H is within (−ridge / 2, ridge) / span. Returns #V labels (−1: on the loop).
std::vector<int> curvature_islands(const Mesh& mesh, const Eigen::VectorXd& H, double span, double ridge,
                                   int& count) {
  const int n = static_cast<int>(H.size());
  std::vector<int> label(n, -1);
  count = 0;
  for (int s = 0; s < n; ++s) {
    auto free = [&](int v) { return label[v] < 0 && H[v] * span < ridge && H[v] * span > -0.5 * ridge; };
    if (!free(s)) continue;
    std::vector<int> stack{s};
    label[s] = count;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (auto w : mesh.vv_range(mesh.vertex_handle(v)))
        if (free(w.idx())) label[w.idx()] = count, stack.push_back(w.idx());
    }
    ++count;
  }
  return label;
}

// One island of curvature_islands(): its vertices and area-weighted sums.
struct Island {
  std::vector<int> vertices;
  double area = 0, curvature = 0;            // Σ A, Σ A H
  Vec3 normal = Vec3::Zero(), mid = Vec3::Zero();  // Σ A n, Σ A x
};

// Whether an island stands on the surface round it: the band within 2ρ of it along edges (its rim and past it;
// ρ = √(area / π)) faces its way (area-weighted mean cosine ≥ 0.8: not a foot's sole, a box's face or a horn's tip,
// elsewhere on cheburashka, spot, the cow, fandisk and the bunny at most 0.76; its eyes 0.83–0.85) and lies below
// it along that way by at least 0.2 ρ; and whether it stands there alone, on a calm surface: at most kCalmLoops of
// the band from 2ρ to 6ρ lies on the loops of strong curvature (label −1) that close islands round. An eyeball's
// surroundings are the head (cheburashka's eyes: 0.16 and 0.18, the other eye and the nose in the band); a curl of
// hair stands among others and their grooves (igea's: 0.24–0.64), like a field of buttons side by side (0.32;
// bench/synthesis.md, eleventh session).
constexpr double kCalmLoops = 0.21;
bool stands_alone(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& N, const Eigen::VectorXd& area,
                  const std::vector<int>& label, const Island& s) {
  std::vector<char> seed(X.rows(), 0);
  for (int v : s.vertices) seed[v] = 1;
  const double rho = std::sqrt(s.area / M_PI);
  const Eigen::VectorXd d = edge_distance(mesh, X, seed, 6 * rho);
  const Vec3 n = s.normal.normalized();
  double a = 0, cosine = 0, outer = 0, loops = 0;
  Vec3 mid = Vec3::Zero();
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    if (d[v] > 0 && d[v] < 2 * rho) {
      a += area[v], cosine += area[v] * N.row(v).dot(n);
      mid += area[v] * X.row(v).transpose();
    } else if (d[v] >= 2 * rho && d[v] < 6 * rho) {
      outer += area[v], loops += label[v] < 0 ? area[v] : 0.0;
    }
  }
  const bool stands = a > 0 && cosine / a >= 0.8 && (s.mid / s.area - mid / a).dot(n) >= 0.2 * rho;
  return stands && loops <= kCalmLoops * outer;
}

// Domes smaller than the texture (an eyeball with no crease round it, cheburashka's; bench/synthesis.md):
// islands closed round by a loop of strong curvature — a ridge (mean curvature above `ridge` / span: the
// eyeball's rounded edge) or a valley (below −ridge / 2 / span: a socket's groove) — that are small (from a
// twentieth of a disk of the span's radius to one), convex on the whole (their mean H ≥ 0: not a pit) and
// stand alone on the surface round them (stands_alone(): not a foot's sole or a box's face, nor one curl among
// many). The weight is 0 on such islands and a quarter of the span round them, rising to 1 at the span.
Eigen::VectorXd dome_weight(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& area, double span,
                            double ridge) {
  const int n = static_cast<int>(X.rows());
  const Eigen::VectorXd H = smooth_mean_curvature(mesh, area);
  const MatrixX3d N = vertex_normals(mesh);
  int count = 0;
  const std::vector<int> label = curvature_islands(mesh, H, span, ridge, count);
  std::vector<Island> islands(count);
  for (int v = 0; v < n; ++v)
    if (label[v] >= 0) {
      Island& s = islands[label[v]];
      s.vertices.push_back(v);
      s.area += area[v], s.curvature += area[v] * H[v];
      s.normal += area[v] * N.row(v).transpose(), s.mid += area[v] * X.row(v).transpose();
    }
  const double disk = M_PI * span * span;
  std::vector<char> dome(n, 0);
  for (const Island& s : islands)
    if (s.area >= disk / 20 && s.area < disk && s.curvature >= 0 && s.normal.norm() > 0 &&
        stands_alone(mesh, X, N, area, label, s))
      for (int v : s.vertices) dome[v] = 1;
  const Eigen::VectorXd e = edge_distance(mesh, X, dome, span);
  return e.unaryExpr([&](double x) { return ramp(x, 0.25 * span, span); });
}

}  // namespace

KeepOut keep_out(const Mesh& target, double span, double crease_angle_deg, bool thin, double pit_depth,
                 double dome_ridge) {
  const Eigen::Index n = target.n_vertices();
  KeepOut k;
  k.creases = k.thin = k.pits = k.domes = k.weight = Eigen::VectorXd::Ones(n);
  k.area = mass_diagonal(target, MassType::Barycentric);
  if (n == 0 || !(span > 0) || !std::isfinite(span)) return k;
  const MatrixX3d X = positions(target);
  if (crease_angle_deg > 0) k.creases = crease_weight(target, X, span, crease_angle_deg);
  if (thin) k.thin = thin_weight(target, X, k.area, span);
  if (pit_depth > 0) k.pits = pit_weight(target, X, k.area, span, pit_depth);
  if (dome_ridge > 0) k.domes = dome_weight(target, X, k.area, span, dome_ridge);
  k.weight = k.creases.cwiseProduct(k.thin).cwiseProduct(k.pits).cwiseProduct(k.domes);
  return k;
}

}  // namespace geotex::detail
