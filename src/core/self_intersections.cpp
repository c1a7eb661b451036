#include "geotex/core/self_intersections.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numeric>
#include <tuple>
#include <utility>
#include <vector>

#include "geotex/core/spatial.h"

namespace geotex {

namespace {

// Faces around a hub (a vertex in more than kHubFaces faces) all reach the hub, so their boxes overlap
// there and a box search from any edge through the hub returns every one of them: a fan of 10^5
// triangles gave 10^10 candidates (issue 30). No edge crosses a face it shares a vertex with, so each
// hub's faces get a tree of their own, which edges through that hub do not search.
constexpr int kHubFaces = 1024;
// A sliver's box is loose: a needle 0.5 long and 5e-5 wide lying diagonally has a box 0.3 on a side,
// and 10^5 random needles' boxes hold a ball around an edge's midpoint thousands of times over (issue
// 30). Slivers are cut into up to kMaxSlabs slabs across their longest edge, each with its own box
// (sliver_slab_count, append_slab_boxes: the slabs of TriangleTree), and their edges searched piece by
// piece: the boxes then hug the faces.
constexpr int kMaxSlabs = 8;

// A bounding-volume tree over boxes, searched by box overlap: the boxes of a long edge's pieces are
// tighter than balls around them (a diagonal piece's box has a
// fifth of its ball's volume), and a flat node array keeps each visit to a few loads.
class BoxTree {
 public:
  explicit BoxTree(std::vector<Eigen::AlignedBox3d> boxes) : boxes_(std::move(boxes)), order_(boxes_.size()) {
    std::iota(order_.begin(), order_.end(), 0);
    if (!boxes_.empty()) build(0, static_cast<int>(boxes_.size()));
    std::vector<Eigen::AlignedBox3d> sorted(boxes_.size());  // each leaf's boxes side by side in memory
    for (size_t i = 0; i < order_.size(); ++i) sorted[i] = boxes_[order_[i]];
    boxes_.swap(sorted);
  }
  //! Calls visit(i) for every box i that meets \p q (closed boxes).
  template <class Visit>
  void overlapping(const Eigen::AlignedBox3d& q, Visit&& visit) const {
    if (nodes_.empty()) return;
    int stack[128], top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!meets(n.box, q)) continue;
      if (n.right < 0) {
        for (int i = n.begin; i < n.end; ++i)
          if (meets(boxes_[i], q)) visit(order_[i]);
      } else if (top + 2 <= 128) {
        stack[top++] = n.right;
        stack[top++] = n.left;
      }
    }
  }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1, begin = 0, end = 0;
  };
  static bool meets(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
    return (a.min().array() <= b.max().array()).all() && (b.min().array() <= a.max().array()).all();
  }
  int build(int begin, int end) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.emplace_back();
    Eigen::AlignedBox3d box;
    box.setEmpty();
    for (int i = begin; i < end; ++i) box.extend(boxes_[order_[i]]);
    nodes_[id].box = box;
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    if (end - begin <= 8) return id;
    int axis;
    box.sizes().maxCoeff(&axis);
    const int mid = (begin + end) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int a, int b) {
      return boxes_[a].min()[axis] + boxes_[a].max()[axis] < boxes_[b].min()[axis] + boxes_[b].max()[axis];
    });
    const int l = build(begin, mid);
    const int r = build(mid, end);
    nodes_[id].left = l;
    nodes_[id].right = r;
    return id;
  }
  std::vector<Eigen::AlignedBox3d> boxes_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

struct FaceGroup {
  int hub = -1;                 // the vertex every face of the group holds, or -1 (faces around no hub)
  std::vector<int> piece_face;  // the tree's boxes as faces of F
  std::unique_ptr<BoxTree> tree;
  Eigen::AlignedBox3d box;      // of the group's faces
};

