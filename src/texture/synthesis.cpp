// Height-and-tilt texture synthesis by best-matching patches (see synthesis.h).

#include "geotex/texture/synthesis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <queue>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/random.h"
#include "geotex/texture/measures.h"
#include "transfer_internal.h"

namespace geotex {

const OptionTable<SynthesisOptions>& SynthesisOptions::table() {
  using O = SynthesisOptions;
  static const auto t = OptionTable<O>()
      .add("exemplar_center", &O::exemplar_center,
           "exemplar base vertex at the centre of the exemplar disk (-1: farthest from the boundary, or nearest "
           "the centroid)",
           at_least(-1))
      .add("exemplar_radius", &O::exemplar_radius,
           "geodesic radius of the exemplar disk, exemplar units (0: 0.95 x the distance to the boundary, or "
           "0.2 sqrt(area))",
           non_negative())
      .add("exemplar_direction", &O::exemplar_direction,
           "the exemplar's anchor: its tangent part at the exemplar centre is turned onto the target's field")
      .add("scale", &O::scale, "target length per exemplar length (0: automatic from exemplar_share)", non_negative())
      .add("exemplar_share", &O::exemplar_share, "automatic scale: the exemplar disk's share of the target's area",
           {0, 1, true, false})
      .add("height_scale", &O::height_scale, "multiply the displacements by this, on top of the scale", non_negative())
      .add("patch_radius", &O::patch_radius, "patch radius as a share of the exemplar disk's radius",
           {0, 0.9, true, false})
      .add("patch_spacing", &O::patch_spacing,
           "a patch is centred wherever a vertex is farther than this share of the patch radius from all centres",
           {0, 1, true, false})
      .add("candidates", &O::candidates, "random exemplar placements compared per patch", at_least(1),
           "Efros and Freeman 2001")
      .add("match_tolerance", &O::match_tolerance,
           "choose at random among placements whose overlap cost is within (1 + this) of the best", non_negative())
      .add("match_samples", &O::match_samples, "overlap vertices compared per placement (at most)", at_least(1))
      .add("blend_power", &O::blend_power, "overlapping patches are averaged with weights (1 - |u|^2/r^2)^(2p)",
           at_least(1))
      .add("direction", &O::direction, "the direction field's guide: its tangent part on the target")
      .nest(&O::field, DirectionFieldOptions::table())
      .add("seed", &O::seed, "random seed: same seed, same result")
      .add("refine_ratio", &O::refine_ratio,
           "refine the target where its edges exceed this times the exemplar's scaled to it (0: never)", non_negative())
      .nest(&O::geodesic, HeatGeodesicOptions::table())
      .nest(&O::texture, TextureOptions::table());
  return t;
}

namespace {

constexpr int kRaster = 128;  // exemplar raster: kRaster × kRaster samples over [−1, 1]²

// The exemplar disk, rastered: local displacements (+u, +v, n) on a grid over the unit disk.
struct Exemplar {
  std::unique_ptr<detail::SourceDisk> disk;
  int center = -1;
  double radius = 0;   // geodesic radius
  double extent = 0;   // R = √(area / π): what |z| = 1 stands for
  double mean_edge = 0;
  std::vector<Vec3> grid;

