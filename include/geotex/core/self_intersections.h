#pragma once
//! \file self_intersections.h Where a triangle mesh crosses itself: a spatial query over its faces (box
//! trees over the faces' slabs, spatial.h), used by the texture layer to count what a texture leaves and
//! by the tools to measure it.

#include <vector>

#include "geotex/core/mesh.h"

namespace geotex {

//! Self-intersections: the faces crossed by an edge of a face they share no vertex with (the edge's
//! segment meets the triangle's interior, Möller–Trumbore with a 1e-9 margin in barycentric and segment
//! terms, so touching and coplanar contact do not count). The same measure as `geval.py
//! self-intersections` (faces_hit). \param V #V by 3, \param F #F by 3.
//! \return #F flags: 1 where the face is crossed.
std::vector<char> self_intersecting_faces(const MatrixX3d& V, const MatrixX3i& F);

}  // namespace geotex