// The tree over the slabs of \p faces (a face that is no sliver is one slab: its own box).
void build_slab_tree(FaceGroup& g, const MatrixX3d& V, const MatrixX3i& F, const std::vector<int>& faces,
                     const std::vector<int>& slabs) {
  std::vector<Eigen::AlignedBox3d> boxes;
  g.box.setEmpty();
  for (int f : faces) {
    const std::array<Vec3, 3> p = {V.row(F(f, 0)).transpose(), V.row(F(f, 1)).transpose(), V.row(F(f, 2)).transpose()};
    Eigen::AlignedBox3d whole(p[0]);
    whole.extend(p[1]).extend(p[2]);
    g.box.extend(whole);
    append_slab_boxes(p[0], p[1], p[2], slabs[f], boxes);
    g.piece_face.resize(boxes.size(), f);
  }
  g.tree = std::make_unique<BoxTree>(std::move(boxes));
}

// The groups of the faces not marked in \p skip (empty: every face); hubs by the valence in all of F.
std::vector<FaceGroup> face_groups(const MatrixX3d& V, const MatrixX3i& F, const std::vector<int>& slabs,
                                   const std::vector<char>& skip) {
  std::vector<int> count(V.rows(), 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++count[F(f, k)];
  std::vector<std::vector<int>> members(1);
  std::vector<int> hubs(1, -1), group_of(V.rows(), -1);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (!skip.empty() && skip[f]) continue;
    int hub = F(f, 0);
    for (int k = 1; k < 3; ++k)
      if (count[F(f, k)] > count[hub]) hub = F(f, k);
    int g = 0;
    if (count[hub] > kHubFaces) {
      if (group_of[hub] < 0) {
        group_of[hub] = static_cast<int>(members.size());
        members.emplace_back();
        hubs.push_back(hub);
      }
      g = group_of[hub];
    }
    members[g].push_back(static_cast<int>(f));
  }
  std::vector<FaceGroup> groups(members.size());
  for (size_t g = 0; g < members.size(); ++g) {
    groups[g].hub = hubs[g];
    if (!members[g].empty()) build_slab_tree(groups[g], V, F, members[g], slabs);
  }
  return groups;
}

// An edge (a, b), a < b, and the pieces it is searched in (those of its most sliver face's slabs).
struct SearchEdge {
  int a, b, pieces;
  bool operator<(const SearchEdge& o) const { return std::tie(a, b, pieces) < std::tie(o.a, o.b, o.pieces); }
};

}  // namespace

