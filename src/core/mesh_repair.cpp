// Repairs of a triangle soup before it becomes a halfedge mesh (make_mesh with BuildOptions):
// non-manifold edges (more than two faces), inconsistent orientation and non-manifold vertices
// (several fans meeting at one vertex). OpenMesh's add_face refuses a face that would make an edge
// or a vertex non-manifold, and a face whose orientation disagrees with a neighbour's looks to it
// like a third face on an edge; so without these repairs a single flipped triangle is dropped and
// leaves a hole, and a second fan at a vertex loses its faces. Here the faces keep their geometry:
// flipped faces are turned round, extra fans get their own copy of the vertex.

#include "geotex/core/mesh_repair.h"

#include <algorithm>
#include <numeric>

#include "union_find.h"

namespace geotex::detail {

namespace {

using Tris = std::vector<std::array<int, 3>>;
using EdgeCorners = std::vector<std::array<int, 2>>;

// Undirected edges of every face corner k: (tris[f][k], tris[f][k+1]); ids by sorting the keys.
// \return the number of edges; \p edge_of gets the edge of corner 3f + k.
int number_edges(const Tris& tris, std::vector<int>& edge_of) {
  const size_t nf = tris.size();
  std::vector<std::pair<uint64_t, uint32_t>> keys(3 * nf);
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = tris[f][k], b = tris[f][(k + 1) % 3];
      keys[3 * f + k] = {(uint64_t(std::min(a, b)) << 32) | std::max(a, b), uint32_t(3 * f + k)};
    }
  std::sort(keys.begin(), keys.end());
  edge_of.assign(3 * nf, 0);
  int n_edges = 0;
  for (size_t i = 0; i < keys.size(); ++i) {
    if (i > 0 && keys[i].first != keys[i - 1].first) ++n_edges;
    edge_of[keys[i].second] = n_edges;
  }
  if (!keys.empty()) ++n_edges;
  return n_edges;
}

// Non-manifold edges: in file order, a face that would be the third on one of its edges is dropped.
// \return which faces are kept; \p dropped counts the others.
std::vector<char> drop_nonmanifold_faces(size_t nf, const std::vector<int>& edge_of, int n_edges, size_t& dropped) {
  std::vector<uint8_t> edge_faces(n_edges, 0);
  std::vector<char> keep(nf, 1);
  for (size_t f = 0; f < nf; ++f) {
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok &= edge_faces[edge_of[3 * f + k]] < 2;
    if (!ok) {
      keep[f] = 0;
      ++dropped;
      continue;
    }
    for (int k = 0; k < 3; ++k) ++edge_faces[edge_of[3 * f + k]];
  }
  return keep;
}

// The two kept faces of every manifold edge (as corner ids 3f + k).
EdgeCorners edge_corners_of(const std::vector<char>& keep, const std::vector<int>& edge_of, int n_edges) {
  EdgeCorners edge_corners(n_edges, {-1, -1});
  for (size_t f = 0; f < keep.size(); ++f) {
    if (!keep[f]) continue;
    for (int k = 0; k < 3; ++k) {
      auto& ec = edge_corners[edge_of[3 * f + k]];
      (ec[0] < 0 ? ec[0] : ec[1]) = int(3 * f + k);
    }
  }
  return edge_corners;
}

// Breadth-first over faces joined by manifold edges: a neighbour must run along the shared edge in
// the opposite direction. Then, per component, the orientation most faces already had wins.
// \return the faces flipped; \p edge_of and \p edge_corners follow the new corner numbering.
size_t orient_consistently(Tris& tris, const std::vector<char>& keep, std::vector<int>& edge_of, EdgeCorners& edge_corners) {
  const size_t nf = tris.size();
  // +1 if face f runs along its corner-k edge from the smaller to the larger index.
  auto dir = [&](int corner) {
    const auto& t = tris[corner / 3];
    return t[corner % 3] < t[(corner % 3 + 1) % 3] ? 1 : -1;
  };
  std::vector<int8_t> sign(nf, 0);
  std::vector<int> queue;
  for (size_t seed = 0; seed < nf; ++seed) {
    if (!keep[seed] || sign[seed] != 0) continue;
    queue.assign(1, int(seed));
    sign[seed] = 1;
    size_t flipped = 0;
    for (size_t q = 0; q < queue.size(); ++q) {
      const int f = queue[q];
      flipped += sign[f] < 0;
      for (int k = 0; k < 3; ++k) {
        const auto& ec = edge_corners[edge_of[3 * f + k]];
        if (ec[1] < 0) continue;  // boundary edge
        const int other = ec[0] == 3 * f + k ? ec[1] : ec[0];
        const int g = other / 3;
        const int8_t want = static_cast<int8_t>(-sign[f] * dir(3 * f + k) * dir(other));
        if (sign[g] == 0) {
          sign[g] = want;
          queue.push_back(g);
        }  // else: a conflict means a non-orientable component; OpenMesh refuses one face later
      }
    }
    if (2 * flipped > queue.size())
      for (int f : queue) sign[f] = static_cast<int8_t>(-sign[f]);
  }
  size_t flipped = 0;
  for (size_t f = 0; f < nf; ++f)
    if (keep[f] && sign[f] < 0) {
      std::swap(tris[f][1], tris[f][2]);
      ++flipped;
    }
  // Flipping (a, b, c) to (a, c, b) turns its corner edges (ab, bc, ca) into (ac, cb, ba).
  for (size_t f = 0; f < nf; ++f)
    if (keep[f] && sign[f] < 0) std::swap(edge_of[3 * f], edge_of[3 * f + 2]);
  edge_corners = edge_corners_of(keep, edge_of, static_cast<int>(edge_corners.size()));
  return flipped;
}

// Corners (f, k) at the same vertex are in one fan when their faces share a manifold edge through
// that vertex. A vertex with several fans keeps the first; each other fan gets a copy (out.n_vertices,
// out.copy_of, out.split_vertices).
void split_fans(Tris& tris, const std::vector<char>& keep, const EdgeCorners& edge_corners, int n_vertices,
                SoupRepair& out) {
  const size_t nf = tris.size();
  UnionFind uf(3 * nf);
  for (const auto& ec : edge_corners) {
    if (ec[1] < 0) continue;
    const int f = ec[0] / 3, g = ec[1] / 3;
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l)
        if (tris[f][k] == tris[g][l]) uf.unite(3 * f + k, 3 * g + l);  // the edge's two ends
  }
  std::vector<int> fan_root(n_vertices, -1);  // root of the fan that keeps the original vertex
  std::vector<int> root_vertex(3 * nf, -1);   // vertex id of the copy made for a fan (by root)
  for (size_t f = 0; f < nf; ++f) {
    if (!keep[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const int c = int(3 * f + k), v = tris[f][k], r = uf.find(c);
      if (fan_root[v] < 0) fan_root[v] = r;
      if (fan_root[v] == r) continue;
      if (root_vertex[r] < 0) {
        root_vertex[r] = out.n_vertices++;
        out.copy_of.push_back(v);
      }
      tris[f][k] = root_vertex[r];
    }
  }
  std::vector<char> split(n_vertices, 0);
  for (int v : out.copy_of) split[v] = 1;
  out.split_vertices = static_cast<size_t>(std::count(split.begin(), split.end(), 1));
}

}  // namespace

SoupRepair repair_soup(int n_vertices, std::vector<std::array<int, 3>> tris, const BuildOptions& options) {
  SoupRepair out;
  const size_t nf = tris.size();
  std::vector<int> edge_of;
  const int n_edges = number_edges(tris, edge_of);
  const std::vector<char> keep = drop_nonmanifold_faces(nf, edge_of, n_edges, out.dropped_faces);
  EdgeCorners edge_corners = edge_corners_of(keep, edge_of, n_edges);
  if (options.fix_orientation) out.flipped_faces = orient_consistently(tris, keep, edge_of, edge_corners);
  out.n_vertices = n_vertices;
  if (options.split_nonmanifold_vertices) split_fans(tris, keep, edge_corners, n_vertices, out);
  out.faces.reserve(nf - out.dropped_faces);
  for (size_t f = 0; f < nf; ++f)
    if (keep[f]) out.faces.push_back(tris[f]);
  return out;
}

}  // namespace geotex::detail
