// Texture transfer between surfaces (thesis Sec. 8.3.3): sampling in local frames, geodesic disks mapped
// to the unit disk, transfer of one disk. Whole-surface transfer is in texture_atlas.cpp.

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/self_intersections.h"
#include "geotex/core/spatial.h"
#include "geotex/texture/measures.h"
#include "geotex/texture/transfer.h"
#include "transfer_internal.h"
#include "geotex/toolkit/parametrization.h"
#include "geotex/toolkit/refine.h"

namespace geotex {

const EnumNames<HeightRule>& height_rule_names() {
  static const EnumNames<HeightRule> n = {
      {"patch-radius", HeightRule::PatchRadius}, {"absolute", HeightRule::Absolute}, {"thesis", HeightRule::Absolute}};
  return n;
}

const OptionTable<TransferOptions>& TransferOptions::table() {
  using O = TransferOptions;
  static const auto t = OptionTable<O>()
      .add("source_center", &O::source_center, "source base vertex at the patch centre", non_negative())
      .add("source_radius", &O::source_radius, "geodesic radius of the source patch (source model units)", non_negative())
      .add("target_center", &O::target_center, "target base vertex at the patch centre", non_negative())
      .add("target_radius", &O::target_radius, "geodesic radius of the target patch (target model units)", non_negative())
      .add("source_direction", &O::source_direction,
           "anchor: this direction's tangent part at the source centre maps to the target's")
      .add("target_direction", &O::target_direction, "anchor: where the source's anchor direction goes at the target")
      .add("rotation", &O::rotation_deg, "then turn the source about its centre by this many degrees")
      .choice("height_rule", &O::height_rule, height_rule_names(),
              "patch-radius (heights times target/source radius) or absolute (model units, the thesis)")
      .add("height_scale", &O::height_scale, "multiply the heights by this, on top of the height rule", between(0, 1e6))
      .add("falloff", &O::falloff, "width of the smooth rim falloff, as a share of the radius (0: none)", unit_interval())
      .add("refine_ratio", &O::refine_ratio,
           "refine the target patch where its edges exceed this times the source's scaled to it (0: never)",
           non_negative())
      .add("damage_warning", &O::damage_warning,
           "warn when the textured target has more than this many folded or self-intersecting faces beyond the "
           "bare target's own",
           between(0, 100000000))  // a face count: at most 10^8, as every count flag
      .nest(&O::geodesic, HeatGeodesicOptions::table())
      .nest(&O::texture, TextureOptions::table())
      .preset("thesis", "absolute heights, no rim falloff, no refinement, the 1-form encoding (Sec. 8.3.3)", [](O& o) {
        o.height_rule = HeightRule::Absolute;
        o.falloff = 0;
        o.refine_ratio = 0;
        TextureOptions::table().apply_preset(o.texture, "thesis");
      });
  return t;
}

// ---------------------------------------------------------------------------------------------
// Sampling

Eigen::Matrix3d local_frame(const Vec3& n, const Vec3& e1_hint) {
  Vec3 e1 = e1_hint - e1_hint.dot(n) * n;
  if (!(e1.norm() > 1e-9 * std::max(1.0, e1_hint.norm()))) {
    e1 = Vec3::UnitX() - n.x() * n;  // the hint is along the normal: the x axis' tangent part, else y's
    if (e1.norm() < 0.1) e1 = Vec3::UnitY() - n.y() * n;
  }
  e1.normalize();
  Eigen::Matrix3d F;
  F.col(0) = e1;
  F.col(1) = n.cross(e1);
  F.col(2) = n;
  return F;
}

TextureSampler::TextureSampler(const Mesh& base, const Texture& texture, const TextureOptions& options)
    : base_(base), F_(faces(base)) {
  TextureOptions o = options;
  o.bound_tilt = false;  // nothing is fitted: decoding only
  const TextureCodec codec(base, o);
  D_ = codec.displacements(texture);
  N_ = codec.normals();
}

Vec3 TextureSampler::sample(int face, const Vec3& bary, const Vec3& e1_hint) const {
  if (face < 0 || face >= F_.rows()) throw InvalidInput("texture sample: face out of range");
  Vec3 d = Vec3::Zero(), n = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    d += bary[k] * D_.row(F_(face, k)).transpose();
    n += bary[k] * N_.row(F_(face, k)).transpose();
  }
  n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3::UnitZ();
  return local_frame(n, e1_hint).transpose() * d;
}

