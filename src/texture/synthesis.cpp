// Height-and-tilt texture synthesis by best-matching patches (see synthesis.h).

#include "geotex/texture/synthesis.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <iterator>
#include <memory>
#include <optional>
#include <queue>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/random.h"
#include "geotex/core/self_intersections.h"
#include "geotex/core/spatial.h"
#include "geotex/texture/measures.h"
#include "keep_out.h"
#include "seam_cut.h"
#include "transfer_internal.h"

namespace geotex {

const EnumNames<SeamMethod>& seam_method_names() {
  static const EnumNames<SeamMethod> n = {{"cut", SeamMethod::Cut}, {"blend", SeamMethod::Blend}};
  return n;
}

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
      .add("scale", &O::scale, "target length per exemplar length (0: automatic from exemplar_share)", between(0, 1e9))
      .add("exemplar_share", &O::exemplar_share,
           "automatic scale: the exemplar disk's share of the target's area (0: 0.05, or more, at most 0.5, where "
           "the refined target would exceed vertex_budget)",
           between(0, 1))
      .add("height_scale", &O::height_scale, "multiply the displacements by this, on top of the scale", between(0, 1e6))
      .add("patch_radius", &O::patch_radius, "patch radius as a share of the exemplar disk's radius",
           {0, 0.9, true, false})
      .add("patch_spacing", &O::patch_spacing,
           "a patch is centred wherever a vertex is farther than this share of the patch radius from all centres",
           {0, 1, true, false})
      .add("candidates", &O::candidates, "random exemplar placements compared per patch", between(1, 1000),
           "Efros and Freeman 2001")
      .add("match_tolerance", &O::match_tolerance,
           "choose at random among placements whose overlap cost is within (1 + this) of the best", non_negative())
      .add("match_samples", &O::match_samples, "overlap vertices compared per placement (at most)", at_least(1))
      .choice("seams", &O::seams, seam_method_names(),
              "cut: each vertex keeps one patch's displacement, the border a minimum cut of the overlap; blend: "
              "overlaps averaged", "Kwatra et al. 2003")
      .add("blend_power", &O::blend_power, "seams=blend: overlapping patches are averaged with weights (1 - |u|^2/r^2)^(2p)",
           at_least(1))
      .add("feather", &O::feather, "seams=cut: rings on either side of a cut over which old and new are mixed",
           at_least(0))
      .add("fold_tries", &O::fold_tries,
           "seams=cut: placements tried in turn until one folds no more faces around the patch (1: no check)",
           at_least(1))
      .add("avoid_crossings", &O::avoid_crossings,
           "seams=cut: placements are also tried in turn until one crosses no more faces near the patch (against "
           "what is placed and the target)")
      .add("drop_collisions", &O::drop_collisions,
           "seams=cut: zero (feathered) the features of a kept placement that still crosses faces")
      .add("fill_holes", &O::fill_holes,
           "seams=cut: after the front, a patch centred wherever a whole feature has room, one of the exemplar's "
           "features at its centre")
      .add("repair_crossings", &O::repair_crossings,
           "where the textured surface still crosses itself, zero the features there, unfold and encode again "
           "(at most 4 times)")
      .add("remove_fragments", &O::remove_fragments,
           "seams=cut: zero (feathered) the displaced regions lower than half the exemplar's lowest whole feature "
           "or smaller than 3/4 of its smallest footprint (broken features) after unfolding")
      .add("drop_folds", &O::drop_folds,
           "seams=cut: zero the features of a kept placement that still folds faces too (not left to unfold)")
      .add("unfold", &O::unfold, "shrink the displacements around faces they fold (by 0.75 a round) until none folds")
      .add("unfold_radius", &O::unfold_radius,
           "the unfolding dip's radius (it reaches twice that) as a share of the patch radius", {0, 1, true, false})
      .add("keep_out_crease_angle", &O::keep_out_crease_angle,
           "keep texture off edges sharper than this dihedral angle, faded in to the texture's span away (0: off)",
           angle_deg())
      .add("keep_out_thin", &O::keep_out_thin,
           "keep texture off parts smaller than its features (the surface within its span under half a disk's area)")
      .add("keep_out_pit_depth", &O::keep_out_pit_depth,
           "keep texture out of closed pits smaller than its span: where the surface round a vertex stands above it "
           "on every side by this share of the ring's radius (0: off)", non_negative())
      .add("keep_out_dome_ridge", &O::keep_out_dome_ridge,
           "keep texture off domes smaller than its span (an eyeball): islands closed round by a ridge whose mean "
           "curvature times the span exceeds this (or a valley below minus half), standing above the surface round "
           "them and alone on it, not one of a field of bumps (0: off)", non_negative())
      .add("direction", &O::direction, "the direction field's guide: its tangent part on the target")
      .nest(&O::field, DirectionFieldOptions::table())
      .add("seed", &O::seed, "random seed: same seed, same result")
      .add("refine_ratio", &O::refine_ratio,
           "refine the target where its edges exceed this times the exemplar's scaled to it (0: never)", non_negative())
      .add("vertex_budget", &O::vertex_budget,
           "automatic exemplar_share: the output vertex count (after refinement) it aims at", between(1000, 1e8))
      .add("max_vertices", &O::max_vertices,
           "refuse, before any work, when the estimated output vertex count exceeds this", between(1000, 1e8))
      .nest(&O::geodesic, HeatGeodesicOptions::table())
      .nest(&O::texture, TextureOptions::table());
  return t;
}

namespace {


// The exemplar disk, rastered: local displacements (+u, +v, n) on a grid over the unit disk.
struct Exemplar {
  std::unique_ptr<detail::SourceDisk> disk;
  int center = -1;
  double radius = 0;   // geodesic radius
  double extent = 0;   // R = √(area / π): what |z| = 1 stands for
  double mean_edge = 0;
  //! The raster: size × size samples over [−1, 1]², at least two per exemplar edge (bilinear reads of a
  //! coarser raster average neighbouring samples: uncorrelated fine relief lost half its rms at 128).
  int size = 128;
  std::vector<Vec3> grid;

  Vec3 at(double u, double v) const {  // bilinear, u, v in [−1, 1] (clamped)
    const double gx = std::clamp((u + 1) * 0.5 * (size - 1), 0.0, size - 1.0);
    const double gy = std::clamp((v + 1) * 0.5 * (size - 1), 0.0, size - 1.0);
    const int i = std::min(static_cast<int>(gx), size - 2), j = std::min(static_cast<int>(gy), size - 2);
    const double a = gx - i, b = gy - j;
    auto g = [&](int x, int y) -> const Vec3& { return grid[static_cast<size_t>(y) * size + x]; };
    return (1 - a) * (1 - b) * g(i, j) + a * (1 - b) * g(i + 1, j) + (1 - a) * b * g(i, j + 1) + a * b * g(i + 1, j + 1);
  }
  double coord(int i) const { return -1 + 2.0 * i / (size - 1); }
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
  ex.size = std::clamp(static_cast<int>(std::ceil(4 * ex.extent / ex.mean_edge)) + 1, 128, 512);
  ex.grid.resize(static_cast<size_t>(ex.size) * ex.size);
  for (int j = 0; j < ex.size; ++j)
    for (int i = 0; i < ex.size; ++i)
      ex.grid[static_cast<size_t>(j) * ex.size + i] = ex.disk->sample(Eigen::Vector2d(ex.coord(i), ex.coord(j)));
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

// The state of a cut synthesis: per vertex the displacement so far (in the field's frame), whether a
// patch wrote it, the patch it came from and the exemplar displacement copied there.
struct Canvas {
  MatrixX3d cur;
  std::vector<char> has;
  Eigen::VectorXi* owner;
  MatrixX3d* copied;
  std::vector<int> slot;  // the current patch's index of a vertex (−1: not in it)
};

// A placement pasted by a minimum cut, not yet committed: per patch vertex its new displacement, the
// exemplar's, and whether it takes it (1), keeps the old one (0), or a mix (feathered, 0 < share < 1).
struct Paste {
  std::vector<Vec3> value, raw;
  std::vector<double> share;  // of the patch's displacement
};

// Paste a patch by a minimum cut (Kwatra, Schödl, Essa, Turk and Bobick, "Graphcut textures", SIGGRAPH
// 2003): on the overlap (patch vertices already written), the vertices next to written ones outside the
// patch keep theirs, those next to unwritten ones inside take the patch's, and the border between the
// two runs along the edges (a, b) of least |old − new|(a) + |old − new|(b), where old and new agree (the
// paper's matching cost). A patch that overlaps everywhere takes at least its centre. The cut is then
// feathered over \p feather rings on either side (the mix goes from ½ at the cut to all at `feather`
// rings), within the overlap, where both are known. Vertices outside the overlap take the patch's.
template <class Read>
Paste cut_paste(const Mesh& T, const ExpMap& m, const std::vector<double>& b, Read read, Canvas& cv, int feather) {
  const size_t k = m.vertices.size();
  Paste p;
  p.value.resize(k);
  p.raw.resize(k);
  p.share.assign(k, 0.0);
  // The patch's vertices (b > 0), its centre first where it has it, cut by seam_cut() (seam_cut.h).
  std::vector<int> vertices;
  std::vector<size_t> index;
  std::vector<Vec3> fresh, old;
  for (size_t s = 0; s < k; ++s) {
    if (!(b[s] > 0)) continue;
    p.value[s] = read(s, &p.raw[s]);
    const int v = m.vertices[s];
    vertices.push_back(v);
    index.push_back(s);
    fresh.push_back(p.value[s]);
    old.push_back(cv.has[v] ? Vec3(cv.cur.row(v).transpose()) : Vec3::Zero());
  }
  const std::vector<double> share = detail::seam_cut(T, vertices, fresh, old, [&](int v) { return cv.has[v] != 0; },
                                                     feather, {}, {}, !index.empty() && index[0] == 0);
  for (size_t i = 0; i < index.size(); ++i) p.share[index[i]] = share[i];
  return p;
}

// The displacement a vertex would hold with \p p (−: unwritten).
template <class F>
void for_pasted(const ExpMap& m, const std::vector<double>& b, const Paste& p, const Canvas& cv, F f) {
  for (size_t s = 0; s < m.vertices.size(); ++s) {
    if (!(b[s] > 0) || !(p.share[s] > 0)) continue;
    const int v = m.vertices[s];
    const Vec3 old = cv.has[v] ? Vec3(cv.cur.row(v).transpose()) : Vec3::Zero();
    f(s, v, (1 - p.share[s]) * old + p.share[s] * p.value[s]);
  }
}

// Faces around a paste: folded (folded_faces()'s test over written faces) after it minus before it.
class FoldCheck {
 public:
  FoldCheck(const Mesh& T, const MatrixX3d& X, const MatrixX3d& N, const MatrixX3d& F)
      : T_(T), X_(X), N_(N), F_(F), Fi_(faces(T)), mark_(Fi_.rows(), 0), temp_(X.rows(), -1) {}

