// Whole-surface texture transfer: an atlas of overlapping geodesic disks, each a copy of one source disk,
// pasted along minimum cuts (or blended) where they overlap, then unfolded (see transfer.h).

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/self_intersections.h"
#include "geotex/texture/transfer.h"
#include "seam_cut.h"
#include "transfer_internal.h"

namespace geotex {

const OptionTable<AtlasOptions>& AtlasOptions::table() {
  using O = AtlasOptions;
  static const auto t = OptionTable<O>()
      .add("source_center", &O::source_center, "source base vertex at the centre of the texture patch", non_negative())
      .add("source_radius", &O::source_radius, "geodesic radius of the source patch (source model units)", non_negative())
      .add("source_direction", &O::source_direction, "the source's anchor direction (its tangent part at the centre)")
      .add("target_radius", &O::target_radius, "geodesic radius of each target disk (0: the source radius)",
           non_negative())
      .add("target_direction", &O::target_direction,
           "orientation field on the target: each disk's anchor is this direction's tangent part at its centre")
      .add("spacing", &O::spacing, "disk centres until every vertex is within this share of the radius of one",
           between(0.05, 1))  // below, a disk per vertex or so: a conformal map each, for no visible change
      .choice("overlap", &O::overlap, atlas_overlap_names(),
              "cut: each vertex takes one disk's displacement, the borders minimum cuts of the overlaps; blend: "
              "overlapping disks averaged (ghosts)", "Kwatra et al. 2003")
      .add("blend_power", &O::blend_power,
           "overlap=blend: overlapping disks are averaged with weights (1 - |z|^2)^(2p): large p, narrow blends",
           at_least(1))
      .add("feather", &O::feather, "overlap=cut: rings on either side of a cut over which the two disks are mixed",
           between(0, 16))
      .add("unfold", &O::unfold,
           "shrink the displacements around faces they fold or make cross (beyond the target's own) until none does")
      .add("unfold_radius", &O::unfold_radius, "unfold: radius of each dip, as a share of the target radius",
           between(0.01, 1))
      .choice("height_rule", &O::height_rule, height_rule_names(),
              "patch-radius (heights times target/source radius) or absolute (model units)")
      .add("height_scale", &O::height_scale, "multiply the heights by this, on top of the height rule", between(0, 1e6))
      .add("refine_ratio", &O::refine_ratio,
           "refine the target where its edges exceed this times the source's scaled to it (0: never)", non_negative())
      .add("damage_warning", &O::damage_warning,
           "warn when the textured target has more than this many folded or self-intersecting faces beyond the "
           "bare target's own",
           between(0, 100000000))  // a face count: at most 10^8, as every count flag
      .nest(&O::geodesic, HeatGeodesicOptions::table())
      .nest(&O::texture, TextureOptions::table());
  return t;
}

const EnumNames<AtlasOverlap>& atlas_overlap_names() {
  static const EnumNames<AtlasOverlap> n = {{"cut", AtlasOverlap::Cut}, {"blend", AtlasOverlap::Blend}};
  return n;
}

namespace {

// The vertices the disks of one part cover: \p part is the target itself (to_target empty) or a
// piece of it, whose vertex i is the target's to_target[i].
struct Part {
  const Mesh& mesh;
  std::vector<int> to_target;
  int target(int v) const { return to_target.empty() ? v : to_target[v]; }
};

// What one disk brings: per vertex it covers (weight b = (1 − |z|²)² > 0; the centre first) the part
// vertex, b, the displacement D and the source's mean M in the vertex's frame (world coordinates), and
// what pasting it there costs a cut: kRimCost × |D − M| × the smoothstep from 0 at |z| = spacing to 1 at
// the rim. A feature the source disk's rim cuts through is pasted only where no disk nearer its centre
// (every vertex lies within spacing of a centre) can give that vertex a value as cheaply.
struct DiskSample {
  std::vector<int> local;
  std::vector<double> w, rim;
  std::vector<Vec3> D, M;
};
constexpr double kRimCost = 2.0;


// What the disks leave at each target vertex. Blend: the variance-preserving blend (as by-example
// noise blends, Heitz and Neyret 2018): with normalised weights w̃_k = b_k^p / Σ_j b_j^p,
// D = Σ w̃_k M_k + Σ w̃_k (D_k − M_k) / √(Σ w̃_k²), M_k the source patch's mean displacement in disk k's
// frame (a plain average of two unrelated pieces of texture has 1/√2 of their contrast; this keeps it);
// sums kept relative to the largest b_k seen so far (b^p underflows for large p). Cut: the canvas of
// displacements pasted so far (seam_cut()).
struct Overlaps {
  MatrixX3d sumM, sumDM;
  Eigen::VectorXd sumW, sumW2;
  MatrixX3d cur;           // cut: the displacement so far
  std::vector<char> has;   // cut: whether a disk wrote it
  std::vector<double> rim; // cut: what keeping it costs (DiskSample::rim, mixed as the displacement)

