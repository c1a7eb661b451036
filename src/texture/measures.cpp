// Measures of texture quality (see measures.h).

#include "geotex/texture/measures.h"

#include <algorithm>
#include <cmath>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/texture/texture.h"

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

Vec3 polar_rotated(const Eigen::Matrix3d& J, const Vec3& n0, const Vec3& n1, const Vec3& v) {
  auto perpendicular = [](const Vec3& n) {
    const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    return Vec3((a - a.dot(n) * n).normalized());
  };
  const Vec3 a0 = perpendicular(n0), b0 = n0.cross(a0), a1 = perpendicular(n1), b1 = n1.cross(a1);
  Eigen::Matrix2d M;  // J_t in the frames (a0, b0) → (a1, b1)
  M << a1.dot(J * a0), a1.dot(J * b0), b1.dot(J * a0), b1.dot(J * b0);
  // The rotation nearest to M (its polar factor): rot(θ) with θ = atan2(M10 − M01, M00 + M11).
  const Eigen::Vector2d p = Eigen::Rotation2Dd(std::atan2(M(1, 0) - M(0, 1), M(0, 0) + M(1, 1))) *
                            Eigen::Vector2d(v.dot(a0), v.dot(b0));
  return p.x() * a1 + p.y() * b1;
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

namespace {

// ∫ h² = A/6 (Σ h_i² + Σ_{i<j} h_i h_j) exactly; ∫ |h| at the centroids of the 16 sub-triangles of a
// 4 × 4 split (exact where h keeps its sign).
void integrate_triangle(const double v[3], double A, double& sum_abs, double& sum_sq) {
  sum_sq += A / 6 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[0] * v[1] + v[1] * v[2] + v[2] * v[0]);
  double acc = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4 - i; ++j) {
      // upward sub-triangle (i, j), and the downward one beside it when there is room
      const double a = (i + 1.0 / 3) / 4, b = (j + 1.0 / 3) / 4;
      acc += std::abs((1 - a - b) * v[0] + a * v[1] + b * v[2]);
      if (i + j < 3) {
        const double c = (i + 2.0 / 3) / 4, d = (j + 2.0 / 3) / 4;
        acc += std::abs((1 - c - d) * v[0] + c * v[1] + d * v[2]);
      }
    }
  sum_abs += A * acc / 16;
}

}  // namespace

HeightStats height_stats_disk(const Mesh& disk, const MatrixX2d& uv, const Eigen::VectorXd& h, double radius) {
  if (uv.rows() != static_cast<Eigen::Index>(disk.n_vertices()) || h.size() != uv.rows())
    throw InvalidInput("disk height statistics: expected one uv and one height per vertex");
  HeightStats s;
  double sum_abs = 0, sum_sq = 0;
  for (auto f : disk.faces()) {
    double v[3];
    int c[3], k = 0;
    bool in = true;
    for (auto vh : disk.fv_range(f)) {
      c[k] = vh.idx();
      v[k++] = h[vh.idx()];
      in &= uv.row(vh.idx()).norm() <= radius;
    }
    if (!in) continue;
    const Eigen::Vector2d a = uv.row(c[1]) - uv.row(c[0]), b = uv.row(c[2]) - uv.row(c[0]);
    const double A = 0.5 * std::abs(a.x() * b.y() - a.y() * b.x());
    s.area += A;
    integrate_triangle(v, A, sum_abs, sum_sq);
    for (double x : v) s.max_abs = std::max(s.max_abs, std::abs(x));
  }
  if (s.area > 0) {
    s.mean_abs = sum_abs / s.area;
    s.rms = std::sqrt(sum_sq / s.area);
  }
  return s;
}

HeightStats height_stats_linear(const Mesh& base, const Eigen::VectorXd& h, const std::vector<char>& mask) {
  if (h.size() != static_cast<Eigen::Index>(base.n_vertices()) || mask.size() != base.n_vertices())
    throw InvalidInput("height statistics: expected one height and one mask entry per vertex");
  const Eigen::VectorXd fa = face_areas(base);
  HeightStats s;
  double sum_abs = 0, sum_sq = 0;
  for (auto f : base.faces()) {
    double v[3];
    int k = 0;
    bool in = true;
    for (auto vh : base.fv_range(f)) {
      in &= mask[vh.idx()] != 0;
      v[k++] = h[vh.idx()];
    }
    if (!in) continue;
    const double A = fa[f.idx()];
    s.area += A;
    integrate_triangle(v, A, sum_abs, sum_sq);
    for (double x : v) s.max_abs = std::max(s.max_abs, std::abs(x));
  }
  if (s.area > 0) {
    s.mean_abs = sum_abs / s.area;
    s.rms = std::sqrt(sum_sq / s.area);
  }
  return s;
}

