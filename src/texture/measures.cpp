// Measures of texture quality (see measures.h).

#include "geotex/texture/measures.h"

#include <algorithm>
#include <cmath>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"

namespace geotex {

std::vector<Protrusion> measure_protrusions(const Mesh& base, const MatrixX3d& textured, const std::vector<int>& feet) {
  const MatrixX3d B = positions(base);
  if (textured.rows() != B.rows()) throw InvalidInput("protrusions: the textured surface has another vertex count");
  const MatrixX3d N = vertex_normals(base, NormalWeighting::Angle);
  std::vector<Protrusion> out;
  for (int v : feet) {
    if (v < 0 || v >= B.rows()) throw InvalidInput("protrusions: foot vertex out of range");
    Protrusion p;
    const Vec3 d = (textured.row(v) - B.row(v)).transpose();
    p.normal = N.row(v).transpose();
    p.length = d.norm();
    if (p.length > 0) p.lean_deg = std::acos(std::clamp(d.dot(p.normal) / p.length, -1.0, 1.0)) * 180.0 / M_PI;
    const Vec3 t = d - d.dot(p.normal) * p.normal;
    if (t.norm() > 1e-12 * std::max(1.0, p.length)) p.direction = t.normalized();
    out.push_back(p);
  }
  return out;
}

size_t folded_faces(const Mesh& mesh) {
  const MatrixX3d FN = face_normals(mesh);
  size_t count = 0;
  for (auto f : mesh.faces()) {
    Vec3 s = Vec3::Zero();
    for (auto g : mesh.ff_range(f)) s += FN.row(g.idx()).transpose();
    count += s.dot(FN.row(f.idx()).transpose()) < 0;
  }
  return count;
}

HeightStats height_stats(const Mesh& base, const Eigen::VectorXd& h, const std::vector<char>& mask) {
  if (h.size() != static_cast<Eigen::Index>(base.n_vertices()) || mask.size() != base.n_vertices())
    throw InvalidInput("height statistics: expected one height and one mask entry per vertex");
  const Eigen::VectorXd fa = face_areas(base);
  Eigen::VectorXd va = Eigen::VectorXd::Zero(h.size());
  for (auto f : base.faces())
    for (auto v : base.fv_range(f)) va[v.idx()] += fa[f.idx()] / 3;
  HeightStats s;
  double sum_abs = 0, sum_sq = 0;
  for (Eigen::Index i = 0; i < h.size(); ++i) {
    if (!mask[i]) continue;
    s.area += va[i];
    sum_abs += va[i] * std::abs(h[i]);
    sum_sq += va[i] * h[i] * h[i];
    s.max_abs = std::max(s.max_abs, std::abs(h[i]));
  }
  if (s.area > 0) {
    s.mean_abs = sum_abs / s.area;
    s.rms = std::sqrt(sum_sq / s.area);
  }
  return s;
}

double max_height_step(const Mesh& mesh, const Eigen::VectorXd& h, const std::vector<char>& mask) {
  if (h.size() != static_cast<Eigen::Index>(mesh.n_vertices()) || (!mask.empty() && mask.size() != mesh.n_vertices()))
    throw InvalidInput("height step: expected one height (and mask entry) per vertex");
  double step = 0;
  for (auto e : mesh.edges()) {
    const auto hh = mesh.halfedge_handle(e, 0);
    const int a = mesh.from_vertex_handle(hh).idx(), b = mesh.to_vertex_handle(hh).idx();
    if (!mask.empty() && !mask[a] && !mask[b]) continue;
    step = std::max(step, std::abs(h[a] - h[b]));
  }
  return step;
}

}  // namespace geotex
