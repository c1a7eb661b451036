#include "geotex/resize/protrusion_placement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include <Eigen/SVD>
#include <Eigen/SparseCholesky>

#include "geotex/core/error.h"
#include "geotex/toolkit/editing.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/simplify.h"

namespace geotex {

namespace {

constexpr double kCore = 0.9;    // a protrusion's core: importance at least this
constexpr double kGrow = 2.0;    // a core is grown to this many times its foot's radius (its flared foot)
constexpr int kMaxGrowRings = 100;
constexpr double kReach = 1.5;   // reach from the foot ring's centroid, in ring radii, that makes a protrusion
constexpr double kExtent = 0.5;  // at most this share of the model's largest extent along any axis

// Is the vertex set \p set (marked \p mark in \p tag) one connected piece of the mesh's graph?
bool connected(const Mesh& mesh, const std::vector<int>& set, const std::vector<int>& tag, int mark) {
  if (set.empty()) return false;
  std::vector<char> seen(tag.size(), 0);
  std::vector<int> stack{set.front()};
  seen[set.front()] = 1;
  size_t reached = 0;
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    ++reached;
    for (auto u : mesh.vv_range(mesh.vertex_handle(v)))
      if (tag[u.idx()] == mark && !seen[u.idx()]) seen[u.idx()] = 1, stack.push_back(u.idx());
  }
  return reached == set.size();
}

// The foot ring's rows of X and Y, centred, and their centroids.
struct Ring {
  Eigen::MatrixX3d P, Q;
  Eigen::RowVector3d pc, qc;
};

Ring ring_of(const MatrixX3d& X, const MatrixX3d& Y, const std::vector<int>& foot) {
  const auto k = static_cast<Eigen::Index>(foot.size());
  Ring r;
  r.P.resize(k, 3), r.Q.resize(k, 3);
  for (Eigen::Index i = 0; i < k; ++i) r.P.row(i) = X.row(foot[i]), r.Q.row(i) = Y.row(foot[i]);
  r.pc = r.P.colwise().mean(), r.qc = r.Q.colwise().mean();
  r.P.rowwise() -= r.pc, r.Q.rowwise() -= r.qc;
  return r;
}

// The similarity x ↦ σ R x + t (σ the protrusion's scale) that puts the foot ring's original positions
// onto \p Y's: R by Umeyama's fit, t moving the centroid onto the centroid.
Similarity foot_similarity(const MatrixX3d& X, const MatrixX3d& Y, const RigidProtrusion& p) {
  const Ring r = ring_of(X, Y, p.foot);
  Similarity s = fit_similarity(r.P, r.Q, false);
  s.s = p.scale;
  s.t = r.qc.transpose() - s.s * (s.R * r.pc.transpose());
  return s;
}

// The centre of the vertices \p ring (rows of X) and their mean distance from it.
std::pair<Vec3, double> ring_circle(const MatrixX3d& X, const std::vector<int>& ring) {
  Vec3 c = Vec3::Zero();
  for (int v : ring) c += X.row(v).transpose();
  c /= std::max<double>(1, static_cast<double>(ring.size()));
  double radius = 0;
  for (int v : ring) radius += (X.row(v).transpose() - c).norm();
  return {c, radius / std::max<double>(1, static_cast<double>(ring.size()))};
}

// D (#V by 3) made harmonic (umbrella weights, Eq. 5.8) on the vertices with \p unknown[i] ≠ 0, its other rows
// fixed: extend_harmonic() from the others.
void harmonic_fill(const Mesh& mesh, const std::vector<int>& unknown, MatrixX3d& D) {
  std::vector<int> known;
  for (Eigen::Index i = 0; i < D.rows(); ++i)
    if (!unknown[i]) known.push_back(static_cast<int>(i));
  if (known.size() == static_cast<size_t>(D.rows())) return;
  D = extend_harmonic(mesh, known, D(known, Eigen::all));
}

// D (#V by 3) made biharmonic on the vertices with \p unknown[i] ≠ 0, its other rows fixed: the unknowns
// minimise Σ_v |(L D)_v|² / deg(v), L the umbrella Laplacian (Eq. 5.8 times the valence), so the band meets the
// placed protrusion and the body with matching slope, not with the kink of a harmonic fill (whose shading showed
// as streaks around the feet under a large stretch; bench/resize.md, issue 25, twelfth session).
void biharmonic_fill(const Mesh& mesh, const std::vector<int>& unknown, MatrixX3d& D) {
  const int n = static_cast<int>(D.rows());
  std::vector<int> index(n, -1);
  int u = 0;
  for (int v = 0; v < n; ++v)
    if (unknown[v]) index[v] = u++;
  if (u == 0) return;
  // Σ_v |(L D)_v|² / deg(v) with L = −deg · (the umbrella operator U of Eq. 5.8) is Σ_v deg(v) |(U D)_v|².
  Eigen::VectorXd degree(n);
  for (int v = 0; v < n; ++v) degree[v] = mesh.valence(mesh.vertex_handle(v));
  const SparseMatrix U = umbrella_laplacian(mesh);
  const SparseMatrix Q = U.transpose() * degree.asDiagonal() * U;
  std::vector<Eigen::Triplet<double>> a;
  MatrixX3d b = MatrixX3d::Zero(u, 3);
  for (int k = 0; k < Q.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(Q, k); it; ++it) {
      const int r = static_cast<int>(it.row()), c = static_cast<int>(it.col());
      if (index[r] < 0) continue;
      if (index[c] >= 0) a.emplace_back(index[r], index[c], it.value());
      else b.row(index[r]) -= it.value() * D.row(c);
    }
  Eigen::SparseMatrix<double> A(u, u);
  A.setFromTriplets(a.begin(), a.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) {  // a band piece touching nothing fixed: the harmonic fill's error
    harmonic_fill(mesh, unknown, D);
    return;
  }
  const MatrixX3d x = solver.solve(b);
  for (int v = 0; v < n; ++v)
    if (index[v] >= 0) D.row(v) = x.row(index[v]);
}

// Does region p stand out of its foot ring like a protrusion: at most kExtent of the model's largest
// extent \p largest along every axis, and reaching kReach ring radii from the ring's centroid?
bool protrusion_shape(const MatrixX3d& X, const RigidProtrusion& p, double largest) {
  if (p.vertices.empty() || p.foot.size() < 3) return false;
  Vec3 rlo = X.row(p.vertices[0]).transpose(), rhi = rlo;
  for (int v : p.vertices) rlo = rlo.cwiseMin(X.row(v).transpose()), rhi = rhi.cwiseMax(X.row(v).transpose());
  if ((rhi - rlo).maxCoeff() > kExtent * largest) return false;
  const auto [c, radius] = ring_circle(X, p.foot);
  double reach = 0;
  for (int v : p.vertices) reach = std::max(reach, (X.row(v).transpose() - c).norm());
  return reach >= kReach * radius;
}

// The band around \p p that place_protrusions() blends: the vertices not yet reached (\p slot −1) reached from p's
// vertices through vertices within \p blend foot radii of its foot ring's centre, marked 0 in \p slot and appended
// to \p band.
void grow_band(const Mesh& mesh, const MatrixX3d& X, const RigidProtrusion& p, double blend, std::vector<int>& slot,
               std::vector<int>& band) {
  const auto [c, mean_radius] = ring_circle(X, p.foot);
  const double radius = blend * mean_radius;
  std::vector<int> wave = p.vertices;
  while (!wave.empty()) {
    std::vector<int> next;
    for (int v : wave)
      for (auto u : mesh.vv_range(mesh.vertex_handle(v)))
        if (slot[u.idx()] == -1 && (X.row(u.idx()).transpose() - c).norm() < radius)
          slot[u.idx()] = 0, band.push_back(u.idx()), next.push_back(u.idx());
    wave.swap(next);
  }
}

}  // namespace