  //! \p fresh (optional) receives the faces folded after and not before.
  long added(const ExpMap& m, const std::vector<double>& b, const Paste& p, const Canvas& cv,
             std::vector<int>* fresh = nullptr) {
    std::vector<int> fs;
    std::vector<Vec3> after;  // per pasted vertex (temp_ indexes it)
    std::vector<int> touched;
    for_pasted(m, b, p, cv, [&](size_t, int v, const Vec3& d) {
      temp_[v] = static_cast<int>(after.size());
      after.push_back(d);
      touched.push_back(v);
      for (auto f : T_.vf_range(T_.vertex_handle(v)))
        if (!mark_[f.idx()]) mark_[f.idx()] = 1, fs.push_back(f.idx());
    });
    long before_count = 0, after_count = 0;
    for (int f : fs) {
      const int was = folded(f, cv, nullptr), is = folded(f, cv, &after);
      before_count += was;
      after_count += is;
      if (fresh && is && !was) fresh->push_back(f);
    }
    for (int f : fs) mark_[f] = 0;
    for (int v : touched) temp_[v] = -1;
    return after_count - before_count;
  }

 private:
  // The displaced position of v (nullopt-like: false when unwritten).
  bool position(int v, const Canvas& cv, const std::vector<Vec3>* after, Vec3& out) const {
    Vec3 d;
    if (after && temp_[v] >= 0) d = (*after)[temp_[v]];
    else if (cv.has[v]) d = cv.cur.row(v).transpose();
    else return false;
    const Vec3 n = N_.row(v).transpose(), f = F_.row(v).transpose();
    out = X_.row(v).transpose() + d.x() * f + d.y() * n.cross(f) + d.z() * n;
    return true;
  }
  bool normal(int f, const Canvas& cv, const std::vector<Vec3>* after, Vec3& out) const {
    Vec3 a, b, c;
    if (!position(Fi_(f, 0), cv, after, a) || !position(Fi_(f, 1), cv, after, b) || !position(Fi_(f, 2), cv, after, c))
      return false;
    out = (b - a).cross(c - a).normalized();
    return true;
  }
  int folded(int f, const Canvas& cv, const std::vector<Vec3>* after) const {
    Vec3 nf, ng, s = Vec3::Zero();
    if (!normal(f, cv, after, nf)) return 0;
    for (auto g : T_.ff_range(T_.face_handle(f)))
      if (normal(g.idx(), cv, after, ng)) s += ng;
    return s.dot(nf) < 0;
  }
  const Mesh& T_;
  const MatrixX3d &X_, &N_, &F_;
  MatrixX3i Fi_;
  std::vector<char> mark_;
  std::vector<int> temp_;
};

// Whether segment (p, q) crosses triangle (a, b, c) inside both (self_intersecting_faces()' test).
bool crosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  constexpr double kEps = 1e-9;
  const Vec3 d = q - p, e1 = b - a, e2 = c - a, pv = d.cross(e2);
  const double det = e1.dot(pv);
  if (!(std::abs(det) > 1e-30)) return false;
  const Vec3 t = p - a, qv = t.cross(e1);
  const double u = t.dot(pv) / det, v = d.dot(qv) / det, w = e2.dot(qv) / det;
  return u > kEps && v > kEps && u + v < 1 - kEps && w > kEps && w < 1 - kEps;
}

// Boxes in a uniform grid over \p box, cells about \p cell a side (at most 64 a side): the boxes whose
// cells a query box meets.
class FaceGrid {
 public:
  FaceGrid(const std::vector<Eigen::AlignedBox3d>& boxes, const Eigen::AlignedBox3d& box, double cell)
      : lo_(box.min()) {
    const Vec3 size = box.sizes();
    h_ = std::max({cell, size.maxCoeff() / 64, 1e-300});
    for (int a = 0; a < 3; ++a) dims_[a] = std::clamp(static_cast<int>(std::ceil(size[a] / h_)), 1, 64);
    std::vector<std::pair<int, int>> entries;  // (cell, box)
    for (size_t j = 0; j < boxes.size(); ++j)
      cells(boxes[j], [&](int c) { entries.emplace_back(c, static_cast<int>(j)); });
    std::sort(entries.begin(), entries.end());
    start_.assign(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2] + 1, 0);
    for (const auto& e : entries) ++start_[e.first + 1];
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    items_.reserve(entries.size());
    for (const auto& e : entries) items_.push_back(e.second);
  }
  //! Call \p f(box index) for the boxes in the cells \p q meets (a box may come more than once).
  template <class Fn>
  void visit(const Eigen::AlignedBox3d& q, Fn f) const {
    cells(q, [&](int c) {
      for (int k = start_[c]; k < start_[c + 1]; ++k) f(items_[k]);
    });
  }

 private:
  template <class Fn>
  void cells(const Eigen::AlignedBox3d& b, Fn f) const {
    std::array<int, 3> a, z;
    for (int i = 0; i < 3; ++i) {
      a[i] = std::clamp(static_cast<int>(std::floor((b.min()[i] - lo_[i]) / h_)), 0, dims_[i] - 1);
      z[i] = std::clamp(static_cast<int>(std::floor((b.max()[i] - lo_[i]) / h_)), 0, dims_[i] - 1);
    }
    for (int x = a[0]; x <= z[0]; ++x)
      for (int y = a[1]; y <= z[1]; ++y)
        for (int w = a[2]; w <= z[2]; ++w) f((x * dims_[1] + y) * dims_[2] + w);
  }
  Vec3 lo_;
  double h_ = 1;
  std::array<int, 3> dims_{1, 1, 1};
  std::vector<int> start_, items_;
};

// Faces crossed near a patch, with a paste or without: the written faces near the patch (what is placed,
// and the target) crossed by an edge of a patch face or crossing one (self_intersecting_faces()' test,
// edges sharing a vertex with the face left out), pairs found in a grid over the patch's faces. A
// displaced point lies within `reach` (the largest displacement) of its base point, so only faces whose
// base comes within the patch's base extent plus twice that can meet the patch: those are found once per
// patch in a tree over the base.
class CrossingCheck {
 public:
  CrossingCheck(const Mesh& T, const MatrixX3d& X, const MatrixX3d& N, const MatrixX3d& F, double reach)
      : X_(X), N_(N), F_(F), Fi_(faces(T)), tree_(X, Fi_), reach_(reach), local_(X.rows(), -1) {}

