// Local refinement (toolkit/refine.h).

#include <iostream>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/refine.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

TEST(Refine, SplitsOnlyTheRegionUntilItsEdgesAreShortAndStaysOnTheSurface) {
  const Mesh coarse = icosphere(1, 1.0);  // 42 vertices
  const MatrixX3d X = positions(coarse);
  std::vector<char> region(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) region[i] = X(i, 2) > 0.3;
  RefineOptions o;
  o.max_edge = 0.15;
  const RefineResult r = refine_region(coarse, region, o);
  EXPECT_GT(r.added, 100u);
  const Mesh& m = r.mesh;
  // Old vertices first, unmoved; topology of a sphere kept; no degenerate faces.
  EXPECT_EQ((positions(m).topRows(X.rows()) - X).norm(), 0.0);
  EXPECT_EQ(euler_characteristic(m), 2);
  EXPECT_EQ(m.n_faces(), coarse.n_faces() + 2 * r.added);
  EXPECT_GT(face_areas(m).minCoeff(), 0.0);
  // Every edge touching the region is short now (fairing evens the spacing out a little); edges far
  // from it are untouched.
  for (auto e : m.edges()) {
    const auto h = m.halfedge_handle(e, 0);
    const int a = m.from_vertex_handle(h).idx(), b = m.to_vertex_handle(h).idx();
    if (r.region[a] || r.region[b]) EXPECT_LE(m.calc_edge_length(e), 1.5 * o.max_edge);
  }
  for (auto v : coarse.vertices())
    if (X(v.idx(), 2) < -0.5) EXPECT_EQ(m.valence(m.vertex_handle(v.idx())), coarse.valence(v));
  // Smoother than the flat facets: the largest bend between neighbouring faces inside the region is
  // smaller (the flat facets keep the coarse mesh's creases; the fair surface bends most at the old vertices), and the new vertices stay near the
  // sphere the coarse mesh samples.
  auto worst_bend = [&](const RefineResult& rr) {
    const Eigen::VectorXd a = dihedral_angles(rr.mesh);
    double w = 0;
    for (auto e : rr.mesh.edges()) {
      const auto h = rr.mesh.halfedge_handle(e, 0);
      if (rr.region[rr.mesh.from_vertex_handle(h).idx()] && rr.region[rr.mesh.to_vertex_handle(h).idx()])
        w = std::max(w, std::abs(a[e.idx()]));
    }
    return w * 180 / M_PI;
  };
  double off = 0;
  for (Eigen::Index i = X.rows(); i < static_cast<Eigen::Index>(m.n_vertices()); ++i)
    off = std::max(off, std::abs(to_eigen(m.point(m.vertex_handle(i))).norm() - 1));
  EXPECT_LT(off, 0.1);
  RefineOptions flat_options = o;
  flat_options.smooth = flat_options.fair = false;
  const RefineResult flat = refine_region(coarse, region, flat_options);
  std::cout << "[ refine icosphere(1) cap ] largest bend inside: " << worst_bend(r) << " deg (flat midpoints "
            << worst_bend(flat) << "), largest distance of a new vertex from the sphere " << off << "\n";
  EXPECT_LT(worst_bend(r), 0.8 * worst_bend(flat));
  EXPECT_THROW(refine_region(coarse, std::vector<char>(3, 1), o), InvalidInput);
  o.max_edge = 0;
  EXPECT_THROW(refine_region(coarse, region, o), InvalidInput);
}
