// Self-intersections a resize adds, and their repair by blending towards a safe result (resize/untangle.h).

#include "geotex/resize/untangle.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <queue>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "geotex/core/geometry.h"
#include "geotex/core/self_intersections.h"
#include "geotex/core/spatial.h"

namespace geotex {

std::string UntangleReport::describe() const {
  if (excess_before() == 0) return fmt::format("no faces intersected beyond the input's own ({})", base);
  if (blended == 0 && shifted == 0)
    return fmt::format("{} faces intersected beyond the input's own ({}); not repaired", excess_before(), base);
  const std::string shift =
      shifted > 0 ? fmt::format("moved apart over {} vertices in {} rounds", shifted, shift_rounds) : "";
  const std::string blend =
      blended > 0 ? fmt::format("blended back over {} vertices in {} rounds", blended, rounds) : "";
  return fmt::format("{} faces intersected beyond the input's own ({}); {}{}{}, {} left", excess_before(), base, shift,
                     shifted > 0 && blended > 0 ? ", then " : "", blend, excess_after());
}

namespace {

// The first bump's plateau radius in mean edge lengths, and the radii tried before t = 1 everywhere. (A bump that
// was 1 only at the seeds, from 4 edges, left crossings next to them at every radius on the teapot: bench/resize.md,
// issue 25 thirteenth session.)
constexpr double kStartEdges = 1.0;
constexpr double kBumpReach = 3.0;  // the bump reaches 0 at kBumpReach times its plateau's radius
constexpr int kMaxRounds = 12;
constexpr double kRaise[3] = {0.25, 0.5, 1.0};  // the bump's heights tried at each radius

size_t count(const std::vector<char>& flags) { return static_cast<size_t>(std::count(flags.begin(), flags.end(), 1)); }

// Marks the vertices of the faces \p hit crosses that neither \p own nor \p safe_hit does; true if there is one.
bool mark_new_crossings(const MatrixX3i& F, const std::vector<char>& hit, const std::vector<char>& own,
                        const std::vector<char>& safe_hit, std::vector<char>& seed) {
  bool any = false;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (hit[f] && !own[f] && !safe_hit[f]) {
      any = true;
      for (int k = 0; k < 3; ++k) seed[F(f, k)] = 1;
    }
  return any;
}

// Marks the vertices of the faces of \p Y turned over against \p safe (normals at more than 90°): a blend of two
// results that turn none can turn one (beetle ×2 z: 2 faces). True if there is one.
bool mark_turned(const MatrixX3i& F, const MatrixX3d& Y, const MatrixX3d& safe, std::vector<char>& seed) {
  bool any = false;
  const auto normal = [&F](const MatrixX3d& P, Eigen::Index f) -> Vec3 {
    const Vec3 a = P.row(F(f, 0)), b = P.row(F(f, 1)), c = P.row(F(f, 2));
    return (b - a).cross(c - a);
  };
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (normal(Y, f).dot(normal(safe, f)) < 0) {
      any = true;
      for (int k = 0; k < 3; ++k) seed[F(f, k)] = 1;
    }
  return any;
}

// t_i = 1 within r of a seed, then s(1 − (d_i − r) / (2r)) (smoothstep s, d_i the distance from X_i to the nearest
// seed) down to 0 at 3r: parts that touch in the input move together near the crossing, not merely its faces. The
// seeds are put in a uniform grid of cells 3r wide (a hash of their cell), so that each vertex looks only at the
// seeds of the 27 cells around its own (the sweep along x before looked at every seed sharing its x, e.g. a rim's).
Eigen::VectorXd bump(const MatrixX3d& X, const std::vector<char>& seed, double r) {
  const double reach = kBumpReach * r;
  const auto cell = [reach](double v) { return static_cast<int64_t>(std::floor(v / reach)); };
  const auto key = [](int64_t a, int64_t b, int64_t c) {
    return (static_cast<uint64_t>(a) * 73856093u) ^ (static_cast<uint64_t>(b) * 19349663u) ^
           (static_cast<uint64_t>(c) * 83492791u);
  };
  std::unordered_map<uint64_t, std::vector<int>> grid;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (seed[i]) grid[key(cell(X(i, 0)), cell(X(i, 1)), cell(X(i, 2)))].push_back(static_cast<int>(i));
  Eigen::VectorXd t = Eigen::VectorXd::Zero(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    double d2 = reach * reach;
    const int64_t cx = cell(X(i, 0)), cy = cell(X(i, 1)), cz = cell(X(i, 2));
    for (int64_t a = cx - 1; a <= cx + 1; ++a)
      for (int64_t b = cy - 1; b <= cy + 1; ++b)
        for (int64_t c = cz - 1; c <= cz + 1; ++c) {
          const auto it = grid.find(key(a, b, c));
          if (it == grid.end()) continue;  // (a hash collision only adds seeds to look at)
          for (int s : it->second) d2 = std::min(d2, (X.row(s) - X.row(i)).squaredNorm());
        }
    const double u = std::clamp(1.0 - (std::sqrt(d2) - r) / (reach - r), 0.0, 1.0);
    t[i] = u * u * (3 - 2 * u);
  }
  return t;
}


// ---- Moving the colliding parts apart (issue 25, fourteenth session) ----

// Push rounds tried (the one crossing the fewest faces is kept), the push's margin beyond the crossed face's plane
// and the spread's plateau (both in mean edge lengths).
constexpr int kShiftRounds = 8;
constexpr double kShiftMargin = 0.1;
constexpr double kShiftEdges = 4.0;

// The vertices' neighbours over the mesh's edges (compressed rows).
struct VertexGraph {
  std::vector<int> start, next;
};

VertexGraph vertex_graph(const MatrixX2i& E, Eigen::Index n) {
  VertexGraph g;
  g.start.assign(n + 1, 0);
  for (Eigen::Index e = 0; e < E.rows(); ++e) ++g.start[E(e, 0) + 1], ++g.start[E(e, 1) + 1];
  for (Eigen::Index i = 0; i < n; ++i) g.start[i + 1] += g.start[i];
  g.next.resize(g.start[n]);
  std::vector<int> at(g.start.begin(), g.start.end() - 1);
  for (Eigen::Index e = 0; e < E.rows(); ++e) g.next[at[E(e, 0)]++] = E(e, 1), g.next[at[E(e, 1)]++] = E(e, 0);
  return g;
}

// The pairs (edge of E, face of F) where the edge's segment crosses the face's interior in \p P
// (segment_crosses_triangle(), the count's test), over the faces flagged in \p target only.
std::vector<std::pair<int, int>> crossing_pairs(const MatrixX3d& P, const MatrixX3i& F, const MatrixX2i& E,
                                                const std::vector<char>& target) {
  std::vector<int> fl;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (target[f]) fl.push_back(static_cast<int>(f));
  std::vector<std::pair<int, int>> pairs;
  if (fl.empty()) return pairs;
  MatrixX3i Fs(static_cast<Eigen::Index>(fl.size()), 3);
  for (size_t k = 0; k < fl.size(); ++k) Fs.row(static_cast<Eigen::Index>(k)) = F.row(fl[k]);
  const TriangleTree tree(P, Fs);
  for (Eigen::Index e = 0; e < E.rows(); ++e) {
    const Vec3 p0 = P.row(E(e, 0)), d = P.row(E(e, 1)) - P.row(E(e, 0));
    tree.visit_within(p0 + 0.5 * d, 0.5 * d.norm(), [&](int k) {
      const Eigen::RowVector3i t = Fs.row(k);
      if ((t.array() == E(e, 0)).any() || (t.array() == E(e, 1)).any()) return;
      const Vec3 A = P.row(t[0]);
      if (segment_crosses_triangle(p0, d, A, Vec3(P.row(t[1])) - A, Vec3(P.row(t[2])) - A))
        pairs.emplace_back(static_cast<int>(e), fl[k]);
    });
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

// Per vertex, the mean push that takes each crossing edge off the face it crosses: the edge's end on the wrong side
// of the face's plane (the side its midpoint lies on in \p safe, where they do not cross) goes half the depth plus
// \p margin along the face's normal, the face's vertices half the other way. \return #V by 3 (0 where none).
MatrixX3d crossing_pushes(const MatrixX3d& P, const MatrixX3d& safe, const MatrixX3i& F, const MatrixX2i& E,
                          const std::vector<std::pair<int, int>>& pairs, double margin) {
  MatrixX3d push = MatrixX3d::Zero(P.rows(), 3);
  Eigen::VectorXd n_push = Eigen::VectorXd::Zero(P.rows());
  const auto unit_normal = [&F](const MatrixX3d& Q, int f) -> Vec3 {
    const Vec3 a = Q.row(F(f, 0)), b = Q.row(F(f, 1)), c = Q.row(F(f, 2));
    return (b - a).cross(c - a).normalized();
  };
  for (const auto& [e, f] : pairs) {
    const Vec3 cs = (safe.row(F(f, 0)) + safe.row(F(f, 1)) + safe.row(F(f, 2))) / 3;
    const Vec3 ms = 0.5 * (safe.row(E(e, 0)) + safe.row(E(e, 1)));
    // The side in safe, carried over to P by the face's normal there (turned or not).
    const Vec3 ns = unit_normal(safe, f), np = unit_normal(P, f);
    const Vec3 m = ((ms - cs).dot(ns) < 0) != (np.dot(ns) < 0) ? Vec3(-np) : np;
    const Vec3 c = (P.row(F(f, 0)) + P.row(F(f, 1)) + P.row(F(f, 2))) / 3;
    for (int k = 0; k < 2; ++k) {
      const int v = E(e, k);
      const double depth = margin - (Vec3(P.row(v)) - c).dot(m);
      if (depth <= 0) continue;
      push.row(v) += 0.5 * depth * m;
      n_push[v] += 1;
      for (int j = 0; j < 3; ++j) push.row(F(f, j)) -= 0.5 * depth * m, n_push[F(f, j)] += 1;
    }
  }
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (n_push[i] > 0) push.row(i) /= n_push[i];
  return push;
}

// Graph distances (Dijkstra over the edges, lengths in \p X) from the pushed vertices up to \p reach, and each
// reached vertex's nearest pushed vertex. \return the reached vertices, nearest first.
std::vector<int> nearest_pushed(const VertexGraph& g, const MatrixX3d& X, const MatrixX3d& push, double reach,
                                std::vector<double>& dist, std::vector<int>& nearest) {
  const Eigen::Index n = X.rows();
  dist.assign(n, reach);
  nearest.assign(n, -1);
  std::vector<int> reached;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!push.row(i).isZero(0)) dist[i] = 0, nearest[i] = static_cast<int>(i), queue.emplace(0.0, static_cast<int>(i));
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;
    reached.push_back(i);
    for (int k = g.start[i]; k < g.start[i + 1]; ++k) {
      const int j = g.next[k];
      const double dj = d + (X.row(i) - X.row(j)).norm();
      if (dj < dist[j]) dist[j] = dj, nearest[j] = nearest[i], queue.emplace(dj, j);
    }
  }
  return reached;
}

// The pushes spread over the surface around them: each vertex within kBumpReach r along the edges takes its nearest
// pushed vertex's push, smoothed by 2 (r / edge)² lazy averaging steps among those vertices, times the bump's
// smoothstep of that distance (1 within r, 0 at kBumpReach r). A part near a crossing then moves as one piece, and the
// part it ran into, nearest to its own pushes, the other way.
MatrixX3d spread_pushes(const VertexGraph& g, const MatrixX3d& X, const MatrixX3d& push, double r, double edge) {
  const double reach = kBumpReach * r;
  std::vector<double> dist;
  std::vector<int> nearest;
  const std::vector<int> reached = nearest_pushed(g, X, push, reach, dist, nearest);
  MatrixX3d field = MatrixX3d::Zero(X.rows(), 3);
  for (int i : reached) field.row(i) = push.row(nearest[i]);
  const int steps = static_cast<int>(std::ceil(2 * (r / edge) * (r / edge)));
  MatrixX3d next = field;
  for (int s = 0; s < steps; ++s) {
    for (int i : reached) {
      Vec3 sum = Vec3::Zero();
      for (int k = g.start[i]; k < g.start[i + 1]; ++k) sum += field.row(g.next[k]);
      const int deg = g.start[i + 1] - g.start[i];
      next.row(i) = deg > 0 ? Vec3(0.5 * Vec3(field.row(i)) + 0.5 * sum / deg) : Vec3(field.row(i));
    }
    field.swap(next);
  }
  for (int i : reached) {
    const double u = std::clamp(1.0 - (dist[i] - r) / (reach - r), 0.0, 1.0);
    field.row(i) *= u * u * (3 - 2 * u);
  }
  return field;
}

}  // namespace

void fit_box_onto(MatrixX3d& Y, const MatrixX3d& B) {
  const Vec3 blo = B.colwise().minCoeff(), bhi = B.colwise().maxCoeff();
  const Vec3 lo = Y.colwise().minCoeff(), hi = Y.colwise().maxCoeff();
  for (int a = 0; a < 3; ++a)
    if (hi[a] > lo[a] && bhi[a] > blo[a])
      Y.col(a) = ((Y.col(a).array() - lo[a]) * ((bhi[a] - blo[a]) / (hi[a] - lo[a])) + blo[a]).matrix();
}

namespace {

// The repair's data: the input's faces and edges, the faces the input and the safe result cross.
struct Crossings {
  MatrixX3i F;
  std::vector<char> own, safe_hit;
  const std::vector<SurfaceTie>* ties = nullptr;  // vertices moved with their points (hold_ties())
};

// Moves the parts that run into each other apart (kShiftRounds rounds of crossing_pushes() spread by spread_pushes(),
// the box refitted after each): each part keeps its similarity but for the spread's rim. \return the result,
// \p clear when nothing crosses beyond the input's own (or only faces \p safe crosses too) and no face is turned
// against safe; else the last round's, for the blend to finish.
MatrixX3d shift_apart(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& Y, const MatrixX3d& safe,
                      const Crossings& c, UntangleReport& counts, const ProgressFn& progress, bool& clear) {
  const MatrixX2i E = edges(mesh);
  const VertexGraph g = vertex_graph(E, X.rows());
  const double edge = mean_edge_length(mesh);
  MatrixX3d out = Y, best = Y;
  size_t fewest = counts.before;
  std::vector<char> seed(X.rows(), 0), moved(X.rows(), 0), moved_best(X.rows(), 0);
  clear = false;
  for (int round = 0; round <= kShiftRounds; ++round) {
    std::vector<char> hit = self_intersecting_faces(out, c.F);
    counts.after = count(hit);
    std::fill(seed.begin(), seed.end(), 0);
    const bool crossing = counts.after > counts.base && mark_new_crossings(c.F, hit, c.own, c.safe_hit, seed);
    if (!crossing && !mark_turned(c.F, out, safe, seed)) {
      clear = true;
      best = out, moved_best = moved;
      break;
    }
    if (counts.after < fewest && !mark_turned(c.F, out, safe, seed))
      fewest = counts.after, best = out, moved_best = moved;
    if (round == kShiftRounds) break;
    for (Eigen::Index f = 0; f < c.F.rows(); ++f) hit[f] = hit[f] && !c.own[f] && !c.safe_hit[f];
    const MatrixX3d push = crossing_pushes(out, safe, c.F, E, crossing_pairs(out, c.F, E, hit), kShiftMargin * edge);
    const auto pushed = (push.array() != 0).rowwise().any().count();
    report(progress, 0.96, fmt::format("move apart {} vertices at crossings", pushed));
    const MatrixX3d field = spread_pushes(g, X, push, kShiftEdges * edge, edge);
    for (Eigen::Index i = 0; i < X.rows(); ++i) moved[i] = moved[i] || !field.row(i).isZero(0);
    out += field;
    if (c.ties) hold_ties(out, X, *c.ties);
    fit_box_onto(out, safe);
    counts.shift_rounds = round + 1;
  }
  // The round that crossed the fewest faces (turning none) is kept: the pushes need not converge.
  counts.shifted = count(moved_best);
  return best;
}

}  // namespace

MatrixX3d untangle_resize(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& Y0, const MatrixX3d& safe,
                          bool repair, UntangleReport& counts, const ProgressFn& progress, UntangleRepair how,
                          const std::vector<SurfaceTie>* ties) {
  counts = {};
  Crossings c{faces(mesh), {}, {}, ties};
  const MatrixX3i& F = c.F;
  std::vector<char> hit = self_intersecting_faces(Y0, F);
  counts.before = counts.after = count(hit);
  if (counts.before == 0) return Y0;  // nothing crosses: the input's own count is not needed
  c.own = self_intersecting_faces(X, F);
  const std::vector<char>& own = c.own;
  counts.base = count(own);
  std::vector<char> seed(X.rows(), 0);
  const std::vector<char> none(F.rows(), 0);
  if (!repair || counts.before <= counts.base || !mark_new_crossings(F, hit, own, none, seed)) return Y0;
  // Faces the safe result crosses too are left: blending towards it cannot remove them.
  c.safe_hit = self_intersecting_faces(safe, F);
  const std::vector<char>& safe_hit = c.safe_hit;
  std::fill(seed.begin(), seed.end(), 0);
  if (!mark_new_crossings(F, hit, own, safe_hit, seed)) return Y0;
  MatrixX3d Y = Y0;
  if (how == UntangleRepair::ShiftThenBlend) {
    bool clear = false;
    Y = shift_apart(mesh, X, Y0, safe, c, counts, progress, clear);
    if (clear) return Y;
    hit = self_intersecting_faces(Y, F);
    std::fill(seed.begin(), seed.end(), 0);
    const bool crossing = mark_new_crossings(F, hit, own, safe_hit, seed);
    if (!mark_turned(F, Y, safe, seed) && !crossing) return Y;
  }
  const double diagonal = (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm();
  double r = kStartEdges * mean_edge_length(mesh);  // the mesh's positions are X
  MatrixX3d out = Y;
  for (int round = 0; round < kMaxRounds * 3 && r < diagonal; ++round) {
    report(progress, 0.97, fmt::format("blend back {} vertices at crossings", count(seed)));
    // At each radius the bump is raised from a quarter to a half to 1; then widened.
    const Eigen::VectorXd t = kRaise[round % 3] * bump(X, seed, r);
    if (round % 3 == 2) r *= 2;
    out = Y + t.asDiagonal() * (safe - Y);
    if (ties) hold_ties(out, X, *ties);
    fit_box_onto(out, safe);
    counts.rounds = round + 1;
    counts.blended = static_cast<size_t>((t.array() > 0).count());
    hit = self_intersecting_faces(out, F);
    counts.after = count(hit);
    // Done when no more faces cross than the input's own (the ruler's excess is 0), or the faces crossed beyond
    // them are all crossed in the safe result too. (Face by face, the teapot's lid, which touches its body, trades
    // a few crossed faces for others at any blend: the count is the measure.)
    // Faces the blend turned over join the seeds too.
    const bool crossing = counts.after > counts.base && mark_new_crossings(F, hit, own, safe_hit, seed);
    if (!mark_turned(F, out, safe, seed) && !crossing) return out;
  }
  counts.rounds += 1;
  counts.blended = static_cast<size_t>(X.rows());
  counts.after = count(safe_hit);
  return safe;
}

}  // namespace geotex