  Vec3 at(double u, double v) const {  // bilinear, u, v in [−1, 1] (clamped)
    const double gx = std::clamp((u + 1) * 0.5 * (kRaster - 1), 0.0, kRaster - 1.0);
    const double gy = std::clamp((v + 1) * 0.5 * (kRaster - 1), 0.0, kRaster - 1.0);
    const int i = std::min(static_cast<int>(gx), kRaster - 2), j = std::min(static_cast<int>(gy), kRaster - 2);
    const double a = gx - i, b = gy - j;
    auto g = [&](int x, int y) -> const Vec3& { return grid[static_cast<size_t>(y) * kRaster + x]; };
    return (1 - a) * (1 - b) * g(i, j) + a * (1 - b) * g(i + 1, j) + (1 - a) * b * g(i, j + 1) + a * b * g(i + 1, j + 1);
  }
  static double coord(int i) { return -1 + 2.0 * i / (kRaster - 1); }
};

Exemplar make_exemplar(const Mesh& base, const Texture& texture, const SynthesisOptions& o) {
  require_valid(base, "texture synthesis: exemplar base");
  if (texture.height.size() != static_cast<Eigen::Index>(base.n_vertices()) ||
      texture.tilt.size() != static_cast<Eigen::Index>(base.n_edges()))
    throw InvalidInput("texture synthesis: the exemplar texture does not match its base");
  if (o.exemplar_center >= static_cast<int>(base.n_vertices()))
    throw InvalidInput(fmt::format("texture synthesis: exemplar centre {} out of range [0, {})", o.exemplar_center,
                                   base.n_vertices()));
  Exemplar ex;
  const HeatGeodesics geo(base, o.geodesic);
  std::vector<int> rim;
  for (const auto& loop : boundary_loops(base)) rim.insert(rim.end(), loop.begin(), loop.end());
  const Eigen::VectorXd to_rim = rim.empty() ? Eigen::VectorXd() : geo.distance(rim);
  ex.center = o.exemplar_center;
  if (ex.center < 0) {
    if (!rim.empty()) {
      Eigen::Index c = 0;
      to_rim.unaryExpr([](double d) { return std::isfinite(d) ? d : -1.0; }).maxCoeff(&c);
      ex.center = static_cast<int>(c);
    } else {
      const Vec3 g = surface_centroid(base);
      const MatrixX3d X = positions(base);
      Eigen::Index c = 0;
      (X.rowwise() - g.transpose()).rowwise().squaredNorm().minCoeff(&c);
      ex.center = static_cast<int>(c);
    }
  }
  ex.radius = o.exemplar_radius > 0 ? o.exemplar_radius
              : rim.empty()         ? 0.2 * std::sqrt(face_areas(base).sum())
                                    : 0.95 * to_rim[ex.center];
  if (!(ex.radius > 0)) throw InvalidInput("texture synthesis: the exemplar centre lies on the boundary");
  for (int attempt = 0; !ex.disk; ++attempt) {
    try {
      ex.disk = std::make_unique<detail::SourceDisk>(base, texture, ex.center, ex.radius, o.exemplar_direction, 0.0,
                                                     o.geodesic, o.texture);
    } catch (const InvalidInput&) {
      if (attempt >= 8) throw;
      ex.radius *= 0.8;  // not a disk there (a handle, a thin part): shrink
    }
  }
  {  // The length a unit of z stands for: the map's area scale over the inner disk |z| < 0.8 (where patches
     // read; the jagged rim of a geodesic disk, spread evenly on the circle, makes √(area / π) 10 % off).
    const Mesh& pm = ex.disk->patch.mesh;
    const Eigen::VectorXd fa = face_areas(pm);
    const MatrixX3i Fp = faces(pm);
    const MatrixX2d& uv = ex.disk->uv;
    double a3 = 0, a2 = 0;
    for (Eigen::Index f = 0; f < Fp.rows(); ++f) {
      const Eigen::Vector2d p = uv.row(Fp(f, 0)), q = uv.row(Fp(f, 1)), r = uv.row(Fp(f, 2));
      if (((p + q + r) / 3).norm() >= 0.8) continue;
      const Eigen::Vector2d e = q - p, g = r - p;
      a3 += fa[f];
      a2 += 0.5 * std::abs(e.x() * g.y() - e.y() * g.x());
    }
    ex.extent = a2 > 0 ? std::sqrt(a3 / a2) : std::sqrt(fa.sum() / M_PI);
  }
  ex.mean_edge = ex.disk->mean_edge;
  ex.grid.resize(static_cast<size_t>(kRaster) * kRaster);
  for (int j = 0; j < kRaster; ++j)
    for (int i = 0; i < kRaster; ++i)
      ex.grid[static_cast<size_t>(j) * kRaster + i] = ex.disk->sample(Eigen::Vector2d(Exemplar::coord(i), Exemplar::coord(j)));
  return ex;
}

// The rotation taking unit a to unit b about a × b (the parallel transport between nearby tangent planes).
Eigen::Matrix3d turn(const Vec3& a, const Vec3& b) {
  const Vec3 v = a.cross(b);
  const double c = a.dot(b);
  if (c <= -1 + 1e-12) return -Eigen::Matrix3d::Identity();  // opposite normals: a fold; any turn will do
  Eigen::Matrix3d K;
  K << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return Eigen::Matrix3d::Identity() + K + K * K / (1 + c);
}

// Discrete exponential map around one centre (Schmidt et al. 2006, single-parent variant): Dijkstra over
// the edges, each vertex's coordinate its parent's plus the edge expressed in the parent's transported frame.
struct ExpMap {
  std::vector<int> vertices;            // reached, in Dijkstra order
  std::vector<Eigen::Vector2d> uv;      // per reached vertex
  std::vector<Vec3> e1;                 // per reached vertex: the centre's e1 transported there
};

class ExpMapper {
 public:
  ExpMapper(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& N)
      : mesh_(mesh), X_(X), N_(N), dist_(X.rows(), std::numeric_limits<double>::infinity()), slot_(X.rows(), -1),
        parent_(X.rows(), -1) {}