  //! The faces near the patch \p m and their vertices' displaced positions now (kept until the next call).
  void near(const ExpMap& m, const Canvas& cv) {
    for (int v : verts_) local_[v] = -1;
    verts_.clear();
    near_.clear();
    const Vec3 c = X_.row(m.vertices[0]).transpose();
    double r = 0;
    for (int v : m.vertices) r = std::max(r, (X_.row(v).transpose() - c).norm());
    r += 2 * reach_;
    // The faces whose boxes come within r of c, in a depth-first walk of the tree (visit_within()):
    // visit_nearest()'s best-first heap took a fifth of a synthesis' time here, and crossed() does not depend on
    // the faces' order.
    if (seen_.empty()) seen_.assign(Fi_.rows(), -1);
    ++stamp_;
    tree_.visit_within(c, r, [&](int f) {
      if (seen_[f] == stamp_) return;
      seen_[f] = stamp_;
      Eigen::AlignedBox3d fb;
      for (int k = 0; k < 3; ++k) fb.extend(Vec3(X_.row(Fi_(f, k)).transpose()));
      if (fb.squaredExteriorDistance(c) > r * r) return;
      near_.push_back(f);
      for (int k = 0; k < 3; ++k)
        if (const int v = Fi_(f, k); local_[v] < 0) local_[v] = static_cast<int>(verts_.size()), verts_.push_back(v);
    });
    pos_.resize(verts_.size(), 3);
    written_.assign(verts_.size(), 0);
    for (size_t i = 0; i < verts_.size(); ++i)
      if (cv.has[verts_[i]]) written_[i] = 1, pos_.row(i) = displaced(verts_[i], cv.cur.row(verts_[i]).transpose());
  }
  //! The near faces crossed with \p p pasted (nullptr: as the canvas is now) by a patch face's edge or
  //! crossing one, sorted.
  std::vector<int> crossed(const ExpMap& m, const std::vector<double>& b, const Paste* p, const Canvas& cv) {
    MatrixX3d P = pos_;
    std::vector<char> W = written_;
    auto set = [&](int v, const Vec3& d) {
      if (local_[v] >= 0) P.row(local_[v]) = displaced(v, d), W[local_[v]] = 1;
    };
    if (p) for_pasted(m, b, *p, cv, [&](size_t, int v, const Vec3& d) { set(v, d); });
    else
      for (int v : m.vertices)
        if (cv.has[v]) set(v, cv.cur.row(v).transpose());
    // The patch's faces (a vertex in the patch), written, in a uniform grid over their boxes.
    std::vector<int> in;
    std::vector<Eigen::AlignedBox3d> boxes;
    Eigen::AlignedBox3d box;
    double diag = 0;
    for (size_t i = 0; i < near_.size(); ++i) {
      const int f = near_[i];
      if (!all_written(f, W) || (cv.slot[Fi_(f, 0)] < 0 && cv.slot[Fi_(f, 1)] < 0 && cv.slot[Fi_(f, 2)] < 0)) continue;
      in.push_back(static_cast<int>(i));
      boxes.push_back(face_box(f, P));
      box.extend(boxes.back());
      diag += boxes.back().diagonal().norm();
    }
    if (in.empty()) return {};
    const FaceGrid grid(boxes, box, diag / in.size());
    std::vector<char> hit(near_.size(), 0);
    std::vector<int> stamp(in.size(), -1);
    for (size_t i = 0; i < near_.size(); ++i) {
      const int f = near_[i];
      if (!all_written(f, W)) continue;
      const Eigen::AlignedBox3d fb = face_box(f, P);
      if (!fb.intersects(box)) continue;
      grid.visit(fb, [&](int j) {
        if (stamp[j] == static_cast<int>(i)) return;
        stamp[j] = static_cast<int>(i);
        if (in[j] != static_cast<int>(i) && boxes[j].intersects(fb)) test(i, in[j], P, hit);
      });
    }
    std::vector<int> out;
    for (size_t i = 0; i < near_.size(); ++i)
      if (hit[i]) out.push_back(near_[i]);
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  Vec3 displaced(int v, const Vec3& d) const {
    const Vec3 n = N_.row(v).transpose(), e = F_.row(v).transpose();
    return X_.row(v).transpose() + d.x() * e + d.y() * n.cross(e) + d.z() * n;
  }
  Eigen::AlignedBox3d face_box(int f, const MatrixX3d& P) const {
    Eigen::AlignedBox3d b;
    for (int k = 0; k < 3; ++k) b.extend(Vec3(P.row(local_[Fi_(f, k)]).transpose()));
    return b;
  }
  bool all_written(int f, const std::vector<char>& W) const {
    return W[local_[Fi_(f, 0)]] && W[local_[Fi_(f, 1)]] && W[local_[Fi_(f, 2)]];
  }
  // Near faces i and j: an edge of either crossing the other marks the other.
  void test(size_t i, size_t j, const MatrixX3d& P, std::vector<char>& hit) const {
    const int f = near_[i], g = near_[j];
    auto one_way = [&](int e, int t, size_t mark) {  // edges of face e against face t
      if (hit[mark]) return;
      const Vec3 a = P.row(local_[Fi_(t, 0)]).transpose(), b = P.row(local_[Fi_(t, 1)]).transpose(),
                 c = P.row(local_[Fi_(t, 2)]).transpose();
      for (int k = 0; k < 3; ++k) {
        const int u = Fi_(e, k), w = Fi_(e, (k + 1) % 3);
        if (u == Fi_(t, 0) || u == Fi_(t, 1) || u == Fi_(t, 2) || w == Fi_(t, 0) || w == Fi_(t, 1) || w == Fi_(t, 2))
          continue;
        if (crosses(P.row(local_[u]).transpose(), P.row(local_[w]).transpose(), a, b, c)) {
          hit[mark] = 1;
          return;
        }
      }
    };
    one_way(g, f, i);
    one_way(f, g, j);
  }
  const MatrixX3d &X_, &N_, &F_;
  MatrixX3i Fi_;
  TriangleTree tree_;
  double reach_;
  std::vector<int> near_, local_, verts_, seen_;
  int stamp_ = 0;
  MatrixX3d pos_;
  std::vector<char> written_;
};

void commit(const ExpMap& m, const std::vector<double>& b, const Paste& p, int patch, Canvas& cv) {
  for_pasted(m, b, p, cv, [&](size_t s, int v, const Vec3& d) {
    cv.cur.row(v) = d.transpose();
    cv.has[v] = 1;
    if (p.share[s] >= 0.5) (*cv.owner)[v] = patch, cv.copied->row(v) = p.raw[s].transpose();
  });
}

// Zero the features holding a vertex of \p faces: the vertices where \p in holds, displaced (\p D, #V by
// 3) by over \p tau, connected to those; then feathered outwards: ring r (1 … feather) keeps
// r / (feather + 1) of its displacement. \p mark: #V zeros, left so. \return the vertices zeroed.
template <class In>
size_t zero_features(const Mesh& T, const MatrixX3i& Fi, const std::vector<int>& faces, double tau, int feather,
                     In in, MatrixX3d& D, std::vector<char>& mark) {
  std::vector<int> queue;
  auto take = [&](int v) {
    if (!in(v) || mark[v] || !(D.row(v).norm() > tau)) return;
    mark[v] = 1;
    queue.push_back(v);
  };
  for (int f : faces)
    for (int k = 0; k < 3; ++k) take(Fi(f, k));
  for (size_t i = 0; i < queue.size(); ++i)
    for (auto w : T.vv_range(T.vertex_handle(queue[i]))) take(w.idx());
  const size_t zeroed = queue.size();
  for (int v : queue) D.row(v).setZero();
  std::vector<int> ring = queue, next;
  for (int r = 1; r <= feather; ++r) {
    next.clear();
    for (int v : ring)
      for (auto w : T.vv_range(T.vertex_handle(v)))
        if (in(w.idx()) && !mark[w.idx()]) mark[w.idx()] = 1, next.push_back(w.idx());
    for (int v : next) D.row(v) *= double(r) / (feather + 1);
    queue.insert(queue.end(), next.begin(), next.end());
    ring.swap(next);
  }
  for (int v : queue) mark[v] = 0;
  return zeroed;
}

// Displacements longer than this share of the target's bounding-box diagonal are not tested for crossings.
constexpr double kCrossingReach = 0.5;

// Paste patches by minimum cuts, placements tried in turn against collisions: the chosen placement,
// then the others by cost, at most fold_tries, until one folds no more faces around the patch than there
// were and crosses no more (avoid_crossings); else the one that crosses fewest, then folds fewest, whose
// colliding features are then dropped (drop_collisions): the connected patch vertices displaced by over
// `tau` that hold a vertex of a face it crosses or folds, zeroed, feathered over `feather` rings. Crossings
// that remain are dropped again with a lower tau (a quarter, twice: at last the patch's whole relief there).
class Placer {
 public:
  Placer(const Mesh& T, const MatrixX3d& X, const MatrixX3d& N, const MatrixX3d& F, double reach,
         const SynthesisOptions& o, SynthesisResult& res)
      : T_(T), X_(X), Fi_(faces(T)), o_(o), res_(res), tau_(0.05 * reach), reach_(reach) {
    if (o.seams != SeamMethod::Cut) return;
    if (o.fold_tries > 1) folds_ = std::make_unique<FoldCheck>(T, X, N, F);
    if (o.avoid_crossings) crossings_ = std::make_unique<CrossingCheck>(T, X, N, F, reach);
  }

  //! \p rp: the patch's radius (for the part of a dropped feature outside the patch).
  //! \p optional: commit nothing unless a placement neither crosses nor folds (a fill). \return whether it did.
  template <class Read>
  bool place(const ExpMap& m, const std::vector<double>& b, const std::vector<Eigen::Vector2d>& order, Read read,
             int patch, double rp, Canvas& cv, bool optional = false) {
    for (size_t s = 0; s < m.vertices.size(); ++s) cv.slot[m.vertices[s]] = static_cast<int>(s);
    centre_ = m.vertices[0];
    drop_reach_ = rp + reach_;
    if (crossings_) crossings_->near(m, cv);
    before_.reset();
    Paste best;
    std::pair<size_t, long> fewest{std::numeric_limits<size_t>::max(), 0};
    std::vector<int> best_folds, best_crossed;
    const size_t tries = folds_ || crossings_ ? std::min(order.size(), static_cast<size_t>(o_.fold_tries)) : 1;
    for (size_t i = 0; i < tries && fewest != std::pair<size_t, long>{0, 0}; ++i) {
      Paste p = cut_paste(T_, m, b, [&](size_t s, Vec3* raw) { return read(order[i], s, raw); }, cv, o_.feather);
      std::vector<int> folded;
      const long added = folds_ ? std::max(0L, folds_->added(m, b, p, cv, &folded)) : 0;
      std::vector<int> crossed = crossings_ ? new_crossings(m, b, &p, cv) : std::vector<int>();
      const std::pair<size_t, long> key{crossed.size(), added};
      if (key < fewest)
        fewest = key, best = std::move(p), best_folds = std::move(folded), best_crossed = std::move(crossed);
      if (i == 0 && key != std::pair<size_t, long>{0, 0} && tries > 1) retrying_ = true;
    }
    if (optional && fewest != std::pair<size_t, long>{0, 0}) {
      for (int v : m.vertices) cv.slot[v] = -1;
      retrying_ = false;
      return false;
    }
    const bool dropping = o_.drop_collisions && (fewest.first > 0 || (o_.drop_folds && fewest.second > 0));
    if (crossings_ && dropping && !before_) before_ = crossings_->crossed(m, b, nullptr, cv);  // for the recheck
    commit(m, b, best, patch, cv);
    if (retrying_ && fewest == std::pair<size_t, long>{0, 0}) ++res_.retried_placements;
    retrying_ = false;
    if (dropping) {
      if (!o_.drop_folds || fewest.second == 0) best_folds.clear();
      best_folds.insert(best_folds.end(), best_crossed.begin(), best_crossed.end());
      res_.dropped_vertices += drop(best_folds, tau_, cv);
      ++res_.dropped_patches;
      for (int round = 0; round < 2 && crossings_; ++round) {  // what zeroing left crossed, or made cross
        best_crossed = new_crossings(m, b, nullptr, cv);
        if (!best_crossed.empty()) res_.dropped_vertices += drop(best_crossed, tau_ * std::pow(0.25, round + 1), cv);
      }
    }
    for (int v : m.vertices) cv.slot[v] = -1;
    return true;
  }