  explicit Overlaps(Eigen::Index n)
      : sumM(MatrixX3d::Zero(n, 3)), sumDM(MatrixX3d::Zero(n, 3)), sumW(Eigen::VectorXd::Zero(n)),
        sumW2(Eigen::VectorXd::Zero(n)), cur(MatrixX3d::Zero(n, 3)), has(n, 0), rim(n, 0.0) {}
  MatrixX3d displacements(AtlasOverlap rule) const {
    if (rule == AtlasOverlap::Cut) return cur;
    MatrixX3d D = MatrixX3d::Zero(cur.rows(), 3);
    for (Eigen::Index i = 0; i < D.rows(); ++i)
      if (sumW[i] > 0) D.row(i) = sumM.row(i) / sumW[i] + sumDM.row(i) / std::sqrt(sumW2[i]);
    return D;
  }
};

void blend_in(const Part& part, const DiskSample& d, int disk, double power, AtlasResult& res, Overlaps& b) {
  for (size_t k = 0; k < d.local.size(); ++k) {
    const int v = part.target(d.local[k]);
    const double w = d.w[k];
    if (w > res.coverage[v]) {  // rescale the sums to the new largest weight
      const double f = res.coverage[v] > 0 ? std::pow(res.coverage[v] / w, power) : 0.0;
      b.sumW[v] *= f;
      b.sumW2[v] *= f * f;
      b.sumM.row(v) *= f;
      b.sumDM.row(v) *= f;
      res.coverage[v] = w;
      res.owner[v] = disk;
    }
    const double wp = std::pow(w / res.coverage[v], power);
    b.sumW[v] += wp;
    b.sumW2[v] += wp * wp;
    b.sumM.row(v) += wp * d.M[k].transpose();
    b.sumDM.row(v) += wp * (d.D[k] - d.M[k]).transpose();
  }
}

// Paste the disk along a minimum cut of its overlap with the disks before it (seam_cut()).
void cut_in(const Part& part, const DiskSample& d, int disk, int feather, AtlasResult& res, Overlaps& c) {
  std::vector<Vec3> old(d.local.size(), Vec3::Zero());
  std::vector<double> old_rim(d.local.size(), 0.0);
  for (size_t k = 0; k < d.local.size(); ++k) {
    const int v = part.target(d.local[k]);
    if (c.has[v]) old[k] = c.cur.row(v).transpose(), old_rim[k] = c.rim[v];
  }
  const std::vector<double> share = detail::seam_cut(
      part.mesh, d.local, d.D, old, [&](int w) { return c.has[part.target(w)] != 0; }, feather, d.rim, old_rim, false);
  for (size_t k = 0; k < d.local.size(); ++k) {
    const int v = part.target(d.local[k]);
    res.coverage[v] = std::max(res.coverage[v], d.w[k]);
    if (!(share[k] > 0)) continue;
    c.cur.row(v) = ((1 - share[k]) * old[k] + share[k] * d.D[k]).transpose();
    c.rim[v] = (1 - share[k]) * old_rim[k] + share[k] * d.rim[k];
    c.has[v] = 1;
    if (share[k] >= 0.5) res.owner[v] = disk;
  }
}

// The disk around part vertex \p c, shrunk when the full radius is not a disk there (a thin part, a
// handle), sampled from the source; \return false when no radius down to R/2 gives a disk.
bool sample_disk(const Part& part, int c, const Eigen::VectorXd& dist, const MatrixX3d& N,
                 const detail::SourceDisk& src, double R, const AtlasOptions& o, double height_factor, DiskSample& out) {
  DiskPatch patch;
  bool ok = false;
  for (double r = R; !ok && r >= 0.5 * R; r *= 0.8) {
    try {
      patch = extract_disk_patch(part.mesh, c, r, dist);
      ok = true;
    } catch (const InvalidInput&) {
    }
  }
  if (!ok) return false;
  const DiskMap map = disk_map(patch, o.target_direction);
  const MatrixX3d e1 = detail::vertex_u_directions(patch.mesh, map.e1);
  const Vec3 mean_local = src.mean_local();
  out = DiskSample{};
  std::vector<size_t> order(patch.vertices.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::swap(order[0], order[patch.center]);  // the centre first
  for (size_t k : order) {
    const int v = part.target(patch.vertices[k]);
    const Eigen::Vector2d z = map.uv.row(k).transpose();
    const double w = std::pow(std::max(0.0, 1 - z.squaredNorm()), 2);
    if (!(w > 0)) continue;
    const Eigen::Matrix3d frame = local_frame(N.row(v).transpose(), e1.row(k).transpose());
    out.local.push_back(patch.vertices[k]);
    out.w.push_back(w);
    out.D.push_back(frame * (height_factor * src.sample(z)));
    out.M.push_back(frame * (height_factor * mean_local));
    const double t = std::clamp((z.norm() - o.spacing) / std::max(1 - o.spacing, 1e-9), 0.0, 1.0);
    out.rim.push_back(kRimCost * t * t * (3 - 2 * t) * (out.D.back() - out.M.back()).norm());
  }
  return !out.local.empty();
}

// Farthest-point sampling of disk centres over one part; each disk is pasted (or blended) in as soon as
// it is placed. A centre in a component no disk has reached yet moves to the vertex farthest from it (an
// extremity, so the disks pack from the outside in). \return the disks left out (not disks).
size_t place_disks(const Part& part, const HeatGeodesics& geo, const MatrixX3d& N, const detail::SourceDisk& src,
                   double R, const AtlasOptions& o, AtlasResult& res, Overlaps& b) {
  const Mesh& T = part.mesh;
  const Eigen::Index n = T.n_vertices();
  Eigen::VectorXd dmin = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  for (auto v : T.vertices())
    if (T.is_isolated(v)) dmin[v.idx()] = 0;  // nothing to cover
  size_t skipped = 0;
  Eigen::Index next = 0;
  DiskSample sample;
  for (int c = dmin.maxCoeff(&next) > o.spacing * R ? static_cast<int>(next) : -1; c >= 0;) {
    if (std::isinf(dmin[c])) {  // a component's first disk: start from its extremity
      const Eigen::VectorXd d0 = geo.distance(c);
      double best = -1;
      for (Eigen::Index i = 0; i < n; ++i)
        if (std::isfinite(d0[i]) && d0[i] > best && !T.is_isolated(T.vertex_handle(static_cast<int>(i)))) {
          best = d0[i];
          c = static_cast<int>(i);
        }
    }
    const Eigen::VectorXd d = geo.distance(c);
    dmin = dmin.cwiseMin(d);
    if (sample_disk(part, c, d, N, src, R, o, res.height_factor, sample)) {
      const int disk = static_cast<int>(res.centers.size());
      if (o.overlap == AtlasOverlap::Cut) cut_in(part, sample, disk, o.feather, res, b);
      else blend_in(part, sample, disk, o.blend_power, res, b);
      res.centers.push_back(part.target(c));
    } else {
      ++skipped;
      for (Eigen::Index i = 0; i < n; ++i)  // give up around it rather than retry forever
        if (d[i] <= o.spacing * R) dmin[i] = 0;
    }
    // The next centre: the vertex farthest from every centre so far, unless all are close enough.
    const double gap = dmin.maxCoeff(&next);
    c = gap > o.spacing * R ? static_cast<int>(next) : -1;
    if (o.progress && part.to_target.empty())
      report(o.progress, c < 0 ? 1.0 : double((dmin.array() <= o.spacing * R).count()) / n, "disks");
  }
  return skipped;
}

constexpr double kSnap = 0.01;

// The faces with an edge that crosses one of the faces \p still at positions \p P (sharing no vertex with
// it; self_intersecting_faces()' test, segment_crosses_triangle()).
std::vector<int> crossing_faces(const MatrixX3d& P, const MatrixX3i& F, const std::vector<int>& still) {
  std::vector<int> out;
  for (int s : still) {
    const Vec3 A = P.row(F(s, 0)).transpose(), B = P.row(F(s, 1)).transpose(), C = P.row(F(s, 2)).transpose();
    const Vec3 lo = A.cwiseMin(B).cwiseMin(C), hi = A.cwiseMax(B).cwiseMax(C), e1 = B - A, e2 = C - A;
    for (Eigen::Index g = 0; g < F.rows(); ++g) {
      if ((F.row(g).array() == F(s, 0) || F.row(g).array() == F(s, 1) || F.row(g).array() == F(s, 2)).any()) continue;
      for (int k = 0; k < 3; ++k) {
        const Vec3 a = P.row(F(g, k)).transpose(), b = P.row(F(g, (k + 1) % 3)).transpose();
        if ((a.cwiseMax(b).array() < lo.array()).any() || (a.cwiseMin(b).array() > hi.array()).any()) continue;
        if (segment_crosses_triangle(a, b - a, A, e1, e2)) {
          out.push_back(static_cast<int>(g));
          break;
        }
      }
    }
  }
  return out;
}

// The faces to dip about this round: every damaged face, and where a face damaged beyond the target's own
// has no displacement left on its corners (it stands still: a spike from elsewhere crosses it, e.g. from
// the teapot's handle through its bare body), the faces whose edges cross it (at most kStillSearched of
// them a round: each is a pass over every face).
constexpr size_t kStillSearched = 64;
std::vector<int> dip_centres(const MatrixX3d& P, const MatrixX3i& F, const std::vector<char>& now,
                             const std::vector<char>& base, const Eigen::VectorXd& alpha, const MatrixX3d& D) {
  std::vector<int> centres, still;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (!now[f]) continue;
    centres.push_back(static_cast<int>(f));
    bool moved = false;
    for (int k = 0; k < 3; ++k) moved |= alpha[F(f, k)] > 0 && D.row(F(f, k)).squaredNorm() > 0;
    if (!base[f] && !moved && still.size() < kStillSearched) still.push_back(static_cast<int>(f));
  }
  const std::vector<int> more = crossing_faces(P, F, still);
  centres.insert(centres.end(), more.begin(), more.end());
  return centres;
}

// Shrink the displacements \p D (#V by 3) around the faces that X + D folds or makes cross another face
// (detail::damaged_faces()) and the bare X does not, smoothly: each round multiplies them by
// 1 − 0.25 exp(−d² / ρ²), d the distance on the bare target from the damaged face's centroid (within 2ρ),
// about every damaged face (the target's own too, while others are), until none is damaged beyond the
// target's own (at most 40 rounds; a step cut would fold the surface at its rim, and a dip about a spike's
// foot lowers the whole spike). \return the vertices shrunk by over 1 %; \p rounds the rounds
// that found damage. A displacement lowered below kSnap of itself is removed (set to 0).
size_t unfold_atlas(const Mesh& T, double rho, MatrixX3d& D, int& rounds, const ProgressFn& progress) {
  const MatrixX3d X = positions(T);
  const MatrixX3i F = faces(T);
  const std::vector<char> base = detail::damaged_faces(T, X);
  Eigen::VectorXd alpha = Eigen::VectorXd::Ones(X.rows());
  std::vector<int> seen(X.rows(), -1), queue;
  int visit = 0;
  rounds = 0;
  for (int round = 0; round < 40; ++round) {
    report(progress, round / 40.0, "unfold");
    const MatrixX3d P = X + alpha.asDiagonal() * D;
    const std::vector<char> now = detail::damaged_faces(T, P);
    bool any = false;
    for (Eigen::Index f = 0; f < F.rows(); ++f) any |= now[f] && !base[f];
    if (!any) break;
    // The target's own folded or crossing faces are lowered too: damage there cannot be told from its own,
    // and displacements standing on them were never lowered, so a face they crossed stayed damaged however
    // low it went (beetle: all 40 rounds found damage, one face was left). A face crossed beyond the own
    // with nothing displaced on it is crossed from elsewhere: dips about the faces crossing it (teapot: 6
    // such faces were left after 40 rounds, crossed by spikes whose feet no dip reached).
    for (int f : dip_centres(P, F, now, base, alpha, D)) {
      const Vec3 c = (X.row(F(f, 0)) + X.row(F(f, 1)) + X.row(F(f, 2))).transpose() / 3;
      queue.assign({F(f, 0), F(f, 1), F(f, 2)});
      for (int v : queue) seen[v] = visit;
      for (size_t i = 0; i < queue.size(); ++i) {
        const int v = queue[i];
        alpha[v] *= 1 - 0.25 * std::exp(-(X.row(v).transpose() - c).squaredNorm() / (rho * rho));
        for (auto w : T.vv_range(T.vertex_handle(v)))
          if (seen[w.idx()] != visit && (X.row(w.idx()).transpose() - c).norm() < 2 * rho)
            seen[w.idx()] = visit, queue.push_back(w.idx());
      }
      ++visit;
    }
    // A displacement lowered below kSnap of itself is removed: where the target's own sheets touch (the
    // teapot's patches meet along seams of duplicated vertices, which its refinement moves apart by a hair
    // on each side), two sheets displaced by different amounts cross however small the amounts are (the
    // crossing depends on their directions only), so geometric dips never end there (teapot: 96 of the 99
    // faces left beyond its own touched a seam, under displacements of 1e-7 and less; 40 rounds).
    for (Eigen::Index i = 0; i < alpha.size(); ++i)
      if (alpha[i] < kSnap) alpha[i] = 0;
    ++rounds;
  }
  report(progress, 1.0, "unfold");
  size_t shrunk = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    shrunk += alpha[i] < 0.99 && D.row(i).norm() > 0;  // a zero displacement is not reduced
    D.row(i) *= alpha[i];
  }
  return shrunk;
}

// Components packed into parts of at least kPartVertices vertices (a larger component is a part of
// its own), in the order of their first vertex. Each disk costs a heat solve and passes over its whole
// part: over the whole target, 10^5 disjoint triangles (a disk each) cost minutes (issue 30).
constexpr int kPartVertices = 64;

std::vector<std::vector<int>> parts_of(const Mesh& T) {
  int k = 0;
  const Eigen::VectorXi comp = connected_components(T, &k);
  std::vector<std::vector<int>> members(k);
  for (int v = 0; v < comp.size(); ++v) members[comp[v]].push_back(v);
  std::vector<std::vector<int>> parts(1);
  for (const auto& m : members) {
    if (static_cast<int>(parts.back().size()) >= kPartVertices) parts.emplace_back();
    parts.back().insert(parts.back().end(), m.begin(), m.end());
  }
  return parts;
}

}  // namespace

