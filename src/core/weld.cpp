// Coincident vertices found on a sorted grid and welded, with the groups that would make the mesh worse left apart
// (weld.h).

#include "geotex/core/weld.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <tuple>

#include "geotex/core/geometry.h"
#include "geotex/core/spatial.h"
#include "union_find.h"

namespace geotex {

namespace {

using detail::UnionFind;

using CellKey = std::array<std::int64_t, 3>;

// Cell of a point on the grid of cell size \p c from \p lo (clamped: a coordinate 1e18 cells out shares a cell).
CellKey cell_of(const MatrixX3d& X, int v, const Vec3& lo, double c) {
  CellKey k;
  for (int a = 0; a < 3; ++a) k[a] = static_cast<std::int64_t>(std::clamp(std::floor((X(v, a) - lo[a]) / c), -1e18, 1e18));
  return k;
}

// Joins \p v with every vertex of the cells next to its own that lie within \p tol of it (only cells whose wall \p v
// is within \p tol of: on a grid of 1024 tol, almost never). \p order is sorted by \p keys.
void join_across_walls(const MatrixX3d& X, int v, const CellKey& k, const Vec3& lo, double c, double tol,
                       const std::vector<int>& order, const std::vector<CellKey>& keys, UnionFind& sets) {
  std::array<std::array<int, 2>, 3> side{};  // per axis: the offsets to look at (0 always, ±1 near a wall)
  for (int a = 0; a < 3; ++a) {
    const double into = X(v, a) - lo[a] - static_cast<double>(k[a]) * c;
    side[a] = {0, into <= tol ? -1 : into >= c - tol ? 1 : 0};
  }
  for (int i = 0; i < 8; ++i) {
    const CellKey n{k[0] + side[0][i & 1], k[1] + side[1][(i >> 1) & 1], k[2] + side[2][(i >> 2) & 1]};
    if (n == k) continue;
    auto lo_it = std::lower_bound(order.begin(), order.end(), n, [&](int u, const CellKey& q) { return keys[u] < q; });
    for (auto it = lo_it; it != order.end() && keys[*it] == n; ++it)
      if ((X.row(*it) - X.row(v)).norm() <= tol) sets.unite(*it, v);
  }
}

}  // namespace

std::vector<int> coincident_groups(const MatrixX3d& X, double tolerance, const std::vector<int>* subset) {
  const int n = static_cast<int>(X.rows());
  std::vector<int> order;
  if (subset) order = *subset;
  else order.resize(n), std::iota(order.begin(), order.end(), 0);
  UnionFind sets(n);
  if (order.empty()) return sets.parent;
  const double tol = std::max(tolerance, 0.0), c = tol > 0 ? 1024 * tol : 1.0;
  Vec3 lo = X.row(order[0]).transpose();
  for (int v : order) lo = lo.cwiseMin(X.row(v).transpose());
  std::vector<CellKey> keys(n);
  for (int v : order) keys[v] = cell_of(X, v, lo, c);
  std::sort(order.begin(), order.end(), [&](int u, int v) { return std::tie(keys[u], u) < std::tie(keys[v], v); });
  for (size_t s = 0, e = 0; s < order.size(); s = e) {  // one cell: its few vertices pairwise
    for (e = s + 1; e < order.size() && keys[order[e]] == keys[order[s]]; ++e)
      for (size_t t = s; t < e; ++t)
        if ((X.row(order[e]) - X.row(order[t])).norm() <= tol) sets.unite(order[e], order[t]);
  }
  if (tol > 0)
    for (int v : order) join_across_walls(X, v, keys[v], lo, c, tol, order, keys, sets);
  std::vector<int> label(n);
  for (int v = 0; v < n; ++v) label[v] = sets.find(v);
  return label;
}

namespace {

// Marks the groups of \p L at the ends of an edge with more than two faces, or two running along it the same way.
void refuse_edges(const MatrixX3i& F, const std::vector<int>& L, const std::vector<int>& size, std::vector<char>& bad) {
  std::vector<std::array<int, 3>> half;  // (lower end, upper end, 1 if it runs upwards)
  half.reserve(3 * F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = L[F(f, k)], b = L[F(f, (k + 1) % 3)];
      half.push_back({std::min(a, b), std::max(a, b), a < b ? 1 : 0});
    }
  std::sort(half.begin(), half.end());
  for (size_t s = 0, e = 0; s < half.size(); s = e) {
    for (e = s + 1; e < half.size() && half[e][0] == half[s][0] && half[e][1] == half[s][1];) ++e;
    if (e - s > 2 || (e - s == 2 && half[s][2] == half[s + 1][2]))
      for (int end : {half[s][0], half[s][1]})
        if (size[end] > 1) bad[end] = 1;
  }
}

// Splits the merged groups of \p L whose faces would not make one fan (the link, each face's two other corners, is not
// one path or cycle: the teapot's handle touching its body at a point) into one group per fan: \p next gets each
// member's fan's smallest member, \p ties a pair of input vertices (first fan's, other fan's) per further fan.
// \return the groups split.
int split_fans(const MatrixX3i& F, const std::vector<int>& L, const std::vector<int>& size, std::vector<int>& next,
               std::vector<std::array<int, 2>>& ties) {
  std::vector<std::array<int, 4>> link;  // (merged vertex, the face's other two corners, the input vertex)
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (size[L[F(f, k)]] > 1) link.push_back({L[F(f, k)], L[F(f, (k + 1) % 3)], L[F(f, (k + 2) % 3)], F(f, k)});
  std::sort(link.begin(), link.end());
  std::vector<int> ends, fan_min;
  std::vector<char> split_group(L.size(), 0), on_fan(L.size(), 0);
  int split = 0;
  for (size_t s = 0, e = 0; s < link.size(); s = e) {
    for (e = s + 1; e < link.size() && link[e][0] == link[s][0];) ++e;
    ends.clear();
    for (size_t i = s; i < e; ++i) ends.insert(ends.end(), {link[i][1], link[i][2]});
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    UnionFind sets(ends.size());
    const auto at = [&](int x) { return static_cast<int>(std::lower_bound(ends.begin(), ends.end(), x) - ends.begin()); };
    for (size_t i = s; i < e; ++i) sets.unite(at(link[i][1]), at(link[i][2]));
    bool one = true;
    for (int j = 0; j < static_cast<int>(ends.size()); ++j) one = one && sets.find(j) == 0;
    if (one) continue;
    ++split, split_group[link[s][0]] = 1;
    fan_min.assign(ends.size(), static_cast<int>(L.size()));
    for (size_t i = s; i < e; ++i) {
      int& m = fan_min[sets.find(at(link[i][1]))];
      m = std::min(m, link[i][3]);
    }
    for (size_t i = s; i < e; ++i) next[link[i][3]] = fan_min[sets.find(at(link[i][1]))], on_fan[link[i][3]] = 1;
    for (size_t j = 1; j < fan_min.size(); ++j)
      if (sets.find(static_cast<int>(j)) == static_cast<int>(j)) ties.push_back({fan_min[0], fan_min[j]});
  }
  for (size_t v = 0; v < L.size(); ++v)  // a split group's members on no face stand alone
    if (split_group[L[v]] && !on_fan[v]) next[v] = static_cast<int>(v);
  return split;
}

// The merged groups of \p L that welding would make worse (weld.h), one kind at a time so that one kind does not show
// as another (a face's two corners in one group also put three faces on one edge): groups making a face degenerate
// are left apart, else those at the ends of a bad edge, else those joining several fans are welded per fan. \p next
// gets the labels after, \p ties the fans split apart (split_fans()); \return the groups changed.
int refuse_some_groups(const MatrixX3i& F, const std::vector<int>& L, std::vector<int>& next,
                       std::vector<std::array<int, 2>>& ties) {
  std::vector<int> size(L.size(), 0);
  for (int l : L) ++size[l];
  std::vector<char> bad(L.size(), 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (L[F(f, k)] == L[F(f, (k + 1) % 3)]) bad[L[F(f, k)]] = 1;
  if (std::find(bad.begin(), bad.end(), 1) == bad.end()) refuse_edges(F, L, size, bad);
  next = L;
  int changed = 0;
  for (size_t g = 0; g < L.size(); ++g) changed += bad[g] && size[g] > 1;
  for (size_t v = 0; v < L.size(); ++v)
    if (bad[L[v]]) next[v] = static_cast<int>(v);
  return changed > 0 ? changed : split_fans(F, L, size, next, ties);
}

// Applies refuse_some_groups() round after round until no group changes (each round only splits groups, so it ends);
// \return the groups changed; \p ties the pairs of input vertices of fans split apart.
int refuse_groups(const MatrixX3i& F, std::vector<int>& L, std::vector<std::array<int, 2>>& ties) {
  int refused = 0;
  std::vector<int> next;
  for (int now; (now = refuse_some_groups(F, L, next, ties)) > 0; L.swap(next)) refused += now;
  return refused;
}

}  // namespace

MatrixX3d Weld::to_input(const MatrixX3d& W) const {
  MatrixX3d V(static_cast<Eigen::Index>(welded.size()), 3);
  for (size_t v = 0; v < welded.size(); ++v) V.row(static_cast<Eigen::Index>(v)) = W.row(welded[v]);
  return V;
}

Eigen::VectorXd Weld::to_input(const Eigen::VectorXd& w) const {
  Eigen::VectorXd v(static_cast<Eigen::Index>(welded.size()));
  for (size_t i = 0; i < welded.size(); ++i) v[static_cast<Eigen::Index>(i)] = w[welded[i]];
  return v;
}

MatrixX3d Weld::to_welded(const MatrixX3d& V) const {
  MatrixX3d W(static_cast<Eigen::Index>(first.size()), 3);
  for (size_t w = 0; w < first.size(); ++w) W.row(static_cast<Eigen::Index>(w)) = V.row(first[w]);
  return W;
}

Eigen::VectorXd Weld::max_to_welded(const Eigen::VectorXd& v) const {
  Eigen::VectorXd w = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(first.size()), -HUGE_VAL);
  for (size_t i = 0; i < welded.size(); ++i) w[welded[i]] = std::max(w[welded[i]], v[static_cast<Eigen::Index>(i)]);
  return w;
}

Weld weld_coincident(const Mesh& mesh, double relative_tolerance) {
  const MatrixX3d X = positions(mesh);
  std::vector<int> L = coincident_groups(X, relative_tolerance * mean_edge_length(mesh));
  Weld w;
  const int n = static_cast<int>(L.size());
  for (int v = 0; v < n; ++v) w.merged += L[v] != v;
  if (w.merged == 0) return w;
  const MatrixX3i F = faces(mesh);
  std::vector<std::array<int, 2>> ties;  // input vertices
  w.refused = refuse_groups(F, L, ties);
  w.merged = 0;
  w.welded.resize(n);
  for (int v = 0; v < n; ++v) {
    if (L[v] == v) w.welded[v] = static_cast<int>(w.first.size()), w.first.push_back(v);
    else w.welded[v] = w.welded[L[v]], ++w.merged;
  }
  for (const auto& [a, b] : ties)  // (a later round may have left a fan's copies apart: its first one is tied)
    if (w.welded[a] != w.welded[b]) w.ties.push_back({w.welded[a], w.welded[b]});
  std::sort(w.ties.begin(), w.ties.end());
  w.ties.erase(std::unique(w.ties.begin(), w.ties.end()), w.ties.end());
  if (w.identity()) return Weld{{}, {}, {}, 0, w.refused, {}};
  MatrixX3i G(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) G(f, k) = w.welded[F(f, k)];
  BuildReport built;
  w.mesh = make_mesh(w.to_welded(X), G, &built);
  // The checks above leave nothing for make_mesh() to drop; should it drop a face anyway (two faces on the same
  // three vertices, the other way round), nothing is welded rather than the input's faces changed.
  if (built.dropped() > 0 || w.mesh.n_faces() != mesh.n_faces()) return Weld{{}, {}, {}, 0, w.refused + 1, {}};
  return w;
}

namespace {

// Mean length of the edges at each vertex of \p mesh (0 for an isolated one).
Eigen::VectorXd local_edge_lengths(const Mesh& mesh, const MatrixX3d& X) {
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(X.rows()), count = Eigen::VectorXd::Zero(X.rows());
  const MatrixX2i E = edges(mesh);
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const double l = (X.row(E(e, 0)) - X.row(E(e, 1))).norm();
    for (int k = 0; k < 2; ++k) sum[E(e, k)] += l, count[E(e, k)] += 1;
  }
  return sum.cwiseQuotient(count.cwiseMax(1.0));
}

// The contact of the rim vertex \p v: its closest point on the nearest face of another part (\p parts, connected by
// edges) within \p tol, where its own part leaves that face on its front (the direction from v to the mean of its
// neighbours, \p inward, at least kContactLeave of a right angle off the face's plane, on the side its normal points
// to): a part resting on the face, not one running along it or through it. \return a tie with vertex −1 when none.
SurfaceTie rim_contact(const MatrixX3d& X, const MatrixX3i& F, const TriangleTree& tree, UnionFind& parts, int v,
                       const Vec3& inward, double tol) {
  const Vec3 p = X.row(v).transpose();
  const int own = parts.find(v);
  double best = tol;
  SurfaceTie tie;
  tree.visit_within(p, tol, [&](int f) {
    if (parts.find(F(f, 0)) == own) return;
    const Vec3 a = X.row(F(f, 0)).transpose(), b = X.row(F(f, 1)).transpose(), c = X.row(F(f, 2)).transpose();
    const Vec3 n = (b - a).cross(c - a);
    if (inward.dot(n) < kContactLeave * inward.norm() * n.norm()) return;
    Vec3 bary;
    const double d = (closest_point_on_triangle(p, a, b, c, &bary) - p).norm();
    if (d < best || (d == best && tie.vertex < 0)) best = d, tie = SurfaceTie{v, {F(f, 0), F(f, 1), F(f, 2)}, bary};
  });
  return tie;
}

}  // namespace