std::vector<RigidProtrusion> untied_protrusions(const Mesh& mesh, const MatrixX3d& X,
                                                std::vector<RigidProtrusion> protrusions,
                                                const std::vector<SurfaceTie>& ties, double blend) {
  if (ties.empty()) return protrusions;
  std::vector<int> slot(X.rows(), -1), band;
  std::erase_if(protrusions, [&](const RigidProtrusion& p) {
    std::fill(slot.begin(), slot.end(), -1);
    for (int v : p.vertices) slot[v] = -2;
    band.clear();
    grow_band(mesh, X, p, blend, slot, band);
    for (const SurfaceTie& t : ties) {
      int moved = slot[t.vertex] != -1, held = 1;
      for (int k = 0; k < 3; ++k)
        if (t.weights[k] != 0) moved += slot[t.corners[k]] != -1, ++held;
      if (moved > 0 && moved < held) return true;  // the placement would move the tie's vertex off its point
    }
    return false;
  });
  return protrusions;
}

int relax_turned_faces(const Mesh& mesh, const MatrixX3d& C, const std::vector<RigidProtrusion>& protrusions,
                       MatrixX3d& Y, int rounds) {
  const int n = static_cast<int>(C.rows());
  std::vector<char> rigid(n, 0);
  for (const RigidProtrusion& p : protrusions)
    for (int v : p.vertices) rigid[v] = 1;
  auto turned = [&] {
    std::vector<int> bad;
    for (auto fh : mesh.faces()) {
      std::array<int, 3> v{};
      int k = 0;
      for (auto vh : mesh.fv_range(fh)) v[k++] = vh.idx();
      auto normal = [&](const MatrixX3d& P) {
        return Vec3((P.row(v[1]) - P.row(v[0])).transpose().cross((P.row(v[2]) - P.row(v[0])).transpose()));
      };
      if (normal(C).dot(normal(Y)) < 0) bad.push_back(fh.idx());
    }
    return bad;
  };
  std::vector<int> bad = turned();
  for (int round = 0; round < rounds && !bad.empty(); ++round) {
    std::vector<int> unknown(n, 0), front;
    for (int f : bad)
      for (auto vh : mesh.fv_range(mesh.face_handle(f)))
        if (!rigid[vh.idx()] && !unknown[vh.idx()]) unknown[vh.idx()] = 1, front.push_back(vh.idx());
    for (int ring = 0; ring < 2 + 2 * round; ++ring) {  // wider each round
      std::vector<int> next;
      for (int v : front)
        for (auto u : mesh.vv_range(mesh.vertex_handle(v)))
          if (!rigid[u.idx()] && !unknown[u.idx()]) unknown[u.idx()] = 1, next.push_back(u.idx());
      front.swap(next);
    }
    MatrixX3d D = Y - C;
    harmonic_fill(mesh, unknown, D);
    Y = C + D;
    bad = turned();
  }
  return static_cast<int>(bad.size());
}