std::vector<char> self_intersecting_faces(const MatrixX3d& V, const MatrixX3i& F) {
  std::vector<char> hit(F.rows(), 0);
  if (F.rows() == 0) return hit;
  std::vector<int> slabs(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    slabs[f] = sliver_slab_count(V.row(F(f, 0)).transpose(), V.row(F(f, 1)).transpose(), V.row(F(f, 2)).transpose(),
                                 kMaxSlabs);
  // Every edge once (as the pair (a, b), a < b, with the most pieces any of its faces asks), then the
  // faces with a slab box meeting a piece's box: the only ones it can cross.
  std::vector<SearchEdge> edges;
  edges.reserve(3 * F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const double longest = std::max({(V.row(F(f, 0)) - V.row(F(f, 1))).norm(), (V.row(F(f, 1)) - V.row(F(f, 2))).norm(),
                                     (V.row(F(f, 2)) - V.row(F(f, 0))).norm()});
    for (int k = 0; k < 3; ++k) {
      const auto [a, b] = std::minmax(F(f, k), F(f, (k + 1) % 3));
      const double share = longest > 0 ? (V.row(a) - V.row(b)).norm() / longest : 1.0;
      edges.push_back({a, b, std::max(1, static_cast<int>(std::ceil(slabs[f] * share - 1e-9)))});
    }
  }
  std::sort(edges.begin(), edges.end());
  {  // one entry per edge, with its largest piece count (the last after sorting)
    size_t w = 0;
    for (size_t i = 0; i < edges.size(); ++i) {
      if (w > 0 && edges[w - 1].a == edges[i].a && edges[w - 1].b == edges[i].b) edges[w - 1] = edges[i];
      else edges[w++] = edges[i];
    }
    edges.resize(w);
  }
  // The pieces searched in the order of a Morton curve through their midpoints: nearby searches share
  // the tree's nodes in cache (random needles in index order wait on memory most of the time). A face
  // found from two pieces, or through two of its slabs, is tested again: the same flag.
  struct Search {
    uint64_t key;
    int edge, piece;
  };
  std::vector<Search> searches;
  {
    const Eigen::RowVector3d lo = V.colwise().minCoeff(), size = V.colwise().maxCoeff() - lo;
    for (size_t e = 0; e < edges.size(); ++e) {
      const Eigen::RowVector3d p0 = V.row(edges[e].a), d = V.row(edges[e].b) - p0;
      for (int piece = 0; piece < edges[e].pieces; ++piece) {
        const Eigen::RowVector3d mid = p0 + (piece + 0.5) / edges[e].pieces * d;
        uint64_t k = 0;
        for (int axis = 0; axis < 3; ++axis) {
          const double t = size[axis] > 0 ? (mid[axis] - lo[axis]) / size[axis] : 0.0;
          const uint64_t q = static_cast<uint64_t>(std::clamp(t, 0.0, 1.0) * 1023.0);
          for (int bit = 0; bit < 10; ++bit) k |= ((q >> bit) & 1) << (3 * bit + axis);
        }
        searches.push_back({k, static_cast<int>(e), piece});
      }
    }
    std::sort(searches.begin(), searches.end(), [](const Search& x, const Search& y) { return x.key < y.key; });
  }
  // A face found crossed is not tested again (a textured soup of 10^5 needles crosses 98% of its faces,
  // most of them from hundreds of edges; issue 30): the flags are shared, set and read relaxed (a
  // face tested twice by two threads at once is flagged twice, the same). One search in 8 (spread
  // evenly along the curve) goes first; if it flagged a quarter of the faces or more, the others
  // search trees over the faces not yet flagged only.
  auto search = [&](const std::vector<FaceGroup>& groups, bool first) {
#pragma omp parallel for schedule(dynamic, 4096)
    for (size_t s = 0; s < searches.size(); ++s) {
      if ((s % 8 == 0) != first) continue;
      const int a = edges[searches[s].edge].a, b = edges[searches[s].edge].b, m = edges[searches[s].edge].pieces;
      const int piece = searches[s].piece;
      const Vec3 p0 = V.row(a).transpose(), d = (V.row(b) - V.row(a)).transpose();
      const double pad = 1e-12 * (d.norm() + p0.cwiseAbs().maxCoeff());  // rounding of the pieces' ends
      Eigen::AlignedBox3d q(Vec3(p0 + double(piece) / m * d));
      q.extend(Vec3(piece + 1 == m ? Vec3(V.row(b).transpose()) : Vec3(p0 + double(piece + 1) / m * d)));
      q = Eigen::AlignedBox3d(q.min().array() - pad, q.max().array() + pad);
      auto test = [&](int f) {
        if (std::atomic_ref<char>(hit[f]).load(std::memory_order_relaxed)) return;
        const int i = F(f, 0), j = F(f, 1), k = F(f, 2);
        if (a == i || a == j || a == k || b == i || b == j || b == k) return;
        const Vec3 A = V.row(i).transpose(), e1 = (V.row(j) - V.row(i)).transpose(),
                   e2 = (V.row(k) - V.row(i)).transpose();
        if (segment_crosses_triangle(p0, d, A, e1, e2)) std::atomic_ref<char>(hit[f]).store(1, std::memory_order_relaxed);
      };
      for (const FaceGroup& g : groups)
        if (g.hub != a && g.hub != b && g.tree && g.box.intersects(q))
          g.tree->overlapping(q, [&](int t) { test(g.piece_face[t]); });
    }
  };
  const std::vector<FaceGroup> groups = face_groups(V, F, slabs, {});
  search(groups, true);
  if (4 * std::count(hit.begin(), hit.end(), 1) >= F.rows()) search(face_groups(V, F, slabs, hit), false);
  else search(groups, false);
  return hit;
}

}  // namespace geotex