std::vector<SurfaceTie> rim_contacts(const Mesh& mesh, double relative_tolerance) {
  const std::vector<std::vector<int>> loops = boundary_loops(mesh);  // (isolated vertices are on none)
  if (loops.empty()) return {};
  const MatrixX3d X = positions(mesh);
  const MatrixX3i F = faces(mesh);
  UnionFind parts(X.rows());  // connected by edges: parts touching at a point welded per fan stay apart
  for (Eigen::Index f = 0; f < F.rows(); ++f) parts.unite(F(f, 0), F(f, 1)), parts.unite(F(f, 0), F(f, 2));
  const Eigen::VectorXd local = local_edge_lengths(mesh, X);
  const double unit = mean_edge_length(mesh);
  const TriangleTree tree(X, F);
  std::vector<SurfaceTie> contact(X.rows());
  enum : signed char { kUnseen, kApart, kOnVertex, kOnFace };
  std::vector<signed char> state(X.rows(), kUnseen);
  std::vector<SurfaceTie> ties;
  for (const std::vector<int>& loop : loops) {
    size_t touching = 0;
    for (int v : loop) {
      if (state[v] != kUnseen) {
        touching += state[v] != kApart;
        continue;
      }
      Vec3 inward = Vec3::Zero();
      int k = 0;
      for (auto u : mesh.vv_range(mesh.vertex_handle(v))) inward += X.row(u.idx()).transpose(), ++k;
      inward = inward / std::max(k, 1) - X.row(v).transpose();
      const SurfaceTie t = rim_contact(X, F, tree, parts, v, inward, std::max(relative_tolerance, 0.0) * local[v]);
      // A rim vertex on another part's vertex is the weld's: a point contact (tied there) or a group it left apart.
      bool on_vertex = false;
      for (int c = 0; c < 3 && t.vertex >= 0; ++c)
        on_vertex = on_vertex || (X.row(t.corners[c]) - X.row(v)).norm() <= kCoincidentTolerance * unit;
      state[v] = t.vertex < 0 ? kApart : on_vertex ? kOnVertex : kOnFace;
      if (state[v] == kOnFace) contact[v] = t;
      touching += state[v] != kApart;
    }
    // A rim rests on the other part when most of its loop does (a few vertices near a face are a pass, not a seat).
    if (2 * touching > loop.size())
      for (int v : loop)
        if (state[v] == kOnFace) ties.push_back(contact[v]);
  }
  std::sort(ties.begin(), ties.end(), [](const SurfaceTie& a, const SurfaceTie& b) { return a.vertex < b.vertex; });
  ties.erase(std::unique(ties.begin(), ties.end(), [](const SurfaceTie& a, const SurfaceTie& b) {
    return a.vertex == b.vertex;
  }), ties.end());
  return ties;
}

void hold_ties(MatrixX3d& Y, const MatrixX3d& X, const std::vector<SurfaceTie>& ties) {
  // Sweeps until nothing moves: a tie's corner may be another tie's vertex (the copies of a point contact on the
  // rim of a part resting on the other: the teapot's handle's lower end has one), which the later tie moves again.
  for (int sweep = 0; sweep < 16; ++sweep) {
    double moved = 0;
    for (const SurfaceTie& t : ties) {
      Vec3 y = X.row(t.vertex).transpose();
      for (int k = 0; k < 3; ++k) y += t.weights[k] * (Y.row(t.corners[k]) - X.row(t.corners[k])).transpose();
      moved = std::max(moved, (y - Y.row(t.vertex).transpose()).norm());
      Y.row(t.vertex) = y.transpose();
    }
    if (moved == 0) break;
  }
}

}  // namespace geotex
