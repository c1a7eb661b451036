#pragma once
//! \file spatial.h An axis-aligned bounding-box tree over triangles, for closest-point queries
//! (metrics, projections) and for finding the triangles near a point (candidate search).

#include <functional>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "geotex/core/mesh.h"

namespace geotex {

//! Closest point on a triangle (a, b, c) to p. \return the point; \p bary receives its barycentric
//! coordinates (weights of a, b, c).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                               Vec3* bary = nullptr);

//! Slabs a sliver triangle (a, b, c) is cut into across its longest edge for tight boxes: 1 up to an
//! aspect (longest edge over the height onto it) of 4, then one per 4, at most \p max_slabs. A needle
//! 0.5 long and 5e-5 wide lying diagonally has an axis-aligned box 0.3 on a side; its slabs' boxes hug it.
int sliver_slab_count(const Vec3& a, const Vec3& b, const Vec3& c, int max_slabs = 8);

//! Append the boxes of triangle (a, b, c) cut into \p slabs equal slabs across its longest edge (each
//! padded by 1e-12 of that edge's length against rounding; an empty slab adds none); slabs = 1 appends
//! the triangle's own box. The boxes together hold the triangle.
void append_slab_boxes(const Vec3& a, const Vec3& b, const Vec3& c, int slabs, std::vector<Eigen::AlignedBox3d>& out);

//! The entries k of \p rows ordered along a Morton curve through the points P.row(rows[k]) in \p box
//! (10 bits an axis; points outside it on its faces): searches made in this order meet the nodes of
//! a tree over the box in cache. \return a permutation of 0 … #rows − 1.
std::vector<int> morton_order(const MatrixX3d& P, std::span<const int> rows, const Eigen::AlignedBox3d& box);

//! A bounding-volume tree over a triangle mesh's faces. A sliver face is held as up to 8 slabs, each
//! with its own tight box (sliver_slab_count), under a budget of 4 references per face on average:
//! the searches below then meet the faces near a point, not every needle whose loose box holds it
//! (issue 30). A mesh without slivers gets one reference per face (the tree of a face per box).
class TriangleTree {
 public:
  //! \param V #V by 3 positions, \param F #F by 3 triangles (copied).
  TriangleTree(const MatrixX3d& V, const MatrixX3i& F);
  explicit TriangleTree(const Mesh& mesh) : TriangleTree(positions(mesh), faces(mesh)) {}

  struct Hit {
    int face = -1;
    Vec3 point = Vec3::Zero();
    Vec3 bary = Vec3::Zero();
    double sq_distance = 0;
  };
  //! Closest point on the surface. Thread-safe (const).
  Hit closest(const Vec3& p) const;
  //! The closest points of the rows \p rows of \p P (#P by 3), one hit per entry of rows, each the
  //! hit of closest(P.row(i)). Searched in parallel (OpenMP) along a Morton curve through the points:
  //! nearby searches share the tree's nodes in cache (points in file order, e.g. random needles',
  //! wait on memory most of the time).
  std::vector<Hit> closest(const MatrixX3d& P, std::span<const int> rows) const;

  //! Visit the faces whose boxes come within \p radius of p, nearest box first (best-first search),
  //! each face once, at the distance of its nearest box (a lower bound on its distance to p).
  //! \p visit(face, box_distance) returns the radius from then on (return the smallest distance that
  //! could still improve a result): faces beyond it are not visited and the search ends. Cost grows
  //! with the faces visited, not with those in the first radius.
  void visit_nearest(const Vec3& p, double radius, const std::function<double(int, double)>& visit) const;
  //! The same, entering only the nodes for which \p enter(node) is true (a pruning test on data the
  //! caller keeps per node, e.g. a cone of normals; see node_count()).
  void visit_nearest(const Vec3& p, double radius, const std::function<double(int, double)>& visit,
                     const std::function<bool(int)>& enter) const;

  //! Visit the faces held by every leaf whose node box comes within \p radius of p, depth-first and in no
  //! particular order: cheaper than visit_nearest()'s heap when the order does not matter. \p visit(face) is
  //! called once per reference, so a sliver's face may come more than once, and a face's own box may lie
  //! farther than \p radius (test it where that matters). Thread-safe (const).
  template <class Visit>
  void visit_within(const Vec3& p, double radius, Visit&& visit) const {
    std::vector<int> stack;
    if (!nodes_.empty()) stack.push_back(0);
    while (!stack.empty()) {
      const Node& n = nodes_[stack.back()];
      stack.pop_back();
      if (n.box.squaredExteriorDistance(p) > radius * radius) continue;
      if (n.left >= 0) {
        stack.push_back(n.left), stack.push_back(n.right);
        continue;
      }
      for (int k = n.begin; k < n.end; ++k) visit(ref_face_[k]);
    }
  }

  //! The tree's nodes, for data kept per node: node 0 is the root and every child has a larger index
  //! than its parent (so a loop from the last node to the first meets children before parents).
  int node_count() const { return static_cast<int>(nodes_.size()); }
  //! Box of a node (it contains the boxes of its faces' references).
  const Eigen::AlignedBox3d& node_box(int node) const { return nodes_[node].box; }
  //! Children of a node, or {−1, −1} for a leaf.
  std::pair<int, int> node_children(int node) const { return {nodes_[node].left, nodes_[node].right}; }
  //! Faces of a leaf, one per reference it holds (a sliver's face may recur, in this leaf or others;
  //! empty for an internal node).
  std::span<const int> node_faces(int node) const {
    const Node& n = nodes_[node];
    return n.left < 0 ? std::span<const int>(ref_face_.data() + n.begin, n.end - n.begin) : std::span<const int>();
  }

  const MatrixX3d& vertices() const { return V_; }
  const MatrixX3i& triangles() const { return F_; }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;  // children (internal node) or -1
    int begin = 0, end = 0;     // range in ref_face_ and ref_box_ (leaf)
  };
  int build(int begin, int end, std::vector<int>& order, const std::vector<Eigen::AlignedBox3d>& box,
            const std::vector<Vec3>& centroid);
  MatrixX3d V_;
  MatrixX3i F_;
  std::vector<Node> nodes_;
  std::vector<int> ref_face_;                    // face of each reference, in leaf order
  std::vector<Eigen::AlignedBox3d> ref_box_;     // its box (the face's, or a slab's)
  bool slabs_ = false;                           // some face has more than one reference
};

}  // namespace geotex