namespace {

double mean_lean_deg(const Texture& t, const std::vector<int>& vertices, const MatrixX2d& uv, double radius) {
  double s = 0, w = 0;
  for (size_t k = 0; k < vertices.size(); ++k)
    if (uv.row(k).norm() <= radius) {
      const double weight = std::abs(t.height[vertices[k]]);
      s += weight * (t.lean.size() ? t.lean[vertices[k]] : 0.0);
      w += weight;
    }
  return w > 0 ? s / w * 180 / M_PI : 0;
}

}  // namespace

TransferQuality transfer_quality(const Mesh& source_base, const Texture& source, const TransferResult& r,
                                 const TransferOptions& o) {
  check_options(o);
  TransferQuality q;
  const double inner = 1 - o.falloff;
  const DiskPatch &S = r.source_patch, &T = r.target_patch;
  Eigen::VectorXd hs(S.vertices.size()), ht(T.vertices.size());
  for (size_t i = 0; i < S.vertices.size(); ++i) hs[i] = r.height_factor * source.height[S.vertices[i]];
  for (size_t i = 0; i < T.vertices.size(); ++i) ht[i] = r.texture.height[T.vertices[i]];
  const HeightStats a = height_stats_disk(S.mesh, r.source_uv, hs, inner), b = height_stats_disk(T.mesh, r.target_uv, ht, inner);
  q.mean_change = b.mean_abs / a.mean_abs - 1;
  q.rms_change = b.rms / a.rms - 1;
  q.max_change = b.max_abs / a.max_abs - 1;
  std::vector<char> ms(source_base.n_vertices(), 0), mt(r.target.n_vertices(), 0);
  for (size_t i = 0; i < S.vertices.size(); ++i) ms[S.vertices[i]] = r.source_uv.row(i).norm() <= inner;
  for (size_t i = 0; i < T.vertices.size(); ++i) mt[T.vertices[i]] = r.target_uv.row(i).norm() <= inner;
  const HeightStats sa = height_stats_linear(source_base, source.height, ms);
  const HeightStats sb = height_stats_linear(r.target, r.texture.height, mt);
  q.surface_mean_change = sb.mean_abs / (r.height_factor * sa.mean_abs) - 1;
  q.surface_rms_change = sb.rms / (r.height_factor * sa.rms) - 1;
  q.lean_change_deg = mean_lean_deg(r.texture, T.vertices, r.target_uv, inner) -
                      mean_lean_deg(source, S.vertices, r.source_uv, inner);
  Mesh textured = r.target;
  set_positions(textured, apply_texture(r.target, r.texture, o.texture));
  q.folded = folded_faces(textured);
  Mesh source_textured = source_base;
  set_positions(source_textured, apply_texture(source_base, source, o.texture));
  q.source_folded = folded_faces(source_textured);
  TransferOptions flat = o;
  flat.falloff = 0;
  const TransferResult r0 = transfer_texture(source_base, source, r.target, flat);
  const double hmax = r0.texture.height.cwiseAbs().maxCoeff();
  if (hmax > 0) {
    for (auto e : r.target.edges()) {
      const auto h = r.target.halfedge_handle(e, 0);
      const int i = r.target.from_vertex_handle(h).idx(), j = r.target.to_vertex_handle(h).idx();
      q.falloff_step = std::max(q.falloff_step, std::abs(r.falloff[i] - r.falloff[j]) *
                                                    std::max(std::abs(r0.texture.height[i]), std::abs(r0.texture.height[j])));
    }
    q.falloff_step /= hmax;
    for (auto v : T.mesh.vertices())
      if (T.mesh.is_boundary(v)) q.rim_cliff = std::max(q.rim_cliff, std::abs(r.texture.height[T.vertices[v.idx()]]) / hmax);
  }
  return q;
}

SeamQuality atlas_seams(const AtlasResult& r) {
  std::vector<double> across, within;
  for (auto e : r.target.edges()) {
    const auto h = r.target.halfedge_handle(e, 0);
    const int a = r.target.from_vertex_handle(h).idx(), b = r.target.to_vertex_handle(h).idx();
    const double slope = std::abs(r.texture.height[a] - r.texture.height[b]) / r.target.calc_edge_length(e);
    (r.owner[a] != r.owner[b] ? across : within).push_back(slope);
  }
  SeamQuality q;
  auto fill = [](std::vector<double>& v, double& p99, double& mx) {
    if (v.empty()) return;
    std::sort(v.begin(), v.end());
    p99 = v[v.size() * 99 / 100];
    mx = v.back();
  };
  fill(across, q.across99, q.across_max);
  fill(within, q.within99, q.within_max);
  return q;
}

}  // namespace geotex
