#include "geotex/tools/metrics.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <unordered_set>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/spatial.h"

namespace geotex {

Eigen::VectorXd point_to_surface_distances(const MatrixX3d& P, const Mesh& mesh) {
  const TriangleTree tree(mesh);
  Eigen::VectorXd d(P.rows());
#pragma omp parallel for schedule(dynamic, 1024)
  for (Eigen::Index i = 0; i < P.rows(); ++i) d[i] = std::sqrt(tree.closest(P.row(i).transpose()).sq_distance);
  return d;
}

Comparison compare_meshes(const Mesh& result, const Mesh& truth) {
  require_valid(result, "result mesh");
  require_valid(truth, "truth mesh");
  Comparison c;
  const MatrixX3d Nr = face_normals(result), Nt = face_normals(truth);
  const MatrixX3i Fr = faces(result), Ft = faces(truth);
  c.faces_by_index = Fr.rows() == Ft.rows() && Fr == Ft;
  Eigen::VectorXd angle(Fr.rows());
  if (c.faces_by_index) {
#pragma omp parallel for schedule(static)
    for (Eigen::Index f = 0; f < Fr.rows(); ++f) {
      const Vec3 a = Nr.row(f), b = Nt.row(f);
      angle[f] = std::atan2(a.cross(b).norm(), a.dot(b));
    }
  } else {
    const TriangleTree tree(truth);
    const MatrixX3d Vr = positions(result);
#pragma omp parallel for schedule(static)
    for (Eigen::Index f = 0; f < Fr.rows(); ++f) {
      const Vec3 centroid = (Vr.row(Fr(f, 0)) + Vr.row(Fr(f, 1)) + Vr.row(Fr(f, 2))).transpose() / 3.0;
      const Vec3 a = Nr.row(f), b = Nt.row(tree.closest(centroid).face);
      angle[f] = std::atan2(a.cross(b).norm(), a.dot(b));
    }
  }
  c.mean_normal_error_deg = angle.mean() * 180.0 / M_PI;
  c.max_normal_error_deg = angle.maxCoeff() * 180.0 / M_PI;

  const Eigen::VectorXd d_rt = point_to_surface_distances(positions(result), truth);
  const Eigen::VectorXd d_tr = point_to_surface_distances(positions(truth), result);
  c.diagonal = bounding_box(truth).diagonal();
  c.ev = std::sqrt(d_rt.squaredNorm() / d_rt.size());
  c.mean_distance = d_rt.mean();
  c.hausdorff = std::max(d_rt.maxCoeff(), d_tr.maxCoeff());
  c.ev_relative = c.ev / c.diagonal;
  c.hausdorff_relative = c.hausdorff / c.diagonal;
  return c;
}

LabelScore score_edge_labels(const MatrixX2i& labelled, const MatrixX2i& truth) {
  auto key = [](int a, int b) { return (uint64_t(std::min(a, b)) << 32) | uint64_t(std::max(a, b)); };
  std::unordered_set<uint64_t> t;
  for (Eigen::Index i = 0; i < truth.rows(); ++i) t.insert(key(truth(i, 0), truth(i, 1)));
  std::unordered_set<uint64_t> l;
  for (Eigen::Index i = 0; i < labelled.rows(); ++i) l.insert(key(labelled(i, 0), labelled(i, 1)));
  LabelScore s;
  s.labelled = l.size();
  s.truth = t.size();
  for (auto k : l) s.true_positive += t.count(k);
  s.precision = s.labelled ? double(s.true_positive) / s.labelled : (s.truth ? 0.0 : 1.0);
  s.recall = s.truth ? double(s.true_positive) / s.truth : 1.0;
  s.f1 = s.precision + s.recall > 0 ? 2 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
  return s;
}

namespace {

// Faces around a hub (a vertex in more than kHubFaces faces) all reach the hub, so their boxes overlap
// there and a box search from any edge through the hub returns every one of them: a fan of 10^5
// triangles gave 10^10 candidates (issue 30). No edge crosses a face it shares a vertex with, so each
// hub's faces get a tree of their own, which edges through that hub do not search.
constexpr int kHubFaces = 1024;

struct FaceGroup {
  int hub = -1;             // the vertex every face of the group holds, or -1 (faces around no hub)
  std::vector<int> faces;   // the tree's faces (its local indices) as faces of F
  std::unique_ptr<TriangleTree> tree;
  Eigen::AlignedBox3d box;  // of the group's faces
};

std::vector<FaceGroup> face_groups(const MatrixX3d& V, const MatrixX3i& F) {
  std::vector<int> count(V.rows(), 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++count[F(f, k)];
  std::vector<FaceGroup> groups(1);
  std::vector<int> group_of(V.rows(), -1);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    int hub = F(f, 0);
    for (int k = 1; k < 3; ++k)
      if (count[F(f, k)] > count[hub]) hub = F(f, k);
    int g = 0;
    if (count[hub] > kHubFaces) {
      if (group_of[hub] < 0) {
        group_of[hub] = static_cast<int>(groups.size());
        groups.emplace_back().hub = hub;
      }
      g = group_of[hub];
    }
    groups[g].faces.push_back(static_cast<int>(f));
  }
  if (groups.size() == 1) {  // no hub: one tree over the mesh as it is
    groups[0].tree = std::make_unique<TriangleTree>(V, F);
    groups[0].box = Eigen::AlignedBox3d(V.colwise().minCoeff().transpose(), V.colwise().maxCoeff().transpose());
    return groups;
  }
  std::vector<int> local(V.rows(), -1);
  for (FaceGroup& g : groups) {
    std::vector<int> used;
    MatrixX3i Fg(g.faces.size(), 3);
    for (size_t j = 0; j < g.faces.size(); ++j)
      for (int k = 0; k < 3; ++k) {
        const int v = F(g.faces[j], k);
        if (local[v] < 0) {
          local[v] = static_cast<int>(used.size());
          used.push_back(v);
        }
        Fg(j, k) = local[v];
      }
    MatrixX3d Vg(used.size(), 3);
    g.box.setEmpty();
    for (size_t i = 0; i < used.size(); ++i) {
      Vg.row(i) = V.row(used[i]);
      g.box.extend(Vg.row(i).transpose());
      local[used[i]] = -1;
    }
    g.tree = std::make_unique<TriangleTree>(Vg, Fg);
  }
  return groups;
}

}  // namespace

std::vector<char> self_intersecting_faces(const MatrixX3d& V, const MatrixX3i& F) {
  std::vector<char> hit(F.rows(), 0);
  if (F.rows() == 0) return hit;
  // Every edge once (as the pair (a, b), a < b), then the faces whose box comes within half its length of
  // its midpoint: the only ones it can cross.
  std::vector<std::pair<int, int>> edges;
  edges.reserve(3 * F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) edges.emplace_back(std::minmax(F(f, k), F(f, (k + 1) % 3)));
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const std::vector<FaceGroup> groups = face_groups(V, F);
  constexpr double kEps = 1e-9;
#pragma omp parallel
  {
    std::vector<int> near;
    std::vector<int> mine;  // faces this thread found crossed
#pragma omp for schedule(dynamic, 4096)
    for (size_t e = 0; e < edges.size(); ++e) {
      const auto [a, b] = edges[e];
      const Vec3 p0 = V.row(a).transpose(), d = (V.row(b) - V.row(a)).transpose();
      const Vec3 mid = p0 + 0.5 * d;
      for (const FaceGroup& g : groups) {
        if (g.hub == a || g.hub == b || g.faces.empty() || g.box.exteriorDistance(mid) > 0.5 * d.norm()) continue;
        g.tree->faces_near(mid, 0.5 * d.norm(), near);
        for (int local_face : near) {
          const int f = groups.size() == 1 ? local_face : g.faces[local_face];
          const int i = F(f, 0), j = F(f, 1), k = F(f, 2);
          if (a == i || a == j || a == k || b == i || b == j || b == k) continue;
          const Vec3 A = V.row(i).transpose(), e1 = (V.row(j) - V.row(i)).transpose(),
                     e2 = (V.row(k) - V.row(i)).transpose();
          const Vec3 pv = d.cross(e2);
          const double det = e1.dot(pv);
          if (!(std::abs(det) > 1e-30)) continue;
          const Vec3 t = p0 - A, q = t.cross(e1);
          const double u = t.dot(pv) / det, v = d.dot(q) / det, w = e2.dot(q) / det;
          if (u > kEps && v > kEps && u + v < 1 - kEps && w > kEps && w < 1 - kEps) mine.push_back(f);
        }
      }
    }
#pragma omp critical
    for (int f : mine) hit[f] = 1;
  }
  return hit;
}

}  // namespace geotex