  ExpMap map(int center, const Vec3& e1, double radius) {
    ExpMap m;
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
    std::vector<int> touched{center};
    dist_[center] = 0;
    q.emplace(0.0, center);
    while (!q.empty()) {
      const auto [d, v] = q.top();
      q.pop();
      if (d > dist_[v] || slot_[v] >= 0) continue;
      const int p = parent_[v];
      Eigen::Vector2d u = Eigen::Vector2d::Zero();
      Vec3 f = e1;
      if (p >= 0) {
        const int s = slot_[p];
        const Vec3 np = N_.row(p).transpose(), nv = N_.row(v).transpose();
        const Vec3 fp = m.e1[s], gp = np.cross(fp);
        const Vec3 e = (X_.row(v) - X_.row(p)).transpose();
        const Eigen::Vector2d l(fp.dot(e), gp.dot(e));
        u = m.uv[s] + (l.norm() > 0 ? Eigen::Vector2d(l * (e.norm() / l.norm())) : Eigen::Vector2d::Zero());
        f = turn(np, nv) * fp;
        f = (f - f.dot(nv) * nv).normalized();
      }
      // Stop on the graph distance (it overestimates, so keep a margin) or once the map leaves the disk.
      if (u.norm() > radius) continue;
      slot_[v] = static_cast<int>(m.vertices.size());
      m.vertices.push_back(v);
      m.uv.push_back(u);
      m.e1.push_back(f);
      for (auto w : mesh_.vv_range(mesh_.vertex_handle(v))) {
        const int j = w.idx();
        if (slot_[j] >= 0) continue;
        const double dj = d + (X_.row(j) - X_.row(v)).norm();
        if (dj < dist_[j] && dj <= 1.5 * radius) {
          if (!std::isfinite(dist_[j])) touched.push_back(j);
          dist_[j] = dj;
          parent_[j] = v;
          q.emplace(dj, j);
        }
      }
    }
    for (int v : touched) {
      dist_[v] = std::numeric_limits<double>::infinity();
      slot_[v] = -1;
      parent_[v] = -1;
    }
    return m;
  }

 private:
  const Mesh& mesh_;
  const MatrixX3d& X_;
  const MatrixX3d& N_;
  std::vector<double> dist_;
  std::vector<int> slot_, parent_;
};

Eigen::VectorXd vertex_areas(const Mesh& mesh) {
  const Eigen::VectorXd fa = face_areas(mesh);
  Eigen::VectorXd va = Eigen::VectorXd::Zero(mesh.n_vertices());
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) va[v.idx()] += fa[f.idx()] / 3;
  return va;
}

// Spread the weights of the first \p known vertices onto the rest (refinement's new vertices, each the
// mean of its neighbours already known; new vertices follow the ones they were split from).
Eigen::VectorXd spread_weight(const Mesh& mesh, const Eigen::VectorXd& w0) {
  const Eigen::Index n = mesh.n_vertices(), known = w0.size();
  Eigen::VectorXd w(n);
  w.head(known) = w0;
  std::vector<char> have(n, 0);
  std::fill(have.begin(), have.begin() + known, 1);
  for (bool changed = true; changed;) {
    changed = false;
    for (Eigen::Index i = known; i < n; ++i) {
      if (have[i]) continue;
      double s = 0;
      int c = 0;
      for (auto v : mesh.vv_range(mesh.vertex_handle(static_cast<int>(i))))
        if (have[v.idx()]) s += w[v.idx()], ++c;
      if (c) w[i] = s / c, have[i] = 1, changed = true;
    }
  }
  for (Eigen::Index i = known; i < n; ++i)
    if (!have[i]) w[i] = 0;
  return w;
}

}  // namespace