std::vector<RigidProtrusion> find_protrusions(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& f) {
  const int n = static_cast<int>(X.rows());
  if (f.size() != n) throw InvalidInput("find_protrusions: one weight per vertex");
  std::vector<int> id(n, -1);
  std::vector<std::vector<int>> regions;
  for (int seed = 0; seed < n; ++seed) {  // the cores: connected regions of f ≥ kCore
    if (f[seed] < kCore || id[seed] >= 0 || mesh.is_isolated(mesh.vertex_handle(seed))) continue;
    const int k = static_cast<int>(regions.size());
    regions.emplace_back(1, seed);
    id[seed] = k;
    for (size_t q = 0; q < regions[k].size(); ++q)
      for (auto u : mesh.vv_range(mesh.vertex_handle(regions[k][q])))
        if (f[u.idx()] >= kCore && id[u.idx()] < 0) id[u.idx()] = k, regions[k].push_back(u.idx());
  }
  // Cores that cannot be protrusions (a cap, a patch of relief: too little reach from their own foot ring,
  // or too large) let go of their vertices before the others grow, so that they block nobody.
  const Vec3 lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  const double largest = (hi - lo).maxCoeff();
  {
    std::vector<std::vector<int>> kept;
    std::vector<int> tag(n, -1);
    for (size_t k = 0; k < regions.size(); ++k) {
      RigidProtrusion core;
      core.vertices = regions[k];
      for (int v : core.vertices)
        for (auto u : mesh.vv_range(mesh.vertex_handle(v)))
          if (id[u.idx()] != static_cast<int>(k) && tag[u.idx()] != static_cast<int>(k))
            tag[u.idx()] = static_cast<int>(k), core.foot.push_back(u.idx());
      if (protrusion_shape(X, core, largest)) kept.push_back(std::move(regions[k]));
      else
        for (int v : regions[k]) id[v] = -1;
    }
    regions.swap(kept);
    for (size_t k = 0; k < regions.size(); ++k)
      for (int v : regions[k]) id[v] = static_cast<int>(k);
  }
  // Each core grown over its flared foot, ring by ring (all together, so that neighbours stay apart),
  // until its newest ring lies kGrow times as far from the core's foot centre as the core's own foot.
  const auto cores = static_cast<int>(regions.size());
  std::vector<Vec3> centre(cores, Vec3::Zero());
  std::vector<double> reach(cores, 0);
  std::vector<std::vector<int>> front(cores);
  for (int k = 0; k < cores; ++k) {
    for (int v : regions[k])
      for (auto u : mesh.vv_range(mesh.vertex_handle(v)))
        if (id[u.idx()] < 0 && std::find(front[k].begin(), front[k].end(), u.idx()) == front[k].end())
          front[k].push_back(u.idx());
    const auto [c, radius] = ring_circle(X, front[k]);
    centre[k] = c, reach[k] = kGrow * radius;
    front[k] = regions[k];
  }
  for (int ring = 0; ring < kMaxGrowRings; ++ring) {
    std::vector<std::pair<int, int>> grown;
    for (int k = 0; k < cores; ++k) {
      std::vector<int> next;
      for (int v : front[k])
        for (auto u : mesh.vv_range(mesh.vertex_handle(v)))
          if (id[u.idx()] < 0 && (X.row(u.idx()).transpose() - centre[k]).norm() < reach[k])
            id[u.idx()] = k, grown.emplace_back(k, u.idx()), next.push_back(u.idx());
      front[k].swap(next);
    }
    if (grown.empty()) break;
    for (const auto& [k, v] : grown) regions[k].push_back(v);
  }
  std::vector<RigidProtrusion> out;
  std::vector<int> tag(n, -1);
  for (size_t k = 0; k < regions.size(); ++k) {
    RigidProtrusion p;
    p.vertices = regions[k];
    bool ok = true;
    for (int v : p.vertices) {
      if (mesh.is_boundary(mesh.vertex_handle(v))) ok = false;
      for (auto u : mesh.vv_range(mesh.vertex_handle(v))) {
        const int j = u.idx();
        if (id[j] == static_cast<int>(k)) continue;
        if (id[j] >= 0) ok = false;  // touches another region: neither can move alone
        if (tag[j] != static_cast<int>(k)) tag[j] = static_cast<int>(k), p.foot.push_back(j);
      }
    }
    if (!ok || p.foot.size() < 3 || !connected(mesh, p.foot, tag, static_cast<int>(k))) continue;
    if (!protrusion_shape(X, p, largest)) continue;
    out.push_back(std::move(p));
  }
  return out;
}

