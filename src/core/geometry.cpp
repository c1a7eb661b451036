#include "geotex/core/geometry.h"

#include <cmath>
#include <numeric>

#include <fmt/format.h>

namespace geotex {

namespace {
inline Vec3 P(const Mesh& m, Mesh::VertexHandle v) { return to_eigen(m.point(v)); }

// The three corners of a face, in order.
inline void corners(const Mesh& m, Mesh::FaceHandle f, Vec3& a, Vec3& b, Vec3& c) {
  auto h = m.halfedge_handle(f);
  a = P(m, m.from_vertex_handle(h));
  b = P(m, m.to_vertex_handle(h));
  c = P(m, m.to_vertex_handle(m.next_halfedge_handle(h)));
}
}  // namespace

MatrixX3d face_normals(const Mesh& mesh) {
  MatrixX3d N(mesh.n_faces(), 3);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < static_cast<int>(mesh.n_faces()); ++i) {
    Vec3 a, b, c;
    corners(mesh, mesh.face_handle(i), a, b, c);
    Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    N.row(i) = (len > 0 ? Vec3(n / len) : Vec3::Zero()).transpose();
  }
  return N;
}

Eigen::VectorXd face_areas(const Mesh& mesh) {
  Eigen::VectorXd A(mesh.n_faces());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < static_cast<int>(mesh.n_faces()); ++i) {
    Vec3 a, b, c;
    corners(mesh, mesh.face_handle(i), a, b, c);
    A[i] = 0.5 * (b - a).cross(c - a).norm();
  }
  return A;
}

MatrixX3d vertex_normals(const Mesh& mesh, NormalWeighting weighting) {
  MatrixX3d N = MatrixX3d::Zero(mesh.n_vertices(), 3);
  for (auto f : mesh.faces()) {
    Vec3 p[3];
    int id[3], k = 0;
    for (auto v : f.vertices()) { p[k] = P(mesh, v); id[k++] = v.idx(); }
    const Vec3 cross = (p[1] - p[0]).cross(p[2] - p[0]);  // |cross| = 2 × area
    const double len = cross.norm();
    if (len == 0) continue;
    for (int j = 0; j < 3; ++j) {
      double w = 1.0;
      if (weighting == NormalWeighting::Area) {
        w = len;
      } else if (weighting == NormalWeighting::Angle) {
        const Vec3 e1 = p[(j + 1) % 3] - p[j], e2 = p[(j + 2) % 3] - p[j];
        w = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      }
      N.row(id[j]) += w * (cross / len).transpose();
    }
  }
  for (Eigen::Index i = 0; i < N.rows(); ++i) {
    const double len = N.row(i).norm();
    if (len > 0) N.row(i) /= len;
  }
  return N;
}

Eigen::VectorXd dihedral_angles(const Mesh& mesh) {
  const MatrixX3d N = face_normals(mesh);
  Eigen::VectorXd D = Eigen::VectorXd::Zero(mesh.n_edges());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < static_cast<int>(mesh.n_edges()); ++i) {
    auto e = mesh.edge_handle(i);
    if (mesh.is_boundary(e)) continue;
    auto h0 = mesh.halfedge_handle(e, 0), h1 = mesh.halfedge_handle(e, 1);
    const Vec3 n0 = N.row(mesh.face_handle(h0).idx()), n1 = N.row(mesh.face_handle(h1).idx());
    const double angle = std::atan2(n0.cross(n1).norm(), n0.dot(n1));
    // Convex if the opposite vertex of face 1 lies below face 0's plane.
    const Vec3 apex1 = P(mesh, mesh.to_vertex_handle(mesh.next_halfedge_handle(h1)));
    const Vec3 a = P(mesh, mesh.from_vertex_handle(h0));
    D[i] = (apex1 - a).dot(n0) <= 0 ? angle : -angle;
  }
  return D;
}

Eigen::VectorXd edge_lengths(const Mesh& mesh) {
  Eigen::VectorXd L(mesh.n_edges());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < static_cast<int>(mesh.n_edges()); ++i) {
    auto h = mesh.halfedge_handle(mesh.edge_handle(i), 0);
    L[i] = (P(mesh, mesh.to_vertex_handle(h)) - P(mesh, mesh.from_vertex_handle(h))).norm();
  }
  return L;
}

double mean_edge_length(const Mesh& mesh) {
  if (mesh.n_edges() == 0) return 0;
  return edge_lengths(mesh).mean();
}

BoundingBox bounding_box(const Mesh& mesh) {
  BoundingBox b;
  if (mesh.n_vertices() == 0) return b;
  b.min = b.max = P(mesh, *mesh.vertices_begin());
  for (auto v : mesh.vertices()) {
    const Vec3 p = P(mesh, v);
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
  }
  return b;
}

