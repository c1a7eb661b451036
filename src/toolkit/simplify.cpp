#include "geotex/toolkit/simplify.h"

#include <fmt/format.h>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include "geotex/core/error.h"
#include "geotex/toolkit/linear_solver.h"

namespace geotex {

SimplifiedMesh simplify(const Mesh& mesh, int target_vertices) {
  require_valid(mesh, "simplification input");
  if (target_vertices < 4) throw InvalidInput(fmt::format("simplify: target of {} vertices (at least 4)", target_vertices));
  SimplifiedMesh out;
  out.mesh = mesh;
  Mesh& m = out.mesh;
  int in_faces = 0;
  for (auto v : m.vertices()) in_faces += !m.is_isolated(v);
  if (in_faces > target_vertices) {
    OpenMesh::VPropHandleT<int> original;
    m.add_property(original);
    for (auto v : m.vertices()) m.property(original, v) = v.idx();
    m.request_vertex_status();
    m.request_edge_status();
    m.request_face_status();
    m.request_face_normals();
    m.update_face_normals();
    using Decimater = OpenMesh::Decimater::DecimaterT<Mesh>;
    Decimater decimater(m);
    OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle no_flip;
    decimater.add(quadric);
    decimater.add(no_flip);
    decimater.module(quadric).unset_max_err();  // priority only; no error bound
    decimater.initialize();
    const int isolated = static_cast<int>(m.n_vertices()) - in_faces;
    decimater.decimate_to(static_cast<size_t>(target_vertices + isolated));
    m.garbage_collection();
    out.original.resize(m.n_vertices());
    for (auto v : m.vertices()) out.original[v.idx()] = m.property(original, v);
    m.remove_property(original);
    m.release_face_normals();
    m.release_face_status();
    m.release_edge_status();
    m.release_vertex_status();
  } else {
    out.original.resize(m.n_vertices());
    for (int i = 0; i < static_cast<int>(m.n_vertices()); ++i) out.original[i] = i;
  }
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
  SparseMatrix A(u, u);
  A.setFromTriplets(t.begin(), t.end());
  SpdSolver solver;
  try {
    solver.compute(A);
  } catch (const SolverError&) {
    throw InvalidInput("extend_harmonic: a connected component holds no known vertex");
  }
  const Eigen::MatrixXd x = solver.solve(b);
  for (int v = 0; v < n; ++v)
    if (index[v] >= 0) out.row(v) = x.row(index[v]);
  return out;
}

}  // namespace geotex