void set_protrusion_scales(const MatrixX3d& X, const MatrixX3d& C, std::vector<RigidProtrusion>& protrusions,
                           bool keep_size) {
  for (RigidProtrusion& p : protrusions) {
    const Ring r = ring_of(X, C, p.foot);
    // The ring's plane: its two largest principal directions; the linear map of the plane that fits best.
    const Eigen::JacobiSVD<Eigen::MatrixX3d> plane(r.P, Eigen::ComputeThinV);
    const Eigen::MatrixX2d U = r.P * plane.matrixV().leftCols<2>();
    const Eigen::Matrix2d UtU = U.transpose() * U;
    p.scale = 1;
    if (!(std::abs(UtU.determinant()) > 0)) continue;
    const Eigen::Matrix<double, 2, 3> Mt = UtU.ldlt().solve(U.transpose() * r.Q);
    const Eigen::Vector2d sv = Eigen::JacobiSVD<Eigen::Matrix<double, 2, 3>>(Mt).singularValues();
    p.scale = keep_size ? sv[1] : std::sqrt(sv[0] * sv[1]);
  }
}

MatrixX3d place_protrusions(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& Y,
                            const std::vector<RigidProtrusion>& protrusions, double blend) {
  const int n = static_cast<int>(X.rows());
  MatrixX3d Z = Y;
  if (protrusions.empty()) return Z;
  std::vector<int> slot(n, -1);  // -1: not reached, -2: a protrusion's, 0: the band's
  MatrixX3d D = MatrixX3d::Zero(n, 3);  // the displacement Z − Y, fixed on the protrusions
  for (const RigidProtrusion& p : protrusions) {
    const Similarity s = foot_similarity(X, Y, p);
    for (int v : p.vertices) {
      Z.row(v) = s(X.row(v).transpose()).transpose();
      D.row(v) = Z.row(v) - Y.row(v);
      slot[v] = -2;
    }
  }
  std::vector<int> band;
  for (const RigidProtrusion& p : protrusions) grow_band(mesh, X, p, blend, slot, band);
  for (int i = 0; i < n; ++i) slot[i] = slot[i] == 0 ? 1 : 0;  // the unknowns: the band
  biharmonic_fill(mesh, slot, D);
  for (int v : band) Z.row(v) += D.row(v);
  return Z;
}