Vec3 TextureSampler::sample_vertex(int v, const Vec3& e1_hint) const {
  if (v < 0 || v >= D_.rows()) throw InvalidInput("texture sample: vertex out of range");
  return local_frame(N_.row(v).transpose(), e1_hint).transpose() * D_.row(v).transpose();
}

Texture texture_from_local(TextureCodec& codec, const MatrixX3d& local, const MatrixX3d& e1) {
  const MatrixX3d& N = codec.normals();
  if (local.rows() != N.rows() || e1.rows() != N.rows())
    throw InvalidInput("texture from local displacements: expected one row per base vertex (" +
                       std::to_string(N.rows()) + ")");
  MatrixX3d D(N.rows(), 3);
  for (Eigen::Index i = 0; i < N.rows(); ++i)
    D.row(i) = (local_frame(N.row(i).transpose(), e1.row(i).transpose()) * local.row(i).transpose()).transpose();
  return codec.from_displacements(D);
}

// ---------------------------------------------------------------------------------------------
// Damage

TextureDamage texture_damage(const Mesh& base, const MatrixX3d& textured) {
  if (textured.rows() != static_cast<Eigen::Index>(base.n_vertices()))
    throw InvalidInput("texture damage: the textured surface has another vertex count than the base");
  Mesh m = base;
  set_positions(m, textured);
  const MatrixX3i F = faces(base);
  TextureDamage d;
  d.folded = folded_faces(m);
  d.base_folded = folded_faces(base);
  const std::vector<char> hit = self_intersecting_faces(textured, F), own = self_intersecting_faces(positions(base), F);
  d.self_intersecting = static_cast<size_t>(std::count(hit.begin(), hit.end(), 1));
  d.base_self_intersecting = static_cast<size_t>(std::count(own.begin(), own.end(), 1));
  return d;
}

std::vector<char> detail::damaged_faces(const Mesh& mesh, const MatrixX3d& P) {
  const MatrixX3i F = faces(mesh);
  MatrixX3d FN(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 a = P.row(F(f, 0)).transpose(), b = P.row(F(f, 1)).transpose(), c = P.row(F(f, 2)).transpose();
    FN.row(f) = (b - a).cross(c - a).normalized().transpose();
  }
  std::vector<char> out = self_intersecting_faces(P, F);
  for (auto f : mesh.faces()) {
    Vec3 s = Vec3::Zero();
    for (auto g : mesh.ff_range(f)) s += FN.row(g.idx()).transpose();
    if (s.dot(FN.row(f.idx()).transpose()) < 0) out[f.idx()] = 1;
  }
  return out;
}

std::string damage_warning(const TextureDamage& d, size_t threshold) {
  if (d.excess_folded() <= threshold && d.excess_self_intersecting() <= threshold) return {};
  return fmt::format("the textured surface has {} folded and {} self-intersecting faces beyond the base's own "
                     "({} and {}): the texture is too large or too steep for this base here",
                     d.excess_folded(), d.excess_self_intersecting(), d.base_folded, d.base_self_intersecting);
}

// ---------------------------------------------------------------------------------------------
// Geodesic disks

