// Texture transfer between disk patches through conformal maps to the unit disk (thesis Sec. 8.3.3).

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "geotex/core/error.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/core/spatial.h"
#include "geotex/texture/texture.h"

namespace geotex {
namespace {

// Coordinates (a, b) of a vector w in the basis (e1, e2), least squares (w in their plane).
Eigen::Vector2d in_basis(const Vec3& e1, const Vec3& e2, const Vec3& w) {
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = e1;
  B.col(1) = e2;
  return (B.transpose() * B).ldlt().solve(B.transpose() * w);
}

// Corner k of original face \p of in the order of the patch face's corners.
struct PatchFace {
  int orig = -1;
  int perm[3];  // patch corner k is original corner perm[k]
};

}  // namespace

DiskPatch extract_disk_patch(const Mesh& mesh, int center, double radius) {
  require_valid(mesh, "disk patch: mesh");
  const int nv = static_cast<int>(mesh.n_vertices());
  if (center < 0 || center >= nv)
    throw InvalidInput("disk patch: centre vertex " + std::to_string(center) + " out of range [0, " +
                       std::to_string(nv) + ")");
  if (!(radius > 0)) throw InvalidInput("disk patch: radius must be positive");
  // Dijkstra along edges: a geodesic ball, up to the edge-path overestimate.
  std::vector<double> dist(nv, std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  dist[center] = 0;
  q.push({0, center});
  while (!q.empty()) {
    const auto [d, v] = q.top();
    q.pop();
    if (d > dist[v] || d > radius) continue;
    const auto vh = mesh.vertex_handle(v);
    for (auto w : mesh.vv_range(vh)) {
      const double nd = d + (mesh.point(w) - mesh.point(vh)).norm();
      if (nd < dist[w.idx()]) {
        dist[w.idx()] = nd;
        q.push({nd, w.idx()});
      }
    }
  }
  DiskPatch patch;
  std::vector<int> local(nv, -1);
  std::vector<Eigen::Vector3i> tris;
  for (auto f : mesh.faces()) {
    int c[3], k = 0;
    bool in = true;
    for (auto v : mesh.fv_range(f)) {
      c[k++] = v.idx();
      in &= dist[v.idx()] <= radius;
    }
    if (!in) continue;
    for (int& x : c) {
      if (local[x] < 0) {
        local[x] = static_cast<int>(patch.vertices.size());
        patch.vertices.push_back(x);
      }
      x = local[x];
    }
    tris.emplace_back(c[0], c[1], c[2]);
    patch.faces.push_back(f.idx());
  }
  if (tris.empty()) throw InvalidInput("disk patch: no face lies within the radius; use a larger radius");
  MatrixX3d V(patch.vertices.size(), 3);
  for (size_t i = 0; i < patch.vertices.size(); ++i)
    V.row(i) = to_eigen(mesh.point(mesh.vertex_handle(patch.vertices[i]))).transpose();
  MatrixX3i F(tris.size(), 3);
  for (size_t f = 0; f < tris.size(); ++f) F.row(f) = tris[f].transpose();
  BuildReport rep;
  patch.mesh = make_mesh(V, F, &rep);
  if (rep.dropped() > 0 || patch.mesh.n_faces() != tris.size())
    throw InvalidInput("disk patch: the patch is not manifold");
  const std::string problem = disk_topology_problem(patch.mesh);
  if (!problem.empty())
    throw InvalidInput("disk patch around vertex " + std::to_string(center) + " with radius " + std::to_string(radius) +
                       " is not a disk: " + problem);
  return patch;
}

TransferResult transfer_texture(const Mesh& source_base, const Texture& source, const Mesh& target_base,
                                const TransferOptions& o) {
  if (source.height.size() != static_cast<Eigen::Index>(source_base.n_vertices()) ||
      source.tilt.size() != static_cast<Eigen::Index>(source_base.n_edges()))
    throw InvalidInput("texture transfer: the source texture does not match the source base");
  if (o.edge_samples < 1) throw InvalidInput("texture transfer: edge_samples must be at least 1");
  TransferResult res;
  res.source_patch = extract_disk_patch(source_base, o.source_center, o.source_radius);
  res.target_patch = extract_disk_patch(target_base, o.target_center, o.target_radius);
  const DiskPatch& S = res.source_patch;
  const DiskPatch& T = res.target_patch;

  // Both patches onto the unit disk by the discrete conformal map with the boundary on the circle.
  MatrixX2d uvS = parametrize(S.mesh), uvT = parametrize(T.mesh);
  if (o.rotation_deg != 0) {
    const Eigen::Rotation2Dd R(o.rotation_deg * M_PI / 180.0);
    for (Eigen::Index i = 0; i < uvS.rows(); ++i) uvS.row(i) = (R * Eigen::Vector2d(uvS.row(i).transpose())).transpose();
  }

  // Point location in the source disk: a triangle tree over the flat (u, v, 0) mesh.
  const MatrixX3i FS = faces(S.mesh), FT = faces(T.mesh);
  MatrixX3d PS = MatrixX3d::Zero(uvS.rows(), 3);
  PS.leftCols(2) = uvS;
  const TriangleTree locate(PS, FS);
  MatrixX3d PT = MatrixX3d::Zero(uvT.rows(), 3);
  PT.leftCols(2) = uvT;
  const TriangleTree locate_target(PT, FT);
  const MatrixX3d XS = positions(source_base), XT = positions(target_base);
  const MatrixX3i FSo = faces(source_base);
  std::vector<PatchFace> sface(FS.rows());
  for (Eigen::Index f = 0; f < FS.rows(); ++f) {
    sface[f].orig = S.faces[f];
    for (int k = 0; k < 3; ++k)
      for (int m = 0; m < 3; ++m)
        if (FSo(S.faces[f], m) == S.vertices[FS(f, k)]) sface[f].perm[k] = m;
  }

  res.texture.height = Eigen::VectorXd::Zero(target_base.n_vertices());
  res.texture.tilt = Eigen::VectorXd::Zero(target_base.n_edges());

  // Heights: barycentric resampling (Sec. 8.3.3).
  for (Eigen::Index v = 0; v < uvT.rows(); ++v) {
    const TriangleTree::Hit hit = locate.closest(Vec3(uvT(v, 0), uvT(v, 1), 0));
    double h = 0;
    for (int k = 0; k < 3; ++k) h += hit.bary[k] * source.height[S.vertices[FS(hit.face, k)]];
    res.texture.height[T.vertices[v]] = h;
  }
  res.target_vertices = uvT.rows();

  // Tilt: for each target patch edge, sample it, evaluate the Whitney-interpolated source field
  // (Eq. 8.3), carry the vector through the source face's map to the disk and back through the target
  // face's map (conformal maps keep angles; the length ‖t‖ = sin α is kept), and integrate t·e.
  for (auto e : T.mesh.edges()) {
    const auto h = T.mesh.halfedge_handle(e, 0);
    const int a = T.mesh.from_vertex_handle(h).idx(), b = T.mesh.to_vertex_handle(h).idx();
    const int ga = T.vertices[a], gb = T.vertices[b];
    const auto gh = target_base.find_halfedge(target_base.vertex_handle(ga), target_base.vertex_handle(gb));
    const auto ge = target_base.edge_handle(gh);
    const double orient = target_base.halfedge_handle(ge, 0) == gh ? 1.0 : -1.0;
    const Vec3 edge = XT.row(gb) - XT.row(ga);
    double sum = 0;
    for (int k = 0; k < o.edge_samples; ++k) {
      const double s = (k + 0.5) / o.edge_samples;  // midpoint rule along the edge
      const Eigen::Vector2d uv = (1 - s) * uvT.row(a).transpose() + s * uvT.row(b).transpose();
      const TriangleTree::Hit hit = locate.closest(Vec3(uv[0], uv[1], 0));
      const PatchFace& pf = sface[hit.face];
      Vec3 bary_orig;
      for (int c = 0; c < 3; ++c) bary_orig[pf.perm[c]] = hit.bary[c];
      const Vec3 t = whitney_interpolate(source_base, source.tilt, pf.orig, bary_orig);  // Eq. (8.3)
      const double len = t.norm();
      if (!(len > 0)) continue;
      // Source face map.
      const int s0 = FS(hit.face, 0), s1 = FS(hit.face, 1), s2 = FS(hit.face, 2);
      const Vec3 Y0 = XS.row(S.vertices[s0]), Y1 = XS.row(S.vertices[s1]), Y2 = XS.row(S.vertices[s2]);
      const Eigen::Vector2d ab = in_basis(Y1 - Y0, Y2 - Y0, t);
      const Eigen::Vector2d w = ab[0] * (uvS.row(s1) - uvS.row(s0)).transpose() + ab[1] * (uvS.row(s2) - uvS.row(s0)).transpose();
      // Target face map at the sample: 3D edge vectors of the face and their uv images.
      const int tf = locate_target.closest(Vec3(uv[0], uv[1], 0)).face;
      const int t0 = FT(tf, 0), t1 = FT(tf, 1), t2 = FT(tf, 2);
      const Vec3 X0 = XT.row(T.vertices[t0]), X1 = XT.row(T.vertices[t1]), X2 = XT.row(T.vertices[t2]);
      Eigen::Matrix2d UT;
      UT.col(0) = (uvT.row(t1) - uvT.row(t0)).transpose();
      UT.col(1) = (uvT.row(t2) - uvT.row(t0)).transpose();
      const Eigen::Vector2d cd = UT.fullPivLu().solve(w);
      Vec3 tt = cd[0] * (X1 - X0) + cd[1] * (X2 - X0);
      const double l2 = tt.norm();
      if (!(l2 > 0) || !tt.allFinite()) continue;
      tt *= len / l2;
      sum += tt.dot(edge);
    }
    res.texture.tilt[ge.idx()] = orient * sum / o.edge_samples;
  }
  // The tilt has magnitude ≤ 1: keep |c| ≤ ‖e‖ (Sec. 8.5).
  const auto len = edge_lengths(target_base);
  for (Eigen::Index e = 0; e < len.size(); ++e) res.texture.tilt[e] = std::clamp(res.texture.tilt[e], -len[e], len[e]);
  return res;
}

}  // namespace geotex