double important_share_of_rest(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& f,
                               const std::vector<RigidProtrusion>& protrusions) {
  if (f.size() != X.rows()) throw InvalidInput("important_share_of_rest: one weight per vertex");
  std::vector<char> in(X.rows(), 0);
  for (const RigidProtrusion& p : protrusions)
    for (int v : p.vertices) in[v] = 1;
  double important = 0, area = 0;
  for (auto fh : mesh.faces()) {
    std::array<int, 3> v{};
    int k = 0;
    for (auto vh : mesh.fv_range(fh)) v[k++] = vh.idx();
    if (in[v[0]] && in[v[1]] && in[v[2]]) continue;
    const double a =
        0.5 * (X.row(v[1]) - X.row(v[0])).transpose().cross((X.row(v[2]) - X.row(v[0])).transpose()).norm();
    area += a;
    if ((f[v[0]] + f[v[1]] + f[v[2]]) / 3 >= 0.5) important += a;
  }
  return area > 0 ? important / area : 0;
}

namespace {

constexpr int kRoomBins = 64;        // slabs of the room's profile along each axis
constexpr double kRoomFloor = 0.1;   // each slab's share of the room at least this against a slab wholly across the axis

// The room's profile along axis \p a: G at the kRoomBins + 1 slab edges over [\p lo, \p hi] of \p B, increasing from 0
// to hi − lo, its slope in each slab proportional to kRoomFloor + the area share of the slab's faces of the rest (not
// \p in a protrusion) across the axis, Σ A_f n_{f,a}² / Σ A_f (a slab with no rest: 1). A face across the stretch
// keeps its shape under it (the ruler's anisotropy, and the warp's in-plane size term, see it as free), one along it
// takes it fully; a uniform profile is the plain per-axis factor. (Floor 0 turned the painted head's ears' room
// over (RigidProtrusionsGiveNoRoomFromAnImportantHead); 0.3: the stick level 0 ×2 y / z 0.482 / 0.518.)
std::vector<double> room_profile(const MatrixX3i& F, const MatrixX3d& B, const std::vector<char>& in, int a, double lo,
                                 double hi) {
  std::vector<double> across(kRoomBins, 0), area(kRoomBins, 0), G(kRoomBins + 1, 0);
  const double w = (hi - lo) / kRoomBins;
  if (!(w > 0)) return G;
  for (Eigen::Index k = 0; k < F.rows(); ++k) {
    if (in[F(k, 0)] || in[F(k, 1)] || in[F(k, 2)]) continue;
    const Vec3 p0 = B.row(F(k, 0)).transpose(), p1 = B.row(F(k, 1)).transpose(), p2 = B.row(F(k, 2)).transpose();
    const Vec3 nk = (p1 - p0).cross(p2 - p0);
    const double n2 = nk.squaredNorm();
    if (!(n2 > 0)) continue;
    const int bin = std::clamp(static_cast<int>(((p0[a] + p1[a] + p2[a]) / 3 - lo) / w), 0, kRoomBins - 1);
    const double ar = 0.5 * std::sqrt(n2);
    across[bin] += ar * nk[a] * nk[a] / n2;
    area[bin] += ar;
  }
  double sum = 0;
  std::vector<double> rho(kRoomBins);
  for (int b = 0; b < kRoomBins; ++b) sum += rho[b] = area[b] > 0 ? kRoomFloor + across[b] / area[b] : 1.0;
  for (int b = 0; b < kRoomBins; ++b) G[b + 1] = G[b] + rho[b] / sum * (hi - lo);
  return G;
}

}  // namespace