// The pin-holes of a disk's faces: each component of the faces left out (`keep` 0) next to a kept one,
// flooded until it is known to be outside — a face with a vertex at no finite distance, at the farthest
// vertex or deeper than the radius plus twice the mesh's longest edge (no hole's longest edge is longer), a
// boundary edge, or a face already known to be outside. The flood stops there, so a disk costs its
// neighbourhood, not the whole rest of the mesh. A component that is not outside and lies within the
// radius plus twice its own longest edge is a hole: kept (appended to `kept`).
static void fill_disk_holes(const Mesh& mesh, const Eigen::VectorXd& dist, double radius, std::vector<char>& keep,
                     std::vector<int>& kept) {
  const int nv = static_cast<int>(mesh.n_vertices()), nf = static_cast<int>(mesh.n_faces());
  int far = -1;
  for (int i = 0; i < nv; ++i)
    if (std::isfinite(dist[i]) && (far < 0 || dist[i] > dist[far])) far = i;
  double mesh_longest = 0;
  for (auto e : mesh.edges()) mesh_longest = std::max(mesh_longest, static_cast<double>(mesh.calc_edge_length(e)));
  const double reach = radius + 2 * mesh_longest;
  enum : char { kUnseen = 0, kQueued = 1, kOutside = 2 };
  std::vector<char> state(nf, kUnseen);
  std::vector<int> comp, stack, seeds;  // seeds: the left-out faces across an edge from a kept one
  for (int f : kept)
    for (auto g : mesh.ff_range(mesh.face_handle(f)))
      if (!keep[g.idx()]) seeds.push_back(g.idx());
  for (int f0 : seeds) {
    if (state[f0] != kUnseen) continue;
    comp.clear();
    stack.assign(1, f0);
    state[f0] = kQueued;
    bool outside = false;
    double deepest = 0;
    while (!stack.empty() && !outside) {
      const auto f = mesh.face_handle(stack.back());
      stack.pop_back();
      comp.push_back(f.idx());
      for (auto v : mesh.fv_range(f)) {
        outside |= !(dist[v.idx()] <= reach) || v.idx() == far;
        deepest = std::max(deepest, dist[v.idx()]);
      }
      for (auto h : mesh.fh_range(f)) {
        const auto g = mesh.opposite_face_handle(h);
        if (!g.is_valid()) {
          outside = true;  // the mesh's boundary
          continue;
        }
        if (keep[g.idx()]) continue;
        if (state[g.idx()] == kOutside) outside = true;
        else if (state[g.idx()] == kUnseen) {
          state[g.idx()] = kQueued;
          stack.push_back(g.idx());
        }
      }
    }
    if (outside) {
      for (int f : comp) state[f] = kOutside;
      for (int f : stack) state[f] = kOutside;
      continue;
    }
    double longest = 0;
    for (int f : comp)
      for (auto h : mesh.fh_range(mesh.face_handle(f)))
        longest = std::max(longest, static_cast<double>(mesh.calc_edge_length(h)));
    if (deepest <= radius + 2 * longest)
      for (int f : comp) keep[f] = 1, kept.push_back(f);
    else
      for (int f : comp) state[f] = kOutside;
  }
}

