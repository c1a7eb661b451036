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

  //! Faces whose bounding box comes within \p radius of p (candidates for other queries).
  void faces_near(const Vec3& p, double radius, std::vector<int>& out) const;

  //! Visit the faces whose bounding box comes within \p radius of p, nearest box first (best-first
  //! search). \p visit(face, box_distance) returns the radius from then on (return the smallest
  //! distance that could still improve a result): faces beyond it are not visited and the search
  //! ends. Cost grows with the faces visited, not with those in the first radius.
  void visit_nearest(const Vec3& p, double radius, const std::function<double(int, double)>& visit) const;
  //! The same, entering only the nodes for which \p enter(node) is true (a pruning test on data the
  //! caller keeps per node, e.g. a cone of normals; see node_count()).
  void visit_nearest(const Vec3& p, double radius, const std::function<double(int, double)>& visit,
                     const std::function<bool(int)>& enter) const;

  //! The tree's nodes, for data kept per node: node 0 is the root and every child has a larger index
  //! than its parent (so a loop from the last node to the first meets children before parents).
  int node_count() const { return static_cast<int>(nodes_.size()); }
  //! Box of a node (it contains the boxes of its faces).
  const Eigen::AlignedBox3d& node_box(int node) const { return nodes_[node].box; }
  //! Children of a node, or {−1, −1} for a leaf.
  std::pair<int, int> node_children(int node) const { return {nodes_[node].left, nodes_[node].right}; }
  //! Faces of a leaf (empty for an internal node).
  std::span<const int> node_faces(int node) const {
    const Node& n = nodes_[node];
    return n.left < 0 ? std::span<const int>(order_.data() + n.begin, n.end - n.begin) : std::span<const int>();
  }

  const MatrixX3d& vertices() const { return V_; }
  const MatrixX3i& triangles() const { return F_; }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;  // children (internal node) or -1
    int begin = 0, end = 0;     // range in order_ (leaf)
  };
  int build(int begin, int end);
  MatrixX3d V_;
  MatrixX3i F_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
  std::vector<Eigen::AlignedBox3d> face_box_;
  std::vector<Vec3> centroid_;
};

}  // namespace geotex
