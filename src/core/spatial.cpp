#include "geotex/core/spatial.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>

namespace geotex {

// Ericson, Real-Time Collision Detection, Sec. 5.1.5: Voronoi regions of the triangle.
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* bary) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  auto out = [&](double u, double v, double w) {
    if (bary) *bary = Vec3(u, v, w);
    return Vec3(u * a + v * b + w * c);
  };
  if (d1 <= 0 && d2 <= 0) return out(1, 0, 0);
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return out(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return out(1 - v, v, 0);
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return out(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return out(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return out(0, 1 - w, w);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return out(1, 0, 0);  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return out(1 - v - w, v, w);
}

namespace {

constexpr int kMaxSlabs = 8;   // slabs of one face
constexpr int kRefBudget = 4;  // references per face on average (memory: about 84 bytes each)

// Box of the part of triangle p with u·x in [s0, s1] (clipped by the two planes, Sutherland–Hodgman).
Eigen::AlignedBox3d slab_box(const std::array<Vec3, 3>& p, const Vec3& u, double s0, double s1) {
  std::vector<Vec3> poly(p.begin(), p.end()), next;
  for (int side = 0; side < 2; ++side) {
    next.clear();
    auto inside = [&](const Vec3& x) { return side == 0 ? u.dot(x) >= s0 : u.dot(x) <= s1; };
    const double s = side == 0 ? s0 : s1;
    for (size_t i = 0; i < poly.size(); ++i) {
      const Vec3 &x = poly[i], &y = poly[(i + 1) % poly.size()];
      if (inside(x)) next.push_back(x);
      if (inside(x) != inside(y)) next.push_back(x + (s - u.dot(x)) / u.dot(y - x) * (y - x));
    }
    poly.swap(next);
  }
  Eigen::AlignedBox3d box;
  box.setEmpty();
  for (const Vec3& x : poly) box.extend(x);
  return box;
}

// The faces one search has met (a sliver's face is met once per slab): open addressing, grown at half full.
class FaceSet {
 public:
  bool insert(int f) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    const size_t mask = slots_.size() - 1;
    for (size_t h = (uint64_t(uint32_t(f)) * 0x9E3779B97F4A7C15ull) >> 32 & mask;; h = (h + 1) & mask) {
      if (slots_[h] == f) return false;
      if (slots_[h] < 0) {
        slots_[h] = f;
        ++size_;
        return true;
      }
    }
  }

 private:
  void grow() {
    std::vector<int> old = std::move(slots_);
    slots_.assign(std::max<size_t>(64, 2 * old.size()), -1);
    size_ = 0;
    for (int f : old)
      if (f >= 0) insert(f);
  }
  std::vector<int> slots_;
  size_t size_ = 0;
};

}  // namespace

int sliver_slab_count(const Vec3& a, const Vec3& b, const Vec3& c, int max_slabs) {
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  const double width = (b - a).cross(c - a).norm() / std::max(longest, 1e-300);
  if (!(longest > 4 * width)) return 1;
  return static_cast<int>(std::min<double>(std::max(max_slabs, 1), std::ceil(longest / (4 * width))));
}

void append_slab_boxes(const Vec3& a, const Vec3& b, const Vec3& c, int slabs, std::vector<Eigen::AlignedBox3d>& out) {
  const std::array<Vec3, 3> p = {a, b, c};
  if (slabs <= 1) {
    Eigen::AlignedBox3d whole(a);
    out.push_back(whole.extend(b).extend(c));
    return;
  }
  int e = 0;  // the longest edge, p[e] to p[e + 1]: the third vertex projects between its ends
  for (int k = 1; k < 3; ++k)
    if ((p[(k + 1) % 3] - p[k]).squaredNorm() > (p[(e + 1) % 3] - p[e]).squaredNorm()) e = k;
  const Vec3 u = (p[(e + 1) % 3] - p[e]).normalized();
  const double t0 = u.dot(p[e]), t1 = u.dot(p[(e + 1) % 3]), pad = 1e-12 * (t1 - t0);
  for (int j = 0; j < slabs; ++j) {
    const Eigen::AlignedBox3d box = slab_box(p, u, t0 + (t1 - t0) * j / slabs, t0 + (t1 - t0) * (j + 1) / slabs);
    if (box.isEmpty()) continue;
    out.push_back(Eigen::AlignedBox3d(box.min().array() - pad, box.max().array() + pad));
  }
}

TriangleTree::TriangleTree(const MatrixX3d& V, const MatrixX3i& F) : V_(V), F_(F) {
  const int nf = static_cast<int>(F_.rows());
  auto corner = [&](int f, int k) { return Vec3(V_.row(F_(f, k)).transpose()); };
  // Slabs per face: each sliver's own count, all capped alike so that the references stay within budget.
  std::vector<int> slabs(nf);
  std::array<int64_t, kMaxSlabs + 1> with{};  // faces asking for k slabs
  for (int f = 0; f < nf; ++f) ++with[slabs[f] = sliver_slab_count(corner(f, 0), corner(f, 1), corner(f, 2), kMaxSlabs)];
  int cap = kMaxSlabs;
  auto refs = [&](int m) {
    int64_t total = 0;
    for (int k = 1; k <= kMaxSlabs; ++k) total += with[k] * std::min(k, m);
    return total;
  };
  while (cap > 1 && refs(cap) > int64_t(kRefBudget) * nf) --cap;
  std::vector<Eigen::AlignedBox3d> box;
  std::vector<int> face;
  box.reserve(refs(cap));
  face.reserve(refs(cap));
  for (int f = 0; f < nf; ++f) {
    const size_t before = box.size();
    append_slab_boxes(corner(f, 0), corner(f, 1), corner(f, 2), std::min(slabs[f], cap), box);
    if (box.size() == before) append_slab_boxes(corner(f, 0), corner(f, 1), corner(f, 2), 1, box);  // NaN slabs
    if (box.size() > before + 1) slabs_ = true;
    face.resize(box.size(), f);
  }
  const int nr = static_cast<int>(box.size());
  std::vector<int> order(nr);
  std::vector<Vec3> centroid(nr);
  for (int r = 0; r < nr; ++r) {
    order[r] = r;
    centroid[r] = box[r].center();
  }
  nodes_.reserve(2 * nr / 4 + 2);
  if (nr > 0) build(0, nr, order, box, centroid);
  // Each leaf's references side by side in memory.
  ref_face_.resize(nr);
  ref_box_.resize(nr);
  for (int i = 0; i < nr; ++i) {
    ref_face_[i] = face[order[i]];
    ref_box_[i] = box[order[i]];
  }
}

int TriangleTree::build(int begin, int end, std::vector<int>& order, const std::vector<Eigen::AlignedBox3d>& face_box,
                        const std::vector<Vec3>& centroid) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box;
  for (int i = begin; i < end; ++i) box.extend(face_box[order[i]]);
  nodes_[id].box = box;
  if (end - begin <= 4) {
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return id;
  }
  int axis;
  box.sizes().maxCoeff(&axis);
  const int mid = (begin + end) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](int a, int b) { return centroid[a][axis] < centroid[b][axis]; });
  const int l = build(begin, mid, order, face_box, centroid);
  const int r = build(mid, end, order, face_box, centroid);
  nodes_[id].left = l;
  nodes_[id].right = r;
  return id;
}