AtlasResult cover_with_texture(const Mesh& source_base, const Texture& source, const Mesh& target_base,
                               const AtlasOptions& o) {
  AtlasOptions::table().check(o);
  require_valid(source_base, "texture atlas: source base");
  require_valid(target_base, "texture atlas: target base");
  if (source.height.size() != static_cast<Eigen::Index>(source_base.n_vertices()) ||
      source.tilt.size() != static_cast<Eigen::Index>(source_base.n_edges()))
    throw InvalidInput("texture atlas: the source texture does not match the source base");
  if (!(o.source_radius > 0)) throw InvalidInput("texture atlas: the source radius must be positive");
  const detail::SourceDisk src(source_base, source, o.source_center, o.source_radius, o.source_direction, 0.0,
                               o.geodesic, o.texture);
  const double R = o.target_radius > 0 ? o.target_radius : o.source_radius;
  AtlasResult res;
  res.source_center = o.source_center;
  res.height_factor = detail::height_factor(o.height_rule, o.source_radius, R, o.height_scale);
  res.target = target_base;
  {
    const std::string line = detail::refine_for(res.target, std::vector<char>(res.target.n_vertices(), 1),
                                                R / o.source_radius * src.mean_edge, o.refine_ratio,
                                                &res.added_vertices);
    if (!line.empty()) res.warnings.push_back(line);
  }
  const Mesh& T = res.target;
  const Eigen::Index n = T.n_vertices();
  const MatrixX3d N = vertex_normals(T, o.texture.normals);
  Overlaps b(n);
  res.coverage = Eigen::VectorXd::Zero(n);
  res.owner = Eigen::VectorXi::Constant(n, -1);
  size_t skipped = 0;
  const std::vector<std::vector<int>> parts = parts_of(T);
  if (parts.size() == 1) {
    skipped = place_disks(Part{T, {}}, HeatGeodesics(T, o.geodesic), N, src, R, o, res, b);
  } else {
    // Each part's heat time the target's: t = time_factor h², h the target's mean edge length.
    const double h = mean_edge_length(T);
    const MatrixX3d X = positions(T);
    const MatrixX3i F = faces(T);
    std::vector<int> part_of(n, -1), local(n, -1);
    for (size_t p = 0; p < parts.size(); ++p)
      for (size_t i = 0; i < parts[p].size(); ++i) part_of[parts[p][i]] = static_cast<int>(p), local[parts[p][i]] = static_cast<int>(i);
    std::vector<std::vector<int>> part_faces(parts.size());
    for (Eigen::Index f = 0; f < F.rows(); ++f) part_faces[part_of[F(f, 0)]].push_back(static_cast<int>(f));
    Eigen::Index done = 0;
    for (size_t p = 0; p < parts.size(); ++p) {
      MatrixX3d Xp(parts[p].size(), 3);
      for (size_t i = 0; i < parts[p].size(); ++i) Xp.row(i) = X.row(parts[p][i]);
      MatrixX3i Fp(part_faces[p].size(), 3);
      for (size_t j = 0; j < part_faces[p].size(); ++j)
        for (int a = 0; a < 3; ++a) Fp(j, a) = local[F(part_faces[p][j], a)];
      if (Fp.rows() == 0) continue;  // isolated vertices only: nothing to cover
      const Mesh piece = make_mesh(Xp, Fp);
      HeatGeodesicOptions g = o.geodesic;
      if (piece.n_edges() > 0) g.time_factor *= std::pow(h / mean_edge_length(piece), 2);
      skipped += place_disks(Part{piece, parts[p]}, HeatGeodesics(piece, g), N, src, R, o, res, b);
      done += static_cast<Eigen::Index>(parts[p].size());
      if (o.progress) report(o.progress, double(done) / n, "disks");
    }
  }
  if (skipped)
    res.warnings.push_back(fmt::format("{} disk(s) of radius down to {:.4g} were not disks (thin parts or handles) "
                                       "and were left out: coverage may have gaps there",
                                       skipped, 0.5 * R));
  MatrixX3d D = b.displacements(o.overlap);
  if (o.unfold) {
    res.unfolded_vertices = unfold_atlas(T, o.unfold_radius * R, D, res.unfold_rounds, o.progress);
    if (res.unfolded_vertices)
      res.warnings.push_back(fmt::format("{} vertices' displacements were lowered so that no face folds or crosses "
                                         "another ({} rounds)", res.unfolded_vertices, res.unfold_rounds));
  }
  TextureCodec codec(T, o.texture);
  res.texture = codec.from_displacements(D);
  res.damage = texture_damage(T, codec.apply(res.texture));
  if (std::string w = damage_warning(res.damage, static_cast<size_t>(o.damage_warning)); !w.empty())
    res.warnings.push_back(std::move(w));
  return res;
}

}  // namespace geotex