std::optional<MatrixX3d> fit_box_around_protrusions(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& B,
                                                    const Vec3& lo, const Vec3& hi,
                                                    const std::vector<RigidProtrusion>& protrusions) {
  if (protrusions.empty()) return B;
  const Vec3 blo = B.colwise().minCoeff(), bhi = B.colwise().maxCoeff();
  const Vec3 target = hi - lo, bc = 0.5 * (blo + bhi), tc = 0.5 * (lo + hi);
  // The first slope of the output's extent in each factor: the profiled extent of what is not a protrusion (then the
  // secant of the last two steps).
  std::vector<char> in(B.rows(), 0);
  for (const RigidProtrusion& p : protrusions)
    for (int v : p.vertices) in[v] = 1;
  Vec3 rlo = Vec3::Constant(1e300), rhi = Vec3::Constant(-1e300);
  for (Eigen::Index i = 0; i < B.rows(); ++i)
    if (!in[i] && !mesh.is_isolated(mesh.vertex_handle(static_cast<int>(i))))
      rlo = rlo.cwiseMin(B.row(i).transpose()), rhi = rhi.cwiseMax(B.row(i).transpose());
  Vec3 rest = rhi - rlo;
  // The room along each axis spread by where the rest's surface lies across that axis (room_profile()).
  std::array<std::vector<double>, 3> G;
  const MatrixX3i F = faces(mesh);
  for (int a = 0; a < 3; ++a) G[a] = room_profile(F, B, in, a, blo[a], bhi[a]);
  auto g = [&](int a, double x) {
    const double w = (bhi[a] - blo[a]) / kRoomBins;
    if (!(w > 0)) return x;
    const double t = std::clamp((x - blo[a]) / w, 0.0, kRoomBins - 1e-12);
    const int b = static_cast<int>(t);
    return blo[a] + G[a][b] + (t - b) * (G[a][b + 1] - G[a][b]);
  };
  for (int a = 0; a < 3; ++a) rest[a] = g(a, rhi[a]) - g(a, rlo[a]);
  auto map = [&](const Vec3& l) {
    MatrixX3d M(B.rows(), 3);
    for (Eigen::Index i = 0; i < B.rows(); ++i)
      for (int a = 0; a < 3; ++a)
        M(i, a) = tc[a] + (B(i, a) - bc[a]) + (l[a] - 1) * (g(a, B(i, a)) - g(a, bc[a]));
    return M;
  };
  Vec3 l = Vec3::Ones(), l_prev = l, extent_prev = Vec3::Zero();
  bool settled = false;
  for (int step = 0; step < 20 && !settled; ++step) {
    const MatrixX3d Z = place_protrusions(mesh, X, map(l), protrusions, 0);
    const Vec3 extent = Z.colwise().maxCoeff() - Z.colwise().minCoeff();
    settled = true;
    for (int a = 0; a < 3; ++a) {
      if (!(target[a] > 0) || !(rest[a] > 1e-9 * (bhi - blo).maxCoeff())) continue;
      settled = settled && std::abs(extent[a] / target[a] - 1) < 1e-7;
      double slope = rest[a];
      if (step > 0 && std::abs(l[a] - l_prev[a]) > 1e-12) {  // the secant: the pieces ride on where their feet went
        const double measured = (extent[a] - extent_prev[a]) / (l[a] - l_prev[a]);
        if (measured > 0.1 * rest[a] && measured < 10 * rest[a]) slope = measured;
      }
      l_prev[a] = l[a], extent_prev[a] = extent[a];
      l[a] += (target[a] - extent[a]) / slope;
      if (!(l[a] > 0.2 && l[a] < 5)) return std::nullopt;  // no room
    }
  }
  if (!settled) return std::nullopt;
  MatrixX3d M = map(l);
  const MatrixX3d Z = place_protrusions(mesh, X, M, protrusions, 0);
  const Vec3 shift = lo - Z.colwise().minCoeff().transpose();  // the box where it is asked
  return M.rowwise() + shift.transpose();
}

}  // namespace geotex
