#pragma once
//! \file self_intersections.h Where a triangle mesh crosses itself: a spatial query over its faces (box
//! trees over the faces' slabs, spatial.h), used by the texture layer to count what a texture leaves and
//! by the tools to measure it.

#include <cmath>
#include <vector>

#include "geotex/core/mesh.h"

namespace geotex {

//! Whether the segment p0 + s d, s in (0, 1), crosses the interior of the triangle A, A + e1, A + e2
//! (Möller–Trumbore with a 1e-9 margin in barycentric and segment terms: touching and coplanar contact do
//! not count). The test self_intersecting_faces() applies to each edge and face.
inline bool segment_crosses_triangle(const Vec3& p0, const Vec3& d, const Vec3& A, const Vec3& e1, const Vec3& e2) {
  constexpr double kEps = 1e-9;
  const Vec3 pv = d.cross(e2);
  const double det = e1.dot(pv);
  if (!(std::abs(det) > 1e-30)) return false;
  const Vec3 t = p0 - A, qv = t.cross(e1);
  const double u = t.dot(pv) / det, v = d.dot(qv) / det, w = e2.dot(qv) / det;
  return u > kEps && v > kEps && u + v < 1 - kEps && w > kEps && w < 1 - kEps;
}

//! Self-intersections: the faces crossed by an edge of a face they share no vertex with (the edge's
//! segment meets the triangle's interior, Möller–Trumbore with a 1e-9 margin in barycentric and segment
//! terms, so touching and coplanar contact do not count). The same measure as `geval.py
//! self-intersections` (faces_hit). \param V #V by 3, \param F #F by 3.
//! \return #F flags: 1 where the face is crossed.
std::vector<char> self_intersecting_faces(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace geotex