DiskPatch extract_disk_patch(const Mesh& mesh, int center, double radius, const Eigen::VectorXd& dist) {
  require_valid(mesh, "disk patch: mesh");
  const int nv = static_cast<int>(mesh.n_vertices());
  if (center < 0 || center >= nv)
    throw InvalidInput("disk patch: centre vertex " + std::to_string(center) + " out of range [0, " +
                       std::to_string(nv) + ")");
  if (!(radius > 0) || !std::isfinite(radius)) throw InvalidInput("disk patch: radius must be positive");
  if (dist.size() != nv) throw InvalidInput("disk patch: expected one distance per vertex");
  DiskPatch patch;
  std::vector<int> local(nv, -1);
  std::vector<Eigen::Vector3i> tris;
  // Boundary-aware: the faces with all corners within the radius that are connected (across edges) to
  // the centre's (islands dropped), plus the pin-holes they enclose: holes whose vertices all lie within
  // the radius plus twice the hole's longest edge (a distance that wobbles by a fraction of an edge). A
  // hole that reaches the mesh's boundary or its farthest vertex, or goes deeper, is outside, not a hole.
  const int nf = static_cast<int>(mesh.n_faces());
  auto within = [&](OpenMesh::FaceHandle f, double r) {
    for (auto v : mesh.fv_range(f))
      if (!(dist[v.idx()] <= r)) return false;
    return true;
  };
  std::vector<char> keep(nf, 0);
  std::vector<int> kept;  // the faces kept, in the order they were found
  {
    std::vector<int> stack;
    for (auto f : mesh.vf_range(mesh.vertex_handle(center)))
      if (within(f, radius)) {
        keep[f.idx()] = 1;
        stack.push_back(f.idx());
      }
    while (!stack.empty()) {
      const auto f = mesh.face_handle(stack.back());
      stack.pop_back();
      kept.push_back(f.idx());
      for (auto g : mesh.ff_range(f))
        if (!keep[g.idx()] && within(g, radius)) {
          keep[g.idx()] = 1;
          stack.push_back(g.idx());
        }
    }
  }
  fill_disk_holes(mesh, dist, radius, keep, kept);
  std::sort(kept.begin(), kept.end());  // the patch's faces in the mesh's order
  for (int fi : kept) {
    const auto f = mesh.face_handle(fi);
    int c[3], k = 0;
    for (auto v : mesh.fv_range(f)) c[k++] = v.idx();
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
  if (tris.empty() || local[center] < 0)
    throw InvalidInput("disk patch: no face around the centre lies within the radius; use a larger radius");
  MatrixX3d V(patch.vertices.size(), 3);
  patch.distance.resize(patch.vertices.size());
  for (size_t i = 0; i < patch.vertices.size(); ++i) {
    V.row(i) = to_eigen(mesh.point(mesh.vertex_handle(patch.vertices[i]))).transpose();
    patch.distance[i] = dist[patch.vertices[i]];
  }
  MatrixX3i F(tris.size(), 3);
  for (size_t f = 0; f < tris.size(); ++f) F.row(f) = tris[f].transpose();
  BuildReport rep;
  patch.mesh = make_mesh(V, F, &rep);
  if (rep.dropped() > 0 || patch.mesh.n_faces() != tris.size())
    throw InvalidInput("disk patch: the patch is not manifold");
  const std::string problem = disk_topology_problem(patch.mesh);
  if (!problem.empty())
    throw InvalidInput("disk patch around vertex " + std::to_string(center) + " with radius " + fmt::format("{:.4g}", radius) +
                       " is not a disk: " + problem + " (try a smaller radius)");
  patch.center = local[center];
  return patch;
}

DiskPatch extract_disk_patch(const Mesh& mesh, int center, double radius) {
  require_valid(mesh, "disk patch: mesh");
  if (center < 0 || center >= static_cast<int>(mesh.n_vertices()))
    throw InvalidInput("disk patch: centre vertex " + std::to_string(center) + " out of range [0, " +
                       std::to_string(mesh.n_vertices()) + ")");
  return extract_disk_patch(mesh, center, radius, heat_geodesic_distance(mesh, {center}));
}

int nearest_vertex(const Mesh& mesh, const Vec3& point) {
  if (mesh.n_vertices() == 0) throw InvalidInput("nearest vertex: the mesh has no vertices");
  if (!point.allFinite()) throw InvalidInput("nearest vertex: non-finite point");
  int best = 0;
  double d = std::numeric_limits<double>::infinity();
  for (auto v : mesh.vertices()) {
    const double e = (to_eigen(mesh.point(v)) - point).squaredNorm();
    if (e < d) {
      d = e;
      best = v.idx();
    }
  }
  return best;
}

namespace detail {

MatrixX3d face_u_directions(const Mesh& mesh, const MatrixX2d& uv) {
  const MatrixX3i F = faces(mesh);
  const MatrixX3d X = positions(mesh);
  MatrixX3d E1(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    Eigen::Matrix<double, 3, 2> E;
    Eigen::Matrix2d U;
    E.col(0) = (X.row(F(f, 1)) - X.row(F(f, 0))).transpose();
    E.col(1) = (X.row(F(f, 2)) - X.row(F(f, 0))).transpose();
    U.col(0) = (uv.row(F(f, 1)) - uv.row(F(f, 0))).transpose();
    U.col(1) = (uv.row(F(f, 2)) - uv.row(F(f, 0))).transpose();
    // X(q) = X0 + E U⁻¹ (q − q0): ∂X/∂u = E U⁻¹ (1, 0)ᵀ.
    const double det = U.determinant();
    Vec3 d = std::abs(det) > 0 ? Vec3(E * (U.inverse() * Eigen::Vector2d(1, 0))) : Vec3::Zero();
    E1.row(f) = d.norm() > 0 ? Eigen::RowVector3d(d.normalized().transpose()) : Eigen::RowVector3d::Zero();
  }
  return E1;
}

MatrixX3d vertex_u_directions(const Mesh& mesh, const MatrixX3d& face_e1) {
  MatrixX3d V = MatrixX3d::Zero(mesh.n_vertices(), 3);
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) V.row(v.idx()) += face_e1.row(f.idx());
  return V;
}

double smoothstep_falloff(double radius, double width) {
  if (!(width > 0)) return radius <= 1 + 1e-9 ? 1.0 : 0.0;  // the rim sits on the circle up to rounding
  const double t = std::clamp((1 - radius) / width, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

Vec3 fade(const Vec3& d, double w) {
  const double len = d.norm();
  if (!(len > 0) || w >= 1) return d;
  const Eigen::Vector2d t = d.head<2>();
  const double lt = t.norm();
  // Lean α from ±n (Eq. 8.8), faded with the height: a half-faded tentacle is shorter and more
  // upright, so that neighbouring displacements shrinking at different rates cannot cross.
  const double lean = std::atan2(lt, std::abs(d.z())) * w * w;
  const double sign = d.z() < 0 ? -1.0 : 1.0;
  Vec3 out;
  out.head<2>() = lt > 0 ? Eigen::Vector2d(t / lt * std::sin(lean)) : Eigen::Vector2d::Zero();
  out.z() = sign * std::cos(lean);
  return w * len * out;
}

double height_factor(HeightRule rule, double source_radius, double target_radius, double scale) {
  return (rule == HeightRule::PatchRadius ? target_radius / source_radius : 1.0) * scale;
}

double mean_patch_edge(const DiskPatch& patch) { return mean_edge_length(patch.mesh); }

SourceDisk::SourceDisk(const Mesh& base, const Texture& texture, int center, double radius, const Vec3& anchor,
                       double rotation_deg, const HeatGeodesicOptions& geodesic, const TextureOptions& options)
    : sampler(base, texture, options) {
  if (!(radius > 0)) throw InvalidInput("texture transfer: the source radius must be positive");
  if (center < 0 || center >= static_cast<int>(base.n_vertices()))
    throw InvalidInput("texture transfer: source centre vertex " + std::to_string(center) + " out of range [0, " +
                       std::to_string(base.n_vertices()) + ")");
  patch = extract_disk_patch(base, center, radius, HeatGeodesics(base, geodesic).distance(center));
  DiskMap map = disk_map(patch, anchor);
  if (rotation_deg != 0) {
    // Reduced first: 1e308 degrees times pi overflows to inf, and a NaN disk map crashed the sampler.
    const Eigen::Rotation2Dd R(std::fmod(rotation_deg, 360.0) * M_PI / 180.0);
    for (Eigen::Index i = 0; i < map.uv.rows(); ++i) map.uv.row(i) = (R * Eigen::Vector2d(map.uv.row(i).transpose())).transpose();
    map.e1 = face_u_directions(patch.mesh, map.uv);
  }
  uv = map.uv;
  e1 = map.e1;
  MatrixX3d flat = MatrixX3d::Zero(uv.rows(), 3);
  flat.leftCols(2) = uv;
  tree = std::make_unique<TriangleTree>(flat, faces(patch.mesh));
  // Patch face corners in the base face's corner order (the sampler's barycentrics).
  const MatrixX3i Fp = faces(patch.mesh), Fb = faces(base);
  perm.resize(Fp.rows());
  for (Eigen::Index f = 0; f < Fp.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      for (int m = 0; m < 3; ++m)
        if (Fb(patch.faces[f], m) == patch.vertices[Fp(f, k)]) perm[f][k] = m;
  mean_edge = mean_patch_edge(patch);
  e1_vertex = vertex_u_directions(patch.mesh, e1);
}

Vec3 SourceDisk::sample(const Eigen::Vector2d& z) const {
  const TriangleTree::Hit hit = tree->closest(Vec3(z.x(), z.y(), 0));
  Vec3 bary, hint = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    bary[perm[hit.face][k]] = hit.bary[k];
    hint += hit.bary[k] * e1_vertex.row(tree->triangles()(hit.face, k)).transpose();
  }
  // The frame's e1 is interpolated from the vertices' (as on the target), not the face's own +u:
  // face-constant frames jump by ~1° between faces of a discrete conformal map.
  return sampler.sample(patch.faces[hit.face], bary, hint);
}

Vec3 SourceDisk::mean_local() const {
  const Eigen::VectorXd fa = face_areas(patch.mesh);
  Eigen::VectorXd va = Eigen::VectorXd::Zero(patch.mesh.n_vertices());
  for (auto f : patch.mesh.faces())
    for (auto v : patch.mesh.fv_range(f)) va[v.idx()] += fa[f.idx()] / 3;
  Vec3 sum = Vec3::Zero();
  for (size_t k = 0; k < patch.vertices.size(); ++k)
    sum += va[k] * sampler.sample_vertex(patch.vertices[k], e1_vertex.row(k).transpose());
  return va.sum() > 0 ? Vec3(sum / va.sum()) : Vec3::Zero();
}

RefineNeed refine_need(const Mesh& target, const std::vector<char>& region, double required_edge, double ratio) {
  RefineNeed r;
  for (size_t i = 0; i < region.size(); ++i) r.region_vertices += region[i] != 0;
  if (!(ratio > 0) || !(required_edge > 0)) return r;
  double sum = 0;
  size_t count = 0;
  for (auto e : target.edges()) {
    const auto h = target.halfedge_handle(e, 0);
    if (!region[target.from_vertex_handle(h).idx()] || !region[target.to_vertex_handle(h).idx()]) continue;
    sum += target.calc_edge_length(e);
    ++count;
  }
  r.mean_edge = count ? sum / count : 0;
  if (!(r.mean_edge > ratio * required_edge)) return r;
  r.refine = true;
  // A refinement that could not finish (a source radius far larger than the target's scales the source's
  // edges down to nothing) is refused by the caller: about area / (edge² √3/4) vertices are needed, and at
  // least length / edge − 1 on every edge (slivers: a fan of 8,000 has little area but 8,000 long spokes).
  const double edge = 0.8 * required_edge;
  double area = 0, on_edges = 0;
  for (auto f : target.faces()) {
    bool inside = true;
    for (auto v : target.fv_range(f)) inside = inside && region[v.idx()];
    if (inside) area += target.calc_face_area(f);
  }
  for (auto e : target.edges()) {
    const auto h = target.halfedge_handle(e, 0);
    if (region[target.from_vertex_handle(h).idx()] && region[target.to_vertex_handle(h).idx()])
      on_edges += std::max(0.0, std::ceil(target.calc_edge_length(e) / edge) - 1);
  }
  r.needed = std::max(area / (edge * edge * std::sqrt(3.0) / 4), on_edges);
  return r;
}

std::string refine_for(Mesh& target, const std::vector<char>& region, double required_edge, double ratio,
                       size_t* added, const ProgressFn& progress, std::vector<char>* refined_region) {
  *added = 0;
  if (refined_region) *refined_region = region;
  const RefineNeed need = refine_need(target, region, required_edge, ratio);
  if (!need.refine) return {};
  const double mean = need.mean_edge, needed = need.needed;
  RefineOptions ro;
  ro.progress = progress;
  ro.expected_added = static_cast<size_t>(needed);
  const double edge = 0.8 * required_edge;
  auto too_many = [&](const char* how, double vertices) {
    return InvalidInput(fmt::format(
        "the target patch would need {} {:.3g} vertices to hold the source's detail at this scale (target "
        "edges of {:.3g}): choose radii closer together, or refine_ratio 0 for no refinement", how, vertices,
        required_edge));
  };
  if (!(needed < 2e6)) throw too_many("about", needed);
  // Bisection of needle triangles (a fan's strips) can add several times the estimate (an 8,000-fan:
  // 4x at edges a tenth of the spokes, 9x at a fortieth): past 8x (and 100,000) it stops, and rather than
  // fair and map a patch refined part way, the transfer is refused.
  ro.max_vertices = std::min<size_t>(ro.max_vertices, target.n_vertices() + static_cast<size_t>(8 * needed) + 100000);
  // Longest-edge bisection leaves edges between half the bound and the bound (mean about 3/4 of it):
  // with the bound at 0.8 × the source's edge the target is sampled ~1.6 times as densely, so that
  // resampling (linear interpolation between points other than the source's vertices) keeps the
  // finest detail's amplitude (within 3 % on igea; at 1× it loses 4–5 %).
  ro.max_edge = edge;
  RefineResult r = refine_region(target, region, ro);
  if (r.capped) throw too_many("more than", static_cast<double>(r.mesh.n_vertices()));
  *added = r.added;
  target = std::move(r.mesh);
  if (refined_region) *refined_region = std::move(r.region);
  return fmt::format("target refined: {} vertices added where its edges (mean {:.4g}) were coarser than the source "
                     "patch's scaled to it ({:.4g})",
                     r.added, mean, required_edge);
}

}  // namespace detail

DiskMap disk_map(const DiskPatch& patch, const Vec3& anchor) {
  if (patch.center < 0 || patch.center >= static_cast<int>(patch.mesh.n_vertices()))
    throw InvalidInput("disk map: the patch has no centre vertex");
  if (!anchor.allFinite()) throw InvalidInput("disk map: the anchor direction must be finite");
  DiskMap m;
  m.uv = parametrize(patch.mesh);  // conformal, boundary on the unit circle (Eq. 5.85)
  // Möbius z ↦ (z − a)/(1 − ā z): the centre to 0, the unit circle onto itself, angles kept.
  using C = std::complex<double>;
  const C a(m.uv(patch.center, 0), m.uv(patch.center, 1));
  for (Eigen::Index i = 0; i < m.uv.rows(); ++i) {
    const C z(m.uv(i, 0), m.uv(i, 1));
    const C w = (z - a) / (1.0 - std::conj(a) * z);
    m.uv(i, 0) = w.real();
    m.uv(i, 1) = w.imag();
  }
  m.uv.row(patch.center).setZero();
  // Turn so that the anchor's image at the centre points along +u: average over the centre's faces of
  // the uv image of the anchor's tangent part (the map is conformal, so the faces agree up to the mesh).
  const MatrixX3d N = vertex_normals(patch.mesh, NormalWeighting::Angle);
  const Vec3 e = local_frame(N.row(patch.center).transpose(), anchor).col(0);
  const MatrixX3d X = positions(patch.mesh);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (auto f : patch.mesh.vf_range(patch.mesh.vertex_handle(patch.center))) {
    int c[3], k = 0;
    for (auto v : patch.mesh.fv_range(f)) c[k++] = v.idx();
    Eigen::Matrix<double, 3, 2> E;
    Eigen::Matrix2d U;
    E.col(0) = (X.row(c[1]) - X.row(c[0])).transpose();
    E.col(1) = (X.row(c[2]) - X.row(c[0])).transpose();
    U.col(0) = (m.uv.row(c[1]) - m.uv.row(c[0])).transpose();
    U.col(1) = (m.uv.row(c[2]) - m.uv.row(c[0])).transpose();
    // 3D → uv on the face's plane: U (EᵀE)⁻¹ Eᵀ.
    const Eigen::Vector2d img = U * (E.transpose() * E).ldlt().solve(E.transpose() * e);
    if (img.norm() > 0 && img.allFinite()) sum += img.normalized();
  }
  if (sum.norm() > 0) {
    const Eigen::Rotation2Dd R(-std::atan2(sum.y(), sum.x()));
    for (Eigen::Index i = 0; i < m.uv.rows(); ++i) m.uv.row(i) = (R * Eigen::Vector2d(m.uv.row(i).transpose())).transpose();
  }
  m.e1 = detail::face_u_directions(patch.mesh, m.uv);
  return m;
}

// ---------------------------------------------------------------------------------------------
// Transfer of one disk

TransferResult transfer_texture(const Mesh& source_base, const Texture& source, const Mesh& target_base,
                                const TransferOptions& o) {
  TransferOptions::table().check(o);
  require_valid(source_base, "texture transfer: source base");
  require_valid(target_base, "texture transfer: target base");
  if (source.height.size() != static_cast<Eigen::Index>(source_base.n_vertices()) ||
      source.tilt.size() != static_cast<Eigen::Index>(source_base.n_edges()))
    throw InvalidInput("texture transfer: the source texture does not match the source base");
  if (!(o.source_radius > 0) || !(o.target_radius > 0))
    throw InvalidInput("texture transfer: the source and target radii must be positive");
  const int nt = static_cast<int>(target_base.n_vertices());
  if (o.target_center < 0 || o.target_center >= nt)
    throw InvalidInput("texture transfer: target centre vertex " + std::to_string(o.target_center) +
                       " out of range [0, " + std::to_string(nt) + ")");
  const detail::SourceDisk src(source_base, source, o.source_center, o.source_radius, o.source_direction,
                               o.rotation_deg, o.geodesic, o.texture);
  report(o.progress, 0.3, "source disk");
  TransferResult res;
  res.source_patch = src.patch;
  res.source_center = o.source_center;
  res.target_center = o.target_center;
  const double lateral = o.target_radius / o.source_radius;
  res.height_factor = detail::height_factor(o.height_rule, o.source_radius, o.target_radius, o.height_scale);

  // The target patch, refined first where it is coarser than the source scaled to it.
  res.target = target_base;
  Eigen::VectorXd dist = HeatGeodesics(res.target, o.geodesic).distance(o.target_center);
  const DiskPatch coarse = extract_disk_patch(res.target, o.target_center, o.target_radius, dist);  // a disk?
  std::vector<char> descends;  // per refined vertex: 2 where it descends from the coarse disk's vertices only
  {
    // Refined within 1.1 × the radius (1); the coarse disk's vertices are marked 2, so that a new vertex is
    // 2 when both ends of its edge were: the faces with three such corners are the coarse disk's, refined.
    std::vector<char> region(nt);
    for (int i = 0; i < nt; ++i) region[i] = dist[i] <= 1.1 * o.target_radius ? 1 : 0;
    for (int v : coarse.vertices) region[v] = 2;
    const std::string line = detail::refine_for(res.target, region, lateral * src.mean_edge, o.refine_ratio,
                                                &res.added_vertices, {}, &descends);
    if (!line.empty()) {
      res.warnings.push_back(line);
      dist = HeatGeodesics(res.target, o.geodesic).distance(o.target_center);
    }
  }
  try {
    res.target_patch = extract_disk_patch(res.target, o.target_center, o.target_radius, dist);
  } catch (const InvalidInput&) {
    if (res.added_vertices == 0) throw;
    // The refined surface within the radius is not a disk where the coarse one was (its finer faces close a
    // ring around a thin part, or open a hole): keep to the coarse disk's faces, refined, within the radius;
    // failing that, all of them (a refinement of a disk is a disk).
    Eigen::VectorXd d = dist;
    for (Eigen::Index i = 0; i < d.size(); ++i)
      if (descends[i] != 2) d[i] = std::numeric_limits<double>::infinity();
    try {
      res.target_patch = extract_disk_patch(res.target, o.target_center, o.target_radius, d);
    } catch (const InvalidInput&) {
      double all = 0;
      for (Eigen::Index i = 0; i < d.size(); ++i)
        if (std::isfinite(d[i])) all = std::max(all, d[i]);
      res.target_patch = extract_disk_patch(res.target, o.target_center, all, d);
    }
    res.warnings.push_back(fmt::format(
        "the refined target within radius {:.4g} is not a disk (a ring closes around a thin part, or a hole "
        "opens); the patch keeps to the coarse target's disk, refined ({} vertices)",
        o.target_radius, res.target_patch.vertices.size()));
  }
  report(o.progress, 0.6, "target disk");
  const DiskPatch& T = res.target_patch;
  const DiskMap map = disk_map(T, o.target_direction);
  report(o.progress, 0.8, "conformal map");
  res.source_uv = src.uv;
  res.target_uv = map.uv;
  const MatrixX3d e1_patch = detail::vertex_u_directions(T.mesh, map.e1);

  // Sample the source at each target patch vertex's disk coordinate, in the matching local frame.
  const Eigen::Index n = res.target.n_vertices();
  MatrixX3d local = MatrixX3d::Zero(n, 3), e1 = MatrixX3d::Zero(n, 3);
  res.falloff = Eigen::VectorXd::Zero(n);
  for (size_t k = 0; k < T.vertices.size(); ++k) {
    const int v = T.vertices[k];
    const Eigen::Vector2d z = map.uv.row(k).transpose();
    const double w = detail::smoothstep_falloff(z.norm(), o.falloff);
    res.falloff[v] = w;
    e1.row(v) = e1_patch.row(k);
    if (w > 0) local.row(v) = detail::fade(res.height_factor * src.sample(z), w).transpose();
  }
  res.target_vertices = T.vertices.size();
  TextureCodec codec(res.target, o.texture);
  res.texture = texture_from_local(codec, local, e1);
  res.damage = texture_damage(res.target, codec.apply(res.texture));
  if (std::string w = damage_warning(res.damage, static_cast<size_t>(o.damage_warning)); !w.empty())
    res.warnings.push_back(std::move(w));
  report(o.progress, 1.0, "encoding");
  return res;
}

}  // namespace geotex
