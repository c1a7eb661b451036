#include "geotex/core/mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_set>

#include <fmt/format.h>
#include <OpenMesh/Core/System/omstream.hh>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/mesh_repair.h"

namespace geotex {

MatrixX3d positions(const Mesh& mesh) {
  MatrixX3d V(mesh.n_vertices(), 3);
  for (auto v : mesh.vertices()) V.row(v.idx()) = to_eigen(mesh.point(v)).transpose();
  return V;
}

MatrixX3i faces(const Mesh& mesh) {
  MatrixX3i F(mesh.n_faces(), 3);
  for (auto f : mesh.faces()) {
    int k = 0;
    for (auto v : f.vertices()) F(f.idx(), k++) = v.idx();
  }
  return F;
}

MatrixX2i edges(const Mesh& mesh) {
  MatrixX2i E(mesh.n_edges(), 2);
  for (auto e : mesh.edges()) {
    E(e.idx(), 0) = e.h0().from().idx();
    E(e.idx(), 1) = e.h0().to().idx();
  }
  return E;
}

void set_positions(Mesh& mesh, const MatrixX3d& V) {
  if (static_cast<size_t>(V.rows()) != mesh.n_vertices())
    throw InvalidInput(fmt::format("set_positions: {} rows for a mesh of {} vertices", V.rows(),
                                   mesh.n_vertices()));
  for (auto v : mesh.vertices()) mesh.set_point(v, to_point(V.row(v.idx()).transpose()));
}

namespace {
// OpenMesh prints "complex edge" lines on omerr for every refused face; we count them instead.
struct SilenceOmerr {
  bool was_enabled = omerr().is_enabled();
  SilenceOmerr() { omerr().disable(); }
  ~SilenceOmerr() {
    if (was_enabled) omerr().enable();
  }
};

struct TriKeyHash {
  size_t operator()(const std::array<int, 3>& k) const {
    uint64_t h = static_cast<uint64_t>(k[0]) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<uint64_t>(k[1]) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h ^= static_cast<uint64_t>(k[2]) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return static_cast<size_t>(h);
  }
};
}  // namespace

Mesh make_mesh(const MatrixX3d& V, const MatrixX3i& F, BuildReport* report, const BuildOptions& options) {
  BuildReport rep;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (!V.row(i).allFinite())
      throw InvalidInput(fmt::format("vertex {} has a non-finite coordinate ({}, {}, {})", i,
                                     V(i, 0), V(i, 1), V(i, 2)));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) < 0 || F(f, k) >= V.rows())
        throw InvalidInput(fmt::format("face {} refers to vertex {}, but there are {} vertices", f,
                                       F(f, k), V.rows()));

  std::vector<std::array<int, 3>> tris;
  tris.reserve(F.rows());
  {
    std::unordered_set<std::array<int, 3>, TriKeyHash> seen;
    seen.reserve(F.rows() * 2);
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
      if (a == b || b == c || a == c) {
        ++rep.degenerate_faces;
        continue;
      }
      std::array<int, 3> key{a, b, c};
      std::sort(key.begin(), key.end());
      if (!seen.insert(key).second) {
        ++rep.duplicate_faces;
        continue;
      }
      tris.push_back({a, b, c});
    }
  }

  // Vertices are V's rows, then copies of the rows named in copy_of; returns the refused faces.
  auto build = [&V](Mesh& mesh, const std::vector<int>& copy_of, const std::vector<std::array<int, 3>>& T) {
    const size_t nv = V.rows() + copy_of.size();
    mesh.clear();
    mesh.reserve(nv, nv + T.size(), T.size());
    std::vector<Mesh::VertexHandle> vh(nv);
    for (Eigen::Index i = 0; i < V.rows(); ++i) vh[i] = mesh.add_vertex(to_point(V.row(i).transpose()));
    for (size_t j = 0; j < copy_of.size(); ++j)
      vh[V.rows() + j] = mesh.add_vertex(to_point(V.row(copy_of[j]).transpose()));
    SilenceOmerr silence;
    size_t refused = 0;
    for (const auto& t : T)
      if (!mesh.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid()) ++refused;
    return refused;
  };
  auto nonmanifold_vertices = [](const Mesh& mesh) {
    size_t n = 0;
    for (auto v : mesh.vertices()) n += !mesh.is_isolated(v) && !mesh.is_manifold(v);
    return n;
  };

  Mesh mesh;
  rep.nonmanifold_faces = build(mesh, {}, tris);
  rep.nonmanifold_vertices = nonmanifold_vertices(mesh);
  // Only when OpenMesh refused a face or kept a pinched vertex: the repairs need an edge table.
  if ((options.fix_orientation || options.split_nonmanifold_vertices) &&
      (rep.nonmanifold_faces > 0 || rep.nonmanifold_vertices > 0)) {
    const detail::SoupRepair fix = detail::repair_soup(static_cast<int>(V.rows()), std::move(tris), options);
    rep.nonmanifold_faces = fix.dropped_faces + build(mesh, fix.copy_of, fix.faces);
    rep.flipped_faces = fix.flipped_faces;
    rep.split_vertices = fix.split_vertices;
    rep.added_vertices = fix.copy_of.size();
    rep.nonmanifold_vertices = nonmanifold_vertices(mesh);
  }
  for (auto v : mesh.vertices())
    if (mesh.is_isolated(v)) ++rep.isolated_vertices;
  if (report) *report = rep;
  return mesh;
}

void require_valid(const Mesh& mesh, const char* what) {
  if (mesh.n_faces() == 0) throw InvalidInput(fmt::format("{} has no faces", what));
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InvalidInput(fmt::format("{}: vertex {} has a non-finite coordinate", what, v.idx()));
  }
  const BoundingBox box = bounding_box(mesh);
  const double reach = std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
  const double extent = box.diagonal();  // finite: each side is at most 2 kMaxCoordinate here
  if (reach > kMaxCoordinate)
    throw InvalidInput(fmt::format("{}: coordinates reach {:.3g}; geotex computes with lengths up to {:g} (fourth "
                                   "powers of larger ones overflow): scale the mesh down",
                                   what, reach, kMaxCoordinate));
  if (extent > 0 && extent < kMinExtent)
    throw InvalidInput(fmt::format("{}: the mesh spans {:.3g}; geotex computes with extents from {:g} (fourth "
                                   "powers of smaller ones underflow): scale the mesh up",
                                   what, extent, kMinExtent));
}

int vertices_in_faces(const Mesh& mesh) {
  int n = 0;
  for (auto v : mesh.vertices()) n += !mesh.is_isolated(v);
  return n;
}

}  // namespace geotex