 private:
  // The faces crossed with \p p (nullptr: now) and not before the patch (its first call computes "before").
  std::vector<int> new_crossings(const ExpMap& m, const std::vector<double>& b, const Paste* p, const Canvas& cv) {
    std::vector<int> after = crossings_->crossed(m, b, p, cv);
    if (after.empty()) return after;
    if (!before_) before_ = crossings_->crossed(m, b, nullptr, cv);
    std::vector<int> out;
    std::set_difference(after.begin(), after.end(), before_->begin(), before_->end(), std::back_inserter(out));
    return out;
  }
  // The whole feature is zeroed, also its part outside the patch (written, within the patch radius plus the
  // largest displacement of the centre): cut at the patch's rim, what is left of it stands as a wall that
  // folds (tentacle plate onto a coarse sphere: 66 of 95 folded faces were next to a dropped vertex, 9 of 28
  // when whole features are dropped; bench/synthesis.md).
  size_t drop(const std::vector<int>& faces, double tau, Canvas& cv) {
    if (mark_.empty()) mark_.assign(cv.has.size(), 0);
    const Vec3 c = X_.row(centre_).transpose();
    auto in = [&](int v) {
      return cv.slot[v] >= 0 || (cv.has[v] && (X_.row(v).transpose() - c).squaredNorm() < drop_reach_ * drop_reach_);
    };
    return zero_features(T_, Fi_, faces, tau, o_.feather, in, cv.cur, mark_);
  }
  const Mesh& T_;
  const MatrixX3d& X_;
  MatrixX3i Fi_;
  const SynthesisOptions& o_;
  SynthesisResult& res_;
  double tau_, reach_, drop_reach_ = 0;
  int centre_ = 0;
  std::unique_ptr<FoldCheck> folds_;
  std::unique_ptr<CrossingCheck> crossings_;
  std::optional<std::vector<int>> before_;
  std::vector<char> mark_;
  bool retrying_ = false;
};

// The faces that P folds (folded_faces()'s test: a face's normal against the sum of its neighbours'), with
// \p next the neighbours of each face (−1: none).
std::vector<char> folded_mask(const MatrixX3i& Fi, const std::vector<std::array<int, 3>>& next, const MatrixX3d& P) {
  const Eigen::Index nf = Fi.rows();
  MatrixX3d FN(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Vec3 a = P.row(Fi(f, 0)).transpose(), b = P.row(Fi(f, 1)).transpose(), c = P.row(Fi(f, 2)).transpose();
    FN.row(f) = (b - a).cross(c - a).normalized().transpose();
  }
  std::vector<char> out(nf, 0);
  for (Eigen::Index f = 0; f < nf; ++f) {
    Vec3 s = Vec3::Zero();
    for (int g : next[f])
      if (g >= 0) s += FN.row(g).transpose();
    out[f] = s.dot(FN.row(f).transpose()) < 0;
  }
  return out;
}

std::vector<std::array<int, 3>> face_neighbours(const Mesh& T) {
  std::vector<std::array<int, 3>> next(T.n_faces(), {-1, -1, -1});
  for (auto f : T.faces()) {
    int c = 0;
    for (auto g : T.ff_range(f)) next[f.idx()][c++] = g.idx();
  }
  return next;
}

// Folds' dips: each face f folded in \p now and not in \p base multiplies \p alpha by
// 1 − depth exp(−d² / r²) within 2r of its centroid (d: distance from it; r: ρ, at least the face's mean edge).
// \return whether any face was folded.
bool dip_folds(const Mesh& T, const MatrixX3d& X, const MatrixX3i& Fi, const std::vector<char>& now,
               const std::vector<char>& base, double rho, double depth, Eigen::VectorXd& alpha) {
  std::vector<int> seen(X.rows(), -1), queue;
  int visit = 0;
  for (Eigen::Index f = 0; f < Fi.rows(); ++f) {
    if (!now[f] || base[f]) continue;
    const Vec3 c = (X.row(Fi(f, 0)) + X.row(Fi(f, 1)) + X.row(Fi(f, 2))).transpose() / 3;
    double edges = 0;  // the face's mean edge: the narrowest dip
    for (int k = 0; k < 3; ++k) edges += (X.row(Fi(f, k)) - X.row(Fi(f, (k + 1) % 3))).norm() / 3;
    const double r = std::max(rho, edges);
    queue.assign({Fi(f, 0), Fi(f, 1), Fi(f, 2)});
    for (int v : queue) seen[v] = visit;
    for (size_t i = 0; i < queue.size(); ++i) {
      const int v = queue[i];
      const double d2 = (X.row(v).transpose() - c).squaredNorm();
      alpha[v] *= 1 - depth * std::exp(-d2 / (r * r));
      for (auto w : T.vv_range(T.vertex_handle(v)))
        if (seen[w.idx()] != visit && (X.row(w.idx()).transpose() - c).norm() < 2 * r)
          seen[w.idx()] = visit, queue.push_back(w.idx());
    }
    ++visit;
  }
  return visit > 0;
}

// Shrink the displacements \p local (#V by 3 in the frames (F, n × F, n)) around the faces that X + D
// folds (folded_faces()'s test) and the base X does not, smoothly: each round multiplies them by
// 1 − 0.25 exp(−d² / ρ²), d the distance from the folded face's centroid (within 2ρ), until none folds (at
// most 40 rounds; a step cut would fold the surface at its rim). ρ is at least the face's mean edge: a
// dip narrower than the mesh moves one vertex, and the encoded texture folded there (spike plate onto the
// unrefined cheburashka, ρ a third of an edge). \return the vertices shrunk by over 1 %.
size_t unfold(const Mesh& T, const MatrixX3d& X, const MatrixX3d& N, const MatrixX3d& F, double rho, MatrixX3d& local,
              const ProgressFn& progress) {
  const MatrixX3i Fi = faces(T);
  const std::vector<std::array<int, 3>> next = face_neighbours(T);
  const std::vector<char> base = folded_mask(Fi, next, X);
  Eigen::VectorXd alpha = Eigen::VectorXd::Ones(X.rows());
  for (int round = 0; round < 40; ++round) {
    report(progress, 0.85 + 0.05 * round / 40.0, "unfold");
    MatrixX3d P = X;
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
      const Vec3 n = N.row(i).transpose(), f = F.row(i).transpose();
      P.row(i) += alpha[i] * (local(i, 0) * f + local(i, 1) * n.cross(f) + local(i, 2) * n).transpose();
    }
    if (!dip_folds(T, X, Fi, folded_mask(Fi, next, P), base, rho, 0.25, alpha)) break;
  }
  size_t shrunk = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    shrunk += alpha[i] < 0.99 && local.row(i).norm() > 0;  // a zero displacement is not reduced
    local.row(i) *= alpha[i];
  }
  return shrunk;
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


// The textured area: faces with a vertex of weight > 0 (what exemplar_share is a share of).
double textured_area(const Mesh& target, const Eigen::VectorXd& weight) {
  const Eigen::VectorXd fa = face_areas(target);
  double area = 0;
  for (auto f : target.faces()) {
    bool any = false;
    for (auto v : target.fv_range(f)) any |= weight[v.idx()] > 0;
    if (any) area += fa[f.idx()];
  }
  return area;
}

std::vector<char> growth_region(const Eigen::VectorXd& weight) {
  std::vector<char> region(weight.size());
  for (Eigen::Index i = 0; i < weight.size(); ++i) region[i] = weight[i] > 0;
  return region;
}

// Calibration of the estimate (bench/synthesis.md, "Estimate"): refinement adds about kAddedPerNeeded ×
// refine_need().needed − the region's vertices (tentacle plate onto a generated sphere: 243,200 added
// where needed was 188,000), and the whole run costs about kSecondsPerVertex CPU seconds per output
// vertex with the default options: the tentacle plate 1.7–2.1e-4 on the six default targets at load 3–4
// since idle OpenMP threads sleep (18 s for 102,402 on the sphere; it was 1.2e-3 with spinning threads at load
// 5–6), the spike plate 0.6–1.0e-4; an exemplar of fine relief (igea) measured up to 4.8e-4 before that.
constexpr double kAddedPerNeeded = 1.3;
constexpr double kSecondsPerVertex = 3e-4;

// The estimate at a given share (or the given scale).
SynthesisEstimate estimate_at(const Exemplar& ex, const Mesh& target, const std::vector<char>& region, double area,
                              double share, const SynthesisOptions& o) {
  SynthesisEstimate e;
  const double disk = M_PI * ex.extent * ex.extent;
  e.scale = o.scale > 0 ? o.scale : std::sqrt(share * area / disk);
  e.exemplar_share = o.scale > 0 ? disk * o.scale * o.scale / area : share;
  const detail::RefineNeed need = detail::refine_need(target, region, e.scale * ex.mean_edge, o.refine_ratio);
  e.refine = need.refine;
  const double added =
      need.refine ? std::max(0.0, kAddedPerNeeded * need.needed - static_cast<double>(need.region_vertices)) : 0.0;
  e.vertices = target.n_vertices() + static_cast<size_t>(std::min(added, 1e15));
  e.seconds = kSecondsPerVertex * static_cast<double>(e.vertices);
  return e;
}

// The estimate with the share given, or chosen: 0.05 unless the refined target would exceed the vertex
// budget, then the smallest share (at most 0.5) that keeps within it (the vertices fall as 1 / share).
SynthesisEstimate estimate_for(const Exemplar& ex, const Mesh& target, const Eigen::VectorXd& weight,
                               const SynthesisOptions& o) {
  const double area = textured_area(target, weight);
  if (!(area > 0)) throw InvalidInput("texture synthesis: the weight is zero everywhere");
  const std::vector<char> region = growth_region(weight);
  if (o.scale > 0 || o.exemplar_share > 0) return estimate_at(ex, target, region, area, o.exemplar_share, o);
  constexpr double kShare = 0.05, kMaxShare = 0.5;
  const auto budget = static_cast<size_t>(std::max<size_t>(o.vertex_budget, target.n_vertices()));
  SynthesisEstimate e = estimate_at(ex, target, region, area, kShare, o);
  if (e.vertices <= budget) return e;
  SynthesisEstimate hi = estimate_at(ex, target, region, area, kMaxShare, o);
  if (hi.vertices > budget) return hi;
  double lo_s = kShare, hi_s = kMaxShare;
  for (int i = 0; i < 12; ++i) {  // bisection on the share (geometric), to within ~3 %
    const double mid = std::sqrt(lo_s * hi_s);
    SynthesisEstimate m = estimate_at(ex, target, region, area, mid, o);
    if (m.vertices <= budget) hi_s = mid, hi = m;
    else lo_s = mid;
  }
  return hi;
}

//! The checks synthesize_texture() and estimate_synthesis() share: options, target, guides.
void check_inputs(const Mesh& target, const SynthesisOptions& o, const SynthesisGuides& guides) {
  SynthesisOptions::table().check(o);
  require_valid(target, "texture synthesis: target");
  const Eigen::Index n0 = target.n_vertices();
  if (guides.weight.size() && guides.weight.size() != n0)
    throw InvalidInput(fmt::format("texture synthesis: expected one weight per target vertex ({})", n0));
  if (guides.weight.size() && !(guides.weight.array() >= 0 && guides.weight.array() <= 1).all())
    throw InvalidInput("texture synthesis: weights must lie in [0, 1]");
  if (guides.direction.rows() && guides.direction.rows() != n0)
    throw InvalidInput(fmt::format("texture synthesis: expected one guide direction per target vertex ({})", n0));
}