std::vector<std::vector<int>> boundary_loops(const Mesh& mesh) {
  std::vector<std::vector<int>> loops;
  std::vector<char> visited(mesh.n_halfedges(), 0);
  for (auto h : mesh.halfedges()) {
    if (!h.is_boundary() || visited[h.idx()]) continue;
    std::vector<int> loop;
    auto cur = h;
    do {
      visited[cur.idx()] = 1;
      loop.push_back(cur.from().idx());
      cur = cur.next();
    } while (cur != h && !visited[cur.idx()]);
    loops.push_back(std::move(loop));
  }
  return loops;
}

Eigen::VectorXi connected_components(const Mesh& mesh, int* n_components) {
  Eigen::VectorXi comp = Eigen::VectorXi::Constant(mesh.n_vertices(), -1);
  int k = 0;
  std::vector<int> stack;
  for (auto seed : mesh.vertices()) {
    if (comp[seed.idx()] >= 0) continue;
    comp[seed.idx()] = k;
    stack.assign(1, seed.idx());
    while (!stack.empty()) {
      auto v = mesh.vertex_handle(stack.back());
      stack.pop_back();
      for (auto w : mesh.vv_range(v))
        if (comp[w.idx()] < 0) {
          comp[w.idx()] = k;
          stack.push_back(w.idx());
        }
    }
    ++k;
  }
  if (n_components) *n_components = k;
  return comp;
}

std::string component_without(const Mesh& mesh, const std::vector<int>& pinned) {
  int k = 0;
  const Eigen::VectorXi comp = connected_components(mesh, &k);
  std::vector<char> held(k, 0);
  for (int v : pinned)
    if (v >= 0 && v < comp.size()) held[comp[v]] = 1;
  std::vector<int> size(k, 0), first(k, -1);
  for (auto v : mesh.vertices()) {
    if (mesh.is_isolated(v)) continue;
    const int c = comp[v.idx()];
    if (size[c]++ == 0) first[c] = v.idx();
  }
  int counted = 0, index = -1, missing = -1;
  for (int c = 0; c < k; ++c) {
    if (size[c] == 0) continue;  // an isolated vertex
    ++counted;
    if (!held[c] && missing < 0) {
      missing = c;
      index = counted;
    }
  }
  if (missing < 0) return {};
  return fmt::format("component {} of {} ({} vertices, e.g. vertex {})", index, counted, size[missing], first[missing]);
}

int euler_characteristic(const Mesh& mesh) {
  return static_cast<int>(mesh.n_vertices()) - static_cast<int>(mesh.n_edges()) +
         static_cast<int>(mesh.n_faces());
}

double surface_area(const Mesh& mesh) { return face_areas(mesh).sum(); }

double signed_volume(const Mesh& mesh) {
  // Tetrahedra on the box's centre, not the origin (the same sum on a closed mesh): far off the origin each
  // term is large and their sum cancelled to noise (10^4 diagonals out, the feature map's protrusion heights
  // moved; bench/invariance.py).
  const Vec3 o = mesh.n_vertices() > 0 ? bounding_box(mesh).center() : Vec3::Zero();
  double vol = 0;
  for (auto f : mesh.faces()) {
    Vec3 a, b, c;
    corners(mesh, f, a, b, c);
    vol += (a - o).dot((b - o).cross(c - o)) / 6.0;
  }
  return vol;
}

Vec3 surface_centroid(const Mesh& mesh) {
  Vec3 c = Vec3::Zero();
  double area = 0;
  for (auto f : mesh.faces()) {
    Vec3 a, b, d;
    corners(mesh, f, a, b, d);
    const double A = 0.5 * (b - a).cross(d - a).norm();
    c += A * (a + b + d) / 3.0;
    area += A;
  }
  return area > 0 ? Vec3(c / area) : c;
}

MeshSummary summarize(const Mesh& mesh) {
  MeshSummary s;
  s.vertices = mesh.n_vertices();
  s.edges = mesh.n_edges();
  s.faces = mesh.n_faces();
  for (auto v : mesh.vertices())
    if (mesh.is_isolated(v)) ++s.isolated_vertices;
  s.boundary_loops = static_cast<int>(boundary_loops(mesh).size());
  connected_components(mesh, &s.components);
  s.components -= static_cast<int>(s.isolated_vertices);
  s.euler = euler_characteristic(mesh) - static_cast<int>(s.isolated_vertices);
  s.closed = s.boundary_loops == 0;
  if (s.components == 1) s.genus = (2 - s.euler - s.boundary_loops) / 2;
  s.mean_edge = mean_edge_length(mesh);
  const Eigen::VectorXd A = face_areas(mesh);
  s.area = A.sum();
  s.min_face_area = A.size() ? A.minCoeff() : 0;
  const double tiny = 1e-12 * s.mean_edge * s.mean_edge;
  s.zero_area_faces = static_cast<size_t>((A.array() <= tiny).count());
  s.volume = s.closed ? signed_volume(mesh) : 0;
  s.box = bounding_box(mesh);
  return s;
}

}  // namespace geotex