SynthesisResult synthesize_texture(const Mesh& exemplar_base, const Texture& exemplar, const Mesh& target,
                                   const SynthesisOptions& o, const SynthesisGuides& guides) {
  SynthesisOptions::table().check(o);
  require_valid(target, "texture synthesis: target");
  const Eigen::Index n0 = target.n_vertices();
  if (guides.weight.size() && guides.weight.size() != n0)
    throw InvalidInput(fmt::format("texture synthesis: expected one weight per target vertex ({})", n0));
  if (guides.weight.size() && !(guides.weight.array() >= 0 && guides.weight.array() <= 1).all())
    throw InvalidInput("texture synthesis: weights must lie in [0, 1]");
  if (guides.direction.rows() && guides.direction.rows() != n0)
    throw InvalidInput(fmt::format("texture synthesis: expected one guide direction per target vertex ({})", n0));
  report(o.progress, 0, "exemplar");
  const Exemplar ex = make_exemplar(exemplar_base, exemplar, o);

  SynthesisResult res;
  res.exemplar_center = ex.center;
  res.exemplar_radius = ex.radius;
  res.exemplar_extent = ex.extent;
  Eigen::VectorXd weight = guides.weight.size() ? guides.weight : Eigen::VectorXd::Ones(n0);
  {
    const Eigen::VectorXd fa = face_areas(target);
    double area = 0;
    for (auto f : target.faces()) {
      bool any = false;
      for (auto v : target.fv_range(f)) any |= weight[v.idx()] > 0;
      if (any) area += fa[f.idx()];
    }
    if (!(area > 0)) throw InvalidInput("texture synthesis: the weight is zero everywhere");
    res.scale = o.scale > 0 ? o.scale : std::sqrt(o.exemplar_share * area / (M_PI * ex.extent * ex.extent));
  }
  res.height_factor = res.scale * o.height_scale;

  // Refine where the target is coarser than the exemplar scaled to it.
  res.target = target;
  {
    std::vector<char> region(n0);
    for (Eigen::Index i = 0; i < n0; ++i) region[i] = weight[i] > 0;
    const std::string line =
        detail::refine_for(res.target, region, res.scale * ex.mean_edge, o.refine_ratio, &res.added_vertices);
    if (!line.empty()) res.warnings.push_back(line);
  }
  const Mesh& T = res.target;
  const Eigen::Index n = T.n_vertices();
  res.weight = n > n0 ? spread_weight(T, weight) : weight;
  report(o.progress, 0.05, "direction field");
  const MatrixX3d X = positions(T);
  const MatrixX3d N = vertex_normals(T, o.texture.normals);
  if (guides.direction.rows()) {
    MatrixX3d g(n, 3);
    g.topRows(n0) = guides.direction;
    for (Eigen::Index i = n0; i < n; ++i) g.row(i) = o.direction.transpose();  // new vertices: the global guide
    res.field = direction_field(T, g, o.field);
  } else {
    res.field = direction_field(T, o.direction.transpose(), o.field);
  }
  const MatrixX3d& F = res.field;

  // Patches in a growing front.
  const double rp_ex = o.patch_radius * ex.extent;  // patch radius, exemplar units
  const double rp = res.scale * rp_ex;               // and on the target
  res.patch_radius = rp;
  const double reach = ex.extent - rp_ex;            // placements: |t| ≤ reach keeps the patch in the disk
  const double spacing = o.patch_spacing * rp;
  Rng rng(o.seed);
  ExpMapper expmap(T, X, N);
  std::vector<double> dmin(n, std::numeric_limits<double>::infinity());
  Eigen::VectorXd sumW = Eigen::VectorXd::Zero(n), bmax = Eigen::VectorXd::Zero(n);
  MatrixX3d sumD = MatrixX3d::Zero(n, 3);
  res.owner = Eigen::VectorXi::Constant(n, -1);
  res.copied = MatrixX3d::Zero(n, 3);
  size_t to_cover = 0, covered = 0;
  std::vector<char> wanted(n, 0);
  for (Eigen::Index i = 0; i < n; ++i)
    if (res.weight[i] >= 0.5 && !T.is_isolated(T.vertex_handle(static_cast<int>(i)))) wanted[i] = 1, ++to_cover;
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> front;  // (jittered distance, vertex)
  std::vector<double> key(n, std::numeric_limits<double>::infinity());
  size_t scan = rng.below(static_cast<uint64_t>(std::max<Eigen::Index>(n, 1)));  // where a new component starts
  auto next_center = [&]() -> int {
    while (!front.empty()) {
      const auto [k, v] = front.top();
      front.pop();
      if (k == key[v] && dmin[v] > spacing) return v;
    }
    for (size_t c = 0; c < static_cast<size_t>(n); ++c) {  // nothing in the front: a part not reached yet
      const int v = static_cast<int>((scan + c) % n);
      if (wanted[v] && dmin[v] > spacing) {
        scan = v;
        return v;
      }
    }
    return -1;
  };

  std::vector<Vec3> cand;  // per patch vertex: a placement's displacement in the vertex's field frame
  for (int c = next_center(); c >= 0; c = next_center()) {
    const int patch = static_cast<int>(res.centers.size());
    res.centers.push_back(c);
    const ExpMap m = expmap.map(c, F.row(c).transpose(), rp);
    const size_t k = m.vertices.size();
    // Per patch vertex: blend weight b. The exemplar's frame (+u, +v, n) maps onto the field's frame at
    // each vertex (not the patch's transported one, which turns away from the field by up to a few
    // degrees across a patch): the lean follows the field exactly, and overlapping patches agree on it.
    std::vector<double> b(k);
    std::vector<size_t> overlap;
    for (size_t s = 0; s < k; ++s) {
      const int v = m.vertices[s];
      const double r2 = m.uv[s].squaredNorm() / (rp * rp);
      b[s] = r2 < 1 ? (1 - r2) * (1 - r2) : 0.0;
      if (b[s] > 0 && sumW[v] > 0) overlap.push_back(s);
    }
    // A placement t (exemplar units): vertex s reads the exemplar at t + uv_s / scale.
    auto read = [&](const Eigen::Vector2d& t, size_t s, Vec3* raw) {
      const Eigen::Vector2d p = (t + m.uv[s] / res.scale) / ex.extent;
      const Vec3 d = res.height_factor * ex.at(p.x(), p.y());
      if (raw) *raw = d;
      return d;
    };
    auto random_placement = [&] {
      double a = rng.uniform(0, 2 * M_PI), r = reach * std::sqrt(rng.uniform());
      return Eigen::Vector2d(r * std::cos(a), r * std::sin(a));
    };
    Eigen::Vector2d t = random_placement();
    if (!overlap.empty() && o.candidates > 1) {
      if (overlap.size() > static_cast<size_t>(o.match_samples)) {  // a seeded subsample
        for (size_t i = 0; i < static_cast<size_t>(o.match_samples); ++i)
          std::swap(overlap[i], overlap[i + rng.below(overlap.size() - i)]);
        overlap.resize(o.match_samples);
      }
      std::vector<Eigen::Vector2d> ts(o.candidates);
      std::vector<double> cost(o.candidates, 0.0);
      ts[0] = t;
      for (int q = 1; q < o.candidates; ++q) ts[q] = random_placement();
      for (int q = 0; q < o.candidates; ++q)
        for (size_t s : overlap) {
          const int v = m.vertices[s];
          const Vec3 old = sumD.row(v).transpose() / sumW[v];
          cost[q] += b[s] * (read(ts[q], s, nullptr) - old).squaredNorm();
        }
      const double best = *std::min_element(cost.begin(), cost.end());
      std::vector<int> good;
      for (int q = 0; q < o.candidates; ++q)
        if (cost[q] <= (1 + o.match_tolerance) * best + 1e-300) good.push_back(q);
      t = ts[good[rng.below(good.size())]];
    }
    // Blend the chosen placement in.
    for (size_t s = 0; s < k; ++s) {
      const int v = m.vertices[s];
      if (m.uv[s].norm() < dmin[v]) {
        const bool was = dmin[v] <= spacing;
        dmin[v] = m.uv[s].norm();
        if (wanted[v] && !was && dmin[v] <= spacing) ++covered;
        if (wanted[v] && dmin[v] > spacing) {
          key[v] = dmin[v] * (1 + 0.3 * rng.uniform());  // seeded jitter: no fixed order of growth
          front.emplace(key[v], v);
        }
      }
      if (!(b[s] > 0)) continue;
      Vec3 raw;
      const Vec3 d = read(t, s, &raw);
      const double w = std::pow(b[s], o.blend_power);
      sumW[v] += w;
      sumD.row(v) += w * d.transpose();
      if (b[s] > bmax[v]) {
        bmax[v] = b[s];
        res.owner[v] = patch;
        res.copied.row(v) = raw.transpose();
      }
    }
    report(o.progress, 0.1 + 0.8 * (to_cover ? double(covered) / to_cover : 1.0), "patches");
  }
  if (covered < to_cover)
    res.warnings.push_back(fmt::format("{} of {} vertices were not reached by any patch (disconnected from the "
                                       "rest and too small for a patch?)",
                                       to_cover - covered, to_cover));

  report(o.progress, 0.9, "encode");
  res.local = MatrixX3d::Zero(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    if (sumW[i] > 0) res.local.row(i) = detail::fade(sumD.row(i).transpose() / sumW[i], res.weight[i]).transpose();
  TextureCodec codec(T, o.texture);
  res.texture = texture_from_local(codec, res.local, F);
  res.textured = codec.apply(res.texture);
  report(o.progress, 1, "done");
  return res;
}

// ---------------------------------------------------------------------------------------------
// Measures

std::vector<int> height_features(const MatrixX3d& P, const Eigen::VectorXd& h, double radius, double threshold) {
  if (P.rows() != h.size()) throw InvalidInput("height features: expected one height per point");
  std::vector<int> order;
  for (Eigen::Index i = 0; i < h.size(); ++i)
    if (h[i] >= threshold) order.push_back(static_cast<int>(i));
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return h[a] > h[b]; });
  std::vector<int> out;
  const double r2 = radius * radius;
  for (int i : order) {
    bool free = true;
    for (int j : out)
      if ((P.row(i) - P.row(j)).squaredNorm() < r2) {
        free = false;
        break;
      }
    if (free) out.push_back(i);
  }
  return out;
}