// The faces owning an edge that crosses one of \p crossed in \p V (the other side of each crossing). Where the
// crossed face itself is not displaced, zeroing its features cannot undo the crossing: the edge moved (the beetle
// with the tentacle plate: 3 faces beyond the base's own, each beside the base's own crossings, crossed by edges
// displaced by 1e-7 to 2e-5). No cap on \p crossed: about 12 µs a crossed face, the tree's build included (a noisy
// icosphere(7), 327,680 faces of which 300,119 crossed: 3.9 s, against 1.7 s for self_intersecting_faces() on it;
// 18,765 of 20,480: 0.23 s; bench/synthesis.md, eleventh session).
std::vector<int> crossing_partners(const MatrixX3d& V, const MatrixX3i& F, const std::vector<int>& crossed) {
  std::vector<int> partners;
  if (crossed.empty()) return partners;
  // An edge crossing face f meets it inside f's bounding sphere about its centroid, so one of the edge's
  // face's boxes (a sliver's slabs) comes within that sphere: the tree's faces there are the candidates.
  const TriangleTree tree(V, F);
  std::vector<char> is_partner(F.rows(), 0);
  for (int f : crossed) {
    const int i = F(f, 0), j = F(f, 1), l = F(f, 2);
    const Vec3 A = V.row(i).transpose(), e1 = (V.row(j) - V.row(i)).transpose(), e2 = (V.row(l) - V.row(i)).transpose();
    const Vec3 centre = A + (e1 + e2) / 3;
    const double radius = std::max({(A - centre).norm(), (A + e1 - centre).norm(), (A + e2 - centre).norm()});
    tree.visit_within(centre, radius, [&](int g) {
      for (int k = 0; k < 3 && !is_partner[g]; ++k) {
        const int a = F(g, k), b = F(g, (k + 1) % 3);
        if (a == i || a == j || a == l || b == i || b == j || b == l) continue;
        const Vec3 p0 = V.row(a).transpose();
        if (segment_crosses_triangle(p0, V.row(b).transpose() - p0, A, e1, e2)) is_partner[g] = 1;
      }
    });
  }
  for (Eigen::Index g = 0; g < F.rows(); ++g)
    if (is_partner[g]) partners.push_back(static_cast<int>(g));
  return partners;
}

// Where the base crosses itself (a messy target: the beetle at 298 faces), a displacement however small moves
// the crossing from face to face and the count beyond the base's own jitters (beetle with the spike plate: 2
// faces, displaced by 1e-4 to 2e-4): both sides of each of the base's own crossings (\p base, its flags) keep the
// base as it is, their one-ring half of its displacement \p D.
void keep_own_crossings(const Mesh& T, const MatrixX3i& Fi, const MatrixX3d& X, const std::vector<char>& base,
                        MatrixX3d& D) {
  std::vector<int> own;
  for (Eigen::Index f = 0; f < Fi.rows(); ++f)
    if (base[f]) own.push_back(static_cast<int>(f));
  std::vector<int> sides = crossing_partners(X, Fi, own);
  sides.insert(sides.end(), own.begin(), own.end());
  std::vector<char> still(X.rows(), 0);
  for (int f : sides)
    for (int k = 0; k < 3; ++k) still[Fi(f, k)] = 1;
  std::vector<char> halved(X.rows(), 0);
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    if (!still[v]) continue;
    D.row(v).setZero();
    for (auto w : T.vv_range(T.vertex_handle(static_cast<int>(v))))
      if (!still[w.idx()] && !halved[w.idx()]) D.row(w.idx()) *= 0.5, halved[w.idx()] = 1;
  }
}

// Encode the displacements res.local as a height-and-tilt texture on T, apply it and count the faces
// the textured surface crosses (self_intersecting_faces()) against the base's own. Where it crosses
// beyond them (the texture reproduces the displacements approximately, and unfolding moved them) and
// repair_crossings is on, the features there are zeroed (zero_features(), above \p tau, then a quarter
// of it), what that folds unfolded, and the texture encoded again: at most kRepairRounds times.
// Rounds of zeroing what still crosses after encoding: the teapot (1,393 faces of its own crossings, patches meeting
// along x = 0) with the tentacle plate left 9 faces crossed beyond them after 2 rounds, none after 4.
constexpr int kRepairRounds = 4;
void encode_and_count(const Mesh& T, const MatrixX3d& X, const MatrixX3d& N, const MatrixX3d& F, double tau,
                      const SynthesisOptions& o, SynthesisResult& res,
                      const std::function<void(const char*)>& stage_done) {
  report(o.progress, 0.9, "encode");
  TextureCodec codec(T, o.texture);
  const MatrixX3i Fi = faces(T);
  const std::vector<std::array<int, 3>> next = face_neighbours(T);
  const std::vector<char> base_folds = folded_mask(Fi, next, X);
  std::vector<char> mark(X.rows(), 0);
  const std::vector<char> base = self_intersecting_faces(X, Fi);
  keep_own_crossings(T, Fi, X, base, res.local);
  for (int round = 0;; ++round) {
    res.texture = texture_from_local(codec, res.local, F);
    res.textured = codec.apply(res.texture);
    // The encoding rounds the displacement a little (height and tilt per vertex), and can fold again a face that
    // unfolding left just unfolded (cheburashka with the tentacle plate: one face; bench/synthesis.md): dipped as
    // unfold() does, on the decoded surface, at most 8 rounds.
    for (int k = 0; o.unfold && k < 8; ++k) {
      Eigen::VectorXd alpha = Eigen::VectorXd::Ones(X.rows());
      if (!dip_folds(T, X, Fi, folded_mask(Fi, next, res.textured), base_folds, o.unfold_radius * res.patch_radius,
                     0.25, alpha))
        break;
      for (Eigen::Index i = 0; i < X.rows(); ++i) {
        res.unfolded_vertices += alpha[i] < 0.99 && alpha[i] > 0.75 && res.local.row(i).norm() > 0;  // once each
        res.local.row(i) *= alpha[i];
      }
      res.texture = texture_from_local(codec, res.local, F);
      res.textured = codec.apply(res.texture);
    }
    if (round == 0) {
      stage_done("encode");
      report(o.progress, 0.95, "self-intersections");
    }
    const std::vector<char> hit = self_intersecting_faces(res.textured, Fi);
    res.self_intersecting = std::count(hit.begin(), hit.end(), 1);
    res.base_self_intersecting = std::count(base.begin(), base.end(), 1);
    res.excess_self_intersecting =
        res.self_intersecting > res.base_self_intersecting ? res.self_intersecting - res.base_self_intersecting : 0;
    std::vector<int> extra;
    for (Eigen::Index f = 0; f < Fi.rows(); ++f)
      if (hit[f] && !base[f]) extra.push_back(static_cast<int>(f));
    if (extra.empty() || !o.repair_crossings || round == kRepairRounds) break;
    res.repaired_vertices += zero_features(T, Fi, extra, tau * std::pow(0.25, round), o.feather,
                                           [](int) { return true; }, res.local, mark);
    // Both sides of each crossing lose what is left of their displacement, however small (below tau).
    std::vector<int> sides = crossing_partners(res.textured, Fi, extra);
    sides.insert(sides.end(), extra.begin(), extra.end());
    for (int f : sides)
      for (int k = 0; k < 3; ++k)
        if (res.local.row(Fi(f, k)).squaredNorm() > 0) res.local.row(Fi(f, k)).setZero(), ++res.repaired_vertices;
    if (o.unfold) res.unfolded_vertices += unfold(T, X, N, F, o.unfold_radius * res.patch_radius, res.local, {});
  }
  if (res.repaired_vertices)
    res.warnings.push_back(fmt::format("displacements zeroed at {} vertices where the textured surface still "
                                       "crossed itself", res.repaired_vertices));
  stage_done("count");
}

// The exemplar's separate features (fill_holes, bare_share; issue 27): the connected regions of the raster
// (4-neighbours, within the unit disk) displaced by over 5 % of its largest displacement, each by the centroid
// of its footprint (a tentacle's foot; unit-disk coordinates); the distance between the closest two whose
// footprints stay off the disk's rim, and the largest radius of those footprints. Relief that is not a set of
// separate features (a region over a fifth of the disk, or fewer than two inside it) has none.
struct ExemplarFeatures {
  std::vector<Eigen::Vector2d> roots;
  double closest = 0;    // unit-disk length
  double footprint = 0;  // unit-disk length
  double lowest = 0;     // the lowest peak |d| of the features off the rim (exemplar units)
  double smallest = 0;   // the smallest footprint area of those (unit-disk area)
};

ExemplarFeatures exemplar_features(const Exemplar& ex) {
  const int s = ex.size;
  double largest = 0;
  for (const Vec3& d : ex.grid) largest = std::max(largest, d.norm());
  auto in = [&](int c) { return std::hypot(ex.coord(c % s), ex.coord(c / s)) <= 1; };
  auto raised = [&](int c) { return in(c) && ex.grid[c].norm() > 0.05 * largest; };
  size_t disk = 0;
  for (int c = 0; c < s * s; ++c) disk += in(c);
  ExemplarFeatures out;
  std::vector<Eigen::Vector2d> inside;  // roots of footprints off the rim
  std::vector<char> seen(static_cast<size_t>(s) * s, 0);
  std::vector<int> queue;
  for (int c0 = 0; c0 < s * s; ++c0) {
    if (seen[c0] || !raised(c0)) continue;
    queue.assign({c0});
    seen[c0] = 1;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    bool rim = false;
    auto at = [&](int c) { return Eigen::Vector2d(ex.coord(c % s), ex.coord(c / s)); };
    for (size_t i = 0; i < queue.size(); ++i) {
      const int c = queue[i], x = c % s, y = c / s;
      sum += at(c);
      rim |= at(c).norm() > 0.95;
      for (const int w : {x > 0 ? c - 1 : -1, x + 1 < s ? c + 1 : -1, y > 0 ? c - s : -1, y + 1 < s ? c + s : -1})
        if (w >= 0 && !seen[w] && raised(w)) seen[w] = 1, queue.push_back(w);
    }
    if (queue.size() > disk / 5) return {};
    if (queue.size() < 4) continue;  // a speck
    out.roots.push_back(sum / static_cast<double>(queue.size()));
    if (rim) continue;
    inside.push_back(out.roots.back());
    double peak = 0;
    for (int c : queue) peak = std::max(peak, ex.grid[c].norm());
    out.lowest = inside.size() == 1 ? peak : std::min(out.lowest, peak);
    const double area = static_cast<double>(queue.size()) * std::pow(2.0 / (s - 1), 2);
    out.smallest = inside.size() == 1 ? area : std::min(out.smallest, area);
    for (int c : queue) out.footprint = std::max(out.footprint, (at(c) - out.roots.back()).norm());
  }
  if (inside.size() < 2) return {};
  out.closest = std::numeric_limits<double>::infinity();
  for (size_t a = 0; a < inside.size(); ++a)
    for (size_t b = a + 1; b < inside.size(); ++b) out.closest = std::min(out.closest, (inside[a] - inside[b]).norm());
  return out;
}

