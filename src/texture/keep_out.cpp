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

// Distance along edges from the vertices where `seed` is set, up to `limit` (beyond: limit).
Eigen::VectorXd edge_distance(const Mesh& mesh, const MatrixX3d& X, const std::vector<char>& seed, double limit) {
  const int n = static_cast<int>(mesh.n_vertices());
  Eigen::VectorXd d = Eigen::VectorXd::Constant(n, limit);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  for (int v = 0; v < n; ++v)
    if (seed[v]) d[v] = 0, q.emplace(0.0, v);
  while (!q.empty()) {
    const auto [dv, v] = q.top();
    q.pop();
    if (dv > d[v]) continue;
    for (auto w : mesh.vv_range(mesh.vertex_handle(v))) {
      const double dw = dv + (X.row(v) - X.row(w.idx())).norm();
      if (dw < d[w.idx()]) d[w.idx()] = dw, q.emplace(dw, w.idx());
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

}  // namespace

KeepOut keep_out(const Mesh& target, double span, double crease_angle_deg, bool thin, double pit_depth) {
  const Eigen::Index n = target.n_vertices();
  KeepOut k;
  k.creases = k.thin = k.pits = k.weight = Eigen::VectorXd::Ones(n);
  k.area = mass_diagonal(target, MassType::Barycentric);
  if (n == 0 || !(span > 0) || !std::isfinite(span)) return k;
  const MatrixX3d X = positions(target);
  if (crease_angle_deg > 0) k.creases = crease_weight(target, X, span, crease_angle_deg);
  if (thin) k.thin = thin_weight(target, X, k.area, span);
  if (pit_depth > 0) k.pits = pit_weight(target, X, k.area, span, pit_depth);
  k.weight = k.creases.cwiseProduct(k.thin).cwiseProduct(k.pits);
  return k;
}

}  // namespace geotex::detail