TriangleTree::Hit TriangleTree::closest(const Vec3& p) const {
  Hit best;
  best.sq_distance = std::numeric_limits<double>::infinity();
  if (nodes_.empty()) return best;
  // Depth-first, nearer child first, pruned by the best distance so far.
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (n.box.squaredExteriorDistance(p) >= best.sq_distance) continue;
    if (n.left < 0) {
      for (int i = n.begin; i < n.end; ++i) {
        // A slab's box holds only its part of the face; the face's nearest point lies in one of them.
        if (slabs_ && ref_box_[i].squaredExteriorDistance(p) >= best.sq_distance) continue;
        const int f = ref_face_[i];
        Vec3 bary;
        const Vec3 q = closest_point_on_triangle(p, V_.row(F_(f, 0)), V_.row(F_(f, 1)), V_.row(F_(f, 2)), &bary);
        const double d = (q - p).squaredNorm();
        if (d < best.sq_distance) best = {f, q, bary, d};
      }
      continue;
    }
    const double dl = nodes_[n.left].box.squaredExteriorDistance(p);
    const double dr = nodes_[n.right].box.squaredExteriorDistance(p);
    if (top + 2 > 128) continue;  // cannot happen for balanced trees under 2^60 faces
    if (dl < dr) {
      stack[top++] = n.right;
      stack[top++] = n.left;
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  return best;
}

std::vector<int> morton_order(const MatrixX3d& P, std::span<const int> rows, const Eigen::AlignedBox3d& box) {
  const int m = static_cast<int>(rows.size());
  const Vec3 lo = box.isEmpty() ? Vec3(Vec3::Zero()) : Vec3(box.min());
  const Vec3 size = box.isEmpty() ? Vec3(Vec3::Zero()) : Vec3(box.sizes());
  std::vector<std::pair<uint32_t, int>> keyed(m);
  for (int k = 0; k < m; ++k) {
    uint32_t key = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double t = size[axis] > 0 ? (P(rows[k], axis) - lo[axis]) / size[axis] : 0.0;
      const uint32_t q = static_cast<uint32_t>(std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * 1023.0);
      for (int bit = 0; bit < 10; ++bit) key |= ((q >> bit) & 1u) << (3 * bit + axis);
    }
    keyed[k] = {key, k};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<int> order(m);
  for (int k = 0; k < m; ++k) order[k] = keyed[k].second;
  return order;
}

std::vector<TriangleTree::Hit> TriangleTree::closest(const MatrixX3d& P, std::span<const int> rows) const {
  std::vector<Hit> out(rows.size());
  if (nodes_.empty()) {
    for (Hit& h : out) h.sq_distance = std::numeric_limits<double>::infinity();
    return out;
  }
  const std::vector<int> order = morton_order(P, rows, nodes_[0].box);
#pragma omp parallel for schedule(dynamic, 1024)
  for (int j = 0; j < static_cast<int>(order.size()); ++j)
    out[order[j]] = closest(Vec3(P.row(rows[order[j]]).transpose()));
  return out;
}

void TriangleTree::visit_nearest(const Vec3& p, double radius, const std::function<double(int, double)>& visit) const {
  visit_nearest(p, radius, visit, [](int) { return true; });
}

void TriangleTree::visit_nearest(const Vec3& p, double radius, const std::function<double(int, double)>& visit,
                                 const std::function<bool(int)>& enter) const {
  if (nodes_.empty() || !enter(0)) return;
  // A min-heap of nodes and references by squared box distance; references are entered as ~reference.
  // A face is visited at its first (nearest) reference: its other slabs' boxes are no nearer.
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  double r2 = radius * radius;
  heap.emplace(nodes_[0].box.squaredExteriorDistance(p), 0);
  FaceSet seen;
  while (!heap.empty()) {
    const auto [d2, id] = heap.top();
    heap.pop();
    if (d2 > r2) break;
    if (id < 0) {
      const int f = ref_face_[~id];
      if (slabs_ && !seen.insert(f)) continue;
      const double r = visit(f, std::sqrt(d2));
      r2 = std::min(r2, r * r);
      continue;
    }
    const Node& n = nodes_[id];
    if (n.left < 0) {
      for (int i = n.begin; i < n.end; ++i) {
        const double fd = ref_box_[i].squaredExteriorDistance(p);
        if (fd <= r2) heap.emplace(fd, ~i);
      }
    } else {
      for (int c : {n.left, n.right}) {
        const double cd = nodes_[c].box.squaredExteriorDistance(p);
        if (cd <= r2 && enter(c)) heap.emplace(cd, c);
      }
    }
  }
}

}  // namespace geotex
