#include "geotex/core/spatial.h"

#include <queue>

#include <algorithm>
#include <limits>

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

TriangleTree::TriangleTree(const MatrixX3d& V, const MatrixX3i& F) : V_(V), F_(F) {
  const int nf = static_cast<int>(F_.rows());
  order_.resize(nf);
  face_box_.resize(nf);
  centroid_.resize(nf);
  for (int f = 0; f < nf; ++f) {
    order_[f] = f;
    Eigen::AlignedBox3d box;
    for (int k = 0; k < 3; ++k) box.extend(Vec3(V_.row(F_(f, k))));
    face_box_[f] = box;
    centroid_[f] = box.center();
  }
  nodes_.reserve(2 * nf / 4 + 2);
  if (nf > 0) build(0, nf);
}

int TriangleTree::build(int begin, int end) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::AlignedBox3d box;
  for (int i = begin; i < end; ++i) box.extend(face_box_[order_[i]]);
  nodes_[id].box = box;
  if (end - begin <= 4) {
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return id;
  }
  int axis;
  box.sizes().maxCoeff(&axis);
  const int mid = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int a, int b) { return centroid_[a][axis] < centroid_[b][axis]; });
  const int l = build(begin, mid);
  const int r = build(mid, end);
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
        const int f = order_[i];
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

void TriangleTree::faces_near(const Vec3& p, double radius, std::vector<int>& out) const {
  out.clear();
  if (nodes_.empty()) return;
  const double r2 = radius * radius;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    const Node& n = nodes_[stack.back()];
    stack.pop_back();
    if (n.box.squaredExteriorDistance(p) > r2) continue;
    if (n.left < 0) {
      for (int i = n.begin; i < n.end; ++i)
        if (face_box_[order_[i]].squaredExteriorDistance(p) <= r2) out.push_back(order_[i]);
    } else {
      stack.push_back(n.left);
      stack.push_back(n.right);
    }
  }
}

void TriangleTree::visit_nearest(const Vec3& p, double radius, const std::function<double(int, double)>& visit) const {
  visit_nearest(p, radius, visit, [](int) { return true; });
}

void TriangleTree::visit_nearest(const Vec3& p, double radius, const std::function<double(int, double)>& visit,
                                 const std::function<bool(int)>& enter) const {
  if (nodes_.empty() || !enter(0)) return;
  // A min-heap of nodes and faces by squared box distance; faces are entered as ~face.
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
  double r2 = radius * radius;
  heap.emplace(nodes_[0].box.squaredExteriorDistance(p), 0);
  while (!heap.empty()) {
    const auto [d2, id] = heap.top();
    heap.pop();
    if (d2 > r2) break;
    if (id < 0) {
      const double r = visit(~id, std::sqrt(d2));
      r2 = std::min(r2, r * r);
      continue;
    }
    const Node& n = nodes_[id];
    if (n.left < 0) {
      for (int i = n.begin; i < n.end; ++i) {
        const double fd = face_box_[order_[i]].squaredExteriorDistance(p);
        if (fd <= r2) heap.emplace(fd, ~order_[i]);
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
