// Self-intersections a resize adds, and their repair by blending towards a safe result (resize/untangle.h).

#include "geotex/resize/untangle.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "geotex/core/geometry.h"
#include "geotex/core/self_intersections.h"

namespace geotex {

std::string UntangleReport::describe() const {
  if (excess_before() == 0) return fmt::format("no faces intersected beyond the input's own ({})", base);
  if (blended == 0)
    return fmt::format("{} faces intersected beyond the input's own ({}); not repaired", excess_before(), base);
  return fmt::format("{} faces intersected beyond the input's own ({}); blended back over {} vertices in {} rounds, "
                     "{} left",
                     excess_before(), base, blended, rounds, excess_after());
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
// seeds are sorted by x, so that each vertex looks only at those within 3r of it along x.
Eigen::VectorXd bump(const MatrixX3d& X, const std::vector<char>& seed, double r) {
  std::vector<int> s;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (seed[i]) s.push_back(static_cast<int>(i));
  std::sort(s.begin(), s.end(), [&X](int a, int b) { return X(a, 0) < X(b, 0); });
  std::vector<double> sx(s.size());
  for (size_t k = 0; k < s.size(); ++k) sx[k] = X(s[k], 0);
  const double reach = kBumpReach * r;
  Eigen::VectorXd t = Eigen::VectorXd::Zero(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    double d2 = reach * reach;
    auto k = std::lower_bound(sx.begin(), sx.end(), X(i, 0) - reach) - sx.begin();
    for (; k < static_cast<long>(s.size()) && sx[k] <= X(i, 0) + reach; ++k)
      d2 = std::min(d2, (X.row(s[k]) - X.row(i)).squaredNorm());
    const double u = std::clamp(1.0 - (std::sqrt(d2) - r) / (reach - r), 0.0, 1.0);
    t[i] = u * u * (3 - 2 * u);
  }
  return t;
}

}  // namespace

void fit_box_onto(MatrixX3d& Y, const MatrixX3d& B) {
  const Vec3 blo = B.colwise().minCoeff(), bhi = B.colwise().maxCoeff();
  const Vec3 lo = Y.colwise().minCoeff(), hi = Y.colwise().maxCoeff();
  for (int a = 0; a < 3; ++a)
    if (hi[a] > lo[a] && bhi[a] > blo[a])
      Y.col(a) = ((Y.col(a).array() - lo[a]) * ((bhi[a] - blo[a]) / (hi[a] - lo[a])) + blo[a]).matrix();
}

MatrixX3d untangle_resize(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& Y, const MatrixX3d& safe, bool repair,
                          UntangleReport& counts, const ProgressFn& progress) {
  counts = {};
  const MatrixX3i F = faces(mesh);
  std::vector<char> hit = self_intersecting_faces(Y, F);
  counts.before = counts.after = count(hit);
  if (counts.before == 0) return Y;  // nothing crosses: the input's own count is not needed
  const std::vector<char> own = self_intersecting_faces(X, F);
  counts.base = count(own);
  std::vector<char> seed(X.rows(), 0);
  const std::vector<char> none(F.rows(), 0);
  if (!repair || counts.before <= counts.base || !mark_new_crossings(F, hit, own, none, seed)) return Y;
  // Faces the safe result crosses too are left: blending towards it cannot remove them.
  const std::vector<char> safe_hit = self_intersecting_faces(safe, F);
  std::fill(seed.begin(), seed.end(), 0);
  if (!mark_new_crossings(F, hit, own, safe_hit, seed)) return Y;
  const double diagonal = (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm();
  double r = kStartEdges * mean_edge_length(mesh);  // the mesh's positions are X
  MatrixX3d out = Y;
  for (int round = 0; round < kMaxRounds * 3 && r < diagonal; ++round) {
    report(progress, 0.97, fmt::format("blend back {} vertices at crossings", count(seed)));
    // At each radius the bump is raised from a quarter to a half to 1; then widened.
    const Eigen::VectorXd t = kRaise[round % 3] * bump(X, seed, r);
    if (round % 3 == 2) r *= 2;
    out = Y + t.asDiagonal() * (safe - Y);
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