// Broken features (issue 27): the connected regions of vertices displaced (\p D, #V by 3) by over \p tau whose
// peak |d| is under \p below or whose footprint (the sum of their vertex areas) is under \p smaller — what a
// drop, a seam or a patch's rim left of a feature — zeroed and feathered as drop_collisions does
// (zero_features()). \return the regions removed; \p zeroed += their vertices.
size_t remove_fragments(const Mesh& T, const MatrixX3i& Fi, double tau, double below, double smaller, int feather,
                        MatrixX3d& D, size_t& zeroed) {
  const Eigen::Index n = D.rows();
  const Eigen::VectorXd va = vertex_areas(T);
  std::vector<char> seen(n, 0), mark(n, 0);
  std::vector<int> queue, seeds;
  for (Eigen::Index v0 = 0; v0 < n; ++v0) {
    if (seen[v0] || !(D.row(v0).norm() > tau)) continue;
    queue.assign({static_cast<int>(v0)});
    seen[v0] = 1;
    double peak = 0, area = 0;
    for (size_t i = 0; i < queue.size(); ++i) {
      peak = std::max(peak, D.row(queue[i]).norm());
      area += va[queue[i]];
      for (auto w : T.vv_range(T.vertex_handle(queue[i])))
        if (!seen[w.idx()] && D.row(w.idx()).norm() > tau) seen[w.idx()] = 1, queue.push_back(w.idx());
    }
    if (peak < below || area < smaller)
      for (auto f : T.vf_range(T.vertex_handle(queue[0]))) {
        seeds.push_back(f.idx());
        break;
      }
  }
  // Zeroed after the search, so that feathering one region does not split another.
  for (int f : seeds) zeroed += zero_features(T, Fi, {f}, tau, feather, [](int) { return true; }, D, mark);
  return seeds.size();
}

// The placement of a patch that overlaps what is written: o.candidates random placements (\p t the
// first), \p t set to one of those whose overlap matches within o.match_tolerance of the best, \p order
// to it and then the others, best first (cut: the placements to try against folds). \p overlap: the
// patch vertices with a weight \p b that are written (a seeded subsample of o.match_samples is kept).
template <class Read, class OldAt, class RandomPlacement>
void choose_placement(std::vector<size_t>& overlap, const std::vector<double>& b, const ExpMap& m,
                      const SynthesisOptions& o, Rng& rng, const Read& read, const OldAt& old_at,
                      const RandomPlacement& random_placement, Eigen::Vector2d& t,
                      std::vector<Eigen::Vector2d>& order) {
  if (overlap.size() > static_cast<size_t>(o.match_samples)) {  // a seeded subsample
    for (size_t i = 0; i < static_cast<size_t>(o.match_samples); ++i)
      std::swap(overlap[i], overlap[i + rng.below(overlap.size() - i)]);
    overlap.resize(o.match_samples);
  }
  std::vector<Eigen::Vector2d> ts(o.candidates);
  std::vector<double> cost(o.candidates, 0.0);
  ts[0] = t;
  for (int q = 1; q < o.candidates; ++q) ts[q] = random_placement();
  // Normalised: Σ b |new − old|² / Σ b (|new|² + |old|²), 0 for a match, ~1 for unrelated relief of any
  // size (the plain sum would prefer the exemplar's quietest parts wherever nothing matches: a
  // non-stationary exemplar's synthesis came out at half its rms).
  for (int q = 0; q < o.candidates; ++q) {
    double energy = 0;
    for (size_t s : overlap) {
      const Vec3 d = read(ts[q], s, nullptr), old = old_at(m.vertices[s]);
      cost[q] += b[s] * (d - old).squaredNorm();
      energy += b[s] * (d.squaredNorm() + old.squaredNorm());
    }
    cost[q] = energy > 0 ? cost[q] / energy : 0.0;
  }
  const double best = *std::min_element(cost.begin(), cost.end());
  std::vector<int> good;
  for (int q = 0; q < o.candidates; ++q)
    if (cost[q] <= (1 + o.match_tolerance) * best + 1e-300) good.push_back(q);
  if (good.empty()) good.push_back(0);  // no comparable cost (it overflowed): the first placement
  const int pick = good[rng.below(good.size())];
  t = ts[pick];
  std::vector<int> rest;  // then the others, best first
  for (int q = 0; q < o.candidates; ++q)
    if (q != pick) rest.push_back(q);
  std::stable_sort(rest.begin(), rest.end(), [&](int a, int b) { return cost[a] < cost[b]; });
  order = {t};
  for (int q : rest) order.push_back(ts[q]);
}

// The options patches are placed with: \p o, without avoiding or repairing crossings when the
// displacements (up to \p largest) are as large as the target \p X (with a warning in \p warnings).
SynthesisOptions placing_options(const SynthesisOptions& o, double largest, const MatrixX3d& X,
                                 std::vector<std::string>& warnings) {
  // Displacements as large as the target itself (a height scale far beyond the exemplar's): every placement
  // crosses the whole target, and testing each would cost the whole target per try (a sphere at
  // --height-scale 1e6: past 120 s). There crossings are counted, not avoided.
  SynthesisOptions placing = o;
  if (largest > kCrossingReach * (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm() &&
      (o.avoid_crossings || o.repair_crossings)) {
    placing.avoid_crossings = placing.drop_collisions = placing.repair_crossings = false;
    warnings.push_back(fmt::format("displacements up to {:.3g} are as large as the target ({:.3g} across): "
                                   "crossings are counted, not avoided",
                                   largest, (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm()));
  }
  return placing;
}

// Patch centres in a growing front: the uncovered vertex nearest to the patches so far (its distance to the
// nearest centre, with seeded jitter: no fixed order of growth), else one of a part not reached yet; a
// vertex (of weight ≥ 0.5) is covered once a centre is within `spacing` of it.
class GrowthFront {
 public:
  GrowthFront(const Mesh& T, const Eigen::VectorXd& weight, double spacing, Rng& rng)
      : n_(T.n_vertices()), spacing_(spacing), rng_(rng), wanted_(n_, 0),
        dmin_(n_, std::numeric_limits<double>::infinity()), key_(n_, std::numeric_limits<double>::infinity()) {
    for (size_t i = 0; i < n_; ++i)
      if (weight[i] >= 0.5 && !T.is_isolated(T.vertex_handle(static_cast<int>(i)))) wanted_[i] = 1, ++to_cover;
    scan_ = rng.below(static_cast<uint64_t>(std::max<size_t>(n_, 1)));  // where a new component starts
  }
  //! The next centre (−1: all covered).
  int next() {
    while (!front_.empty()) {
      const auto [k, v] = front_.top();
      front_.pop();
      if (k == key_[v] && dmin_[v] > spacing_) return v;
    }
    for (size_t c = 0; c < n_; ++c) {  // nothing in the front: a part not reached yet
      const int v = static_cast<int>((scan_ + c) % n_);
      if (wanted_[v] && dmin_[v] > spacing_) {
        scan_ = v;
        return v;
      }
    }
    return -1;
  }
  //! A new patch reaches vertex \p v at distance \p d from its centre.
  void reach(int v, double d) {
    if (!(d < dmin_[v])) return;
    const bool was = dmin_[v] <= spacing_;
    dmin_[v] = d;
    if (wanted_[v] && !was && d <= spacing_) ++covered;
    if (wanted_[v] && d > spacing_) {
      key_[v] = d * (1 + 0.3 * rng_.uniform());
      front_.emplace(key_[v], v);
    }
  }
  size_t to_cover = 0, covered = 0;

 private:
  using Item = std::pair<double, int>;
  size_t n_;
  double spacing_;
  Rng& rng_;
  std::vector<char> wanted_;
  std::vector<double> dmin_, key_;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> front_;  // (jittered distance, vertex)
  size_t scan_ = 0;
};

// Per vertex the distance along edges to the nearest vertex whose displacement \p D (#V by 3) exceeds \p tau,
// up to \p limit (beyond: limit).
Eigen::VectorXd bare_distance(const Mesh& T, const MatrixX3d& X, const MatrixX3d& D, double tau, double limit) {
  const int n = static_cast<int>(X.rows());
  Eigen::VectorXd d = Eigen::VectorXd::Constant(n, limit);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  for (int v = 0; v < n; ++v)
    if (D.row(v).norm() > tau) d[v] = 0, q.emplace(0.0, v);
  while (!q.empty()) {
    const auto [dv, v] = q.top();
    q.pop();
    if (dv > d[v]) continue;
    for (auto w : T.vv_range(T.vertex_handle(v)))
      if (const double dw = dv + (X.row(v) - X.row(w.idx())).norm(); dw < d[w.idx()]) d[w.idx()] = dw, q.emplace(dw, w.idx());
  }
  return d;
}

// Where a whole feature has room and none stands (the fill after the front): vertices of weight ≥ 0.5 whose
// bare_distance() \p d is at least \p room, the farthest first, none within \p apart of one taken before (a
// Poisson-disk rule).
std::vector<int> feature_holes(const Mesh& T, const MatrixX3d& X, const Eigen::VectorXd& d,
                               const Eigen::VectorXd& weight, double room, double apart) {
  std::vector<int> order;
  for (int v = 0; v < static_cast<int>(X.rows()); ++v)
    if (weight[v] >= 0.5 && d[v] >= room && !T.is_isolated(T.vertex_handle(v))) order.push_back(v);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return d[a] > d[b]; });
  std::vector<int> out;
  for (int v : order) {
    bool free = true;
    for (int c : out) free &= (X.row(c) - X.row(v)).squaredNorm() >= apart * apart;
    if (free) out.push_back(v);
  }
  return out;
}

// The bare share (SynthesisResult::bare_share): the area share of the growth region (weight ≥ 0.5) where a
// whole feature would fit between the displaced vertices of res.local (0 without separate features).
double bare_share(const Exemplar& ex, const Mesh& T, const MatrixX3d& X, double largest, const SynthesisResult& res) {
  const ExemplarFeatures features = exemplar_features(ex);
  if (!(features.closest > 0)) return 0;
  const double room = features.footprint * ex.extent * res.scale;
  const Eigen::VectorXd d = bare_distance(T, X, res.local, 0.05 * largest, room);
  const Eigen::VectorXd va = vertex_areas(T);
  double all = 0, bare = 0;
  for (Eigen::Index v = 0; v < X.rows(); ++v)
    if (res.weight[v] >= 0.5) all += va[v], bare += d[v] >= room ? va[v] : 0.0;
  return all > 0 ? bare / all : 0.0;
}