namespace {

// Mean nearest-neighbour distance of points \p idx; only points with \p keep (their neighbour nearer than
// the rim) count. \return 0 with fewer than two.
double mean_spacing(const MatrixX3d& P, const std::vector<int>& idx, const std::vector<double>& rim = {}) {
  double sum = 0;
  size_t count = 0;
  for (size_t a = 0; a < idx.size(); ++a) {
    double best = std::numeric_limits<double>::infinity();
    for (size_t b = 0; b < idx.size(); ++b)
      if (a != b) best = std::min(best, (P.row(idx[a]) - P.row(idx[b])).norm());
    if (!std::isfinite(best) || (!rim.empty() && best > rim[a])) continue;
    sum += best;
    ++count;
  }
  return count ? sum / count : 0.0;
}

double pseudo_height(const Vec3& d) { return (d.z() < 0 ? -1.0 : 1.0) * d.norm(); }  // Eq. 8.5

}  // namespace

SynthesisQuality synthesis_quality(const Mesh& exemplar_base, const Texture& exemplar, const SynthesisResult& r,
                                   const SynthesisOptions& o) {
  const Exemplar ex = make_exemplar(exemplar_base, exemplar, o);
  const Mesh& T = r.target;
  const Eigen::Index n = T.n_vertices();
  if (r.texture.height.size() != n || r.owner.size() != n || r.local.rows() != n)
    throw InvalidInput("synthesis quality: the result does not match its target");
  SynthesisQuality q;

  // The exemplar's heights on its raster (the unit disk, |z| ≤ 1; uniform area up to the conformal map).
  const double unit = r.scale * ex.extent;  // target length of a unit-disk length
  std::vector<int> in_disk;
  for (int j = 0; j < kRaster; ++j)
    for (int i = 0; i < kRaster; ++i)
      if (std::hypot(Exemplar::coord(i), Exemplar::coord(j)) <= 1) in_disk.push_back(j * kRaster + i);
  const Eigen::Index ne = static_cast<Eigen::Index>(in_disk.size());
  Eigen::VectorXd he(ne), ae = Eigen::VectorXd::Ones(ne);
  MatrixX3d Pe = MatrixX3d::Zero(ne, 3);
  std::vector<double> rim(ne);
  for (Eigen::Index k = 0; k < ne; ++k) {
    const int i = in_disk[k] % kRaster, j = in_disk[k] / kRaster;
    he[k] = r.height_factor * pseudo_height(ex.grid[in_disk[k]]);
    Pe(k, 0) = unit * Exemplar::coord(i);
    Pe(k, 1) = unit * Exemplar::coord(j);
    rim[k] = unit * (1 - std::hypot(Exemplar::coord(i), Exemplar::coord(j)));
  }
  // The target's covered vertices.
  const Eigen::VectorXd va = vertex_areas(T);
  std::vector<int> cov;
  double want_area = 0, cov_area = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(r.weight[i] > 0)) continue;
    want_area += va[i];
    if (r.owner[i] >= 0) cov.push_back(static_cast<int>(i)), cov_area += va[i];
  }
  q.coverage = want_area > 0 ? cov_area / want_area : 0.0;
  const Eigen::VectorXd& ht = r.texture.height;

  // Histograms.
  double lo = he.minCoeff(), hi = he.maxCoeff();
  for (int i : cov) lo = std::min(lo, ht[i]), hi = std::max(hi, ht[i]);
  constexpr int kBins = 40;
  const double width = hi > lo ? (hi - lo) / kBins : 1.0;
  Eigen::VectorXd H1 = Eigen::VectorXd::Zero(kBins), H2 = Eigen::VectorXd::Zero(kBins);
  auto bin = [&](double h) { return std::clamp(static_cast<int>((h - lo) / width), 0, kBins - 1); };
  for (Eigen::Index k = 0; k < ne; ++k) H1[bin(he[k])] += ae[k];
  for (int i : cov) H2[bin(ht[i])] += va[i];
  if (H1.sum() > 0) H1 /= H1.sum();
  if (H2.sum() > 0) H2 /= H2.sum();
  q.histogram_tv = 0.5 * (H1 - H2).cwiseAbs().sum();
  double cdf = 0, w1 = 0;
  for (int b = 0; b < kBins; ++b) cdf += H1[b] - H2[b], w1 += std::abs(cdf) * width;
  const double mean_abs_e = he.cwiseAbs().mean();
  q.histogram_w1 = mean_abs_e > 0 ? w1 / mean_abs_e : 0.0;
  q.exemplar_rms = std::sqrt(he.squaredNorm() / ne);
  {
    double s2 = 0, a = 0;
    for (int i : cov) s2 += va[i] * ht[i] * ht[i], a += va[i];
    q.target_rms = a > 0 ? std::sqrt(s2 / a) : 0.0;
  }

  // Features: NMS radius = twice the exemplar's correlation length (the shortest lag along u and v where
  // the autocorrelation of its heights reaches 0: a quarter period of a sinusoid, a bump's half width),
  // threshold = mean + std.
  const double mean_e = he.mean(), std_e = std::sqrt((he.array() - mean_e).square().mean());
  double corr = 0;
  {
    std::vector<double> g(static_cast<size_t>(kRaster) * kRaster, std::nan(""));
    for (Eigen::Index k = 0; k < ne; ++k) g[in_disk[k]] = he[k] - mean_e;
    int lag_found = kRaster / 4;
    for (int lag = 1; lag < kRaster / 4; ++lag) {
      double s = 0, s0 = 0;
      for (int j = 0; j < kRaster; ++j)
        for (int i = 0; i + lag < kRaster; ++i) {
          const double a = g[j * kRaster + i], bx = g[j * kRaster + i + lag];
          const double by = j + lag < kRaster ? g[(j + lag) * kRaster + i] : std::nan("");
          if (std::isnan(a)) continue;
          if (!std::isnan(bx)) s += a * bx, s0 += a * a;
          if (!std::isnan(by)) s += a * by, s0 += a * a;
        }
      if (s0 > 0 && s / s0 < 0) {
        lag_found = lag;
        break;
      }
    }
    corr = 2 * unit * 2.0 * lag_found / (kRaster - 1);  // twice the lag: one bump, one feature
  }
  const double thr = mean_e + std_e;
  const std::vector<int> fe = height_features(Pe, he, corr, thr);
  std::vector<double> fe_rim;
  for (int k : fe) fe_rim.push_back(rim[k]);
  q.exemplar_features = fe.size();
  q.exemplar_spacing = mean_spacing(Pe, fe, fe_rim);
  {
    Eigen::VectorXd hc(cov.size());
    MatrixX3d Pc(cov.size(), 3);
    for (size_t k = 0; k < cov.size(); ++k) hc[k] = ht[cov[k]], Pc.row(k) = positions(T).row(cov[k]);
    const std::vector<int> ft = height_features(Pc, hc, corr, thr);
    q.target_features = ft.size();
    q.target_spacing = mean_spacing(Pc, ft);
  }
  q.spacing_change = q.exemplar_spacing > 0 ? q.target_spacing / q.exemplar_spacing - 1 : 0.0;

  // Lean direction against the field.
  // The displacements of the textured target (after encoding and decoding) in the field's frames.
  const MatrixX3d Xt = positions(T);
  const MatrixX3d Nt = vertex_normals(T, o.texture.normals);
  MatrixX3d Dl(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3 d = (r.textured.row(i) - Xt.row(i)).transpose(), nv = Nt.row(i).transpose();
    const Vec3 f = r.field.row(i).transpose();
    Dl.row(i) = Eigen::RowVector3d(f.dot(d), nv.cross(f).dot(d), nv.dot(d));
  }
  double hmax = 0;
  for (int i : cov) hmax = std::max(hmax, Dl.row(i).norm());
  double se = 0, sw = 0;
  for (int i : cov) {
    const Vec3 d = Dl.row(i).transpose(), c = r.copied.row(i).transpose();
    const double len = d.norm(), lean = std::atan2(d.head<2>().norm(), std::abs(d.z()));
    const double clean = std::atan2(c.head<2>().norm(), std::abs(c.z()));
    if (len < 0.1 * hmax || lean < 5 * M_PI / 180 || clean < 5 * M_PI / 180) continue;
    double a = std::atan2(d.y(), d.x()) - std::atan2(c.y(), c.x());
    a = std::abs(std::remainder(a, 2 * M_PI));
    const double w = len * std::sin(lean);
    se += w * a;
    sw += w;
  }
  q.lean_angle_error_deg = sw > 0 ? se / sw * 180 / M_PI : 0.0;

  // Steps across seams and within patches.
  const double href = he.cwiseAbs().maxCoeff();  // already times height_factor
  std::vector<double> across, within;
  for (auto e : T.edges()) {
    const auto h = T.halfedge_handle(e, 0);
    const int a = T.from_vertex_handle(h).idx(), b = T.to_vertex_handle(h).idx();
    if (r.owner[a] < 0 || r.owner[b] < 0) continue;
    (r.owner[a] != r.owner[b] ? across : within).push_back(std::abs(ht[a] - ht[b]));
  }
  auto pct = [&](std::vector<double>& v, double p) {
    if (v.empty() || !(href > 0)) return 0.0;
    const size_t k = std::min(v.size() - 1, static_cast<size_t>(p * v.size()));
    std::nth_element(v.begin(), v.begin() + k, v.end());
    return v[k] / href;
  };
  q.seam_step99 = pct(across, 0.99);
  q.seam_step_max = pct(across, 1.0);
  q.within_step99 = pct(within, 0.99);
  q.within_step_max = pct(within, 1.0);

  Mesh textured = T;
  set_positions(textured, r.textured);
  const size_t base_folded = folded_faces(T), tex_folded = folded_faces(textured);
  q.folded = tex_folded > base_folded ? tex_folded - base_folded : 0;
  return q;
}

}  // namespace geotex
