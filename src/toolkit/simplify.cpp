#include "geotex/toolkit/simplify.h"

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/progress.h"
#include "geotex/toolkit/linear_solver.h"

namespace geotex {

namespace {

// Would collapsing h (its from-vertex onto its to-vertex, which stays where it is) turn a face round,
// against its own normal or against the input's normals at its corners (\p normal, #V by 3 in input
// order; \p original maps to it)? The second test stops folds building up over many collapses.
bool flips_a_face(const Mesh& m, Mesh::HalfedgeHandle h, const MatrixX3d& normal,
                  const OpenMesh::VPropHandleT<int>& original) {
  const auto v0 = m.from_vertex_handle(h), v1 = m.to_vertex_handle(h);
  const Vec3 p1 = to_eigen(m.point(v1));
  for (auto f : m.vf_range(v0)) {
    Vec3 p[3], q[3], n = Vec3::Zero();
    int k = 0;
    bool has_v1 = false;
    for (auto v : m.fv_range(f)) {
      has_v1 |= v == v1;
      n += normal.row(m.property(original, v == v0 ? v1 : v)).transpose();
      p[k] = to_eigen(m.point(v));
      q[k] = v == v0 ? p1 : p[k];
      ++k;
    }
    if (has_v1) continue;  // one of the two faces the collapse removes
    const Vec3 before = (p[1] - p[0]).cross(p[2] - p[0]), after = (q[1] - q[0]).cross(q[2] - q[0]);
    if (!(after.dot(before) > 0) || !(after.dot(n) > 0)) return true;
  }
  return false;
}

}  // namespace

SimplifiedMesh simplify(const Mesh& mesh, int target_vertices) {
  require_valid(mesh, "simplification input");
  if (target_vertices < 4) throw InvalidInput(fmt::format("simplify: target of {} vertices (at least 4)", target_vertices));
  SimplifiedMesh out;
  out.mesh = mesh;
  Mesh& m = out.mesh;
  int in_faces = vertices_in_faces(m);
  OpenMesh::VPropHandleT<int> original;
  m.add_property(original);
  for (auto v : m.vertices()) m.property(original, v) = v.idx();
  const MatrixX3d normal = vertex_normals(mesh);
  m.request_vertex_status();
  m.request_edge_status();
  m.request_face_status();
  // Quadric error (Garland and Heckbert 1997): Q_v sums the squared distances to the planes of the
  // faces around v; collapsing u onto v costs vᵀ(Q_u + Q_v)v, and v inherits Q_u + Q_v.
  std::vector<Eigen::Matrix4d> Q(m.n_vertices(), Eigen::Matrix4d::Zero());
  for (auto f : m.faces()) {
    Vec3 p[3];
    int k = 0;
    std::array<int, 3> ids{};
    for (auto v : m.fv_range(f)) ids[k] = v.idx(), p[k++] = to_eigen(m.point(v));
    const Vec3 c = (p[1] - p[0]).cross(p[2] - p[0]);
    const double area2 = c.norm();
    if (!(area2 > 0)) continue;
    Eigen::Vector4d plane;
    plane << c / area2, -c.dot(p[0]) / area2;
    const Eigen::Matrix4d K = plane * plane.transpose();  // not area-weighted: small faces count as much
    for (int i : ids) Q[i] += K;
  }
  auto cost = [&](Mesh::HalfedgeHandle h) {
    const auto u = m.from_vertex_handle(h), v = m.to_vertex_handle(h);
    Eigen::Vector4d x;
    x << to_eigen(m.point(v)), 1.0;
    // The quadric keeps the shape; a little of the edge's length keeps flat parts from
    // turning into long thin triangles, which a Laplace spectrum dislikes.
    return x.dot((Q[u.idx()] + Q[v.idx()]) * x) + 1e-3 * m.calc_edge_sqr_length(h);
  };
  // Passes of cheapest-first collapses on vertex-disjoint stars (no collapse touches a vertex another
  // one in the same pass changed), until the target is reached or no collapse is allowed. A collapse
  // removes a boundary vertex only along the boundary, and none that would break the manifold
  // (OpenMesh's link test) or turn a face round.
  std::vector<std::pair<double, int>> order;
  std::vector<char> touched;
  while (in_faces > target_vertices) {
    check_interrupt();
    order.clear();
    for (auto h : m.halfedges())
      if (!m.status(m.edge_handle(h)).deleted()) order.emplace_back(cost(h), h.idx());
    std::sort(order.begin(), order.end());
    touched.assign(m.n_vertices(), 0);
    // At most an eighth of the vertices per pass: a pass must stop before it reaches the expensive
    // collapses (the tips of thin protrusions), which later passes may still find cheap by comparison.
    const int budget = std::min(in_faces - target_vertices, std::max(1, in_faces / 8));
    int removed = 0;
    for (const auto& [c, hi] : order) {
      if (removed >= budget) break;
      const auto h = m.halfedge_handle(hi);
      if (m.status(m.edge_handle(h)).deleted()) continue;
      const auto v0 = m.from_vertex_handle(h), v1 = m.to_vertex_handle(h);
      if (touched[v0.idx()] || touched[v1.idx()]) continue;
      if (m.is_boundary(v0) && !m.is_boundary(m.edge_handle(h))) continue;  // a boundary vertex only along it
      if (!m.is_collapse_ok(h) || flips_a_face(m, h, normal, original)) continue;
      for (auto w : m.vv_range(v0)) touched[w.idx()] = 1;
      touched[v0.idx()] = touched[v1.idx()] = 1;
      Q[v1.idx()] += Q[v0.idx()];
      m.collapse(h);
      ++removed;
    }
    if (removed == 0) break;
    in_faces -= removed;
  }
  m.garbage_collection();
  out.original.resize(m.n_vertices());
  for (auto v : m.vertices()) out.original[v.idx()] = m.property(original, v);
  m.remove_property(original);
  m.release_face_status();
  m.release_edge_status();
  m.release_vertex_status();
  return out;
}

Eigen::MatrixXd extend_harmonic(const Mesh& mesh, const std::vector<int>& known, const Eigen::MatrixXd& values) {
  const int n = static_cast<int>(mesh.n_vertices());
  if (static_cast<Eigen::Index>(known.size()) != values.rows())
    throw InvalidInput(fmt::format("extend_harmonic: {} known vertices, {} rows of values", known.size(), values.rows()));
  // Unknowns: vertices in faces that are not known; index[v] ≥ 0 numbers them, −1 marks known ones.
  std::vector<int> index(n, -2);  // −2: isolated (0)
  for (auto v : mesh.vertices())
    if (!mesh.is_isolated(v)) index[v.idx()] = 0;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, values.cols());
  for (size_t k = 0; k < known.size(); ++k) {
    const int v = known[k];
    if (v < 0 || v >= n) throw InvalidInput(fmt::format("extend_harmonic: vertex {} out of range", v));
    out.row(v) = values.row(static_cast<Eigen::Index>(k));
    if (index[v] == 0) index[v] = -1;
  }
  int u = 0;
  for (int v = 0; v < n; ++v)
    if (index[v] == 0) index[v] = u++;
  if (u == 0) return out;
  // Umbrella equations at the unknowns (Eq. 5.8 times the valence): deg(v) x_v − Σ_unknown x_w =
  // Σ_known x_w. SPD when every component holds a known vertex.
  std::vector<Triplet> t;
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(u, values.cols());
  for (int v = 0; v < n; ++v) {
    if (index[v] < 0) continue;
    int degree = 0;
    for (auto w : mesh.vv_range(mesh.vertex_handle(v))) {
      ++degree;
      if (index[w.idx()] >= 0)
        t.emplace_back(index[v], index[w.idx()], -1.0);
      else
        b.row(index[v]) += out.row(w.idx());
    }
    t.emplace_back(index[v], index[v], degree);
  }
  // SPD exactly when every component holds a known vertex: decided here, not by the factorization.
  if (const std::string c = component_without(mesh, known); !c.empty())
    throw InvalidInput(fmt::format("extend_harmonic: {} holds no known vertex", c));
  SparseMatrix A(u, u);
  A.setFromTriplets(t.begin(), t.end());
  SpdSolver solver;
  solver.compute(A);
  const Eigen::MatrixXd x = solver.solve(b);
  for (int v = 0; v < n; ++v)
    if (index[v] >= 0) out.row(v) = x.row(index[v]);
  return out;
}

}  // namespace geotex