// Faces turned against the base (SynthesisResult::inward_share; issue 27): among the faces of the relief (a
// corner displaced by over \p tau), the area share of those whose displaced normal points against the base's
// normal at the same face (n_displaced · n_base < 0), areas of the displaced faces.
double inward_share(const MatrixX3i& Fi, const MatrixX3d& base, const MatrixX3d& displaced, double tau) {
  double all = 0, against = 0;
  for (Eigen::Index f = 0; f < Fi.rows(); ++f) {
    bool relief = false;
    for (int k = 0; k < 3; ++k) relief |= (displaced.row(Fi(f, k)) - base.row(Fi(f, k))).norm() > tau;
    if (!relief) continue;
    auto normal = [&](const MatrixX3d& P) {
      const Vec3 a = P.row(Fi(f, 0)), b = P.row(Fi(f, 1)), c = P.row(Fi(f, 2));
      return Vec3((b - a).cross(c - a));
    };
    const Vec3 nd = normal(displaced), nb = normal(base);
    all += 0.5 * nd.norm();
    against += nd.dot(nb) < 0 ? 0.5 * nd.norm() : 0.0;
  }
  return all > 0 ? against / all : 0.0;
}

// The same for the exemplar as synthesis reads it: its raster over |z| ≤ 0.95 (the placements' reach) as a
// displaced grid, two triangles a cell, the base the flat disk (exemplar units; relief over 5 % of the largest).
double exemplar_inward_share(const Exemplar& ex) {
  const int s = ex.size;
  double largest = 0;
  for (const Vec3& d : ex.grid) largest = std::max(largest, d.norm());
  std::vector<int> id(static_cast<size_t>(s) * s, -1);
  std::vector<Vec3> base, moved;
  for (int j = 0; j < s; ++j)
    for (int i = 0; i < s; ++i)
      if (std::hypot(ex.coord(i), ex.coord(j)) <= 0.95) {
        id[static_cast<size_t>(j) * s + i] = static_cast<int>(base.size());
        base.emplace_back(ex.coord(i) * ex.extent, ex.coord(j) * ex.extent, 0.0);
        moved.push_back(base.back() + ex.grid[static_cast<size_t>(j) * s + i]);
      }
  std::vector<Eigen::Vector3i> tri;
  for (int j = 0; j + 1 < s; ++j)
    for (int i = 0; i + 1 < s; ++i) {
      const int a = id[static_cast<size_t>(j) * s + i], b = id[static_cast<size_t>(j) * s + i + 1],
                c = id[static_cast<size_t>(j + 1) * s + i + 1], d = id[static_cast<size_t>(j + 1) * s + i];
      if (a < 0 || b < 0 || c < 0 || d < 0) continue;
      tri.emplace_back(a, b, c), tri.emplace_back(a, c, d);  // counter-clockwise in (u, v): normals +n
    }
  MatrixX3i Fi(static_cast<Eigen::Index>(tri.size()), 3);
  for (size_t f = 0; f < tri.size(); ++f) Fi.row(static_cast<Eigen::Index>(f)) = tri[f].transpose();
  MatrixX3d B(static_cast<Eigen::Index>(base.size()), 3), M(static_cast<Eigen::Index>(base.size()), 3);
  for (size_t v = 0; v < base.size(); ++v)
    B.row(static_cast<Eigen::Index>(v)) = base[v].transpose(), M.row(static_cast<Eigen::Index>(v)) = moved[v].transpose();
  return inward_share(Fi, B, M, 0.05 * largest);
}

// Patches in a growing front (the "patches" stage): res.centers, res.owner, res.copied, res.patch_radius
// and the displacements written, faded by the weights, in res.local. \p largest: how far a displaced
// point can be from its base point; \p placing: the options placements are made with (placing_options()).
// Then (fill_holes) patches where a whole feature has room, each trying the exemplar's features at its centre.
void place_patches(const Exemplar& ex, const Mesh& T, const MatrixX3d& X, const MatrixX3d& N, const MatrixX3d& F,
                   double largest, const SynthesisOptions& o, const SynthesisOptions& placing, SynthesisResult& res,
                   const std::function<void(const char*)>& stage_done) {
  const Eigen::Index n = T.n_vertices();
  const double rp_ex = o.patch_radius * ex.extent;  // patch radius, exemplar units
  const double rp = res.scale * rp_ex;               // and on the target
  res.patch_radius = rp;
  // Placements: |t| ≤ reach keeps the patch within |z| ≤ 0.95 of the disk: off the raster's points outside
  // it, and off the jagged rim of the geodesic disk, where the map turns the frames by a few degrees (a
  // cut copies what it reads there; a blend averaged it away).
  const double reach = 0.95 * ex.extent - rp_ex;
  Rng rng(o.seed);
  ExpMapper expmap(T, X, N);
  GrowthFront front(T, res.weight, o.patch_spacing * rp, rng);
  const bool cut = o.seams == SeamMethod::Cut;
  const ExemplarFeatures features = cut ? exemplar_features(ex) : ExemplarFeatures();
  Eigen::VectorXd sumW = Eigen::VectorXd::Zero(n), bmax = Eigen::VectorXd::Zero(n);  // blend
  MatrixX3d sumD = MatrixX3d::Zero(n, 3);                                             // blend
  res.owner = Eigen::VectorXi::Constant(n, -1);
  res.copied = MatrixX3d::Zero(n, 3);
  Canvas cv{cut ? MatrixX3d::Zero(n, 3) : MatrixX3d(), std::vector<char>(cut ? n : 0, 0), &res.owner, &res.copied,
            std::vector<int>(n, -1)};
  Placer placer(T, X, N, F, largest, placing, res);
  auto written = [&](int v) { return cut ? cv.has[v] != 0 : sumW[v] > 0; };
  auto old_at = [&](int v) -> Vec3 {
    return cut ? Vec3(cv.cur.row(v).transpose()) : Vec3(sumD.row(v).transpose() / sumW[v]);
  };
  // One patch at c: its placement chosen against the overlap, or (a fill) one of \p given that neither
  // crosses nor folds (tried in turn; none: no patch). \return whether a patch was placed.
  auto place_at = [&](int c, const std::vector<Eigen::Vector2d>* given) {
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
      const double r2 = m.uv[s].squaredNorm() / (rp * rp);
      b[s] = r2 < 1 ? (1 - r2) * (1 - r2) : 0.0;
      if (b[s] > 0 && written(m.vertices[s])) overlap.push_back(s);
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
    Eigen::Vector2d t = given ? given->front() : random_placement();
    std::vector<Eigen::Vector2d> order{t};  // cut: the placements to try against folds, in turn
    if (given) order = *given;
    else if (!overlap.empty() && o.candidates > 1)
      choose_placement(overlap, b, m, o, rng, read, old_at, random_placement, t, order);
    for (size_t s = 0; s < k; ++s) {  // blend the chosen placement in
      const int v = m.vertices[s];
      front.reach(v, m.uv[s].norm());
      if (cut || !(b[s] > 0)) continue;
      Vec3 raw;
      const Vec3 d = read(t, s, &raw);
      const double w = std::pow(b[s], o.blend_power);
      sumW[v] += w;
      sumD.row(v) += w * d.transpose();
      if (b[s] > bmax[v]) bmax[v] = b[s], res.owner[v] = patch, res.copied.row(v) = raw.transpose();
    }
    if (cut && !placer.place(m, b, order, read, patch, rp, cv, given != nullptr)) {
      res.centers.pop_back();
      return false;
    }
    return true;
  };
  for (int c = front.next(); c >= 0; c = front.next()) {
    place_at(c, nullptr);
    report(o.progress, 0.25 + 0.6 * (front.to_cover ? double(front.covered) / front.to_cover : 1.0), "patches");
  }
  if (front.covered < front.to_cover)
    res.warnings.push_back(fmt::format("{} of {} vertices were not reached by any patch (disconnected from the "
                                       "rest and too small for a patch?)",
                                       front.to_cover - front.covered, front.to_cover));
  if (o.fill_holes && features.closest > 0) {
    // The exemplar's features at the patch's centre, the nearest the disk's centre first.
    std::vector<Eigen::Vector2d> at_centre;
    for (const Eigen::Vector2d& z : features.roots)
      if (z.norm() * ex.extent <= reach) at_centre.push_back(z * ex.extent);
    std::sort(at_centre.begin(), at_centre.end(), [](const auto& a, const auto& b) { return a.norm() < b.norm(); });
    const double unit = ex.extent * res.scale;  // target length per unit-disk length
    // Room for a feature whose root stays 0.9 of the closest spacing from the others' (their footprints
    // reach a footprint radius from theirs), and at least its own footprint.
    const double room = std::max(features.footprint, 0.9 * features.closest - features.footprint) * unit;
    if (!at_centre.empty())
      for (int c : feature_holes(T, X, bare_distance(T, X, cv.cur, 0.05 * largest, room), res.weight, room,
                                 features.closest * unit))
        res.filled_patches += place_at(c, &at_centre);
  }

  stage_done("patches");
  report(o.progress, 0.85, "unfold");
  res.local = MatrixX3d::Zero(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    if (written(static_cast<int>(i))) res.local.row(i) = detail::fade(old_at(static_cast<int>(i)), res.weight[i]).transpose();
}

// The automatic keep-out (keep_out.h) multiplied into the growth weight, its area shares in the result.
// \p largest: the features' length on the target (their largest displacement).
void apply_keep_out(const Mesh& target, const Exemplar& ex, double largest, const SynthesisOptions& o,
                    Eigen::VectorXd& weight, SynthesisResult& res) {
  if (!(o.keep_out_crease_angle > 0) && !o.keep_out_thin && !(o.keep_out_pit_depth > 0) &&
      !(o.keep_out_dome_ridge > 0))
    return;
  const double span = std::min(largest, res.scale * o.patch_radius * ex.extent);  // or their patch radius
  const detail::KeepOut k = detail::keep_out(target, span, o.keep_out_crease_angle, o.keep_out_thin,
                                                  o.keep_out_pit_depth, o.keep_out_dome_ridge);
  weight = weight.cwiseProduct(k.weight);
  const double total = k.area.sum();
  auto share = [&](const Eigen::VectorXd& w) {
    double a = 0;
    for (Eigen::Index i = 0; i < w.size(); ++i) a += w[i] < 0.5 ? k.area[i] : 0.0;
    return total > 0 ? a / total : 0.0;
  };
  res.kept_out_share = share(k.weight);
  res.kept_out_creases = share(k.creases);
  res.kept_out_thin = share(k.thin);
  res.kept_out_pits = share(k.pits);
  res.kept_out_domes = share(k.domes);
}

}  // namespace

SynthesisResult synthesize_texture(const Mesh& exemplar_base, const Texture& exemplar, const Mesh& target,
                                   const SynthesisOptions& o, const SynthesisGuides& guides) {
  check_inputs(target, o, guides);
  const Eigen::Index n0 = target.n_vertices();
  // Stages: progress fractions and wall seconds per stage.
  using Clock = std::chrono::steady_clock;
  SynthesisResult res;
  auto stage_start = Clock::now();
  auto stage_done = [&](const char* name) {
    const auto now = Clock::now();
    res.stage_seconds.emplace_back(name, std::chrono::duration<double>(now - stage_start).count());
    stage_start = now;
  };
  report(o.progress, 0, "exemplar");
  const Exemplar ex = make_exemplar(exemplar_base, exemplar, o);
  res.exemplar_center = ex.center;
  res.exemplar_radius = ex.radius;
  res.exemplar_extent = ex.extent;
  Eigen::VectorXd weight = guides.weight.size() ? guides.weight : Eigen::VectorXd::Ones(n0);
  res.estimate = estimate_for(ex, target, weight, o);
  if (res.estimate.vertices > static_cast<size_t>(o.max_vertices))
    throw InvalidInput(fmt::format(
        "texture synthesis: about {} output vertices estimated (about {:.0f} s), beyond max_vertices {}: choose a "
        "larger exemplar_share (now {:.3g}) or scale, refine_ratio 0, or a larger max_vertices",
        res.estimate.vertices, res.estimate.seconds, o.max_vertices, res.estimate.exemplar_share));
  if (o.on_estimate) o.on_estimate(res.estimate);
  res.scale = res.estimate.scale;
  res.height_factor = res.scale * o.height_scale;
  stage_done("exemplar");
  double largest = 0;  // displacement: how far a displaced point can be from its base point
  for (const Vec3& d : ex.grid) largest = std::max(largest, res.height_factor * d.norm());
  apply_keep_out(target, ex, largest, o, weight, res);
  stage_done("keep-out");

  // Refine where the target is coarser than the exemplar scaled to it.
  res.target = target;
  {
    const ProgressFn refine_progress = [&](double f, std::string_view) { report(o.progress, 0.02 + 0.2 * f, "refine"); };
    const std::string line = detail::refine_for(res.target, growth_region(weight), res.scale * ex.mean_edge,
                                                o.refine_ratio, &res.added_vertices, refine_progress);
    if (!line.empty()) res.warnings.push_back(line);
  }
  stage_done("refine");
  const Mesh& T = res.target;
  const Eigen::Index n = T.n_vertices();
  res.weight = n > n0 ? spread_weight(T, weight) : weight;
  report(o.progress, 0.22, "direction field");
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
  stage_done("field");

  // Patches in a growing front.
  const SynthesisOptions placing = placing_options(o, largest, X, res.warnings);
  place_patches(ex, T, X, N, F, largest, o, placing, res, stage_done);
  if (o.unfold) {
    res.unfolded_vertices = unfold(T, X, N, F, o.unfold_radius * res.patch_radius, res.local, o.progress);
    if (res.unfolded_vertices)
      res.warnings.push_back(fmt::format("displacements shrunk at {} vertices where they folded the surface",
                                         res.unfolded_vertices));
  }
  if (o.remove_fragments && o.seams == SeamMethod::Cut) {
    const ExemplarFeatures features = exemplar_features(ex);
    // A whole feature's footprint on the target measured 0.91–2.2 × the exemplar's (igea, tentacle plate); the
    // pieces cut off by a seam or a drop 0.2–0.73 (bench/synthesis.md, eleventh session, fragments).
    const double unit = ex.extent * res.scale;  // target length per unit-disk length
    if (features.lowest > 0)
      res.fragments_removed =
          remove_fragments(T, faces(T), 0.05 * largest, 0.5 * res.height_factor * features.lowest,
                           0.75 * features.smallest * unit * unit, o.feather, res.local, res.fragment_vertices);
  }
  stage_done("unfold");
  encode_and_count(T, X, N, F, 0.05 * largest, placing, res, stage_done);
  res.bare_share = bare_share(ex, T, X, largest, res);
  res.inward_share = inward_share(faces(T), X, res.textured, 0.05 * largest);
  res.exemplar_inward_share = exemplar_inward_share(ex);
  res.shrunk_share = n ? double(res.unfolded_vertices) / n : 0.0;
  res.refined_share = n ? double(res.added_vertices) / n : 0.0;
  report(o.progress, 1, "done");
  return res;
}

SynthesisEstimate estimate_synthesis(const Mesh& exemplar_base, const Texture& exemplar, const Mesh& target,
                                     const SynthesisOptions& o, const SynthesisGuides& guides) {
  check_inputs(target, o, guides);
  const Eigen::Index n0 = target.n_vertices();
  const Exemplar ex = make_exemplar(exemplar_base, exemplar, o);
  return estimate_for(ex, target, guides.weight.size() ? guides.weight : Eigen::VectorXd::Ones(n0), o);
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

namespace {

// Twice the exemplar's correlation length (target units, \p unit per unit-disk length): the shortest lag
// along u and v where the autocorrelation of its heights \p he (at the raster cells \p in_disk, mean
// \p mean_e) reaches 0.
double feature_radius(const Exemplar& ex, const std::vector<int>& in_disk, const Eigen::VectorXd& he, double mean_e,
                      double unit) {
  const Eigen::Index ne = he.size();
  std::vector<double> g(static_cast<size_t>(ex.size) * ex.size, std::nan(""));
  for (Eigen::Index k = 0; k < ne; ++k) g[in_disk[k]] = he[k] - mean_e;
  int lag_found = ex.size / 4;
  for (int lag = 1; lag < ex.size / 4; ++lag) {
    double s = 0, s0 = 0;
    for (int j = 0; j < ex.size; ++j)
      for (int i = 0; i + lag < ex.size; ++i) {
        const double a = g[j * ex.size + i], bx = g[j * ex.size + i + lag];
        const double by = j + lag < ex.size ? g[(j + lag) * ex.size + i] : std::nan("");
        if (std::isnan(a)) continue;
        if (!std::isnan(bx)) s += a * bx, s0 += a * a;
        if (!std::isnan(by)) s += a * by, s0 += a * a;
      }
    if (s0 > 0 && s / s0 < 0) {
      lag_found = lag;
      break;
    }
  }
  return 2 * unit * 2.0 * lag_found / (ex.size - 1);  // twice the lag: one bump, one feature
}

// The lean's direction against the field (SynthesisQuality::lean_angle_error_deg) over the covered
// vertices \p cov: the displacements of the textured target (after encoding and decoding) in the field's
// frames against what each vertex copied.
double lean_error_deg(const SynthesisResult& r, const SynthesisOptions& o, const std::vector<int>& cov) {
  const Mesh& T = r.target;
  const Eigen::Index n = T.n_vertices();
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
  return sw > 0 ? se / sw * 180 / M_PI : 0.0;
}

}  // namespace

SynthesisQuality synthesis_quality(const Mesh& exemplar_base, const Texture& exemplar, const SynthesisResult& r,
                                   const SynthesisOptions& o) {
  check_options(o);
  const Exemplar ex = make_exemplar(exemplar_base, exemplar, o);
  const Mesh& T = r.target;
  const Eigen::Index n = T.n_vertices();
  if (r.texture.height.size() != n || r.owner.size() != n || r.local.rows() != n)
    throw InvalidInput("synthesis quality: the result does not match its target");
  SynthesisQuality q;

  // The exemplar's heights on its raster (the unit disk, |z| ≤ 1; uniform area up to the conformal map).
  const double unit = r.scale * ex.extent;  // target length of a unit-disk length
  std::vector<int> in_disk;
  for (int j = 0; j < ex.size; ++j)
    for (int i = 0; i < ex.size; ++i)
      if (std::hypot(ex.coord(i), ex.coord(j)) <= 1) in_disk.push_back(j * ex.size + i);
  const Eigen::Index ne = static_cast<Eigen::Index>(in_disk.size());
  Eigen::VectorXd he(ne), ae = Eigen::VectorXd::Ones(ne);
  MatrixX3d Pe = MatrixX3d::Zero(ne, 3);
  std::vector<double> rim(ne);
  for (Eigen::Index k = 0; k < ne; ++k) {
    const int i = in_disk[k] % ex.size, j = in_disk[k] / ex.size;
    he[k] = r.height_factor * pseudo_height(ex.grid[in_disk[k]]);
    Pe(k, 0) = unit * ex.coord(i);
    Pe(k, 1) = unit * ex.coord(j);
    rim[k] = unit * (1 - std::hypot(ex.coord(i), ex.coord(j)));
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
  const double corr = feature_radius(ex, in_disk, he, mean_e, unit);
  const double thr = mean_e + std_e;
  const std::vector<int> fe = height_features(Pe, he, corr, thr);
  std::vector<double> fe_rim;
  for (int k : fe) fe_rim.push_back(rim[k]);
  q.exemplar_features = fe.size();
  q.exemplar_spacing = mean_spacing(Pe, fe, fe_rim);
  {
    Eigen::VectorXd hc(cov.size());
    MatrixX3d Pc(cov.size(), 3);
    const MatrixX3d X = positions(T);  // once: inside the loop it made the report quadratic (issue 30)
    for (size_t k = 0; k < cov.size(); ++k) hc[k] = ht[cov[k]], Pc.row(k) = X.row(cov[k]);
    const std::vector<int> ft = height_features(Pc, hc, corr, thr);
    q.target_features = ft.size();
    q.target_spacing = mean_spacing(Pc, ft);
  }
  q.spacing_change = q.exemplar_spacing > 0 ? q.target_spacing / q.exemplar_spacing - 1 : 0.0;

  q.lean_angle_error_deg = lean_error_deg(r, o, cov);

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
